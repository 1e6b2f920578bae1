#pragma once
// Motor prognosis: remaining useful life (RUL) of a BLDC motor whose bearing has a spall
// (dissertation §3.4, §3.4.1; Table 5.4 and §5.3.2.3; docs/modelling-choices.md#landing-loads-motor, #margins,
// #spall-growth-time-scale).
//
// The model, eq. 3.8 (Paris law, after the dissertation's ref. [80]):
//     D(t + Δt) = D(t) + Δ C_D D(t)^n          spall area D grows
//     C_D       = C_D + ω_CD                    the parameters take zero-mean random steps
//     n         = n + ω_n
// with D₀ = 0.01 mm², the failure (jam) threshold D_f = 1 mm², C_D = 0.2, n = 1 and 100 particles
// (§3.4.1). How we read what eq. 3.8 leaves open (each choice is ours, marked where it is an estimate):
//
//  1. Growth steps and time. Eq. 3.8 advances in growth steps N (Paris-law load blocks). One step
//     lasts τ = `time_per_growth_step_s`, the calibration parameter of
//     docs/modelling-choices.md#spall-growth-time-scale. Within a step the parameters are held and the Paris law dD/dN
//     = C_D D^n is integrated exactly (eq. 3.8 in the limit of small Δ):  D(N₀+f)^(1−n) = D(N₀)^(1−n) + (1−n) C_D f,
//     or D(N₀) e^(C_D f) when n = 1. So the area is a continuous, non-decreasing function of time, the jam instant is
//     the exact threshold crossing, and neither depends on the step a caller advances by. With the noise off
//     and n = 1 the time to failure is the closed form ln(D_f/D₀)/C_D · τ = 23.03 τ.
//  2. Noise. ω_CD and ω_n are Gaussian, drawn once per growth step, and accumulate (a random walk:
//     eq. 3.8 *assigns* C_D + ω_CD to C_D, as in ref. [80]'s particle filter). Their standard deviations
//     are our estimates (see SpallGrowthParams). The growth uses max(C_D, 0): a spall never heals, so
//     the area never decreases even if the walk crossed zero (beyond 6σ within 40 steps with the
//     defaults).
//  3. Units. C_D and n are defined for D in mm² (for n ≠ 1 the law depends on the unit of area), so
//     areas stay in mm² and carry the suffix `_mm2`; times are in seconds (SI).
//  4. "Measured as the dissertation did" (Table 5.4: P(JF|SF) = 0.002809 "obtained by 1000
//     simulations of the motor prognosis algorithm", §5.3.2.3). Table 5.4 is a per-epoch (1 s, CMA
//     rate, docs/defaults.md#guidance-and-control) constant-hazard Markov transition, whose maximum-likelihood
//     estimate from observed sojourns in SF is   p̂ = jams / spalled epochs.
//     We simulate `runs` = 1000 spall histories from D₀; a history that jams at time T counts
//     max(1, ⌈T/epoch⌉) spalled epochs (the motor is seen jammed at the first epoch at or after T)
//     and one jam; a history still below D_f at the step horizon counts its epochs and no jam. With
//     every history jammed this is p̂ = 1 / (mean time-to-jam in epochs), the sojourn mean 1/p of
//     the Markov chain. CalibrateTimePerGrowthStep picks τ so that p̂ equals the target on a fixed
//     seed; the default τ below is its output, and motor_rul_test checks they agree.
//  5. "RUL now" for the CMA motor margin MM = 1 − t_flight_remaining / t_RUL (eq. 5.14,
//     docs/modelling-choices.md#margins): t_RUL is the MEAN of the particle RULs (§3.4.1: "Mean RUL value is then computed").
//     The particles start at the current (fully observable, §5.3.2.1) spall area with the nominal
//     C_D and n, since the prognoser does not observe the true parameter walk.
//
// Randomness is explicit: every stochastic call takes a uascma::RandomStream (common/random.h, specified
// bit for bit, so a seed replays identically everywhere); the per-motor event owns a stream seeded by
// its caller.
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "uascma/common/bounds.h"
#include "uascma/common/random.h"

namespace uascma::prognostics {

// ---- Constants of the dissertation --------------------------------------------------------------

// P(JF | SF) per CMA epoch under NoOp, Table 5.4.
inline constexpr double kTable54JamProbabilityPerEpoch = 0.002809;
// P(JF | SF) per CMA epoch under LandASAP / LandPract (the landing manoeuvre loads the motors),
// docs/modelling-choices.md#landing-loads-motor. Calibrate τ to it for a landing-load growth model.
inline constexpr double kLandingJamProbabilityPerEpoch = 0.008583;
// The CMA decision epoch: 1 Hz (docs/defaults.md#guidance-and-control, "EOD, CMA, battery-MDP rates").
inline constexpr double kCmaEpoch_s = 1.0;

// ---- Parameters -------------------------------------------------------------------------------

struct SpallGrowthParams {
  double initial_area_mm2 = 0.01;  // D₀, §3.4.1 ("always assumes the initial defect area as 0.01mm²")
  double failure_area_mm2 = 1.0;   // D_f, §3.4.1 (threshold of 1 mm²; crossing it jams the motor)
  double paris_coefficient = 0.2;  // C_D per growth step, for D in mm², §3.4.1 (after ref. [80])
  double paris_exponent = 1.0;     // n, §3.4.1 (after ref. [80])
  // σ of ω_CD per growth step. Our estimate: 2.5 % of C_D, which gives a time-to-jam spread of about
  // ±7 % (1σ) and keeps the walk of C_D far from zero (0.2 / (0.005 √40) > 6σ within 40 steps);
  // 0.01 already gives stalled, heavy-tailed histories. The dissertation gives no value.
  double paris_coefficient_noise_std = 0.005;
  // σ of ω_n per growth step. Our estimate, chosen like the one above (the dissertation gives none).
  double paris_exponent_noise_std = 0.005;
  // τ, seconds per growth step (docs/modelling-choices.md#spall-growth-time-scale). Default: CalibrateTimePerGrowthStep
  // with the defaults above and CalibrationOptions{} (Table 5.4's 0.002809 per 1 s epoch over 1000 runs);
  // motor_rul_test "StoredDefaultTimeScaleIsTheCalibrationOutput" recomputes it. A scenario with
  // faster growth sets a smaller τ, e.g. from CalibrateTimePerGrowthStep with a larger target.
  double time_per_growth_step_s = 15.3308;
  // Plausible τ (common/bounds.h): 1 ms to one hour per step, our bound around the
  // 0.7128 s of docs/modelling-choices.md#spall-growth-time-scale and the Table 5.4 calibration's 15.3 s.
  static constexpr Bounds kTimePerGrowthStepBounds{0.001, 3600.0, "s"};
  // A history not at D_f after this many growth steps stops and is reported as censored. Our bound:
  // 100 × the deterministic 23 steps; no default history comes near it.
  int max_growth_steps = 2300;
  int particles = 100;  // §3.4.1 ("propagating 100 particles")

  // True when usable; otherwise writes the first problem ("field: expected …") to *error.
  bool IsValid(std::string* error) const;
  bool operator==(const SpallGrowthParams&) const = default;
};

// One particle of the spall state: its area and the current values of its parameter walks.
struct SpallParticle {
  double area_mm2 = 0.0;
  double paris_coefficient = 0.0;  // C_D for the coming growth step
  double paris_exponent = 0.0;     // n for the coming growth step
  bool operator==(const SpallParticle&) const = default;
};

// A spall history propagated to the threshold, in growth steps (τ-free, so one sample serves any τ).
struct SpallHistory {
  double growth_steps = 0.0;  // steps from the start to the crossing of D_f (or to the horizon)
  bool jammed = false;        // false: censored at max_growth_steps, still below D_f
};

// ---- Results ----------------------------------------------------------------------------------

enum class RulStatus {
  kOk,              // every particle reached D_f
  kHorizonReached,  // some particles were still below D_f at max_growth_steps (censored)
};

struct RulDistribution {
  RulStatus status = RulStatus::kOk;
  int particles = 0;
  int censored_particles = 0;  // their RUL is the horizon, a lower bound
  double mean_s = 0.0;         // t_RUL for the motor margin (item 5 of the header comment)
  double p05_s = 0.0;          // percentiles: linear interpolation between order statistics
  double p50_s = 0.0;
  double p95_s = 0.0;
  // Jams per spalled epoch over the particles (item 4): from the onset, the Table 5.4 quantity; from a
  // later state, the constant per-epoch hazard with the same mean remaining epochs.
  double jam_probability_per_epoch = 0.0;
  double epoch_s = kCmaEpoch_s;
  std::vector<double> rul_s;  // [particles] in particle order
};

struct JamProbabilityMeasurement {
  int runs = 0;
  int jams = 0;
  double spalled_epochs = 0.0;             // Σ max(1, ⌈T/epoch⌉) over the runs
  double mean_time_to_jam_s = 0.0;         // over the jammed runs (NaN when none jammed)
  double jam_probability_per_epoch = 0.0;  // jams / spalled_epochs (item 4)
  double epoch_s = kCmaEpoch_s;
};

// ---- The model --------------------------------------------------------------------------------

// Immutable after construction; every method is const and takes its state and random stream explicitly,
// so one model serves any number of threads.
class MotorRulModel {
 public:
  // Throws InputError naming the field when the parameters are not valid.
  explicit MotorRulModel(const SpallGrowthParams& params = {});

  const SpallGrowthParams& params() const { return params_; }
  bool operator==(const MotorRulModel&) const = default;

  // A particle at `area_mm2` with the nominal C_D and n.
  SpallParticle MakeParticle(double area_mm2) const;

  // Area after `step_fraction` ∈ [0, 1] of a growth step with the particle's parameters held
  // (exact integral of dD/dN = max(C_D, 0) D^n). +∞ when an n > 1 law blows up within the interval.
  double CalcAreaAfter(const SpallParticle& particle, double step_fraction) const;

  // Growth steps needed to reach `area_mm2` with the particle's parameters held (the inverse of
  // CalcAreaAfter); 0 when already there, +∞ when C_D ≤ 0. May exceed one step.
  double CalcStepsToReach(const SpallParticle& particle, double area_mm2) const;

  // One whole growth step of eq. 3.8: the area grows with the held parameters, then the parameters
  // take their random step (draws: ω_CD, then ω_n).
  SpallParticle Step(const SpallParticle& particle, RandomStream& random) const;

  // Propagates one particle until it crosses D_f or max_growth_steps is reached.
  SpallHistory PropagateToFailure(SpallParticle particle, RandomStream& random) const;

  // RUL distribution of a spall state (the particles, propagated in order with one stream).
  RulDistribution PredictRul(std::span<const SpallParticle> particles, RandomStream& random) const;

  // RUL now from an observed area: params().particles particles at `area_mm2`, nominal parameters.
  RulDistribution PredictRulFromArea(double area_mm2, RandomStream& random) const;

  // The per-epoch jam probability measured as the dissertation did (item 4): `runs` histories from
  // D₀. Throws InputError when runs < 1 or epoch_s is not positive.
  JamProbabilityMeasurement MeasureJamProbability(int runs, RandomStream& random, double epoch_s = kCmaEpoch_s) const;

 private:
  SpallGrowthParams params_;
};

// The estimator of item 4 on given histories at a given τ: jams / Σ max(1, ⌈τ·steps/epoch⌉).
double EstimateJamProbabilityPerEpoch(std::span<const SpallHistory> histories, double time_per_growth_step_s,
                                      double epoch_s);

// ---- Calibration of τ (docs/modelling-choices.md#spall-growth-time-scale) -------------------------------------------

struct CalibrationOptions {
  double target_jam_probability_per_epoch = kTable54JamProbabilityPerEpoch;  // Table 5.4
  double epoch_s = kCmaEpoch_s;  // 1 s CMA epoch, docs/defaults.md#guidance-and-control
  int runs = 1000;          // §5.3.2.3: "1000 simulations of the motor prognosis algorithm"
  std::uint64_t seed = 15;  // arbitrary fixed seed (15: the decision's number)
  bool IsValid(std::string* error) const;
};

struct CalibrationResult {
  double time_per_growth_step_s = 0.0;
  double mean_growth_steps_to_jam = 0.0;   // over the jammed calibration runs
  double jam_probability_per_epoch = 0.0;  // achieved on the calibration sample (≤ target, closest)
  int runs = 0;
  int jams = 0;
};

// τ such that the estimator of item 4, on `runs` histories drawn from RandomStream(seed), equals
// the target. The histories are drawn once in growth steps (they do not depend on τ); p̂(τ) is then a
// non-increasing step function of τ and the result is the smallest τ with p̂(τ) ≤ target, found by
// bisection between the bounds that ⌈x⌉ ∈ [x, x+1) gives. The params' own τ is ignored.
// Throws InputError for invalid params or options, or a target above jams/runs (unreachable).
CalibrationResult CalibrateTimePerGrowthStep(const SpallGrowthParams& params, const CalibrationOptions& options = {});

// ---- The spall → jam event of one motor (for the simulator) -----------------------------------

struct SpallJamStep {
  double time_s = 0.0;
  double area_mm2 = 0.0;
  bool jammed = false;
  double jam_time_s = 0.0;  // the exact crossing instant when jammed, NaN before
};

// The true spall of one motor from its onset: one realisation of eq. 3.8 drawn from its own stream
// (seeded at construction, so the jam time replays from the seed whatever else the simulator draws).
// Advance moves the area along the exact path of item 1: the jam time does not depend on the dt's.
// Once jammed the area stays at D_f.
class SpallJamEvent {
 public:
  SpallJamEvent(const MotorRulModel& model, double onset_time_s, std::uint64_t seed);

  // Advances by dt_s ≥ 0 (InputError otherwise). Reports the state at the new time.
  SpallJamStep Advance(double dt_s);

  double time_s() const { return time_s_; }
  double area_mm2() const { return area_mm2_; }
  bool jammed() const { return jammed_; }
  double jam_time_s() const { return jam_time_s_.value_or(std::numeric_limits<double>::quiet_NaN()); }  // NaN before

  // RUL now (item 5): PredictRulFromArea at the current area; t_RUL for MM is its mean_s. A jammed
  // motor has RUL 0.
  RulDistribution PredictRulNow(RandomStream& random) const;
  bool operator==(const SpallJamEvent&) const = default;  // a value (sim/flight.h compares flight states whole)

 private:
  MotorRulModel model_;
  RandomStream random_;
  SpallParticle step_start_;  // state at the start of the current growth step
  double onset_time_s_;       // the current step starts at onset + steps done · τ
  std::int64_t growth_steps_done_ = 0;
  double time_s_;
  double area_mm2_;
  bool jammed_ = false;
  std::optional<double> jam_time_s_;  // none before the jam (not NaN: an event then equals its copy)
};

// Motor margin, eq. 5.14 with one fault type (n_f = 1) and docs/modelling-choices.md#margins:
// MM = 1 − t_flight_remaining / t_RUL; +∞ RUL (no fault) gives 1, t_RUL ≤ 0 (jammed) gives −∞.
double CalcMotorMargin(double flight_remaining_s, double rul_s);

}  // namespace uascma::prognostics
