#pragma once
// The motor RUL as a distribution and its calibration against the jam times of simulated spalls.
// The RUL distribution is the prognoser's 100 particles (motor_rul.h, §3.4.1): its quantiles are
// the particles' (type 7, as RulDistribution's p05/p50/p95). The truth is what the simulator draws: one
// SpallJamEvent per history (the spall's own growth time scale τ_truth), from its onset to the exact jam.
//
// A history h (its seed DeriveSeed(seed, h); the truth spall draws from sub-stream 3, the prognoser from
// sub-stream 4, the numbers sim/flight_internal.h gives kSpallStream and kPrognosisStream) is scored at every
// epoch t_k = k · epoch_s from the onset while the motor has not jammed (t_k < T_jam); the truth is
// T_jam − t_k. Two ways to predict (RulPredictionMode):
//   kOnsetCountdown  what the CMA does (sim/epoch.cc): the particles' RUL from the initial spall at the
//                    onset, counted down with the flight time, max(q − t_k, 0);
//   kObservedArea    the spall area is fully observable (§5.3.2.1): re-predicted at every epoch from the
//                    area the truth spall has then, with the nominal C_D and n (the prognoser does not see the
//                    truth's parameter walk).
//   kSurvivalConditioned  what `cma-vehicle` and the vehicle-level belief policies read: the particles' RUL from the
//                    onset given that the motor has run t_k without a jam, {q − t_k : q > t_k} (the jam is observed:
//                    a running motor has not jammed), its quantiles and mean; when every particle has jammed before
//                    t_k, the jam is due within the epoch and the RUL is one epoch
//                    (docs/modelling-choices.md#vehicle-rul).
// Times are from the onset (the unit's life for the Saxena metrics). Pure and replayable from the seed.
//
// The distribution the vehicle-level policies read (FitRulTimeScale, docs/modelling-choices.md#vehicle-rul): the
// prognoser of motor_rul.h (eq. 3.8, 100 particles from D₀, nominal C_D and n) with its time scale τ fitted on
// training histories of the simulator's spall-to-jam process (sim::FlightState's SpallJamEvent at the scenario's
// τ_truth): τ̂ = mean training jam time / mean growth steps of the prognoser's histories from D₀ (the method of
// moments: the particles' mean RUL at the onset equals the training mean jam time). The simulated spall grows with
// time alone (no input of the battery's health or the motors' load), so one fit serves every health and load group.
// Table 5.4's time scale (motor_rul.h) stays the one `cma` and `reproduce` read.
#include <cstdint>
#include <string>
#include <vector>

#include "uascma/common/bounds.h"
#include "uascma/prognostics/calibration.h"
#include "uascma/prognostics/motor_rul.h"

namespace uascma::prognostics {

// τ of the simulated spall in the campaigns (campaign/config.h fault.time_per_growth_step_s,
// docs/modelling-choices.md#spall-growth-time-scale: a spall jams in ~17 s as in §5.5.1-5.5.2).
inline constexpr double kCampaignTruthTimePerGrowthStep_s = 0.7128;

// Quantiles of the particles' RUL at `levels` (each in [0, 1]), linear between order statistics.
std::vector<double> CalcRulQuantiles(const RulDistribution& rul, const std::vector<double>& levels);

enum class RulPredictionMode { kOnsetCountdown = 0, kObservedArea = 1, kSurvivalConditioned = 2 };
const char* RulPredictionModeName(
    RulPredictionMode mode);  // "onset_countdown", "observed_area", "survival_conditioned"
// InputError naming `source` and the valid names otherwise.
RulPredictionMode ParseRulPredictionMode(const std::string& name, const std::string& source);

struct RulCalibrationOptions {
  int histories = 930;  // >= 930 spall histories (the size of the dissertation's campaign, §5.5)
  std::uint64_t seed = 29;
  double truth_time_per_growth_step_s = kCampaignTruthTimePerGrowthStep_s;
  // What the CMA's prognoser uses unless a scenario sets fault.prognosis_time_per_growth_step_s: the
  // Table 5.4 calibration (motor_rul.h).
  double prognosis_time_per_growth_step_s = SpallGrowthParams{}.time_per_growth_step_s;
  RulPredictionMode mode = RulPredictionMode::kOnsetCountdown;
  double epoch_s = kCmaEpoch_s;  // the CMA's 1 Hz epoch
  int particles = SpallGrowthParams{}.particles;
  // Our bound on histories: 1 to 10^6 (10^6 fast-growth histories take about a minute).
  static constexpr Bounds kHistoryBounds{1.0, 1e6, ""};
  bool IsValid(std::string* error) const;
};

struct RulCalibration {
  RulCalibrationOptions options;
  PredictionSet predictions;                   // levels: StandardQuantileLevels(); unit = history index
  std::vector<double> jam_time_s;              // [histories] truth: time from the onset to the jam
  int censored_histories = 0;                  // not jammed within the truth's step horizon: not scored
  double mean_jam_time_s = 0.0;                // over the jammed histories
  double mean_predicted_rul_at_onset_s = 0.0;  // the particles' mean RUL at the onset (the CMA's t_RUL), averaged
  CalibrationReport report;                    // at the standard levels, Saxena defaults
};

// Throws InputError for invalid options.
RulCalibration CalibrateRul(const RulCalibrationOptions& options);

// ---- The survival-conditioned RUL (kSurvivalConditioned) ----

// The particles' RUL at the onset, sorted ascending, given the motor has run `elapsed_s` since the onset without a
// jam: {q − elapsed_s : q > elapsed_s}, or {epoch_s} when none is left (file comment).
std::vector<double> SurvivingRul(const std::vector<double>& sorted_rul_at_onset_s, double elapsed_s, double epoch_s);
// Its mean (the t_RUL of the vehicle-level motor margin), without building the set.
double SurvivingRulMean(const std::vector<double>& sorted_rul_at_onset_s, double elapsed_s, double epoch_s);
// Quantiles of sorted values at `levels`, type 7 (CalcRulQuantiles's).
std::vector<double> SortedQuantiles(const std::vector<double>& sorted, const std::vector<double>& levels);

// ---- The time scale fitted on training histories (file comment) ----

// Our choice: as many training histories as the dissertation's campaign has flights (§5.5), drawn from a seed of
// their own stream (kRulTrainingStream below) so that no --seed of `uascma rul --calibrate` scores them.
inline constexpr int kRulTrainingHistories = 930;
inline constexpr std::uint64_t kRulTrainingSeed = 7919;             // arbitrary
inline constexpr std::uint64_t kRulTrainingStream = 0x7261696EULL;  // "rain": a sub-stream no scoring seed draws

struct RulTimeScaleFit {
  double truth_time_per_growth_step_s = 0.0;
  int histories = 0;
  std::uint64_t seed = 0;
  double mean_jam_time_s = 0.0;             // the training histories' (all jam within the step horizon by default)
  int censored_histories = 0;               // not jammed within the horizon: not used
  double mean_particle_growth_steps = 0.0;  // the prognoser's histories from D₀, in growth steps
  double time_per_growth_step_s = 0.0;      // τ̂ = mean_jam_time_s / mean_particle_growth_steps
};
// Throws InputError for a τ_truth outside SpallGrowthParams::kTimePerGrowthStepBounds or histories < 1.
RulTimeScaleFit FitRulTimeScale(double truth_time_per_growth_step_s, int histories = kRulTrainingHistories,
                                std::uint64_t seed = kRulTrainingSeed);
// FitRulTimeScale with the defaults, computed once per τ_truth (thread-safe).
const RulTimeScaleFit& VehicleRulTimeScale(double truth_time_per_growth_step_s);

}  // namespace uascma::prognostics
