#include <cmath>

#include <gtest/gtest.h>

#include "uascma/common/error.h"
#include "uascma/models/wind.h"

namespace uascma::models {
namespace {

constexpr double kFeet = 0.3048;

// dryden.md check values at h = 100 ft: L_u = 505.169 ft, σ_u/σ_w = 1.715849 (6 significant digits).
TEST(DrydenTest, LowAltitudeMatchesTheSpecCheckValues) {
  const DrydenIntensity in = CalcDrydenIntensity(TurbulenceCategory::kLowLight, 100.0 * kFeet, 1500.0 * kFeet);
  EXPECT_NEAR(in.length_u / kFeet, 505.169, 1e-3);
  EXPECT_NEAR(in.length_v / kFeet, 505.169, 1e-3);
  EXPECT_NEAR(in.length_w / kFeet, 100.0, 1e-9);
  EXPECT_NEAR(in.sigma_u / in.sigma_w, 1.715849, 1e-6);
  // σ_w = 0.1 W20, W20 = 15 kt (light) and 30 kt (moderate).
  EXPECT_NEAR(in.sigma_w, 0.1 * 15.0 * 1852.0 / 3600.0, 1e-12);
  const DrydenIntensity moderate =
      CalcDrydenIntensity(TurbulenceCategory::kLowModerate, 100.0 * kFeet, 1500.0 * kFeet);
  EXPECT_NEAR(moderate.sigma_w, 2.0 * in.sigma_w, 1e-12);
}

TEST(DrydenTest, MediumBandInterpolatesTowardsIsotropic) {
  const DrydenIntensity at_top = CalcDrydenIntensity(TurbulenceCategory::kMediumLight, 0.0, 1000.0 * kFeet);
  const DrydenIntensity at_bottom = CalcDrydenIntensity(TurbulenceCategory::kMediumLight, 0.0, 2000.0 * kFeet);
  // At 1000 ft the low model is already isotropic in σ (0.177 + 0.823 = 1) and L = 1000 ft.
  EXPECT_NEAR(at_top.sigma_u, at_top.sigma_w, 1e-12);
  EXPECT_NEAR(at_top.length_u / kFeet, 1000.0, 1e-9);
  EXPECT_NEAR(at_bottom.length_u / kFeet, 1750.0, 1e-9);
  EXPECT_NEAR(at_bottom.length_w / kFeet, 1750.0, 1e-9);
}

// Long runs: the sample standard deviation of each gust axis matches σ within 5 % (dryden.md).
// V = 20 m/s keeps the correlation times short (L_u/V ≈ 8 s) so 20,000 s hold ~2,500 independent
// samples (expected relative error of the σ estimate ≈ 1.5 %).
class DrydenVarianceTest : public ::testing::TestWithParam<TurbulenceCategory> {};

TEST_P(DrydenVarianceTest, SampleRmsMatchesSigma) {
  constexpr double kAltitude = 30.0;  // m
  constexpr double kAirspeed = 20.0;  // m/s
  constexpr double kDt = 0.005;       // s, the GNC step
  constexpr int kSteps = 4'000'000;   // 20,000 s
  WindParams params;
  params.turbulence = GetParam();
  params.mean_speed = 2.0;
  params.direction_rad = 0.7;
  const WindModel model(params);
  RandomStream random(11);
  WindState state = model.InitialState(kAltitude, random);
  const Eigen::Vector3d axis_u(std::cos(0.7), std::sin(0.7), 0.0);
  const Eigen::Vector3d axis_v(-std::sin(0.7), std::cos(0.7), 0.0);
  double sum_u = 0, sum_uu = 0, sum_v = 0, sum_vv = 0, sum_w = 0, sum_ww = 0;
  for (int k = 0; k < kSteps; ++k) {
    const Eigen::Vector3d gust = model.Step(state, kAltitude, kAirspeed, kDt, random) - model.MeanWind_W();
    const double u = gust.dot(axis_u), v = gust.dot(axis_v), w = gust.z();
    sum_u += u; sum_uu += u * u; sum_v += v; sum_vv += v * v; sum_w += w; sum_ww += w * w;
  }
  auto stddev = [](double sum, double sum_sq) {
    const double mean = sum / kSteps;
    return std::sqrt(sum_sq / kSteps - mean * mean);
  };
  const DrydenIntensity in = CalcDrydenIntensity(GetParam(), kAltitude, params.medium_band_altitude);
  constexpr double kRelativeTolerance = 0.05;
  EXPECT_NEAR(stddev(sum_u, sum_uu) / in.sigma_u, 1.0, kRelativeTolerance);
  EXPECT_NEAR(stddev(sum_v, sum_vv) / in.sigma_v, 1.0, kRelativeTolerance);
  EXPECT_NEAR(stddev(sum_w, sum_ww) / in.sigma_w, 1.0, kRelativeTolerance);
}

INSTANTIATE_TEST_SUITE_P(Categories, DrydenVarianceTest,
                         ::testing::Values(TurbulenceCategory::kLowLight, TurbulenceCategory::kLowModerate,
                                           TurbulenceCategory::kMediumLight,
                                           TurbulenceCategory::kMediumModerate));

TEST(WindModelTest, MeanWindBlowsTowardsItsDirectionAndCalmHasNoGust) {
  WindParams params;
  params.mean_speed = 3.0;
  params.direction_rad = std::acos(-1.0) / 2.0;  // towards East
  const WindModel model(params);
  RandomStream random(1);
  WindState state;
  const Eigen::Vector3d wind = model.Step(state, 20.0, 5.0, 0.005, random);
  EXPECT_NEAR(wind.x(), 0.0, 1e-12);
  EXPECT_NEAR(wind.y(), 3.0, 1e-12);
  EXPECT_NEAR(wind.z(), 0.0, 1e-12);
}

TEST(WindModelTest, SameSeedSameGusts) {
  WindParams params;
  params.turbulence = TurbulenceCategory::kLowModerate;
  const WindModel model(params);
  RandomStream a(5), b(5);
  WindState sa, sb;
  for (int k = 0; k < 1000; ++k) {
    const Eigen::Vector3d wa = model.Step(sa, 25.0, 6.0, 0.005, a);
    const Eigen::Vector3d wb = model.Step(sb, 25.0, 6.0, 0.005, b);
    ASSERT_EQ(wa, wb);  // bit-identical by construction
  }
}

TEST(WindModelTest, ParsesCategoriesAndRejectsUnknown) {
  EXPECT_EQ(ParseTurbulenceCategory("medium-moderate", "s.yaml"), TurbulenceCategory::kMediumModerate);
  EXPECT_THROW(ParseTurbulenceCategory("stormy", "s.yaml"), InputError);
  WindParams bad;
  bad.mean_speed = -1.0;
  EXPECT_THROW(WindModel{bad}, InputError);
}

}  // namespace
}  // namespace uascma::models
