// Identification and validation of a motor-propeller pair (see propulsion_identification.h).
#include "uascma/identification/propulsion_identification.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include <boost/math/distributions/students_t.hpp>
#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/identification/least_absolute.h"

namespace uascma::identification {
namespace {

constexpr double kAirDensity = 1.225;       // kg/m³, ISA sea level (as defaults.md's drag table)
constexpr double kMetresPerInch = 0.0254;
// Dimensionless static C_T of small propellers lies well inside this range (ours: 5-inch props measure 0.08-0.2);
// outside it the RPM column's scaling (pole pairs) is suspect.
constexpr double kPlausibleCtLow = 0.02, kPlausibleCtHigh = 0.4;

struct Points {
  std::vector<double> throttle_us, power_w, rpm, thrust_n, torque_nm;
  bool has_torque = true;
};

Points Gather(const std::vector<ThrustStandRecord>& records) {
  Points points;
  for (const ThrustStandRecord& record : records) {
    points.has_torque = points.has_torque && !record.torque_nm.empty();
    for (int k = 0; k < record.size(); ++k) {
      points.throttle_us.push_back(record.throttle_us[k]);
      points.power_w.push_back(record.power_w[k]);
      points.rpm.push_back(record.rpm[k]);
      points.thrust_n.push_back(record.thrust_n[k]);
      if (!record.torque_nm.empty()) points.torque_nm.push_back(record.torque_nm[k]);
    }
  }
  return points;
}

double Mean(const std::vector<double>& values) {
  double sum = 0.0;
  for (double v : values) sum += v;
  return sum / static_cast<double>(values.size());
}

double SampleStd(const std::vector<double>& values, double mean) {
  double sum = 0.0;
  for (double v : values) sum += (v - mean) * (v - mean);
  return std::sqrt(sum / static_cast<double>(values.size() - 1));
}

double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

Eigen::RowVectorXd DesignRow(const RpmSurface& surface, double throttle_us, double power_w) {
  const double x = (throttle_us - surface.throttle_mean_us) / surface.throttle_std_us;
  const double y = (power_w - surface.power_mean_w) / surface.power_std_w;
  Eigen::RowVectorXd row(surface.terms.size());
  for (std::size_t t = 0; t < surface.terms.size(); ++t) {
    row[t] = std::pow(x, surface.terms[t][0]) * std::pow(y, surface.terms[t][1]);
  }
  return row;
}

// The surface of `order` fitted by LAR to the points selected by `use` (normalisation of all points).
std::optional<RpmSurface> FitSurface(const Points& points, const std::vector<char>& use, int order) {
  RpmSurface surface;
  surface.order = order;
  surface.terms = SurfaceTerms(order);
  surface.throttle_mean_us = Mean(points.throttle_us);
  surface.throttle_std_us = SampleStd(points.throttle_us, surface.throttle_mean_us);
  surface.power_mean_w = Mean(points.power_w);
  surface.power_std_w = SampleStd(points.power_w, surface.power_mean_w);
  const int p = static_cast<int>(surface.terms.size());
  std::vector<int> rows;
  for (std::size_t k = 0; k < use.size(); ++k) {
    if (use[k]) rows.push_back(static_cast<int>(k));
  }
  if (static_cast<int>(rows.size()) < p + 1) return std::nullopt;
  Eigen::MatrixXd design(rows.size(), p);
  Eigen::VectorXd rpm(rows.size());
  surface.min_throttle_us = surface.min_power_w = std::numeric_limits<double>::infinity();
  surface.max_throttle_us = surface.max_power_w = -std::numeric_limits<double>::infinity();
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const int k = rows[r];
    design.row(r) = DesignRow(surface, points.throttle_us[k], points.power_w[k]);
    rpm[r] = points.rpm[k];
    surface.min_throttle_us = std::min(surface.min_throttle_us, points.throttle_us[k]);
    surface.max_throttle_us = std::max(surface.max_throttle_us, points.throttle_us[k]);
    surface.min_power_w = std::min(surface.min_power_w, points.power_w[k]);
    surface.max_power_w = std::max(surface.max_power_w, points.power_w[k]);
  }
  const LarResult fit = FitLeastAbsoluteResiduals(design, rpm);
  if (fit.status == LarStatus::kRankDeficient) return std::nullopt;
  surface.coefficients = fit.coefficients;
  surface.degrees_of_freedom = static_cast<int>(rows.size()) - p;
  surface.residual_scale_rpm = std::sqrt((rpm - design * fit.coefficients).squaredNorm() / surface.degrees_of_freedom);
  surface.inverse_normal = (design.transpose() * design).inverse();
  return surface;
}

struct CrossValidation {
  std::optional<double> median_relative_error;
  double max_relative_error = 0.0;
  double share_within_bounds = 0.0;
  std::vector<LeftOutPrediction> predictions;  // [points]
};

// Leave one throttle step out (every point at that ESC signal, from every file), fit the rest, predict it.
CrossValidation LeaveOneStepOut(const Points& points, int order) {
  std::map<long, std::vector<int>> steps;
  for (std::size_t k = 0; k < points.throttle_us.size(); ++k) {
    steps[std::lround(points.throttle_us[k])].push_back(static_cast<int>(k));
  }
  std::vector<double> errors;
  std::vector<LeftOutPrediction> predictions(points.throttle_us.size());
  int within = 0;
  for (const auto& [step, members] : steps) {
    std::vector<char> use(points.throttle_us.size(), 1);
    for (int k : members) use[k] = 0;
    const std::optional<RpmSurface> surface = FitSurface(points, use, order);
    if (!surface) return {};
    for (int k : members) {
      const double predicted = surface->CalcRpm(points.throttle_us[k], points.power_w[k]);
      const double bound = surface->CalcBoundHalfWidth(points.throttle_us[k], points.power_w[k]);
      predictions[k] = {predicted, bound};
      errors.push_back(std::abs(predicted - points.rpm[k]) / points.rpm[k]);
      if (std::abs(predicted - points.rpm[k]) <= bound) ++within;
    }
  }
  CrossValidation result;
  result.median_relative_error = Median(errors);
  result.max_relative_error = *std::max_element(errors.begin(), errors.end());
  result.share_within_bounds = static_cast<double>(within) / static_cast<double>(errors.size());
  result.predictions = std::move(predictions);
  return result;
}

}  // namespace

std::vector<SurfaceTerm> SurfaceTerms(int order) {
  // Eq. 2.12's nine terms (cubic in throttle, quadratic in power) and the lower orders.
  switch (order) {
    case 3: return {{0, 0}, {1, 0}, {0, 1}, {2, 0}, {1, 1}, {0, 2}, {3, 0}, {2, 1}, {1, 2}};
    case 2: return {{0, 0}, {1, 0}, {0, 1}, {2, 0}, {1, 1}, {0, 2}};
    case 1: return {{0, 0}, {1, 0}, {0, 1}};
    default: UASCMA_CHECK(false, "surface orders are 1, 2 and 3"); return {};
  }
}

std::string TermName(const SurfaceTerm& term) { return fmt::format("p{}{}", term[0], term[1]); }

double RpmSurface::CalcRpm(double throttle_us, double power_w) const {
  return DesignRow(*this, throttle_us, power_w).dot(coefficients);
}

double RpmSurface::CalcBoundHalfWidth(double throttle_us, double power_w) const {
  const Eigen::RowVectorXd row = DesignRow(*this, throttle_us, power_w);
  const double leverage = row * inverse_normal * row.transpose();
  const boost::math::students_t distribution(static_cast<double>(degrees_of_freedom));
  const double t = boost::math::quantile(distribution, 0.975);
  return t * residual_scale_rpm * std::sqrt(1.0 + leverage);
}

bool RpmSurface::InRange(double throttle_us, double power_w) const {
  return throttle_us >= min_throttle_us && throttle_us <= max_throttle_us && power_w >= min_power_w &&
         power_w <= max_power_w;
}

bool PropulsionIdentificationOptions::IsValid(std::string* error) const {
  if (!CheckWithin(pole_pairs, kPolePairsBounds, "pole_pairs", error)) return false;
  if (!CheckWithin(diameter_in, kDiameterBounds, "diameter_in", error)) return false;
  return CheckWithin(thrust_check_above_us, kThrottleBounds, "thrust_check_above_us", error);
}

namespace {

// C_T of eq. 2.1 by LAR through the origin: min Σ |T_k − C_T n_k²| = min Σ n_k² |T_k / n_k² − C_T|, the weighted
// median of T/n² with weights n² (exact, no iteration). The same for C_Q with torque.
double FitSquareLaw(const std::vector<double>& rpm, const std::vector<double>& value) {
  Eigen::VectorXd ratio(rpm.size()), weight(rpm.size());
  for (std::size_t k = 0; k < rpm.size(); ++k) {
    weight[k] = rpm[k] * rpm[k];
    ratio[k] = value[k] / weight[k];
  }
  return WeightedMedian(ratio, weight);
}

void CheckThrust(const Points& points, const PropulsionIdentificationOptions& options,
                 PropulsionIdentification* result) {
  std::vector<double> errors;
  for (std::size_t k = 0; k < points.rpm.size(); ++k) {
    if (!(points.throttle_us[k] > options.thrust_check_above_us) || !(points.thrust_n[k] > 0.0)) continue;
    const double predicted = result->thrust_coefficient_n_per_rpm2 * points.rpm[k] * points.rpm[k];
    errors.push_back(std::abs(predicted - points.thrust_n[k]) / points.thrust_n[k]);
  }
  result->thrust_check_points = static_cast<int>(errors.size());
  if (errors.empty()) return;
  result->thrust_median_relative_error = Median(errors);
  result->thrust_max_relative_error = *std::max_element(errors.begin(), errors.end());
}

// T_max and the power law of one motor (propulsion_identification.h): LAR of ln P = ln k + b ln T over the points
// above the check throttle, where the stand's thrust and power are well above their noise.
void FitRotorLimits(const Points& points, const PropulsionIdentificationOptions& options,
                    PropulsionIdentification* result) {
  std::vector<double> log_thrust, log_power;
  for (std::size_t k = 0; k < points.rpm.size(); ++k) {
    result->max_thrust_n = std::max(result->max_thrust_n, points.thrust_n[k]);
    if (!(points.throttle_us[k] > options.thrust_check_above_us) || !(points.thrust_n[k] > 0.0) ||
        !(points.power_w[k] > 0.0)) {
      continue;
    }
    log_thrust.push_back(std::log(points.thrust_n[k]));
    log_power.push_back(std::log(points.power_w[k]));
  }
  result->power_law_points = static_cast<int>(log_thrust.size());
  if (log_thrust.size() < 3) return;
  Eigen::MatrixXd design(log_thrust.size(), 2);
  Eigen::VectorXd observed(log_thrust.size());
  for (std::size_t k = 0; k < log_thrust.size(); ++k) {
    design(k, 0) = 1.0;
    design(k, 1) = log_thrust[k];
    observed[k] = log_power[k];
  }
  const LarResult fit = FitLeastAbsoluteResiduals(design, observed);
  if (fit.status == LarStatus::kRankDeficient) return;
  result->power_law_w_at_one_newton = std::exp(fit.coefficients[0]);
  result->power_law_exponent = fit.coefficients[1];
}

}  // namespace

PropulsionIdentification IdentifyPropulsion(const std::vector<ThrustStandRecord>& records,
                                            const PropulsionIdentificationOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("propulsion identification options", "options", error);
  const Points points = Gather(records);
  const std::string source = records.empty() ? std::string("thrust-stand data") : records.front().source;
  if (points.rpm.size() < 4 || Mean(points.throttle_us) == points.throttle_us.front()) {
    throw InputError(source, "points", fmt::format("at least 4 turning points at two or more throttle steps for the "
                                                   "lowest-order surface, got {}", points.rpm.size()));
  }
  PropulsionIdentification result;
  result.points = static_cast<int>(points.rpm.size());
  // The dissertation's 9-term surface unless a lower order cross-validates better.
  int chosen = 0;
  CrossValidation chosen_cv;
  for (int order : {3, 2, 1}) {
    const CrossValidation cv = LeaveOneStepOut(points, order);
    result.candidates.push_back({order, static_cast<int>(SurfaceTerms(order).size()), cv.median_relative_error});
    if (!cv.median_relative_error) continue;
    if (chosen == 0 || *cv.median_relative_error < *chosen_cv.median_relative_error) chosen = order, chosen_cv = cv;
  }
  if (chosen == 0) {
    throw InputError(source, "points", fmt::format("enough points at distinct throttle steps to cross-validate even "
                                                   "the 3-term surface, got {}", points.rpm.size()));
  }
  const std::vector<char> all(points.rpm.size(), 1);
  result.surface = *FitSurface(points, all, chosen);
  result.loo_rpm_median_relative_error = *chosen_cv.median_relative_error;
  result.loo_rpm_max_relative_error = chosen_cv.max_relative_error;
  result.loo_share_within_95_bounds = chosen_cv.share_within_bounds;
  result.loo_predictions = chosen_cv.predictions;
  if (chosen != 3) {
    result.warnings.push_back(fmt::format("the data supports {} coefficients, not eq. 2.12's 9 (leave-one-step-out)",
                                          result.surface.terms.size()));
  }
  result.thrust_coefficient_n_per_rpm2 = FitSquareLaw(points.rpm, points.thrust_n);
  if (points.has_torque && !points.torque_nm.empty()) {
    result.torque_coefficient_nm_per_rpm2 = FitSquareLaw(points.rpm, points.torque_nm);
  }
  // C_T [N/RPM²] · 3600 [RPM² per (rev/s)²] / (ρ D⁴): the propeller's dimensionless static thrust coefficient.
  const double diameter = options.diameter_in * kMetresPerInch;
  result.thrust_coefficient_dimensionless =
      result.thrust_coefficient_n_per_rpm2 * 3600.0 / (kAirDensity * std::pow(diameter, 4));
  if (!(result.thrust_coefficient_dimensionless >= kPlausibleCtLow &&
        result.thrust_coefficient_dimensionless <= kPlausibleCtHigh)) {
    result.warnings.push_back(fmt::format(
        "dimensionless C_T {:.3g} is outside {}-{} for a {:g}-inch propeller: check --pole-pairs (the RPM column's "
        "scaling) and --diameter-in", result.thrust_coefficient_dimensionless, kPlausibleCtLow, kPlausibleCtHigh,
        options.diameter_in));
  }
  CheckThrust(points, options, &result);
  FitRotorLimits(points, options, &result);
  return result;
}

PropulsionValidation ValidatePropulsion(const RpmSurface& surface, double thrust_coefficient_n_per_rpm2,
                                        const std::vector<ThrustStandRecord>& records) {
  PropulsionValidation result;
  std::vector<double> rpm_errors, thrust_errors;
  int within = 0;
  for (const ThrustStandRecord& record : records) {
    for (int k = 0; k < record.size(); ++k) {
      PropulsionValidation::Point point{};
      point.throttle_us = record.throttle_us[k];
      point.power_w = record.power_w[k];
      point.rpm = record.rpm[k];
      point.predicted_rpm = surface.CalcRpm(point.throttle_us, point.power_w);
      point.bound_rpm = surface.CalcBoundHalfWidth(point.throttle_us, point.power_w);
      point.thrust_n = record.thrust_n[k];
      point.predicted_thrust_n = thrust_coefficient_n_per_rpm2 * point.rpm * point.rpm;
      point.in_range = surface.InRange(point.throttle_us, point.power_w);
      result.detail.push_back(point);
      ++result.points;
      if (!point.in_range) {
        ++result.out_of_range;
        continue;
      }
      rpm_errors.push_back(std::abs(point.predicted_rpm - point.rpm) / point.rpm);
      if (std::abs(point.predicted_rpm - point.rpm) <= point.bound_rpm) ++within;
      if (point.thrust_n > 0.0) thrust_errors.push_back(std::abs(point.predicted_thrust_n - point.thrust_n) / point.thrust_n);
    }
  }
  if (!rpm_errors.empty()) {
    result.share_within_95_bounds = static_cast<double>(within) / static_cast<double>(rpm_errors.size());
    result.rpm_median_relative_error = Median(rpm_errors);
    result.rpm_max_relative_error = *std::max_element(rpm_errors.begin(), rpm_errors.end());
  }
  result.thrust_median_relative_error = Median(thrust_errors);
  return result;
}

}  // namespace uascma::identification
