#include "uascma/common/decay.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace uascma {
namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();

// The series branch against libm over the whole range where it is used, and the libm branch beyond.
TEST(ExpDecayTest, MatchesLibmToTheLastBitsOnBothSidesOfTheSeriesLimit) {
  for (double x = 1e-12; x < 8.0; x *= 1.07) {
    const ExpDecay d = CalcExpDecay(x);
    EXPECT_NEAR(d.factor, std::exp(-x), 2.0 * kEpsilon * std::exp(-x)) << "x = " << x;
    // The complement against expm1, relative: 2 ulp.
    EXPECT_NEAR(d.complement, -std::expm1(-x), 2.0 * kEpsilon * -std::expm1(-x)) << "x = " << x;
  }
}

TEST(ExpDecayTest, ComplementKeepsItsDigitsWhereTheDifferenceLosesThem) {
  const double x = 1e-10;
  // 1 − e^{−x} ≈ x − x²/2: a plain difference keeps only ~6 significant digits here.
  EXPECT_NEAR(CalcExpDecay(x).complement, x - 0.5 * x * x, 1e-26);
  EXPECT_GT(std::abs((1.0 - std::exp(-x)) - (x - 0.5 * x * x)), 1e-18);
}

TEST(ExpDecayTest, ZeroAndTheLimitItself) {
  EXPECT_EQ(CalcExpDecay(0.0).factor, 1.0);
  EXPECT_EQ(CalcExpDecay(0.0).complement, 0.0);
  const ExpDecay at_limit = CalcExpDecay(kExpDecaySeriesLimit);  // the libm branch
  EXPECT_EQ(at_limit.factor, std::exp(-kExpDecaySeriesLimit));
}

}  // namespace
}  // namespace uascma
