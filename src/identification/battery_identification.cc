// Identification of the cell model from a recorded discharge and a charge (see battery_identification.h).
#include "uascma/identification/battery_identification.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/identification/least_absolute.h"

namespace uascma::identification {
namespace {

constexpr double kSecondsPerHour = 3600.0;
constexpr int kMinimumLoadedSamples = 10;  // ours: a few per OCV node at the coarsest useful table
// The weights of the L1 reweighting stop growing below 0.1 mV (ours: well below any cycler's resolution).
constexpr double kResidualFloorV = 1e-4;
// τ1 grid of the start, as multiples of the record's median sample period (ours: 0.5 to ~1000 periods).
constexpr double kTauGridPeriods[] = {0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 128.0, 256.0, 512.0, 1024.0};

// Quantities that do not depend on the trial resistances: interval currents, SOC at each sample, which samples
// are loaded.
struct Prepared {
  std::vector<double> interval_current_a;  // [samples − 1], mean of the interval's two samples
  std::vector<double> interval_s;          // [samples − 1]
  std::vector<double> soc_fraction;        // [samples]
  std::vector<char> loaded;                // [samples]
  double capacity_as = 0.0;
  double capacity_standard_error_as = 0.0;
  double initial_rc_current_a = 0.0;  // 0 from rest; the first current when the record starts under load
  double median_period_s = 0.0;
  double largest_step_resistance_ohm = 0.0;  // |Δv / Δi| at the largest change of current: a starting value
  // Samples 0..fitted_samples − 1 enter the fit: up to the record's deepest point. The rest after a discharge to
  // the cut-off relaxes by diffusion the one-RC model does not have (docs/identification.md), so it is only reported.
  int fitted_samples = 0;
};

struct Trial {
  double r0_ohm, r1_ohm, tau_s;
};

// The Coulomb count of a record, `sign` +1 for the charge drawn (a discharge), −1 for the charge put in: the
// intervals (each at the mean of its two samples' currents), the median sample period and half the difference of
// the left and right Riemann sums over the whole record, into `prepared`; returns the running count at each sample.
std::vector<double> CountCharge(const BatteryRecord& record, double sign, Prepared* prepared) {
  const int n = record.size();
  std::vector<double> charge_as(n, 0.0);
  double left_sum = 0.0, right_sum = 0.0;
  std::vector<double> periods;
  for (int k = 0; k + 1 < n; ++k) {
    const double dt = record.time_s[k + 1] - record.time_s[k];
    prepared->interval_s.push_back(dt);
    prepared->interval_current_a.push_back(0.5 * (record.current_a[k] + record.current_a[k + 1]));
    charge_as[k + 1] = charge_as[k] + sign * prepared->interval_current_a.back() * dt;
    left_sum += sign * record.current_a[k] * dt;
    right_sum += sign * record.current_a[k + 1] * dt;
    periods.push_back(dt);
  }
  std::nth_element(periods.begin(), periods.begin() + periods.size() / 2, periods.end());
  prepared->median_period_s = periods[periods.size() / 2];
  prepared->capacity_standard_error_as = 0.5 * std::abs(left_sum - right_sum);
  return charge_as;
}

Prepared Prepare(const BatteryRecord& record, const CellIdentificationOptions& options) {
  const int n = record.size();
  Prepared prepared;
  const double largest = *std::max_element(record.current_a.begin(), record.current_a.end());
  const double threshold = options.load_fraction * largest;
  const std::vector<double> charge_as = CountCharge(record, 1.0, &prepared);
  double largest_step = 0.0;
  for (int k = 0; k + 1 < n; ++k) {
    const double step = std::abs(record.current_a[k + 1] - record.current_a[k]);
    if (step > largest_step && step > threshold) {
      largest_step = step;
      prepared.largest_step_resistance_ohm = std::abs(record.voltage_v[k + 1] - record.voltage_v[k]) / step;
    }
  }
  // SOC 1 at the first sample, SOC 0 at the deepest point of the record.
  // The discharge ends at the last loaded sample; the interval after it (the load switched off somewhere inside)
  // still counts: SOC 0 is at the first sample after the discharge.
  int last_loaded = n - 1;
  while (last_loaded > 0 && !(record.current_a[last_loaded] > threshold)) --last_loaded;
  prepared.capacity_as = charge_as[std::min(last_loaded + 1, n - 1)];
  prepared.fitted_samples = last_loaded + 1;
  for (int k = 0; k < n; ++k) {
    prepared.soc_fraction.push_back(1.0 - charge_as[k] / prepared.capacity_as);
    prepared.loaded.push_back(record.current_a[k] > threshold ? 1 : 0);
  }
  prepared.initial_rc_current_a = prepared.loaded[0] ? record.current_a[0] : 0.0;
  return prepared;
}

// A charge record's view (battery_identification.h): SOC from 0 at its first sample to 1 at its end, by the charge put
// in (−i); loaded where the charging current exceeds the load fraction of its largest.
Prepared PrepareCharge(const BatteryRecord& record, const CellIdentificationOptions& options) {
  const int n = record.size();
  Prepared prepared;
  const double largest = -*std::min_element(record.current_a.begin(), record.current_a.end());
  const double threshold = options.load_fraction * largest;
  const std::vector<double> charged_as = CountCharge(record, -1.0, &prepared);
  prepared.capacity_as = charged_as[n - 1];
  prepared.fitted_samples = n;
  for (int k = 0; k < n; ++k) {
    prepared.soc_fraction.push_back(charged_as[k] / prepared.capacity_as);
    prepared.loaded.push_back(-record.current_a[k] > threshold ? 1 : 0);
  }
  prepared.initial_rc_current_a = prepared.loaded[0] ? record.current_a[0] : 0.0;
  return prepared;
}

// i_R1 at each sample: the first-order lag of eq. 3.1 under the interval currents.
std::vector<double> CalcRcCurrent(const Prepared& prepared, double tau_s) {
  std::vector<double> rc(prepared.soc_fraction.size());
  rc[0] = prepared.initial_rc_current_a;
  for (std::size_t k = 0; k + 1 < rc.size(); ++k) {
    const double decay = std::exp(-prepared.interval_s[k] / tau_s);
    rc[k + 1] = decay * rc[k] + (1.0 - decay) * prepared.interval_current_a[k];
  }
  return rc;
}

// A node's OCV: a LAR line through the loaded samples within `half_width` of it, evaluated at the node.
std::optional<double> FitNode(const std::vector<double>& soc, const std::vector<double>& ocv, double node,
                              double half_width) {
  for (double width = half_width; width <= 4.0 * half_width; width *= 2.0) {
    std::vector<int> inside;
    for (std::size_t k = 0; k < soc.size(); ++k) {
      if (std::abs(soc[k] - node) <= width) inside.push_back(static_cast<int>(k));
    }
    if (inside.size() < 3) continue;
    Eigen::MatrixXd design(inside.size(), 2);
    Eigen::VectorXd values(inside.size());
    for (std::size_t row = 0; row < inside.size(); ++row) {
      design(row, 0) = 1.0;
      design(row, 1) = soc[inside[row]] - node;
      values[row] = ocv[inside[row]];
    }
    const LarResult fit = FitLeastAbsoluteResiduals(design, values);
    if (fit.status == LarStatus::kRankDeficient) continue;
    return fit.coefficients[0];
  }
  return std::nullopt;
}

// Pool adjacent violators (equal weights), then a strict rise of 10 µV per node where the curve is flat.
void MakeIncreasing(std::vector<double>* values) {
  std::vector<double> block_mean;
  std::vector<int> block_size;
  for (double value : *values) {
    block_mean.push_back(value);
    block_size.push_back(1);
    while (block_mean.size() > 1 && block_mean[block_mean.size() - 2] > block_mean.back()) {
      const double total = block_mean.back() * block_size.back() +
                           block_mean[block_mean.size() - 2] * block_size[block_size.size() - 2];
      block_size[block_size.size() - 2] += block_size.back();
      block_mean[block_mean.size() - 2] = total / block_size[block_size.size() - 2];
      block_mean.pop_back();
      block_size.pop_back();
    }
  }
  std::size_t index = 0;
  for (std::size_t b = 0; b < block_mean.size(); ++b) {
    for (int j = 0; j < block_size[b]; ++j) (*values)[index++] = block_mean[b];
  }
  constexpr double kMinimumRiseV = 1e-5;
  for (std::size_t k = 1; k < values->size(); ++k) (*values)[k] = std::max((*values)[k], (*values)[k - 1] + kMinimumRiseV);
}

struct OcvNodes {
  std::vector<double> soc_fraction, voltage_v;
};

OcvNodes BuildOcv(const BatteryRecord& record, const Prepared& prepared, const std::vector<double>& rc_current,
                  const Trial& trial, int node_count) {
  std::vector<double> soc, ocv;
  for (int k = 0; k < record.size(); ++k) {
    if (!prepared.loaded[k]) continue;
    soc.push_back(prepared.soc_fraction[k]);
    ocv.push_back(record.voltage_v[k] + trial.r0_ohm * record.current_a[k] + trial.r1_ohm * rc_current[k]);
  }
  OcvNodes nodes;
  const double spacing = 1.0 / (node_count - 1);
  for (int n = 0; n < node_count; ++n) {
    const std::optional<double> value = FitNode(soc, ocv, n * spacing, spacing);
    if (!value) continue;
    nodes.soc_fraction.push_back(n * spacing);
    nodes.voltage_v.push_back(*value);
  }
  MakeIncreasing(&nodes.voltage_v);
  return nodes;
}

// v − v̂ at every sample for a trial (v̂ = OCV(z) − R0 i − R1 i_R1, eq. 3.3 with M = M0 = 0); empty when the trial's
// OCV has fewer than two nodes.
Eigen::VectorXd CalcResiduals(const BatteryRecord& record, const Prepared& prepared, const Trial& trial,
                              int node_count, OcvNodes* nodes_out = nullptr, bool every_sample = false) {
  const std::vector<double> rc_current = CalcRcCurrent(prepared, trial.tau_s);
  OcvNodes nodes = BuildOcv(record, prepared, rc_current, trial, node_count);
  if (nodes.soc_fraction.size() < 2) return {};
  const models::OcvTable ocv(nodes.soc_fraction, nodes.voltage_v, record.source);
  const int count = every_sample ? record.size() : prepared.fitted_samples;
  Eigen::VectorXd residual(count);
  for (int k = 0; k < count; ++k) {
    const double model_v = ocv.CalcVoltage(prepared.soc_fraction[k]) - trial.r0_ohm * record.current_a[k] -
                           trial.r1_ohm * rc_current[k];
    residual[k] = record.voltage_v[k] - model_v;
  }
  if (nodes_out != nullptr) *nodes_out = std::move(nodes);
  return residual;
}

// The search stays within 10 µΩ to 10 Ω and τ1 within 10 ms to 10⁶ s (ours: beyond any cell).
Trial FromLog(const Eigen::Vector3d& theta) {
  auto bounded = [](double log_value, double low, double high) { return std::exp(std::clamp(log_value, std::log(low), std::log(high))); };
  return {bounded(theta[0], 1e-5, 10.0), bounded(theta[1], 1e-5, 10.0), bounded(theta[2], 1e-2, 1e6)};
}

double AbsoluteSum(const Eigen::VectorXd& residual) {
  return residual.size() == 0 ? std::numeric_limits<double>::infinity() : residual.cwiseAbs().sum();
}

// Forward-difference Jacobian of the residuals in (ln R0, ln R1, ln τ1).
Eigen::MatrixXd CalcJacobian(const BatteryRecord& record, const Prepared& prepared, const Eigen::Vector3d& theta,
                             const Eigen::VectorXd& residual, int node_count) {
  constexpr double kLogStep = 1e-4;
  Eigen::MatrixXd jacobian(residual.size(), 3);
  for (int j = 0; j < 3; ++j) {
    Eigen::Vector3d shifted = theta;
    shifted[j] += kLogStep;
    const Eigen::VectorXd moved = CalcResiduals(record, prepared, FromLog(shifted), node_count);
    jacobian.col(j) = moved.size() == residual.size() ? Eigen::VectorXd((moved - residual) / kLogStep)
                                                      : Eigen::VectorXd::Zero(residual.size());
  }
  return jacobian;
}

// The best τ1 of the grid (R0 = R1 = half the largest step resistance), then Levenberg-Marquardt with L1 weights.
Eigen::Vector3d Minimise(const BatteryRecord& record, const Prepared& prepared, const CellIdentificationOptions& options,
                         int* iterations) {
  const double resistance = prepared.largest_step_resistance_ohm > 0.0 ? prepared.largest_step_resistance_ohm : 0.05;
  Eigen::Vector3d theta(std::log(0.5 * resistance), std::log(0.5 * resistance), 0.0);
  double best = std::numeric_limits<double>::infinity();
  for (double periods : kTauGridPeriods) {
    const Eigen::Vector3d trial(theta[0], theta[1], std::log(periods * prepared.median_period_s));
    const double sum = AbsoluteSum(CalcResiduals(record, prepared, FromLog(trial), options.ocv_points));
    if (sum < best) best = sum, theta = trial;
  }
  double damping = 1e-3;
  for (*iterations = 0; *iterations < options.max_iterations; ++*iterations) {
    const Eigen::VectorXd residual = CalcResiduals(record, prepared, FromLog(theta), options.ocv_points);
    const Eigen::MatrixXd jacobian = CalcJacobian(record, prepared, theta, residual, options.ocv_points);
    const Eigen::VectorXd weight = residual.cwiseAbs().cwiseMax(kResidualFloorV).cwiseInverse();
    const Eigen::Matrix3d normal = jacobian.transpose() * weight.asDiagonal() * jacobian;
    const Eigen::Vector3d gradient = jacobian.transpose() * weight.asDiagonal() * residual;
    bool improved = false;
    for (int attempt = 0; attempt < 8 && !improved; ++attempt) {
      Eigen::Matrix3d damped = normal;
      damped.diagonal() += damping * normal.diagonal().cwiseMax(1e-12);
      const Eigen::Vector3d step = -damped.ldlt().solve(gradient);
      const Eigen::Vector3d candidate = theta + step;
      const double sum = AbsoluteSum(CalcResiduals(record, prepared, FromLog(candidate), options.ocv_points));
      if (sum < best) {
        improved = best - sum > 1e-9 * best;
        theta = candidate, best = sum, damping = std::max(damping / 3.0, 1e-9);
        if (!improved) return theta;  // converged: the decrease is below 1e-9 of the sum
      } else {
        damping *= 4.0;
      }
    }
    if (!improved) break;
  }
  return theta;
}

// Standard errors in linear units from s² (JᵀJ)⁻¹; nullopt when JᵀJ is singular.
std::optional<Eigen::Matrix3d> CalcCovariance(const Eigen::MatrixXd& log_jacobian, const Trial& trial,
                                              const Eigen::VectorXd& residual) {
  Eigen::MatrixXd jacobian = log_jacobian;
  jacobian.col(0) /= trial.r0_ohm;
  jacobian.col(1) /= trial.r1_ohm;
  jacobian.col(2) /= trial.tau_s;
  const Eigen::Matrix3d normal = jacobian.transpose() * jacobian;
  Eigen::FullPivLU<Eigen::Matrix3d> lu(normal);
  if (lu.rank() < 3) return std::nullopt;
  const double variance = residual.squaredNorm() / std::max<double>(1.0, static_cast<double>(residual.size() - 3));
  return Eigen::Matrix3d(variance * lu.inverse());
}

}  // namespace

bool CellIdentificationOptions::IsValid(std::string* error) const {
  auto fail = [error](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (!(ocv_points >= 3 && ocv_points <= 201)) return fail(fmt::format("ocv_points: 3 to 201, got {}", ocv_points));
  if (!(load_fraction > 0.0 && load_fraction < 1.0)) return fail(fmt::format("load_fraction: in (0, 1), got {}", load_fraction));
  if (max_iterations < 1) return fail(fmt::format("max_iterations: at least 1, got {}", max_iterations));
  if (!(max_relative_standard_error > 0.0)) {
    return fail(fmt::format("max_relative_standard_error: positive, got {}", max_relative_standard_error));
  }
  return true;
}

models::OcvTable CellIdentification::MakeOcvTable() const {
  return models::OcvTable(ocv_soc_fraction, ocv_voltage_v, "identified OCV");
}

models::SelfCorrectingCell CellIdentification::MakeCell() const {
  return models::SelfCorrectingCell(params, MakeOcvTable(), "identified cell");
}

namespace {

void FlagUncertain(const char* parameter, double value, std::optional<double> standard_error, double limit,
                   CellIdentification* result) {
  if (standard_error && *standard_error <= limit * std::abs(value)) return;
  const std::string reason =
      standard_error ? fmt::format("relative standard error {:.0f} % above {:.0f} %: the record does not separate it",
                                   100.0 * *standard_error / std::abs(value), 100.0 * limit)
                     : std::string("the record does not excite it (singular Jacobian)");
  result->not_identified.push_back({parameter, reason + "; kept: the fitted value", value});
}

void ReportUnidentified(const Prepared& prepared, const Trial& trial, const CellIdentificationOptions& options,
                        CellIdentification* result) {
  const models::CellParams kept = result->params;
  if (!result->charge) {
    result->not_identified.push_back(
        {"hysteresis_m_v", "hysteresis needs charge data; kept 0 (OCV is the discharge branch)", 0.0});
    result->not_identified.push_back(
        {"hysteresis_m0_v", "hysteresis needs charge data; kept 0 (OCV is the discharge branch)", 0.0});
    result->not_identified.push_back({"hysteresis_gamma",
                                      "hysteresis needs charge data; kept Table 3.1 cell 1 (unused while M = 0)",
                                      kept.hysteresis_gamma});
    result->not_identified.push_back({"eta_charge", "needs charge data; kept Table 3.1", kept.eta_charge});
  } else {
    const char* split =
        "the split of M + M0 shows only where the current reverses in mid-charge; kept in Table 3.1 "
        "cell 1's proportion";
    result->not_identified.push_back({"hysteresis_m_v", split, kept.hysteresis_m_v});
    result->not_identified.push_back({"hysteresis_m0_v", split, kept.hysteresis_m0_v});
    result->not_identified.push_back(
        {"hysteresis_gamma", "the rate shows only where the current reverses in mid-charge; kept Table 3.1 cell 1",
         kept.hysteresis_gamma});
    if (!result->charge->eta_charge_standard_error) {
      result->not_identified.push_back(
          {"eta_charge",
           "Q over the charge put in exceeds 1 by more than two standard errors: the records are "
           "not one charge-discharge cycle; kept Table 3.1",
           kept.eta_charge});
    }
  }
  if (trial.tau_s < prepared.median_period_s) {
    result->not_identified.push_back(
        {"rc[0]", fmt::format("time constant {:.3g} s below the median sample period {:.3g} s; kept: the fitted value",
                              trial.tau_s, prepared.median_period_s),
         trial.r1_ohm});
  }
  FlagUncertain("r0_ohm", trial.r0_ohm, result->r0_standard_error_ohm, options.max_relative_standard_error, result);
  FlagUncertain("rc[0].resistance_ohm", trial.r1_ohm, result->r1_standard_error_ohm, options.max_relative_standard_error,
                result);
  FlagUncertain("rc[0].capacitance_f", kept.rc[0].capacitance_f, result->c1_standard_error_f,
                options.max_relative_standard_error, result);
}

void SetUncertainties(const BatteryRecord& record, const Prepared& prepared, const Eigen::Vector3d& theta,
                      const Eigen::VectorXd& residual, int node_count, CellIdentification* result) {
  const Trial trial = FromLog(theta);
  const std::optional<Eigen::Matrix3d> covariance =
      CalcCovariance(CalcJacobian(record, prepared, theta, residual, node_count), trial, residual);
  if (!covariance) return;
  const Eigen::Matrix3d& c = *covariance;
  result->r0_standard_error_ohm = std::sqrt(c(0, 0));
  result->r1_standard_error_ohm = std::sqrt(c(1, 1));
  // C1 = τ1 / R1, by the delta method.
  const double capacitance = trial.tau_s / trial.r1_ohm;
  const double relative_variance = c(2, 2) / (trial.tau_s * trial.tau_s) + c(1, 1) / (trial.r1_ohm * trial.r1_ohm) -
                                   2.0 * c(1, 2) / (trial.tau_s * trial.r1_ohm);
  result->c1_standard_error_f = capacitance * std::sqrt(std::max(0.0, relative_variance));
}

// A branch's OCV nodes without the samples where h of eq. 3.3 is still turning after its record's start: the first
// 3 / γ of SOC (95 % of the turn; γ of Table 3.1, kept). A discharge starts at SOC 1, a charge at SOC 0.
OcvNodes BuildSettledBranch(const BatteryRecord& record, Prepared prepared, bool starts_full, double gamma,
                            const Trial& trial, int node_count) {
  const double turning = 3.0 / gamma;
  for (std::size_t k = 0; k < prepared.loaded.size(); ++k) {
    const double turned = starts_full ? 1.0 - prepared.soc_fraction[k] : prepared.soc_fraction[k];
    if (turned < turning) prepared.loaded[k] = 0;
  }
  return BuildOcv(record, prepared, CalcRcCurrent(prepared, trial.tau_s), trial, node_count);
}

// M + M0 as the median half-gap of the branches over the nodes both reach, and the OCV as their mean
// (battery_identification.h). Throws InputError(source, …) when they share no node.
OcvNodes CombineBranches(const OcvNodes& discharge_nodes, const OcvNodes& charge_nodes, int node_count,
                         const std::string& source, ChargeIdentification* added) {
  const double spacing = 1.0 / (node_count - 1);
  auto node_of = [spacing](double soc) { return static_cast<int>(std::lround(soc / spacing)); };
  std::vector<std::optional<double>> low(node_count), high(node_count);
  for (std::size_t k = 0; k < discharge_nodes.soc_fraction.size(); ++k) {
    low[node_of(discharge_nodes.soc_fraction[k])] = discharge_nodes.voltage_v[k];
  }
  for (std::size_t k = 0; k < charge_nodes.soc_fraction.size(); ++k) {
    high[node_of(charge_nodes.soc_fraction[k])] = charge_nodes.voltage_v[k];
  }
  std::vector<double> half_gaps;
  for (int n = 0; n < node_count; ++n) {
    if (low[n] && high[n]) half_gaps.push_back(0.5 * (*high[n] - *low[n]));
  }
  if (half_gaps.empty()) {
    throw InputError(source, "voltage", "a charge branch at SOC nodes the discharge reaches, but they share none");
  }
  added->shared_nodes = static_cast<int>(half_gaps.size());
  std::vector<double> sorted = half_gaps;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t m = sorted.size();
  const double median = m % 2 == 1 ? sorted[m / 2] : 0.5 * (sorted[m / 2 - 1] + sorted[m / 2]);
  added->hysteresis_total_v = std::max(0.0, median);  // a charge branch below the discharge branch: none seen
  if (m >= 2) {
    double mean = 0.0, squares = 0.0;
    for (double gap : half_gaps) mean += gap / static_cast<double>(m);
    for (double gap : half_gaps) squares += (gap - mean) * (gap - mean);
    constexpr double kMedianEfficiency = 1.2533;  // sqrt(π / 2): the median's standard error over the mean's
    added->hysteresis_total_standard_error_v =
        kMedianEfficiency * std::sqrt(squares / static_cast<double>(m - 1) / static_cast<double>(m));
  }
  OcvNodes ocv;
  for (int n = 0; n < node_count; ++n) {
    if (!low[n] && !high[n]) continue;
    ocv.soc_fraction.push_back(n * spacing);
    if (low[n] && high[n]) {
      ocv.voltage_v.push_back(0.5 * (*low[n] + *high[n]));
    } else {
      ocv.voltage_v.push_back(low[n] ? *low[n] + added->hysteresis_total_v : *high[n] - added->hysteresis_total_v);
    }
  }
  MakeIncreasing(&ocv.voltage_v);
  return ocv;
}

// RMS and largest |v − v̂| over samples [0, count), mV.
struct VoltageErrors {
  double rms_mv = 0.0, max_mv = 0.0;
};

VoltageErrors CalcVoltageErrors(const BatteryRecord& record, const std::vector<double>& model_v, int count) {
  VoltageErrors errors;
  double squares = 0.0;
  for (int k = 0; k < count; ++k) {
    const double error_v = record.voltage_v[k] - model_v[k];
    squares += error_v * error_v;
    errors.max_mv = std::max(errors.max_mv, 1e3 * std::abs(error_v));
  }
  errors.rms_mv = 1e3 * std::sqrt(squares / count);
  return errors;
}

// The figures of the final cell: the discharge from full after a charge (h = +1, s = +1), the charge from empty after
// a discharge (h = −1, s = −1).
void SetFinalCellFigures(const BatteryRecord& discharge, const Prepared& discharge_prepared,
                         const BatteryRecord& charge, const Prepared& charge_prepared, CellIdentification* result,
                         ChargeIdentification* added) {
  const models::SelfCorrectingCell cell = result->MakeCell();
  models::CellState full;
  full.soc_fraction = 1.0, full.hysteresis = 1.0, full.hysteresis_sign = 1.0;
  full.rc_current_a[0] = discharge_prepared.initial_rc_current_a;
  result->model_v = SimulateTerminalVoltage(cell, full, discharge);
  const VoltageErrors fitted = CalcVoltageErrors(discharge, result->model_v, discharge_prepared.fitted_samples);
  result->fit_rms_mv = fitted.rms_mv, result->fit_max_mv = fitted.max_mv;
  result->rms_every_sample_mv = CalcVoltageErrors(discharge, result->model_v, discharge.size()).rms_mv;
  models::CellState empty;
  empty.soc_fraction = 0.0, empty.hysteresis = -1.0, empty.hysteresis_sign = -1.0;
  empty.rc_current_a[0] = charge_prepared.initial_rc_current_a;
  added->model_v = SimulateTerminalVoltage(cell, empty, charge);
  added->samples = charge.size();
  const VoltageErrors charging = CalcVoltageErrors(charge, added->model_v, charge.size());
  added->fit_rms_mv = charging.rms_mv, added->fit_max_mv = charging.max_mv;
}

// The charge branch, the OCV as the mean of the branches, M + M0 and η_charge (battery_identification.h).
void AddChargeBranch(const BatteryRecord& discharge, const Prepared& discharge_prepared, const BatteryRecord& charge,
                     const Trial& trial, const CellIdentificationOptions& options, CellIdentification* result) {
  const Prepared prepared = PrepareCharge(charge, options);
  const auto loaded = std::count(prepared.loaded.begin(), prepared.loaded.end(), 1);
  if (loaded < kMinimumLoadedSamples) {
    throw InputError(charge.source, "current",
                     fmt::format("at least {} samples charging (above {:g} % of the largest charging current) to "
                                 "derive the charge branch, got {}",
                                 kMinimumLoadedSamples, 100.0 * options.load_fraction, loaded));
  }
  const double gamma = result->params.hysteresis_gamma;
  const OcvNodes charge_nodes = BuildSettledBranch(charge, prepared, false, gamma, trial, options.ocv_points);
  ChargeIdentification added;
  added.branch = {charge_nodes.soc_fraction, charge_nodes.voltage_v};
  const OcvNodes ocv =
      CombineBranches(BuildSettledBranch(discharge, discharge_prepared, true, gamma, trial, options.ocv_points),
                      charge_nodes, options.ocv_points, charge.source, &added);
  result->ocv_soc_fraction = ocv.soc_fraction;
  result->ocv_voltage_v = ocv.voltage_v;
  const models::CellParams table = models::Table31Cell(1);
  const double dynamic_share = table.hysteresis_m_v / (table.hysteresis_m_v + table.hysteresis_m0_v);
  result->params.hysteresis_m_v = dynamic_share * added.hysteresis_total_v;
  result->params.hysteresis_m0_v = added.hysteresis_total_v - result->params.hysteresis_m_v;
  // η_charge cannot exceed 1: a ratio above it by at most two standard errors is 1 (the count's error).
  const double eta = discharge_prepared.capacity_as / prepared.capacity_as;
  const double eta_error =
      eta * std::hypot(discharge_prepared.capacity_standard_error_as / discharge_prepared.capacity_as,
                       prepared.capacity_standard_error_as / prepared.capacity_as);
  if (eta > 0.0 && eta - 2.0 * eta_error <= 1.0) {
    result->params.eta_charge = std::min(eta, 1.0);
    added.eta_charge_standard_error = eta_error;
  }
  SetFinalCellFigures(discharge, discharge_prepared, charge, prepared, result, &added);
  result->charge = std::move(added);
}

}  // namespace

CellIdentification IdentifyCell(const BatteryRecord& record, const CellIdentificationOptions& options) {
  return IdentifyCell(record, std::nullopt, options);
}

CellIdentification IdentifyCell(const BatteryRecord& record, const std::optional<BatteryRecord>& charge,
                                const CellIdentificationOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("identification options", "options", error);
  const Prepared prepared = Prepare(record, options);
  const auto loaded = std::count(prepared.loaded.begin(), prepared.loaded.end(), 1);
  if (loaded < kMinimumLoadedSamples) {
    throw InputError(record.source, "current",
                     fmt::format("at least {} samples under load (above {:g} % of the largest current) to derive "
                                 "OCV(z), got {}", kMinimumLoadedSamples, 100.0 * options.load_fraction, loaded));
  }
  CellIdentification result;
  const Eigen::Vector3d theta = Minimise(record, prepared, options, &result.iterations);
  const Trial trial = FromLog(theta);
  OcvNodes nodes;
  const Eigen::VectorXd residual = CalcResiduals(record, prepared, trial, options.ocv_points, &nodes);
  UASCMA_CHECK(residual.size() == prepared.fitted_samples, "the optimum has an OCV table");
  const Eigen::VectorXd every_residual = CalcResiduals(record, prepared, trial, options.ocv_points, nullptr, true);
  result.params = models::Table31Cell(1);  // γ and η_charge are kept (not identified from a discharge)
  result.params.capacity_ah = prepared.capacity_as / kSecondsPerHour;
  result.params.r0_ohm = trial.r0_ohm;
  result.params.rc = {};
  result.params.rc[0] = {trial.r1_ohm, trial.tau_s / trial.r1_ohm};
  result.params.rc_pair_count = 1;
  result.params.hysteresis_m_v = 0.0;
  result.params.hysteresis_m0_v = 0.0;
  result.params.eta_discharge = 1.0;  // Table 3.1: Coulomb counting defines Q with η = 1
  result.ocv_soc_fraction = nodes.soc_fraction;
  result.ocv_voltage_v = nodes.voltage_v;
  result.capacity_standard_error_ah = prepared.capacity_standard_error_as / kSecondsPerHour;
  result.fit_rms_mv = 1e3 * std::sqrt(residual.squaredNorm() / static_cast<double>(residual.size()));
  result.fit_max_mv = 1e3 * residual.cwiseAbs().maxCoeff();
  result.samples = record.size();
  result.fitted_samples = prepared.fitted_samples;
  result.rms_every_sample_mv = 1e3 * std::sqrt(every_residual.squaredNorm() / static_cast<double>(every_residual.size()));
  for (int k = 0; k < record.size(); ++k) result.model_v.push_back(record.voltage_v[k] - every_residual[k]);
  result.median_sample_period_s = prepared.median_period_s;
  if (!record.temperature_degc.empty()) {
    double sum = 0.0;
    for (double t : record.temperature_degc) sum += t;
    result.mean_temperature_degc = sum / static_cast<double>(record.temperature_degc.size());
  }
  result.discharge_branch = {nodes.soc_fraction, nodes.voltage_v};
  SetUncertainties(record, prepared, theta, residual, options.ocv_points, &result);
  if (charge) AddChargeBranch(record, prepared, *charge, trial, options, &result);
  ReportUnidentified(prepared, trial, options, &result);
  return result;
}

std::vector<double> SimulateTerminalVoltage(const models::SelfCorrectingCell& cell, const models::CellState& initial,
                                            const BatteryRecord& record) {
  std::vector<double> voltage(record.size());
  models::CellState state = initial;
  for (int k = 0; k < record.size(); ++k) {
    voltage[k] = cell.CalcTerminalVoltage(state, record.current_a[k]);
    if (k + 1 < record.size()) {
      const double current = 0.5 * (record.current_a[k] + record.current_a[k + 1]);
      state = cell.Step(state, current, record.time_s[k + 1] - record.time_s[k]);
    }
  }
  return voltage;
}

}  // namespace uascma::identification
