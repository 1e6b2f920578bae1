// The RUL distribution against simulated jam times (see the header).
#include "uascma/prognostics/rul_calibration.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/random.h"

namespace uascma::prognostics {
namespace {

constexpr char kRulCalibrationSource[] = "RUL calibration";
// Sub-streams of a history's seed: the numbers the simulator gives the spall truth and the prognosis
// (sim/flight_internal.h's streams).
constexpr std::uint64_t kTruthSpallStream = 3;
constexpr std::uint64_t kPrognosisSpallStream = 4;

// Particle quantiles at the standard levels, counted down by `elapsed_s` (never below 0).
std::vector<double> CountedDown(const std::vector<double>& quantiles_s, double elapsed_s) {
  std::vector<double> shifted;
  shifted.reserve(quantiles_s.size());
  for (double q : quantiles_s) shifted.push_back(std::max(q - elapsed_s, 0.0));
  return shifted;
}

// One history: the truth spall's jam time and the predictions at its epochs (appended to *set).
// Returns the jam time from the onset, or NaN when the truth did not jam within its step horizon.
double ScoreHistory(const RulCalibrationOptions& options, int history, const MotorRulModel& truth,
                    const MotorRulModel& prognosis, PredictionSet* set, double* onset_mean_rul_s) {
  const std::uint64_t history_seed = DeriveSeed(options.seed, static_cast<std::uint64_t>(history));
  SpallJamEvent spall(truth, 0.0, DeriveSeed(history_seed, kTruthSpallStream));
  RandomStream prognosis_random(DeriveSeed(history_seed, kPrognosisSpallStream));
  // The truth first (its own stream: the predictions do not change it), the epochs' areas kept.
  const double horizon_s = truth.params().max_growth_steps * truth.params().time_per_growth_step_s;
  std::vector<double> area_at_epoch_mm2;
  while (!spall.jammed() && spall.time_s() < horizon_s) {
    area_at_epoch_mm2.push_back(spall.area_mm2());
    spall.Advance(options.epoch_s);
  }
  const RulDistribution at_onset = prognosis.PredictRulFromArea(prognosis.params().initial_area_mm2, prognosis_random);
  *onset_mean_rul_s = at_onset.mean_s;
  if (!spall.jammed()) return std::nan("");
  const double jam_s = spall.jam_time_s();
  const std::vector<double> onset_quantiles_s = CalcRulQuantiles(at_onset, set->levels);
  std::vector<double> onset_sorted_s = at_onset.rul_s;
  std::sort(onset_sorted_s.begin(), onset_sorted_s.end());
  for (std::size_t k = 0; k < area_at_epoch_mm2.size(); ++k) {
    const double t_s = static_cast<double>(k) * options.epoch_s;
    if (t_s >= jam_s) break;
    QuantilePrediction prediction{history, t_s, jam_s - t_s, {}};
    if (options.mode == RulPredictionMode::kSurvivalConditioned) {
      prediction.quantiles_s = SortedQuantiles(SurvivingRul(onset_sorted_s, t_s, options.epoch_s), set->levels);
    } else if (options.mode == RulPredictionMode::kOnsetCountdown || k == 0) {
      prediction.quantiles_s = CountedDown(onset_quantiles_s, t_s);
    } else {
      prediction.quantiles_s =
          CalcRulQuantiles(prognosis.PredictRulFromArea(area_at_epoch_mm2[k], prognosis_random), set->levels);
    }
    set->predictions.push_back(std::move(prediction));
  }
  return jam_s;
}

}  // namespace

std::vector<double> CalcRulQuantiles(const RulDistribution& rul, const std::vector<double>& levels) {
  if (rul.rul_s.empty()) throw InputError(kRulCalibrationSource, "rul_s", "at least one particle");
  std::vector<double> sorted = rul.rul_s;
  std::sort(sorted.begin(), sorted.end());
  return SortedQuantiles(sorted, levels);
}

std::vector<double> SortedQuantiles(const std::vector<double>& sorted, const std::vector<double>& levels) {
  if (sorted.empty()) throw InputError(kRulCalibrationSource, "rul_s", "at least one particle");
  std::vector<double> quantiles;
  quantiles.reserve(levels.size());
  for (double p : levels) {
    if (!(p >= 0.0 && p <= 1.0)) throw InputError(kRulCalibrationSource, "levels", "each within [0, 1]");
    const double position = p * static_cast<double>(sorted.size() - 1);
    const auto below = static_cast<std::size_t>(std::floor(position));
    const std::size_t above = std::min(below + 1, sorted.size() - 1);
    quantiles.push_back(sorted[below] + (position - static_cast<double>(below)) * (sorted[above] - sorted[below]));
  }
  return quantiles;
}

const char* RulPredictionModeName(RulPredictionMode mode) {
  switch (mode) {
    case RulPredictionMode::kOnsetCountdown:
      return "onset_countdown";
    case RulPredictionMode::kObservedArea:
      return "observed_area";
    case RulPredictionMode::kSurvivalConditioned:
      return "survival_conditioned";
  }
  return "unknown";
}

RulPredictionMode ParseRulPredictionMode(const std::string& name, const std::string& source) {
  if (name == "onset_countdown") return RulPredictionMode::kOnsetCountdown;
  if (name == "observed_area") return RulPredictionMode::kObservedArea;
  if (name == "survival_conditioned") return RulPredictionMode::kSurvivalConditioned;
  throw InputError(source, "value",
                   fmt::format("onset_countdown, observed_area or survival_conditioned, got \"{}\"", name));
}

std::vector<double> SurvivingRul(const std::vector<double>& sorted_rul_at_onset_s, double elapsed_s, double epoch_s) {
  const auto first = std::upper_bound(sorted_rul_at_onset_s.begin(), sorted_rul_at_onset_s.end(), elapsed_s);
  if (first == sorted_rul_at_onset_s.end()) return {epoch_s};
  std::vector<double> left;
  left.reserve(static_cast<std::size_t>(sorted_rul_at_onset_s.end() - first));
  for (auto it = first; it != sorted_rul_at_onset_s.end(); ++it) left.push_back(*it - elapsed_s);
  return left;
}

double SurvivingRulMean(const std::vector<double>& sorted_rul_at_onset_s, double elapsed_s, double epoch_s) {
  const auto first = std::upper_bound(sorted_rul_at_onset_s.begin(), sorted_rul_at_onset_s.end(), elapsed_s);
  if (first == sorted_rul_at_onset_s.end()) return epoch_s;
  double sum_s = 0.0;
  for (auto it = first; it != sorted_rul_at_onset_s.end(); ++it) sum_s += *it - elapsed_s;
  return sum_s / static_cast<double>(sorted_rul_at_onset_s.end() - first);
}

RulTimeScaleFit FitRulTimeScale(double truth_time_per_growth_step_s, int histories, std::uint64_t seed) {
  std::string error;
  if (!CheckWithin(truth_time_per_growth_step_s, SpallGrowthParams::kTimePerGrowthStepBounds,
                   "truth_time_per_growth_step_s", &error)) {
    throw InputError(kRulCalibrationSource, "truth_time_per_growth_step_s", error);
  }
  if (!CheckWithin(histories, RulCalibrationOptions::kHistoryBounds, "histories", &error)) {
    throw InputError(kRulCalibrationSource, "histories", error);
  }
  SpallGrowthParams truth_params;
  truth_params.time_per_growth_step_s = truth_time_per_growth_step_s;
  const MotorRulModel truth(truth_params);
  const MotorRulModel prognosis{SpallGrowthParams{}};
  RulTimeScaleFit fit;
  fit.truth_time_per_growth_step_s = truth_time_per_growth_step_s;
  fit.histories = histories;
  fit.seed = seed;
  const std::uint64_t training_seed = DeriveSeed(seed, kRulTrainingStream);
  const double horizon_s = truth_params.max_growth_steps * truth_time_per_growth_step_s;
  int jammed = 0;
  double particle_steps = 0.0;
  for (int h = 0; h < histories; ++h) {
    const std::uint64_t history_seed = DeriveSeed(training_seed, static_cast<std::uint64_t>(h));
    // The simulator's truth up to the first CMA epoch at or after the horizon, as a flight would have advanced it
    // epoch by epoch. One call: SpallJamEvent's jam instant is exact whatever the step (the growth steps and their
    // crossings do not depend on it), so this is bit-identical to the epoch loop at a cost of O(growth steps)
    // instead of O(horizon / epoch) — at an hour per growth step, ~10^6 epochs per history.
    SpallJamEvent spall(truth, 0.0, DeriveSeed(history_seed, kTruthSpallStream));
    spall.Advance(std::ceil(horizon_s / kCmaEpoch_s) * kCmaEpoch_s);
    if (spall.jammed()) {
      fit.mean_jam_time_s += spall.jam_time_s();
      ++jammed;
    } else {
      ++fit.censored_histories;
    }
    // One history of the prognoser's growth from D₀ (growth steps: τ-free).
    RandomStream random(DeriveSeed(history_seed, kPrognosisSpallStream));
    particle_steps +=
        prognosis.PropagateToFailure(prognosis.MakeParticle(prognosis.params().initial_area_mm2), random).growth_steps;
  }
  if (jammed == 0) throw InputError(kRulCalibrationSource, "histories", "at least one training history that jams");
  fit.mean_jam_time_s /= jammed;
  fit.mean_particle_growth_steps = particle_steps / histories;
  fit.time_per_growth_step_s = fit.mean_jam_time_s / fit.mean_particle_growth_steps;
  return fit;
}

const RulTimeScaleFit& VehicleRulTimeScale(double truth_time_per_growth_step_s) {
  static std::mutex mutex;
  static std::map<double, RulTimeScaleFit> fits;
  const std::lock_guard<std::mutex> lock(mutex);
  auto it = fits.find(truth_time_per_growth_step_s);
  if (it == fits.end())
    it = fits.emplace(truth_time_per_growth_step_s, FitRulTimeScale(truth_time_per_growth_step_s)).first;
  return it->second;
}

bool RulCalibrationOptions::IsValid(std::string* error) const {
  if (!CheckWithin(histories, kHistoryBounds, "histories", error)) return false;
  if (!CheckWithin(truth_time_per_growth_step_s, SpallGrowthParams::kTimePerGrowthStepBounds,
                   "truth_time_per_growth_step_s", error)) {
    return false;
  }
  if (!CheckWithin(prognosis_time_per_growth_step_s, SpallGrowthParams::kTimePerGrowthStepBounds,
                   "prognosis_time_per_growth_step_s", error)) {
    return false;
  }
  if (!(epoch_s > 0.0 && std::isfinite(epoch_s))) {
    if (error != nullptr) *error = "epoch_s: expected a positive time";
    return false;
  }
  if (particles < 1) {
    if (error != nullptr) *error = "particles: expected at least 1";
    return false;
  }
  return true;
}

RulCalibration CalibrateRul(const RulCalibrationOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError(kRulCalibrationSource, "options", error);
  SpallGrowthParams truth_params;
  truth_params.time_per_growth_step_s = options.truth_time_per_growth_step_s;
  SpallGrowthParams prognosis_params;
  prognosis_params.time_per_growth_step_s = options.prognosis_time_per_growth_step_s;
  prognosis_params.particles = options.particles;
  const MotorRulModel truth(truth_params);
  const MotorRulModel prognosis(prognosis_params);

  RulCalibration result;
  result.options = options;
  result.predictions.levels = StandardQuantileLevels();
  int jammed = 0;
  for (int h = 0; h < options.histories; ++h) {
    double onset_mean_s = 0.0;
    const double jam_s = ScoreHistory(options, h, truth, prognosis, &result.predictions, &onset_mean_s);
    result.jam_time_s.push_back(jam_s);
    result.mean_predicted_rul_at_onset_s += onset_mean_s / options.histories;
    if (std::isnan(jam_s)) {
      ++result.censored_histories;
    } else {
      result.mean_jam_time_s += jam_s;
      ++jammed;
    }
  }
  if (jammed > 0) result.mean_jam_time_s /= jammed;
  result.report = CalcCalibrationReport(result.predictions);
  return result;
}

}  // namespace uascma::prognostics
