// Calibration metrics of probabilistic prognostics (see the header for the definitions and sources).
#include "uascma/prognostics/calibration.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "uascma/common/error.h"

namespace uascma::prognostics {
namespace {

constexpr char kCalibrationSource[] = "calibration";
// z of the two-sided 95 % normal interval, for the Wilson score interval.
constexpr double kWilsonZ = 1.959963984540054;
// PIT histogram of the report: 10 bins (deciles), ours.
constexpr int kReportPitBins = 10;

void RequireValidPredictions(const PredictionSet& set) {
  std::string error;
  if (!set.IsValid(&error)) throw InputError(kCalibrationSource, "predictions", error);
}

void WilsonInterval(int successes, int trials, double* low, double* high) {
  if (trials == 0) {
    *low = 0.0;
    *high = 1.0;
    return;
  }
  const double n = trials;
  const double p = successes / n;
  const double z2 = kWilsonZ * kWilsonZ;
  const double denominator = 1.0 + z2 / n;
  const double center = (p + z2 / (2.0 * n)) / denominator;
  const double half = kWilsonZ / denominator * std::sqrt(p * (1.0 - p) / n + z2 / (4.0 * n * n));
  *low = std::max(0.0, center - half);
  *high = std::min(1.0, center + half);
}

// Probability mass the prediction puts inside [low_s, high_s].
double MassInside(const std::vector<double>& levels, const QuantilePrediction& prediction, double low_s,
                  double high_s) {
  return PredictedCdf(levels, prediction.quantiles_s, high_s) - PredictedCdf(levels, prediction.quantiles_s, low_s);
}

UnitMetrics CalcUnitMetrics(const PredictionSet& set, std::vector<const QuantilePrediction*> unit,
                            const SaxenaOptions& options) {
  std::stable_sort(unit.begin(), unit.end(), [](const auto* a, const auto* b) { return a->time_s < b->time_s; });
  UnitMetrics metrics;
  metrics.unit = unit.front()->unit;
  metrics.predictions = static_cast<int>(unit.size());
  const double end_of_life_s = unit.front()->time_s + unit.front()->true_remaining_s;
  metrics.end_of_life_s = end_of_life_s;
  // PH: the first prediction with mass ≥ β inside the fixed band r* ± α t_EoL.
  for (const auto* prediction : unit) {
    const double band_s = options.alpha * end_of_life_s;
    const double truth_s = prediction->true_remaining_s;
    if (MassInside(set.levels, *prediction, truth_s - band_s, truth_s + band_s) >= options.beta) {
      metrics.prognostic_horizon_s = end_of_life_s - prediction->time_s;
      break;
    }
  }
  // α-λ and RA at the first prediction at or after t_λ (the last one when every prediction is earlier).
  const double first_time_s = unit.front()->time_s;
  const double lambda_time_s = first_time_s + options.lambda * (end_of_life_s - first_time_s);
  const QuantilePrediction* judged = unit.back();
  for (const auto* prediction : unit) {
    if (prediction->time_s >= lambda_time_s) {
      judged = prediction;
      break;
    }
  }
  metrics.lambda_time_s = judged->time_s;
  const double truth_s = judged->true_remaining_s;
  const double mass = MassInside(set.levels, *judged, (1.0 - options.alpha) * truth_s, (1.0 + options.alpha) * truth_s);
  metrics.alpha_lambda_met = truth_s > 0.0 && mass >= options.beta;
  const double median_s = PredictedQuantile(set.levels, judged->quantiles_s, 0.5);
  metrics.relative_accuracy = truth_s > 0.0 ? 1.0 - std::abs(truth_s - median_s) / truth_s : 0.0;
  return metrics;
}

}  // namespace

bool PredictionSet::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (levels.empty()) return fail("levels: at least one probability level");
  for (std::size_t i = 0; i < levels.size(); ++i) {
    if (!(levels[i] > 0.0 && levels[i] < 1.0)) return fail("levels: each inside (0, 1)");
    if (i > 0 && !(levels[i] > levels[i - 1])) return fail("levels: strictly increasing");
  }
  for (std::size_t k = 0; k < predictions.size(); ++k) {
    const QuantilePrediction& prediction = predictions[k];
    std::ostringstream where;
    where << "predictions[" << k << "]: ";
    if (prediction.quantiles_s.size() != levels.size()) return fail(where.str() + "one quantile per level");
    if (!std::isfinite(prediction.time_s)) return fail(where.str() + "a finite time_s");
    if (!(std::isfinite(prediction.true_remaining_s) && prediction.true_remaining_s >= 0.0)) {
      return fail(where.str() + "a finite true_remaining_s >= 0");
    }
    for (std::size_t i = 0; i < prediction.quantiles_s.size(); ++i) {
      if (!std::isfinite(prediction.quantiles_s[i])) return fail(where.str() + "finite quantiles");
      if (i > 0 && prediction.quantiles_s[i] < prediction.quantiles_s[i - 1]) {
        return fail(where.str() + "non-decreasing quantiles");
      }
    }
  }
  return true;
}

bool SaxenaOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (!(alpha > 0.0 && alpha < 1.0)) return fail("alpha: inside (0, 1)");
  if (!(beta > 0.0 && beta <= 1.0)) return fail("beta: inside (0, 1]");
  if (!(lambda >= 0.0 && lambda <= 1.0)) return fail("lambda: inside [0, 1]");
  return true;
}

std::vector<double> StandardQuantileLevels() {
  std::vector<double> levels{0.025};
  for (int i = 1; i <= 19; ++i) levels.push_back(0.05 * i);
  levels.push_back(0.975);
  return levels;
}

std::vector<double> StandardIntervalLevels() { return {0.50, 0.80, 0.90, 0.95}; }

std::vector<double> StandardReliabilityLevels() {
  std::vector<double> levels;
  for (int i = 1; i <= 19; ++i) levels.push_back(0.05 * i);
  return levels;
}

double PredictedCdf(const std::vector<double>& levels, const std::vector<double>& quantiles_s, double x_s) {
  UASCMA_CHECK(!levels.empty() && levels.size() == quantiles_s.size(), "one quantile per level");
  if (x_s < quantiles_s.front()) return 0.0;
  if (x_s >= quantiles_s.back()) return 1.0;
  // The last level whose quantile is ≤ x; x < back, so k + 1 exists and q[k+1] > x ≥ q[k].
  const auto after = std::upper_bound(quantiles_s.begin(), quantiles_s.end(), x_s);
  const std::size_t k = static_cast<std::size_t>(after - quantiles_s.begin()) - 1;
  const double fraction = (x_s - quantiles_s[k]) / (quantiles_s[k + 1] - quantiles_s[k]);
  return levels[k] + fraction * (levels[k + 1] - levels[k]);
}

double PredictedQuantile(const std::vector<double>& levels, const std::vector<double>& quantiles_s, double p) {
  UASCMA_CHECK(!levels.empty() && levels.size() == quantiles_s.size(), "one quantile per level");
  constexpr double kLevelSlack = 1e-12;  // a level computed as 0.05 * 19 may differ from 0.95 by rounding
  if (p < levels.front() - kLevelSlack || p > levels.back() + kLevelSlack) {
    std::ostringstream expected;
    expected << "a level inside [" << levels.front() << ", " << levels.back() << "] (the given quantiles), got " << p;
    throw InputError(kCalibrationSource, "level", expected.str());
  }
  if (p <= levels.front()) return quantiles_s.front();
  if (p >= levels.back()) return quantiles_s.back();
  const auto after = std::upper_bound(levels.begin(), levels.end(), p);
  const std::size_t k = static_cast<std::size_t>(after - levels.begin()) - 1;
  const double fraction = (p - levels[k]) / (levels[k + 1] - levels[k]);
  return quantiles_s[k] + fraction * (quantiles_s[k + 1] - quantiles_s[k]);
}

IntervalCoverage CalcIntervalCoverage(const PredictionSet& set, double central_probability) {
  RequireValidPredictions(set);
  if (!(central_probability > 0.0 && central_probability < 1.0)) {
    throw InputError(kCalibrationSource, "central_probability", "inside (0, 1)");
  }
  IntervalCoverage coverage;
  coverage.nominal = central_probability;
  const double low_level = 0.5 * (1.0 - central_probability);
  const double high_level = 0.5 * (1.0 + central_probability);
  for (const QuantilePrediction& prediction : set.predictions) {
    const double low_s = PredictedQuantile(set.levels, prediction.quantiles_s, low_level);
    const double high_s = PredictedQuantile(set.levels, prediction.quantiles_s, high_level);
    ++coverage.predictions;
    if (prediction.true_remaining_s < low_s) {
      ++coverage.below;
    } else if (prediction.true_remaining_s > high_s) {
      ++coverage.above;
    } else {
      ++coverage.covered;
    }
  }
  coverage.fraction = coverage.predictions > 0 ? static_cast<double>(coverage.covered) / coverage.predictions : 0.0;
  WilsonInterval(coverage.covered, coverage.predictions, &coverage.wilson_low, &coverage.wilson_high);
  return coverage;
}

std::vector<ReliabilityRow> CalcReliabilityTable(const PredictionSet& set, const std::vector<double>& nominal_levels) {
  RequireValidPredictions(set);
  std::vector<ReliabilityRow> rows;
  for (double p : nominal_levels) {
    ReliabilityRow row;
    row.nominal = p;
    int at_or_below = 0;
    for (const QuantilePrediction& prediction : set.predictions) {
      if (prediction.true_remaining_s <= PredictedQuantile(set.levels, prediction.quantiles_s, p)) ++at_or_below;
      ++row.predictions;
    }
    row.observed = row.predictions > 0 ? static_cast<double>(at_or_below) / row.predictions : 0.0;
    rows.push_back(row);
  }
  return rows;
}

std::vector<int> CalcPitHistogram(const PredictionSet& set, int bins) {
  RequireValidPredictions(set);
  if (bins < 1) throw InputError(kCalibrationSource, "bins", "at least 1");
  std::vector<int> counts(static_cast<std::size_t>(bins), 0);
  for (const QuantilePrediction& prediction : set.predictions) {
    const double pit = PredictedCdf(set.levels, prediction.quantiles_s, prediction.true_remaining_s);
    const int bin = std::min(bins - 1, static_cast<int>(std::floor(pit * bins)));
    ++counts[static_cast<std::size_t>(bin)];
  }
  return counts;
}

SaxenaMetrics CalcSaxenaMetrics(const PredictionSet& set, const SaxenaOptions& options) {
  RequireValidPredictions(set);
  std::string error;
  if (!options.IsValid(&error)) throw InputError(kCalibrationSource, "saxena options", error);
  std::map<int, std::vector<const QuantilePrediction*>> units;
  for (const QuantilePrediction& prediction : set.predictions) units[prediction.unit].push_back(&prediction);
  SaxenaMetrics metrics;
  metrics.options = options;
  int met = 0;
  for (const auto& [unit, predictions] : units) {
    metrics.per_unit.push_back(CalcUnitMetrics(set, predictions, options));
    const UnitMetrics& last = metrics.per_unit.back();
    metrics.mean_prognostic_horizon_s += last.prognostic_horizon_s;
    metrics.mean_relative_accuracy += last.relative_accuracy;
    met += last.alpha_lambda_met ? 1 : 0;
  }
  metrics.units = static_cast<int>(units.size());
  if (metrics.units > 0) {
    metrics.mean_prognostic_horizon_s /= metrics.units;
    metrics.mean_relative_accuracy /= metrics.units;
    metrics.alpha_lambda_fraction = static_cast<double>(met) / metrics.units;
  }
  return metrics;
}

CalibrationReport CalcCalibrationReport(const PredictionSet& set, const SaxenaOptions& options) {
  CalibrationReport report;
  for (double level : StandardIntervalLevels()) report.intervals.push_back(CalcIntervalCoverage(set, level));
  report.reliability = CalcReliabilityTable(set, StandardReliabilityLevels());
  report.pit_histogram = CalcPitHistogram(set, kReportPitBins);
  report.saxena = CalcSaxenaMetrics(set, options);
  return report;
}

}  // namespace uascma::prognostics
