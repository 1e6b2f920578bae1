// The RUL distribution against simulated jam times (see the header).
#include "uascma/prognostics/rul_calibration.h"

#include <algorithm>
#include <cmath>

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
  for (std::size_t k = 0; k < area_at_epoch_mm2.size(); ++k) {
    const double t_s = static_cast<double>(k) * options.epoch_s;
    if (t_s >= jam_s) break;
    QuantilePrediction prediction{history, t_s, jam_s - t_s, {}};
    if (options.mode == RulPredictionMode::kOnsetCountdown || k == 0) {
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
  return mode == RulPredictionMode::kOnsetCountdown ? "onset_countdown" : "observed_area";
}

RulPredictionMode ParseRulPredictionMode(const std::string& name, const std::string& source) {
  if (name == "onset_countdown") return RulPredictionMode::kOnsetCountdown;
  if (name == "observed_area") return RulPredictionMode::kObservedArea;
  throw InputError(source, "value", fmt::format("onset_countdown or observed_area, got \"{}\"", name));
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
