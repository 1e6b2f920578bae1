// The motor RUL distribution against the jam times of simulated spalls: the particle
// quantiles, calibration when the prognoser and the spall share the growth time scale, and the miss when
// they do not (the campaigns' default: the truth grows at 0.7128 s per step, the prognoser at Table 5.4's).
#include "uascma/prognostics/rul_calibration.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "uascma/common/error.h"
#include "uascma/common/random.h"

namespace uascma::prognostics {
namespace {

constexpr double kTight = 1e-12;

TEST(RulCalibrationTest, ParticleQuantilesAreTheDistributionsPercentiles) {
  const MotorRulModel model;
  RandomStream random(5);
  const RulDistribution rul = model.PredictRulFromArea(0.01, random);
  const std::vector<double> quantiles = CalcRulQuantiles(rul, {0.05, 0.50, 0.95});
  EXPECT_NEAR(quantiles[0], rul.p05_s, kTight * rul.p05_s);
  EXPECT_NEAR(quantiles[1], rul.p50_s, kTight * rul.p50_s);
  EXPECT_NEAR(quantiles[2], rul.p95_s, kTight * rul.p95_s);
  EXPECT_THROW(CalcRulQuantiles(rul, {1.5}), InputError);
}

// The predictions made at the onset (one per history).
PredictionSet AtOnset(const RulCalibration& calibration) {
  PredictionSet onset;
  onset.levels = calibration.predictions.levels;
  for (const QuantilePrediction& prediction : calibration.predictions.predictions) {
    if (prediction.time_s == 0.0) onset.predictions.push_back(prediction);
  }
  return onset;
}

TEST(RulCalibrationTest, APrognoserWithTheSpallsTimeScaleIsCalibratedAtTheOnset) {
  // Same law, same parameters, same start: each onset truth is one more draw of the particles' distribution,
  // so its PIT is uniform. Expected coverage of a central interval from 100 particles' type-7 quantiles:
  // (position of the upper − position of the lower order statistic) / (n + 1), e.g. (94.05 − 4.95) / 101 =
  // 0.882 for 90 % and 0.490 for 50 %. Tolerance: 4 binomial σ over 930 histories (0.042 at 90 %, 0.066 at
  // 50 %).
  RulCalibrationOptions options;
  options.prognosis_time_per_growth_step_s = options.truth_time_per_growth_step_s;
  const RulCalibration calibration = CalibrateRul(options);
  const PredictionSet onset = AtOnset(calibration);
  ASSERT_EQ(onset.predictions.size(), 930u);
  EXPECT_EQ(calibration.censored_histories, 0);
  const double n = 930.0;
  for (const double level : {0.5, 0.9}) {
    const double lower = 99.0 * 0.5 * (1.0 - level), upper = 99.0 * 0.5 * (1.0 + level);
    const double expected = (upper - lower) / 101.0;
    const double tolerance = 4.0 * std::sqrt(expected * (1.0 - expected) / n);
    EXPECT_NEAR(CalcIntervalCoverage(onset, level).fraction, expected, tolerance) << level;
  }
  // The mean RUL at the onset is the mean jam time (both ~ 23 steps x 0.7128 s), within 4 standard errors
  // of the jam times' mean (their spread is about 7 %, motor_rul.h).
  EXPECT_NEAR(calibration.mean_predicted_rul_at_onset_s, calibration.mean_jam_time_s,
              4.0 * 0.07 * calibration.mean_jam_time_s / std::sqrt(n));
}

TEST(RulCalibrationTest, TheCampaignDefaultsPrognoserMissesEveryJam) {
  // Truth 0.7128 s per step, prognoser Table 5.4's 15.33 s: the RUL is 21.5 times too long, every truth lies
  // below every interval.
  const RulCalibration calibration = CalibrateRul(RulCalibrationOptions{});
  const IntervalCoverage coverage = CalcIntervalCoverage(calibration.predictions, 0.95);
  EXPECT_EQ(coverage.covered, 0);
  EXPECT_EQ(coverage.below, coverage.predictions);
  EXPECT_GT(calibration.mean_predicted_rul_at_onset_s, 10.0 * calibration.mean_jam_time_s);
}

TEST(RulCalibrationTest, ReplaysFromTheSeedAndScoresEveryEpochBeforeTheJam) {
  RulCalibrationOptions options;
  options.histories = 20;
  options.mode = RulPredictionMode::kObservedArea;
  const RulCalibration first = CalibrateRul(options);
  const RulCalibration again = CalibrateRul(options);
  ASSERT_EQ(first.predictions.predictions.size(), again.predictions.predictions.size());
  for (std::size_t i = 0; i < first.predictions.predictions.size(); ++i) {
    EXPECT_EQ(first.predictions.predictions[i].quantiles_s, again.predictions.predictions[i].quantiles_s);
  }
  std::size_t expected = 0;
  for (double jam_s : first.jam_time_s) expected += static_cast<std::size_t>(std::ceil(jam_s / options.epoch_s));
  EXPECT_EQ(first.predictions.predictions.size(), expected);
  options.seed += 1;
  EXPECT_NE(CalibrateRul(options).jam_time_s, first.jam_time_s);
  options.histories = 0;
  EXPECT_THROW(CalibrateRul(options), InputError);
}

TEST(RulCalibrationTest, TheSurvivingRulByHand) {
  const std::vector<double> sorted = {1.0, 2.0, 4.0, 8.0};
  EXPECT_NEAR(SurvivingRulMean(sorted, 0.0, 1.0), 3.75, kTight);
  EXPECT_NEAR(SurvivingRulMean(sorted, 3.0, 1.0), (1.0 + 5.0) / 2.0, kTight);  // 4 and 8 left, less 3 s
  EXPECT_EQ(SurvivingRul(sorted, 3.0, 1.0), (std::vector<double>{1.0, 5.0}));
  EXPECT_NEAR(SurvivingRulMean(sorted, 8.0, 1.0), 1.0, kTight);  // none left: the jam is due within the epoch
  EXPECT_EQ(SurvivingRul(sorted, 9.0, 0.5), (std::vector<double>{0.5}));
}

// The fit recovers the simulated spall's own time scale: the training jam times are the truth's growth steps × τ_truth,
// the prognoser's histories the same law's steps, so τ̂ / τ_truth is a ratio of two means of one distribution. Its
// relative standard error is about 0.07 · sqrt(2 / 930) = 0.33 %; tolerance 4 σ.
TEST(RulCalibrationTest, TheFittedTimeScaleIsTheSimulatedSpallsOwn) {
  for (const double truth_s : {kCampaignTruthTimePerGrowthStep_s, SpallGrowthParams{}.time_per_growth_step_s}) {
    const RulTimeScaleFit fit = FitRulTimeScale(truth_s);
    EXPECT_EQ(fit.histories, kRulTrainingHistories);
    EXPECT_EQ(fit.censored_histories, 0);
    EXPECT_NEAR(fit.time_per_growth_step_s, truth_s, 4.0 * 0.0033 * truth_s) << truth_s;
    EXPECT_NEAR(fit.mean_jam_time_s, fit.time_per_growth_step_s * fit.mean_particle_growth_steps, 1e-9 * truth_s);
    EXPECT_EQ(VehicleRulTimeScale(truth_s).time_per_growth_step_s, fit.time_per_growth_step_s);
  }
  EXPECT_THROW(FitRulTimeScale(0.0), InputError);
  EXPECT_THROW(FitRulTimeScale(0.7, 0), InputError);
}

// The fit advances each training spall to its horizon in one call; a flight advances it epoch by epoch. The jam
// instant does not depend on the step, so the two give the same mean jam time bit for bit (here on 40 histories,
// at the campaigns' growth speed and at a slow one, 90 s per step, where a history spans ~2,000 epochs).
TEST(RulCalibrationTest, TrainingJamsAreTheFlightsEpochByEpochJams) {
  constexpr int kHistories = 40;
  for (const double truth_s : {kCampaignTruthTimePerGrowthStep_s, 90.0}) {
    SpallGrowthParams params;
    params.time_per_growth_step_s = truth_s;
    const MotorRulModel truth(params);
    const std::uint64_t training_seed = DeriveSeed(kRulTrainingSeed, kRulTrainingStream);
    double jam_sum_s = 0.0;
    int jammed = 0;
    for (int h = 0; h < kHistories; ++h) {
      // The simulator's truth stream of a history (sub-stream 3 of its seed, as sim/flight_internal.h draws it).
      SpallJamEvent spall(truth, 0.0, DeriveSeed(DeriveSeed(training_seed, static_cast<std::uint64_t>(h)), 3));
      const double horizon_s = params.max_growth_steps * truth_s;
      while (!spall.jammed() && spall.time_s() < horizon_s) spall.Advance(kCmaEpoch_s);
      if (spall.jammed()) {
        jam_sum_s += spall.jam_time_s();
        ++jammed;
      }
    }
    ASSERT_GT(jammed, 0);
    EXPECT_EQ(FitRulTimeScale(truth_s, kHistories).mean_jam_time_s, jam_sum_s / jammed) << truth_s;
  }
}

// The distribution the vehicle-level policies read, scored on fresh histories (seeds the fit never drew): its 90 %
// interval covers 85-95 % of the simulated jams at every epoch before them. Expected near the 0.882 of 100 particles'
// type-7 quantiles (test above); the bounds are the requirement's.
TEST(RulCalibrationTest, TheFittedSurvivalConditionedRulCoversFreshJams) {
  for (const std::uint64_t seed : {101u, 202u}) {
    RulCalibrationOptions options;
    options.seed = seed;
    options.prognosis_time_per_growth_step_s =
        VehicleRulTimeScale(options.truth_time_per_growth_step_s).time_per_growth_step_s;
    options.mode = RulPredictionMode::kSurvivalConditioned;
    const RulCalibration calibration = CalibrateRul(options);
    const double coverage = CalcIntervalCoverage(calibration.predictions, 0.9).fraction;
    EXPECT_GE(coverage, 0.85) << seed;
    EXPECT_LE(coverage, 0.95) << seed;
  }
}

}  // namespace
}  // namespace uascma::prognostics
