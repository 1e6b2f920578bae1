#include "uascma/common/fast_angles.h"

#include <cmath>
#include <limits>
#include <numbers>

#include <gtest/gtest.h>

namespace uascma {
namespace {

// The bounds stated in fast_angles.h, against libm (itself within an ulp of the exact value).
constexpr double kAtan2Bound = 4.5e-16;  // rad: 2 ulp of π
constexpr double kAtanBound = 2.3e-16;   // rad: 1 ulp of π/2
constexpr double kAsinBound = 4.5e-16;   // rad

TEST(FastAnglesTest, Atan2IsWithinItsBoundAllAroundTheCircleAndAcrossScales) {
  double worst = 0.0;
  for (int k = 0; k <= 200000; ++k) {
    const double angle = -std::numbers::pi + 2.0 * std::numbers::pi * k / 200000.0;
    for (double radius : {1e-300, 1e-8, 0.3, 1.0, 7.0, 1e8, 1e300}) {
      const double y = radius * std::sin(angle);
      const double x = radius * std::cos(angle);
      worst = std::max(worst, std::abs(FastAtan2(y, x) - std::atan2(y, x)));
    }
  }
  EXPECT_LE(worst, kAtan2Bound);
}

TEST(FastAnglesTest, Atan2KeepsTheSignedZerosAndAxesOfLibm) {
  for (double y : {0.0, -0.0, 1.0, -1.0}) {
    for (double x : {0.0, -0.0, 1.0, -1.0}) {
      const double fast = FastAtan2(y, x);
      const double exact = std::atan2(y, x);
      EXPECT_NEAR(fast, exact, kAtan2Bound) << y << ", " << x;
      EXPECT_EQ(std::signbit(fast), std::signbit(exact)) << y << ", " << x;
    }
  }
  EXPECT_TRUE(std::isnan(FastAtan2(std::numeric_limits<double>::quiet_NaN(), 1.0)));
}

TEST(FastAnglesTest, AtanAndAsinAreWithinTheirBounds) {
  double worst_atan = 0.0;
  double worst_asin = 0.0;
  for (int k = -200000; k <= 200000; ++k) {
    const double x = 50.0 * std::sinh(k / 20000.0) / std::sinh(10.0);  // dense near 0, out to ±50
    worst_atan = std::max(worst_atan, std::abs(FastAtan(x) - std::atan(x)));
    const double s = k / 200000.0;
    worst_asin = std::max(worst_asin, std::abs(FastAsin(s) - std::asin(s)));
  }
  EXPECT_LE(worst_atan, kAtanBound);
  EXPECT_LE(worst_asin, kAsinBound);
  EXPECT_NEAR(FastAtan(1e300), std::numbers::pi / 2, kAtanBound);
}

}  // namespace
}  // namespace uascma
