// Motor RUL (dissertation §3.4.1, eq. 3.8; Table 5.4; docs/modelling-choices.md#margins, #spall-growth-time-scale):
// closed forms with the noise off, an independent Euler integration of eq. 3.8, the Table 5.4 calibration on an
// independent sample, invariants, and replay from a seed.
#include "uascma/prognostics/motor_rul.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../support/input_error.h"

#include "uascma/common/error.h"

namespace uascma::prognostics {
namespace {

using testing_support::InputErrorMessage;

// Closed forms are evaluated with a handful of exp/log/expm1 calls: agreement to round-off.
constexpr double kClosedFormRelativeTolerance = 1e-12;
// Table 5.4's P(JF|SF) = 0.002809 per 1 s epoch, reproduced within 10 % (the requirement).
constexpr double kTable54RelativeTolerance = 0.10;
// The stored default τ has six significant digits (rounding ≤ 3.3e-6 relative); a different libm
// could flip one ceil in 356 000 epochs, moving τ by ~3e-6 relative.
constexpr double kStoredTimeScaleRelativeTolerance = 1e-5;
// Jam times from the exact path, however it is stepped: the onset + k·τ sums differ by round-off.
constexpr double kJamTimeTolerance_s = 1e-9;
// Explicit Euler on eq. 3.8 with a step of 1e-4 growth steps has a first-order error of about
// C_D·Δ/2 = 1e-5 relative in the time to failure; we allow 1e-4.
constexpr double kEulerRelativeTolerance = 1e-4;
constexpr double kEulerStep = 1e-4;  // growth steps

const double kDeterministicStepsToFailure = std::log(100.0) / 0.2;  // ln(D_f/D₀)/C_D, §3.4.1 values

SpallGrowthParams NoiseFree() {
  SpallGrowthParams params;
  params.paris_coefficient_noise_std = 0.0;
  params.paris_exponent_noise_std = 0.0;
  return params;
}

// Growth steps from D₀ = 0.01 mm² to D_f = 1 mm² with the noise off and Paris exponent n.
double NoiseFreeStepsToFailure(double n) {
  SpallGrowthParams params = NoiseFree();
  params.paris_exponent = n;
  const MotorRulModel model(params);
  RandomStream random(1);
  const SpallHistory history = model.PropagateToFailure(model.MakeParticle(0.01), random);
  EXPECT_TRUE(history.jammed);
  return history.growth_steps;
}

bool BitwiseIdentical(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::bit_cast<std::uint64_t>(a[i]) != std::bit_cast<std::uint64_t>(b[i])) return false;
  }
  return true;
}

// ---- Closed forms (noise off) -------------------------------------------------------------------

TEST(MotorRulClosedFormTest, ExponentialGrowthTakesLn100OverCdSteps) {
  EXPECT_NEAR(NoiseFreeStepsToFailure(1.0), kDeterministicStepsToFailure,
              kClosedFormRelativeTolerance * kDeterministicStepsToFailure);

  const MotorRulModel model(NoiseFree());
  RandomStream random(1);

  const RulDistribution rul = model.PredictRulFromArea(0.01, random);
  const double expected_s = kDeterministicStepsToFailure * model.params().time_per_growth_step_s;
  EXPECT_NEAR(rul.mean_s, expected_s, kClosedFormRelativeTolerance * expected_s);
  EXPECT_NEAR(rul.p05_s, expected_s, kClosedFormRelativeTolerance * expected_s);
  EXPECT_NEAR(rul.p95_s, expected_s, kClosedFormRelativeTolerance * expected_s);
}

TEST(MotorRulClosedFormTest, RulFromALargerAreaIsTheRemainingLogDistance) {
  const MotorRulModel model(NoiseFree());
  RandomStream random(1);
  const double expected_s = std::log(1.0 / 0.1) / 0.2 * model.params().time_per_growth_step_s;
  const RulDistribution rul = model.PredictRulFromArea(0.1, random);
  EXPECT_NEAR(rul.mean_s, expected_s, kClosedFormRelativeTolerance * expected_s);
}

TEST(MotorRulClosedFormTest, PowerLawGrowthMatchesItsIntegral) {
  // n ≠ 1: ∫ dD / (C_D D^n) from D₀ to D_f = (D_f^(1−n) − D₀^(1−n)) / ((1−n) C_D).
  for (const double n : {0.8, 1.2}) {
    const double expected = (std::pow(1.0, 1.0 - n) - std::pow(0.01, 1.0 - n)) / ((1.0 - n) * 0.2);
    EXPECT_NEAR(NoiseFreeStepsToFailure(n), expected, kClosedFormRelativeTolerance * expected) << "n = " << n;
  }
}

TEST(MotorRulClosedFormTest, EulerIntegrationOfEq38ConvergesToTheModel) {
  // An independent computation: eq. 3.8 as printed, D ← D + Δ C_D D^n, with a small Δ.
  for (const double n : {1.0, 1.1}) {
    const double model_steps = NoiseFreeStepsToFailure(n);
    double area_mm2 = 0.01;
    long euler_steps = 0;
    while (area_mm2 < 1.0) {
      area_mm2 += kEulerStep * 0.2 * std::pow(area_mm2, n);
      ++euler_steps;
    }
    EXPECT_NEAR(euler_steps * kEulerStep, model_steps, kEulerRelativeTolerance * model_steps) << "n = " << n;
  }
}

TEST(MotorRulClosedFormTest, StepsToReachInvertsAreaAfterAcrossExponents) {
  const MotorRulModel model;
  // 1 + 1e-13 exercises the series branch near n = 1.
  for (const double n : {0.9, 1.0, 1.0 + 1e-13, 1.1}) {
    const SpallParticle particle{0.05, 0.2, n};
    const double steps = model.CalcStepsToReach(particle, 0.07);
    EXPECT_NEAR(model.CalcAreaAfter(particle, steps), 0.07, kClosedFormRelativeTolerance * 0.07) << n;
  }
  EXPECT_NEAR(model.CalcStepsToReach({0.05, 0.2, 1.0 + 1e-13}, 0.07), model.CalcStepsToReach({0.05, 0.2, 1.0}, 0.07),
              1e-11);
}

// ---- Calibration of τ to Table 5.4 (docs/modelling-choices.md#spall-growth-time-scale) ------------------------------

TEST(MotorRulCalibrationTest, DefaultModelReproducesTable54OnAnIndependentSample) {
  const MotorRulModel model;
  // A seed other than the calibration's: 1000 fresh histories, measured as the dissertation did.
  RandomStream random(2024);
  const JamProbabilityMeasurement measured = model.MeasureJamProbability(1000, random);
  EXPECT_EQ(measured.runs, 1000);
  EXPECT_EQ(measured.jams, 1000);
  EXPECT_NEAR(measured.jam_probability_per_epoch, kTable54JamProbabilityPerEpoch,
              kTable54RelativeTolerance * kTable54JamProbabilityPerEpoch);
  // With every history jammed the estimator is 1 / (mean epochs to jam); epochs round up by < 1 s.
  EXPECT_NEAR(1.0 / measured.jam_probability_per_epoch, measured.mean_time_to_jam_s + 0.5, 0.5);
}

TEST(MotorRulCalibrationTest, StoredDefaultTimeScaleIsTheCalibrationOutput) {
  const CalibrationResult calibration = CalibrateTimePerGrowthStep(SpallGrowthParams{});
  const double stored_s = SpallGrowthParams{}.time_per_growth_step_s;
  EXPECT_NEAR(calibration.time_per_growth_step_s, stored_s, kStoredTimeScaleRelativeTolerance * stored_s);
  // On its own sample the calibration hits the target up to one epoch in Σ epochs (~356 000).
  EXPECT_LE(calibration.jam_probability_per_epoch, kTable54JamProbabilityPerEpoch);
  EXPECT_NEAR(calibration.jam_probability_per_epoch, kTable54JamProbabilityPerEpoch,
              1e-4 * kTable54JamProbabilityPerEpoch);
  EXPECT_EQ(calibration.jams, 1000);
  // Wald: the mean step count is near the deterministic ln(100)/C_D (zero-mean parameter noise).
  EXPECT_NEAR(calibration.mean_growth_steps_to_jam, kDeterministicStepsToFailure, 0.05 * kDeterministicStepsToFailure);
}

TEST(MotorRulCalibrationTest, FasterScenarioGrowthAndLandingLoadCalibrateToTheirTargets) {
  // Scenario I (§5.5.1): spall at 175 s, jam at 192 s → a mean of ~17 epochs to jam.
  for (const double target : {1.0 / 17.0, kLandingJamProbabilityPerEpoch}) {
    CalibrationOptions options;
    options.target_jam_probability_per_epoch = target;
    SpallGrowthParams params;
    params.time_per_growth_step_s = CalibrateTimePerGrowthStep(params, options).time_per_growth_step_s;
    RandomStream random(99);
    const double measured = MotorRulModel(params).MeasureJamProbability(1000, random).jam_probability_per_epoch;
    EXPECT_NEAR(measured, target, kTable54RelativeTolerance * target) << "target " << target;
  }
}

TEST(MotorRulCalibrationTest, JamEstimatorCountsSpalledEpochsRoundedUp) {
  // τ = 2 s, epoch 1 s: 1.25 steps → 2.5 s → 3 epochs; 2 steps → 4 epochs; a history jammed at
  // onset still counts one epoch; a censored one counts its 10 steps = 20 epochs and no jam.
  const std::vector<SpallHistory> histories = {{1.25, true}, {2.0, true}, {0.0, true}, {10.0, false}};
  EXPECT_NEAR(EstimateJamProbabilityPerEpoch(histories, 2.0, 1.0), 3.0 / 28.0, 1e-15);
  EXPECT_NE(InputErrorMessage([] { EstimateJamProbabilityPerEpoch({}, 2.0, 1.0); }), "");
}

TEST(MotorRulCalibrationTest, UnreachableTargetIsAnInputError) {
  CalibrationOptions options;
  options.target_jam_probability_per_epoch = 1.0;  // not in (0, 1)
  EXPECT_NE(InputErrorMessage([&] { CalibrateTimePerGrowthStep({}, options); }).find("target_jam_probability"),
            std::string::npos);
  SpallGrowthParams params;
  params.max_growth_steps = 5;  // every history censored: no jams, nothing to calibrate
  options.target_jam_probability_per_epoch = 0.01;
  EXPECT_NE(InputErrorMessage([&] { CalibrateTimePerGrowthStep(params, options); }).find("jams/runs"),
            std::string::npos);
}

// ---- Invariants ---------------------------------------------------------------------------------

TEST(MotorRulInvariantTest, AreaNeverDecreasesEvenWhenTheCoefficientWalksBelowZero) {
  SpallGrowthParams params;
  params.paris_coefficient_noise_std = 0.2;  // large enough that C_D often walks below zero
  params.paris_exponent_noise_std = 0.05;
  const MotorRulModel model(params);
  RandomStream random(3);
  bool saw_negative_coefficient = false;
  for (int run = 0; run < 200; ++run) {
    SpallParticle particle = model.MakeParticle(0.01);
    for (int step = 0; step < 40 && particle.area_mm2 < 1.0; ++step) {
      const SpallParticle next = model.Step(particle, random);
      ASSERT_GE(next.area_mm2, particle.area_mm2) << "run " << run << " step " << step;
      ASSERT_GE(model.CalcAreaAfter(particle, 0.5), particle.area_mm2);
      saw_negative_coefficient |= next.paris_coefficient < 0.0;
      particle = next;
    }
  }
  EXPECT_TRUE(saw_negative_coefficient);
}

TEST(MotorRulInvariantTest, PercentilesAreOrderedAndInsideTheSample) {
  const MotorRulModel model;
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    for (const double area_mm2 : {0.01, 0.3}) {
      RandomStream random(seed);
      const RulDistribution rul = model.PredictRulFromArea(area_mm2, random);
      ASSERT_EQ(rul.status, RulStatus::kOk);
      ASSERT_EQ(rul.rul_s.size(), 100u);
      const auto [min_it, max_it] = std::minmax_element(rul.rul_s.begin(), rul.rul_s.end());
      EXPECT_LE(*min_it, rul.p05_s);
      EXPECT_LE(rul.p05_s, rul.p50_s);
      EXPECT_LE(rul.p50_s, rul.p95_s);
      EXPECT_LE(rul.p95_s, *max_it);
      EXPECT_LT(rul.p05_s, rul.p95_s);  // the noise spreads the particles
      EXPECT_GE(rul.mean_s, *min_it);
      EXPECT_LE(rul.mean_s, *max_it);
    }
  }
}

TEST(MotorRulInvariantTest, LargerSpallHasShorterRul) {
  const MotorRulModel model;
  RandomStream random(5);
  const double onset_s = model.PredictRulFromArea(0.01, random).mean_s;
  const double later_s = model.PredictRulFromArea(0.1, random).mean_s;
  EXPECT_LT(later_s, onset_s);
  // Noise-free, from 0.1 mm² half the log distance remains; with noise the mean stays within 15 %.
  EXPECT_NEAR(later_s / onset_s, 0.5, 0.5 * 0.15);
}

TEST(MotorRulInvariantTest, HorizonCensorsAndReportsIt) {
  SpallGrowthParams params;
  params.max_growth_steps = 10;  // below the ~23 steps to failure
  const MotorRulModel model(params);
  RandomStream random(1);
  const RulDistribution rul = model.PredictRulFromArea(0.01, random);
  EXPECT_EQ(rul.status, RulStatus::kHorizonReached);
  EXPECT_EQ(rul.censored_particles, 100);
  EXPECT_NEAR(rul.mean_s, 10 * params.time_per_growth_step_s, kJamTimeTolerance_s);
  EXPECT_NEAR(rul.jam_probability_per_epoch, 0.0, 1e-15);
}

// ---- Reproducibility ----------------------------------------------------------------------------

TEST(MotorRulReproducibilityTest, SameSeedSameDistributionOtherSeedOtherSamples) {
  const MotorRulModel model;
  RandomStream first(11), again(11), other(12);
  const RulDistribution a = model.PredictRulFromArea(0.01, first);
  const RulDistribution b = model.PredictRulFromArea(0.01, again);
  const RulDistribution c = model.PredictRulFromArea(0.01, other);
  EXPECT_TRUE(BitwiseIdentical(a.rul_s, b.rul_s));
  EXPECT_TRUE(BitwiseIdentical({a.mean_s, a.p05_s, a.p50_s, a.p95_s, a.jam_probability_per_epoch},
                               {b.mean_s, b.p05_s, b.p50_s, b.p95_s, b.jam_probability_per_epoch}));
  int differing = 0;
  for (std::size_t i = 0; i < a.rul_s.size(); ++i) differing += std::abs(a.rul_s[i] - c.rul_s[i]) > 1e-6;
  EXPECT_GT(differing, 90);
}

// ---- The spall → jam event ----------------------------------------------------------------------

TEST(SpallJamEventTest, JamTimeDoesNotDependOnTheStepAndReplaysTheHistory) {
  const MotorRulModel model;
  constexpr double kOnset_s = 175.0;  // Scenario I's spall onset, §5.5.1
  constexpr std::uint64_t kSeed = 31;
  RandomStream random(kSeed);
  const double expected_s = kOnset_s + model.params().time_per_growth_step_s *
                                           model.PropagateToFailure(model.MakeParticle(0.01), random).growth_steps;
  for (const double dt_s : {1.0, 0.005, 37.0, 5000.0}) {
    SpallJamEvent event(model, kOnset_s, kSeed);
    double previous_area_mm2 = event.area_mm2();
    while (!event.jammed()) {
      const SpallJamStep step = event.Advance(dt_s);
      ASSERT_GE(step.area_mm2, previous_area_mm2);
      previous_area_mm2 = step.area_mm2;
      ASSERT_LT(step.time_s, kOnset_s + 1e5);
    }
    EXPECT_NEAR(event.jam_time_s(), expected_s, kJamTimeTolerance_s) << "dt " << dt_s;
    EXPECT_GE(event.time_s(), event.jam_time_s());
    EXPECT_LT(event.time_s() - event.jam_time_s(), dt_s + kJamTimeTolerance_s);
  }
}

TEST(SpallJamEventTest, AnEventEqualsItsCopyBeforeAndAfterTheJam) {
  // A flight state is compared whole (sim/flight.h): an event before its jam (no jam time yet) must equal its copy.
  const MotorRulModel model;
  SpallJamEvent event(model, 175.0, 31);
  event.Advance(1.0);
  ASSERT_FALSE(event.jammed());
  EXPECT_TRUE(std::isnan(event.jam_time_s()));
  EXPECT_TRUE(event == SpallJamEvent(event));
  SpallJamEvent other = event;
  other.Advance(0.5);
  EXPECT_FALSE(other == event);
  while (!event.jammed()) event.Advance(10.0);
  EXPECT_TRUE(event == SpallJamEvent(event));
}

TEST(SpallJamEventTest, NoiseFreeAreaFollowsTheExponentialAndJamsOnTime) {
  const MotorRulModel model(NoiseFree());
  const double tau_s = model.params().time_per_growth_step_s;
  SpallJamEvent event(model, 10.0, 1);
  EXPECT_TRUE(std::isnan(event.jam_time_s()));
  for (int k = 1; k <= 100; ++k) {
    const SpallJamStep step = event.Advance(1.0);
    if (step.jammed) break;
    const double expected_mm2 = 0.01 * std::exp(0.2 * k / tau_s);
    ASSERT_NEAR(step.area_mm2, expected_mm2, kClosedFormRelativeTolerance * expected_mm2) << k;
  }
  while (!event.jammed()) event.Advance(1.0);
  EXPECT_NEAR(event.jam_time_s(), 10.0 + kDeterministicStepsToFailure * tau_s, kJamTimeTolerance_s);
  EXPECT_NEAR(event.area_mm2(), 1.0, 1e-15);

  RandomStream random(1);
  const RulDistribution now = event.PredictRulNow(random);
  EXPECT_NEAR(now.mean_s, 0.0, 1e-15);
  EXPECT_NEAR(now.jam_probability_per_epoch, 1.0, 1e-15);
}

TEST(SpallJamEventTest, RulNowShrinksAsTheSpallGrows) {
  const MotorRulModel model(NoiseFree());
  SpallJamEvent event(model, 0.0, 1);
  RandomStream random(1);
  const double at_onset_s = event.PredictRulNow(random).mean_s;
  event.Advance(100.0);
  const double later_s = event.PredictRulNow(random).mean_s;
  // Noise-free, the prediction from the true area is exactly the remaining deterministic time.
  EXPECT_NEAR(at_onset_s - later_s, 100.0, 1e-9 * at_onset_s);
}

TEST(SpallJamEventTest, RejectsNegativeOrNonFiniteSteps) {
  SpallJamEvent event(MotorRulModel{}, 0.0, 1);
  EXPECT_NE(InputErrorMessage([&] { event.Advance(-1.0); }).find("dt_s"), std::string::npos);
  EXPECT_NE(InputErrorMessage([&] { event.Advance(std::nan("")); }).find("dt_s"), std::string::npos);
}

// ---- Motor margin and validation ----------------------------------------------------------------

TEST(MotorMarginTest, FollowsEq514AndTheStatedMarginDefinition) {
  EXPECT_NEAR(CalcMotorMargin(100.0, 400.0), 0.75, 1e-15);
  EXPECT_LT(CalcMotorMargin(500.0, 400.0), 0.0);  // RUL shorter than the flight: MM0
  EXPECT_NEAR(CalcMotorMargin(100.0, std::numeric_limits<double>::infinity()), 1.0, 1e-15);
  EXPECT_TRUE(std::isinf(CalcMotorMargin(100.0, 0.0)));
  EXPECT_LT(CalcMotorMargin(100.0, 0.0), 0.0);
  EXPECT_NE(InputErrorMessage([] { CalcMotorMargin(-1.0, 10.0); }), "");
}

TEST(MotorRulValidationTest, InvalidParametersNameTheirField) {
  SpallGrowthParams params;
  params.particles = 0;
  EXPECT_NE(InputErrorMessage([&] { MotorRulModel{params}; }).find("particles"), std::string::npos);
  params = {};
  params.failure_area_mm2 = 0.005;
  EXPECT_NE(InputErrorMessage([&] { MotorRulModel{params}; }).find("failure_area_mm2"), std::string::npos);
  params = {};
  params.paris_coefficient_noise_std = -0.1;
  EXPECT_NE(InputErrorMessage([&] { MotorRulModel{params}; }).find("paris_coefficient_noise_std"), std::string::npos);
  params = {};
  params.time_per_growth_step_s = 0.0;
  EXPECT_NE(InputErrorMessage([&] { MotorRulModel{params}; }).find("time_per_growth_step_s"), std::string::npos);
  const MotorRulModel model;
  RandomStream random(1);
  EXPECT_NE(InputErrorMessage([&] { model.MeasureJamProbability(0, random); }).find("runs"), std::string::npos);
  EXPECT_NE(InputErrorMessage([&] { model.PredictRulFromArea(-1.0, random); }).find("particle"), std::string::npos);
}

}  // namespace
}  // namespace uascma::prognostics
