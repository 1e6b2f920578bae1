// Calibration metrics of probabilistic prognostics: hand-computed cases (interpolated CDF and quantile,
// exact interval coverage on a grid of truths, the Wilson interval, the PIT histogram, and the Saxena et al.
// PH, α-λ accuracy and RA of two hand-made units).
#include "uascma/prognostics/calibration.h"

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "uascma/common/error.h"

namespace uascma::prognostics {
namespace {

// Rounding only: every expected value below is an exact or a 6-digit hand computation.
constexpr double kTight = 1e-9;
constexpr double kHandComputed = 1e-5;
constexpr int kGridTruths = 1000;

// The uniform distribution on [0, 100] s (q(p) = 100 p) scaled about its median by `width`, at the standard levels.
std::vector<double> UniformQuantiles(double width) {
  std::vector<double> quantiles;
  for (double p : StandardQuantileLevels()) quantiles.push_back(50.0 + width * (100.0 * p - 50.0));
  return quantiles;
}

// kGridTruths predictions of the same distribution with truths at the grid (k + 0.5) / N · 100 s.
PredictionSet GridSet(double width) {
  PredictionSet set;
  set.levels = StandardQuantileLevels();
  for (int k = 0; k < kGridTruths; ++k) {
    set.predictions.push_back({k, 0.0, (k + 0.5) / kGridTruths * 100.0, UniformQuantiles(width)});
  }
  return set;
}

TEST(CalibrationTest, CdfAndQuantileInterpolateLinearlyBetweenLevels) {
  const std::vector<double> levels{0.25, 0.5, 0.75};
  const std::vector<double> quantiles{10.0, 20.0, 40.0};
  EXPECT_NEAR(PredictedCdf(levels, quantiles, 15.0), 0.375, kTight);
  EXPECT_NEAR(PredictedCdf(levels, quantiles, 30.0), 0.625, kTight);
  EXPECT_NEAR(PredictedCdf(levels, quantiles, 10.0), 0.25, kTight);
  EXPECT_EQ(PredictedCdf(levels, quantiles, 5.0), 0.0);
  EXPECT_EQ(PredictedCdf(levels, quantiles, 40.0), 1.0);
  EXPECT_NEAR(PredictedQuantile(levels, quantiles, 0.6), 28.0, kTight);
  EXPECT_NEAR(PredictedQuantile(levels, quantiles, 0.5), 20.0, kTight);
  EXPECT_THROW(PredictedQuantile(levels, quantiles, 0.9), InputError);
}

TEST(CalibrationTest, ACalibratedPredictorCoversEachCentralIntervalExactlyOnAGridOfTruths) {
  const PredictionSet set = GridSet(1.0);
  for (double level : StandardIntervalLevels()) {
    const IntervalCoverage coverage = CalcIntervalCoverage(set, level);
    EXPECT_EQ(coverage.predictions, kGridTruths);
    EXPECT_EQ(coverage.covered, static_cast<int>(level * kGridTruths + 0.5)) << level;
    EXPECT_EQ(coverage.below, coverage.above) << level;
    EXPECT_LE(coverage.wilson_low, coverage.fraction);
    EXPECT_GE(coverage.wilson_high, coverage.fraction);
  }
}

TEST(CalibrationTest, AnOverconfidentPredictorCoversLess) {
  // Half the width: the 90 % interval is [27.5, 72.5] s and holds 45 % of the grid.
  const IntervalCoverage coverage = CalcIntervalCoverage(GridSet(0.5), 0.90);
  EXPECT_EQ(coverage.covered, 450);
  EXPECT_EQ(coverage.below, 275);
  EXPECT_EQ(coverage.above, 275);
}

TEST(CalibrationTest, WilsonIntervalOfEightInTen) {
  // Hand: center (0.8 + z²/20)/(1 + z²/10) = 0.716739, half-width 0.226578.
  PredictionSet set;
  set.levels = {0.25, 0.75};
  for (int k = 0; k < 10; ++k) set.predictions.push_back({k, 0.0, k < 8 ? 5.0 : 50.0, {0.0, 10.0}});
  const IntervalCoverage coverage = CalcIntervalCoverage(set, 0.5);
  EXPECT_EQ(coverage.covered, 8);
  EXPECT_EQ(coverage.above, 2);
  EXPECT_NEAR(coverage.wilson_low, 0.490161, kHandComputed);
  EXPECT_NEAR(coverage.wilson_high, 0.943318, kHandComputed);
}

TEST(CalibrationTest, ReliabilityIsTheDiagonalAndThePitFlatWhenCalibrated) {
  const PredictionSet set = GridSet(1.0);
  for (const ReliabilityRow& row : CalcReliabilityTable(set, StandardReliabilityLevels())) {
    EXPECT_NEAR(row.observed, row.nominal, kTight);
  }
  for (int count : CalcPitHistogram(set, 10)) EXPECT_EQ(count, kGridTruths / 10);
  // Too narrow: the PIT piles up at both ends and the reliability is steeper than the diagonal.
  const std::vector<int> narrow = CalcPitHistogram(GridSet(0.5), 10);
  EXPECT_GT(narrow.front(), kGridTruths / 10);
  EXPECT_GT(narrow.back(), kGridTruths / 10);
  const std::vector<ReliabilityRow> rows = CalcReliabilityTable(GridSet(0.5), {0.05, 0.95});
  EXPECT_GT(rows[0].observed, 0.05);
  EXPECT_LT(rows[1].observed, 0.95);
}

QuantilePrediction Narrow(int unit, double time_s, double end_of_life_s, double predicted_s) {
  return {unit, time_s, end_of_life_s - time_s, {predicted_s - 1.0, predicted_s, predicted_s + 1.0}};
}

TEST(CalibrationTest, SaxenaMetricsOfTwoHandMadeUnits) {
  PredictionSet set;
  set.levels = {0.25, 0.5, 0.75};
  // Unit 0: EoL 100 s. PH band ±α·100 = ±20 s: first met at t = 40 (70 vs 60): PH = 60 s. t_λ = 50 → t = 60:
  // r* = 40, r̂ = 45, inside [32, 48]: met; RA = 1 − 5/40 = 0.875. Out of time order on purpose.
  set.predictions = {Narrow(0, 60.0, 100.0, 45.0), Narrow(0, 0.0, 100.0, 150.0), Narrow(0, 20.0, 100.0, 130.0),
                     Narrow(0, 40.0, 100.0, 70.0), Narrow(0, 80.0, 100.0, 20.0)};
  // Unit 1: EoL 50 s. Band ±10 s: met at t = 10 (40 vs 40): PH = 40 s. t_λ = 30: r* = 20, r̂ = 30, outside
  // [16, 24]: not met; RA = 1 − 10/20 = 0.5.
  set.predictions.push_back(Narrow(1, 10.0, 50.0, 40.0));
  set.predictions.push_back(Narrow(1, 30.0, 50.0, 30.0));
  const SaxenaMetrics metrics = CalcSaxenaMetrics(set);
  ASSERT_EQ(metrics.units, 2);
  EXPECT_NEAR(metrics.per_unit[0].prognostic_horizon_s, 60.0, kTight);
  EXPECT_TRUE(metrics.per_unit[0].alpha_lambda_met);
  EXPECT_NEAR(metrics.per_unit[0].relative_accuracy, 0.875, kTight);
  EXPECT_NEAR(metrics.per_unit[0].lambda_time_s, 60.0, kTight);
  EXPECT_NEAR(metrics.per_unit[1].prognostic_horizon_s, 40.0, kTight);
  EXPECT_FALSE(metrics.per_unit[1].alpha_lambda_met);
  EXPECT_NEAR(metrics.per_unit[1].relative_accuracy, 0.5, kTight);
  EXPECT_NEAR(metrics.mean_prognostic_horizon_s, 50.0, kTight);
  EXPECT_NEAR(metrics.alpha_lambda_fraction, 0.5, kTight);
  EXPECT_NEAR(metrics.mean_relative_accuracy, 0.6875, kTight);
}

TEST(CalibrationTest, AlphaLambdaCountsTheMassInsideTheCone) {
  // r* = 50 s at t_λ; the cone [40, 60] s holds part of a prediction with quantiles {40, 50, 80} at {0.25, 0.5,
  // 0.75}: CDF(60) − CDF(40) = (0.5 + 0.25·10/30) − 0.25 = 1/3 < β = 0.5; with β = 0.3 it is met.
  PredictionSet set;
  set.levels = {0.25, 0.5, 0.75};
  set.predictions = {{0, 0.0, 50.0, {40.0, 50.0, 80.0}}};
  SaxenaOptions options;
  options.lambda = 0.0;
  EXPECT_FALSE(CalcSaxenaMetrics(set, options).per_unit[0].alpha_lambda_met);
  options.beta = 0.3;
  EXPECT_TRUE(CalcSaxenaMetrics(set, options).per_unit[0].alpha_lambda_met);
}

TEST(CalibrationTest, InvalidSetsAreRefusedNamingTheProblem) {
  PredictionSet set;
  set.levels = {0.5, 0.25};
  std::string error;
  EXPECT_FALSE(set.IsValid(&error));
  EXPECT_NE(error.find("increasing"), std::string::npos);
  set.levels = {0.25, 0.75};
  set.predictions = {{0, 0.0, 5.0, {10.0, 1.0}}};
  EXPECT_FALSE(set.IsValid(&error));
  EXPECT_NE(error.find("predictions[0]"), std::string::npos);
  EXPECT_THROW(CalcIntervalCoverage(set, 0.5), InputError);
  set.predictions = {{0, 0.0, -1.0, {1.0, 10.0}}};
  EXPECT_THROW(CalcPitHistogram(set, 10), InputError);
  SaxenaOptions options;
  options.alpha = 0.0;
  EXPECT_FALSE(options.IsValid(&error));
}

}  // namespace
}  // namespace uascma::prognostics
