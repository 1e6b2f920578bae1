// Least Absolute Residuals (identification/least_absolute.h): closed forms and robustness against outliers.
#include <random>

#include <gtest/gtest.h>

#include "uascma/identification/least_absolute.h"

namespace uascma::identification {
namespace {

// A surface of eq. 2.12's form (cubic in x, quadratic in y) sampled on a grid, with noise of 20 RPM and a few gross
// outliers (a dropped RPM reading, a doubled one): LAR recovers the coefficients, least squares is pulled away.
TEST(LeastAbsoluteTest, BeatsLeastSquaresOnASurfaceWithOutliers) {
  const Eigen::VectorXd truth = (Eigen::VectorXd(9) << 12390, -803.8, 4125, 979.3, -2757, 334.4, 450, -17.38, 69.46).finished();
  std::mt19937_64 generator(44);
  std::normal_distribution<double> noise(0.0, 20.0);
  Eigen::MatrixXd design(60, 9);
  Eigen::VectorXd rpm(60);
  for (int k = 0; k < 60; ++k) {
    const double x = -1.5 + 3.0 * (k % 10) / 9.0, y = -1.0 + 2.0 * (k / 10) / 5.0;
    design.row(k) << 1, x, y, x * x, x * y, y * y, x * x * x, x * x * y, x * y * y;
    rpm[k] = design.row(k).dot(truth) + noise(generator);
  }
  for (int k : {3, 17, 31, 44, 58}) rpm[k] = (k % 2 == 0) ? 0.0 : 2.0 * rpm[k];  // five gross outliers
  const LarResult lar = FitLeastAbsoluteResiduals(design, rpm);
  ASSERT_EQ(lar.status, LarStatus::kConverged) << lar.BriefReport();
  const Eigen::VectorXd least_squares = FitLeastSquares(design, rpm);
  // Error of the fitted surface at the clean points, RPM.
  Eigen::VectorXd clean = design * truth;
  const double lar_error = (design * lar.coefficients - clean).cwiseAbs().maxCoeff();
  const double least_squares_error = (design * least_squares - clean).cwiseAbs().maxCoeff();
  constexpr double kLarToleranceRpm = 100.0;  // five times the noise's standard deviation
  EXPECT_LT(lar_error, kLarToleranceRpm);
  EXPECT_GT(least_squares_error, 5.0 * lar_error);
  EXPECT_LE(lar.absolute_residual_sum, lar.least_squares_absolute_sum);
}

// With as many points as coefficients, both fits interpolate: Σ|r| is zero.
TEST(LeastAbsoluteTest, InterpolatesWhenSquare) {
  Eigen::MatrixXd design(3, 3);
  design << 1, 0, 0, 1, 1, 1, 1, 2, 4;
  const Eigen::VectorXd values = (Eigen::VectorXd(3) << 1, 3, 9).finished();
  const LarResult lar = FitLeastAbsoluteResiduals(design, values);
  constexpr double kTolerance = 1e-9;
  EXPECT_NEAR(lar.absolute_residual_sum, 0.0, kTolerance);
  EXPECT_NEAR(lar.coefficients[2], 2.0, kTolerance);
}

TEST(LeastAbsoluteTest, ReportsARankDeficientDesign) {
  Eigen::MatrixXd design(4, 2);
  design << 1, 2, 1, 2, 1, 2, 1, 2;
  const LarResult lar = FitLeastAbsoluteResiduals(design, Eigen::VectorXd::Ones(4));
  EXPECT_EQ(lar.status, LarStatus::kRankDeficient);
}

// The weighted median minimises Σ w |v − c|: checked against a scan of c.
TEST(LeastAbsoluteTest, WeightedMedianMinimisesTheWeightedAbsoluteSum) {
  const Eigen::VectorXd values = (Eigen::VectorXd(5) << 3.0, -1.0, 7.0, 2.0, 10.0).finished();
  const Eigen::VectorXd weights = (Eigen::VectorXd(5) << 1.0, 4.0, 2.0, 0.5, 3.0).finished();
  const double median = WeightedMedian(values, weights);
  auto cost = [&](double c) { return (weights.array() * (values.array() - c).abs()).sum(); };
  for (double c = -2.0; c <= 11.0; c += 0.01) EXPECT_LE(cost(median), cost(c) + 1e-12);
  EXPECT_DOUBLE_EQ(median, 3.0);  // cumulative weights 4, 4.5, 5.5 of 10.5: half reached at 3
}

}  // namespace
}  // namespace uascma::identification
