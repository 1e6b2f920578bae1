// Motor RUL by Paris-law spall growth (dissertation §3.4.1, eq. 3.8). The contract, the reading of
// eq. 3.8 and the estimator of Table 5.4 are in the header; this file follows them step by step.
#include "uascma/prognostics/motor_rul.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <fmt/format.h>

#include "uascma/common/error.h"

namespace uascma::prognostics {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Below this |1 − n| the two Paris-law quotients below switch to their second-order series, whose
// truncation error (~(a·x)²/6 relative) is then far below round-off; above it the library functions
// expm1 and log1p keep full relative accuracy.
constexpr double kSeriesExponentGap = 1e-12;

// (e^(a·x) − 1) / a, → x as a → 0.
double ExpRelative(double a, double x) {
  if (std::abs(a) < kSeriesExponentGap) return x * (1.0 + 0.5 * a * x);
  return std::expm1(a * x) / a;
}

// ln(1 + a·x) / a, → x as a → 0. Requires 1 + a·x > 0.
double LogRelative(double a, double x) {
  if (std::abs(a) < kSeriesExponentGap) return x * (1.0 - 0.5 * a * x);
  return std::log1p(a * x) / a;
}

bool IsPositiveFinite(double value) { return std::isfinite(value) && value > 0.0; }

// The epochs a history spends in SF before it is seen jammed (header, item 4).
double SpalledEpochs(double time_s, double epoch_s) { return std::max(1.0, std::ceil(time_s / epoch_s)); }

// jams / Σ spalled epochs: the header's item 4 on histories at a time scale τ.
double JamsPerSpalledEpoch(std::span<const SpallHistory> histories, double time_per_growth_step_s, double epoch_s,
                           double* spalled_epochs = nullptr) {
  double epochs = 0.0;
  int jams = 0;
  for (const SpallHistory& history : histories) {
    epochs += SpalledEpochs(time_per_growth_step_s * history.growth_steps, epoch_s);
    jams += history.jammed ? 1 : 0;
  }
  if (spalled_epochs != nullptr) *spalled_epochs = epochs;
  return jams / epochs;
}

// `runs` histories from D₀ with the nominal parameters, one stream, in order.
std::vector<SpallHistory> DrawHistoriesFromOnset(const MotorRulModel& model, int runs, RandomStream& random) {
  const SpallParticle onset = model.MakeParticle(model.params().initial_area_mm2);
  std::vector<SpallHistory> histories(static_cast<std::size_t>(runs));
  for (SpallHistory& history : histories) history = model.PropagateToFailure(onset, random);
  return histories;
}

// Mean growth steps of the jammed histories (NaN when none jammed).
double MeanStepsOfJammed(std::span<const SpallHistory> histories, int* jams) {
  double steps = 0.0;
  int count = 0;
  for (const SpallHistory& history : histories) {
    if (!history.jammed) continue;
    steps += history.growth_steps;
    ++count;
  }
  *jams = count;
  return count > 0 ? steps / count : std::nan("");
}

// Percentile q ∈ [0, 1] of a sorted sample, linear between order statistics (Hyndman & Fan type 7).
double Percentile(const std::vector<double>& sorted, double q) {
  const double position = q * static_cast<double>(sorted.size() - 1);
  const std::size_t below = static_cast<std::size_t>(std::floor(position));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  return sorted[below] + (position - static_cast<double>(below)) * (sorted[above] - sorted[below]);
}

void RequireValidEpoch(double epoch_s, const char* source) {
  if (!IsPositiveFinite(epoch_s)) {
    throw InputError(source, "epoch_s", fmt::format("a positive epoch in seconds, got {}", epoch_s));
  }
}

}  // namespace

// ---- Parameters -------------------------------------------------------------------------------

bool SpallGrowthParams::IsValid(std::string* error) const {
  const auto fail = [error](std::string message) {
    if (error != nullptr) *error = std::move(message);
    return false;
  };
  if (!IsPositiveFinite(initial_area_mm2)) {
    return fail(fmt::format("initial_area_mm2: a positive area in mm², got {}", initial_area_mm2));
  }
  if (!(std::isfinite(failure_area_mm2) && failure_area_mm2 > initial_area_mm2)) {
    return fail(fmt::format("failure_area_mm2: a finite area above initial_area_mm2 ({}), got {}", initial_area_mm2,
                            failure_area_mm2));
  }
  if (!IsPositiveFinite(paris_coefficient)) {
    return fail(fmt::format("paris_coefficient: a positive C_D, got {}", paris_coefficient));
  }
  if (!IsPositiveFinite(paris_exponent)) {
    return fail(fmt::format("paris_exponent: a positive n, got {}", paris_exponent));
  }
  if (!(std::isfinite(paris_coefficient_noise_std) && paris_coefficient_noise_std >= 0.0)) {
    return fail(
        fmt::format("paris_coefficient_noise_std: a standard deviation >= 0, got {}", paris_coefficient_noise_std));
  }
  if (!(std::isfinite(paris_exponent_noise_std) && paris_exponent_noise_std >= 0.0)) {
    return fail(fmt::format("paris_exponent_noise_std: a standard deviation >= 0, got {}", paris_exponent_noise_std));
  }
  if (!CheckWithin(time_per_growth_step_s, kTimePerGrowthStepBounds, "time_per_growth_step_s", error)) return false;
  if (max_growth_steps < 1) {
    return fail(fmt::format("max_growth_steps: at least 1, got {}", max_growth_steps));
  }
  if (particles < 1) return fail(fmt::format("particles: at least 1, got {}", particles));
  return true;
}

bool CalibrationOptions::IsValid(std::string* error) const {
  const auto fail = [error](std::string message) {
    if (error != nullptr) *error = std::move(message);
    return false;
  };
  if (!(std::isfinite(target_jam_probability_per_epoch) && target_jam_probability_per_epoch > 0.0 &&
        target_jam_probability_per_epoch < 1.0)) {
    return fail(fmt::format("target_jam_probability_per_epoch: a probability in (0, 1), got {}",
                            target_jam_probability_per_epoch));
  }
  if (!IsPositiveFinite(epoch_s)) {
    return fail(fmt::format("epoch_s: a positive epoch in seconds, got {}", epoch_s));
  }
  if (runs < 1) return fail(fmt::format("runs: at least 1, got {}", runs));
  return true;
}

// ---- The model --------------------------------------------------------------------------------

MotorRulModel::MotorRulModel(const SpallGrowthParams& params) : params_(params) {
  std::string error;
  if (!params_.IsValid(&error)) throw InputError("motor RUL parameters: " + error);
}

SpallParticle MotorRulModel::MakeParticle(double area_mm2) const {
  return {area_mm2, params_.paris_coefficient, params_.paris_exponent};
}

// With C = max(C_D, 0), a = 1 − n and D₀ the area at the start of the interval, dD/dN = C D^n gives
//   D^a(f) = D₀^a + a C f   ⇔   ln(D(f)/D₀) = ln(1 + a·s)/a,   s = C f D₀^(n−1),
// which tends to s (exponential growth) as n → 1. For n > 1 (a < 0) the area is infinite once
// 1 + a·s ≤ 0 (finite-time blow-up of the power law).
double MotorRulModel::CalcAreaAfter(const SpallParticle& particle, double step_fraction) const {
  const double coefficient = std::max(particle.paris_coefficient, 0.0);
  const double a = 1.0 - particle.paris_exponent;
  const double s = coefficient * step_fraction * std::pow(particle.area_mm2, -a);
  if (1.0 + a * s <= 0.0) return kInfinity;
  return particle.area_mm2 * std::exp(LogRelative(a, s));
}

// The inverse: reaching D from D₀ takes s = (e^(a·L) − 1)/a with L = ln(D/D₀), i.e.
// f = s / (C D₀^(n−1)) growth steps; for n = 1, f = L / C.
double MotorRulModel::CalcStepsToReach(const SpallParticle& particle, double area_mm2) const {
  if (area_mm2 <= particle.area_mm2) return 0.0;
  const double coefficient = std::max(particle.paris_coefficient, 0.0);
  if (coefficient <= 0.0) return kInfinity;
  const double a = 1.0 - particle.paris_exponent;
  const double log_ratio = std::log(area_mm2 / particle.area_mm2);
  return ExpRelative(a, log_ratio) / (coefficient * std::pow(particle.area_mm2, -a));
}

SpallParticle MotorRulModel::Step(const SpallParticle& particle, RandomStream& random) const {
  SpallParticle next;
  next.area_mm2 = CalcAreaAfter(particle, 1.0);  // eq. 3.8, first line, over one whole step
  const double coefficient_noise = random.Normal();
  const double exponent_noise = random.Normal();
  next.paris_coefficient =
      particle.paris_coefficient + params_.paris_coefficient_noise_std * coefficient_noise;           // C_D + ω_CD
  next.paris_exponent = particle.paris_exponent + params_.paris_exponent_noise_std * exponent_noise;  // n + ω_n
  return next;
}

SpallHistory MotorRulModel::PropagateToFailure(SpallParticle particle, RandomStream& random) const {
  if (!(IsPositiveFinite(particle.area_mm2) && std::isfinite(particle.paris_coefficient) &&
        std::isfinite(particle.paris_exponent))) {
    throw InputError("motor RUL", "particle",
                     fmt::format("a positive finite area and finite C_D, n; got area {} mm², C_D {}, n {}",
                                 particle.area_mm2, particle.paris_coefficient, particle.paris_exponent));
  }
  // Step k covers growth steps [k, k+1): either the threshold is crossed inside it with the held
  // parameters, or the particle takes the whole step and its parameters walk.
  for (int step = 0;; ++step) {
    const double to_failure = CalcStepsToReach(particle, params_.failure_area_mm2);
    if (to_failure <= 1.0) return {step + to_failure, true};
    if (step + 1 >= params_.max_growth_steps) {
      return {static_cast<double>(params_.max_growth_steps), false};
    }
    particle = Step(particle, random);
  }
}

RulDistribution MotorRulModel::PredictRul(std::span<const SpallParticle> particles, RandomStream& random) const {
  if (particles.empty()) throw InputError("motor RUL", "particles", "at least one particle");
  RulDistribution result;
  result.particles = static_cast<int>(particles.size());
  result.epoch_s = kCmaEpoch_s;
  std::vector<SpallHistory> histories;
  histories.reserve(particles.size());
  result.rul_s.reserve(particles.size());
  double sum_s = 0.0;
  for (const SpallParticle& particle : particles) {
    const SpallHistory history = PropagateToFailure(particle, random);
    histories.push_back(history);
    const double rul_s = history.growth_steps * params_.time_per_growth_step_s;
    result.rul_s.push_back(rul_s);
    sum_s += rul_s;
    if (!history.jammed) ++result.censored_particles;
  }
  result.status = result.censored_particles > 0 ? RulStatus::kHorizonReached : RulStatus::kOk;
  result.mean_s = sum_s / static_cast<double>(particles.size());
  std::vector<double> sorted = result.rul_s;
  std::sort(sorted.begin(), sorted.end());
  result.p05_s = Percentile(sorted, 0.05);
  result.p50_s = Percentile(sorted, 0.50);
  result.p95_s = Percentile(sorted, 0.95);
  result.jam_probability_per_epoch = JamsPerSpalledEpoch(histories, params_.time_per_growth_step_s, result.epoch_s);
  return result;
}

RulDistribution MotorRulModel::PredictRulFromArea(double area_mm2, RandomStream& random) const {
  const std::vector<SpallParticle> particles(static_cast<std::size_t>(params_.particles), MakeParticle(area_mm2));
  return PredictRul(particles, random);
}

JamProbabilityMeasurement MotorRulModel::MeasureJamProbability(int runs, RandomStream& random, double epoch_s) const {
  if (runs < 1) throw InputError("jam probability", "runs", fmt::format("at least 1, got {}", runs));
  RequireValidEpoch(epoch_s, "jam probability");
  const std::vector<SpallHistory> histories = DrawHistoriesFromOnset(*this, runs, random);
  JamProbabilityMeasurement result;
  result.runs = runs;
  result.epoch_s = epoch_s;
  result.mean_time_to_jam_s = MeanStepsOfJammed(histories, &result.jams) * params_.time_per_growth_step_s;
  result.jam_probability_per_epoch =
      JamsPerSpalledEpoch(histories, params_.time_per_growth_step_s, epoch_s, &result.spalled_epochs);
  return result;
}

double EstimateJamProbabilityPerEpoch(std::span<const SpallHistory> histories, double time_per_growth_step_s,
                                      double epoch_s) {
  if (histories.empty()) throw InputError("jam probability", "histories", "at least one history");
  if (!IsPositiveFinite(time_per_growth_step_s)) {
    throw InputError("jam probability", "time_per_growth_step_s",
                     fmt::format("a positive time in seconds, got {}", time_per_growth_step_s));
  }
  RequireValidEpoch(epoch_s, "jam probability");
  return JamsPerSpalledEpoch(histories, time_per_growth_step_s, epoch_s);
}

// ---- Calibration ------------------------------------------------------------------------------

CalibrationResult CalibrateTimePerGrowthStep(const SpallGrowthParams& params, const CalibrationOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("motor RUL calibration: " + error);
  const MotorRulModel model(params);
  RandomStream random(options.seed);
  const std::vector<SpallHistory> histories = DrawHistoriesFromOnset(model, options.runs, random);

  CalibrationResult result;
  result.runs = options.runs;
  result.mean_growth_steps_to_jam = MeanStepsOfJammed(histories, &result.jams);
  const double target = options.target_jam_probability_per_epoch;
  const double jams = result.jams;
  const double runs = options.runs;
  // At τ → 0 every history takes one epoch: p̂ = jams/runs is the largest reachable value.
  if (!(target < jams / runs)) {
    throw InputError("motor RUL calibration", "target_jam_probability_per_epoch",
                     fmt::format("below jams/runs = {} (the value when every history takes one epoch), got {}",
                                 jams / runs, target));
  }
  double total_steps = 0.0;
  for (const SpallHistory& history : histories) total_steps += history.growth_steps;
  // Bracket: Σ⌈x_i⌉ lies in [Σx_i, Σx_i + runs) with x_i = τ·steps_i/epoch, so p̂(τ) ≤ target at
  // τ_hi = epoch·jams/(target·Σsteps) and p̂(τ) ≥ target at τ_lo = epoch·(jams/target − runs)/Σsteps.
  double high = options.epoch_s * jams / (target * total_steps);
  double low = std::max(0.0, options.epoch_s * (jams / target - runs) / total_steps);
  constexpr int kMaxBisections = 200;
  constexpr double kRelativeWidth = 1e-12;
  for (int i = 0; i < kMaxBisections && high - low > kRelativeWidth * high; ++i) {
    const double middle = 0.5 * (low + high);
    if (JamsPerSpalledEpoch(histories, middle, options.epoch_s) <= target) {
      high = middle;
    } else {
      low = middle;
    }
  }
  result.time_per_growth_step_s = high;
  result.jam_probability_per_epoch = JamsPerSpalledEpoch(histories, high, options.epoch_s);
  return result;
}

// ---- The spall → jam event --------------------------------------------------------------------

SpallJamEvent::SpallJamEvent(const MotorRulModel& model, double onset_time_s, std::uint64_t seed)
    : model_(model),
      random_(seed),
      step_start_(model.MakeParticle(model.params().initial_area_mm2)),
      onset_time_s_(onset_time_s),
      time_s_(onset_time_s),
      area_mm2_(model.params().initial_area_mm2) {
  if (!std::isfinite(onset_time_s)) {
    throw InputError("spall jam event", "onset_time_s", fmt::format("a finite time, got {}", onset_time_s));
  }
}

SpallJamStep SpallJamEvent::Advance(double dt_s) {
  if (!(std::isfinite(dt_s) && dt_s >= 0.0)) {
    throw InputError("spall jam event", "dt_s", fmt::format("a finite step >= 0 s, got {}", dt_s));
  }
  const double target_s = time_s_ + dt_s;
  const double time_per_step_s = model_.params().time_per_growth_step_s;
  const double failure_area_mm2 = model_.params().failure_area_mm2;
  // Walk the growth steps up to the target time: a crossing inside the current step jams the motor
  // at its exact instant; a target inside the step sets the area; otherwise take the whole step.
  while (!jammed_) {
    const double step_start_s = onset_time_s_ + growth_steps_done_ * time_per_step_s;
    const double step_end_s = step_start_s + time_per_step_s;
    const double crossing_s = step_start_s + time_per_step_s * model_.CalcStepsToReach(step_start_, failure_area_mm2);
    if (crossing_s <= std::min(target_s, step_end_s)) {
      jammed_ = true;
      jam_time_s_ = crossing_s;
      area_mm2_ = failure_area_mm2;
      break;
    }
    if (target_s < step_end_s) {
      area_mm2_ = model_.CalcAreaAfter(step_start_, (target_s - step_start_s) / time_per_step_s);
      break;
    }
    step_start_ = model_.Step(step_start_, random_);
    ++growth_steps_done_;
  }
  time_s_ = target_s;
  return {time_s_, area_mm2_, jammed_, jam_time_s()};
}

RulDistribution SpallJamEvent::PredictRulNow(RandomStream& random) const {
  return model_.PredictRulFromArea(area_mm2_, random);
}

double CalcMotorMargin(double flight_remaining_s, double rul_s) {
  if (!(std::isfinite(flight_remaining_s) && flight_remaining_s >= 0.0)) {
    throw InputError("motor margin", "flight_remaining_s",
                     fmt::format("a finite time >= 0 s, got {}", flight_remaining_s));
  }
  if (std::isnan(rul_s)) throw InputError("motor margin", "rul_s", "a time in seconds, got NaN");
  if (rul_s <= 0.0) return -kInfinity;  // jammed: MM0 (docs/modelling-choices.md#margins)
  if (std::isinf(rul_s)) return 1.0;    // no fault: MM1
  return 1.0 - flight_remaining_s / rul_s;
}

}  // namespace uascma::prognostics
