// common/lane_math.h: the four-lane forms equal the scalar functions bit for bit on every path the CPU has, and the
// scalar functions keep the error bounds stated in the header, in ulp of the exact value (a long-double reference:
// x86-64's 64-bit significand, 11 bits finer than a double's), over dense grids and the edge cases.
#include "uascma/common/lane_math.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <iostream>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "uascma/common/lane_math_kernels.h"
#include "uascma/common/random.h"

namespace uascma::lane_math {
namespace {

// The bounds stated in lane_math.h (ulp of the exact value).
constexpr double kAsinBoundUlp = 1.0;
constexpr double kAtanBoundUlp = 1.5;
constexpr double kAtan2BoundUlp = 2.0;
constexpr double kCosBoundUlp = 2.0;
constexpr double kCosQuarterTurnBoundUlp = 1.0;  // |x| ≤ π/4, where no reduction is made
constexpr double kExpBoundUlp = 1.0;
constexpr double kExpm1BoundUlp = 1.5;

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

std::uint64_t BitsOf(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof(b));
  return b;
}
double FromBitsOf(std::uint64_t b) {
  double x;
  std::memcpy(&x, &b, sizeof(x));
  return x;
}

// The paths to check: SSE2 always, AVX2 where the CPU has it.
std::vector<LaneMathPath> Paths() {
  std::vector<LaneMathPath> paths{LaneMathPath::kSse2};
  if (LaneMathPathSupported(LaneMathPath::kAvx2)) {
    paths.push_back(LaneMathPath::kAvx2);
  } else {
    std::cout << "note: this CPU has no AVX2; only the SSE2 path is checked\n";
  }
  return paths;
}

// Arguments for the bit-equality checks: each function's domain densely, its edges, and raw random bit patterns
// (every finite, infinite and NaN double alike).
std::vector<double> Arguments(RandomStream& random, double low, double high) {
  std::vector<double> x;
  for (int i = 0; i < 20000; ++i) x.push_back(random.Uniform(low, high));
  for (int i = 0; i < 4000; ++i)
    x.push_back(std::ldexp(random.Uniform(-1.0, 1.0), static_cast<int>(random.UniformIndex(120)) - 100));
  for (int i = 0; i < 4000; ++i) x.push_back(FromBitsOf(random.Next()));
  for (double edge : {0.0, -0.0, 0.5, -0.5, 1.0, -1.0, 2.0, 1e-310, -1e-310, 700.0, -700.0, 709.8, -745.5, -40.0, 1e6,
                      -1e6, kInfinity, -kInfinity, kNan}) {
    for (double sign : {1.0, -1.0}) x.push_back(sign * edge);
    x.push_back(std::nextafter(edge, kInfinity));
    x.push_back(std::nextafter(edge, -kInfinity));
  }
  while (x.size() % 4 != 0) x.push_back(0.0);
  return x;
}

void ExpectLanesEqualScalar(const std::string& name, const std::vector<double>& x,
                            const std::function<Lanes4(LaneMathPath, const Lanes4&)>& lanes,
                            const std::function<double(double)>& scalar) {
  for (LaneMathPath path : Paths()) {
    int mismatches = 0;
    for (std::size_t i = 0; i < x.size(); i += 4) {
      const Lanes4 in{x[i], x[i + 1], x[i + 2], x[i + 3]};
      const Lanes4 out = lanes(path, in);
      for (int lane = 0; lane < 4; ++lane) {
        if (BitsOf(out[lane]) != BitsOf(scalar(in[lane])) && ++mismatches <= 3) {
          ADD_FAILURE() << name << " on " << LaneMathPathName(path) << ", lane " << lane << ": x = " << in[lane]
                        << " gives " << out[lane] << ", the scalar " << scalar(in[lane]);
        }
      }
    }
    EXPECT_EQ(mismatches, 0) << name << " on " << LaneMathPathName(path);
  }
}

TEST(LaneMathTest, EveryPathGivesTheScalarBitsOfEachLane) {
  RandomStream random(27);
  ExpectLanesEqualScalar("asin", Arguments(random, -1.0, 1.0), Asin4, [](double s) { return Asin(s); });
  ExpectLanesEqualScalar("atan", Arguments(random, -50.0, 50.0), Atan4, [](double x) { return Atan(x); });
  ExpectLanesEqualScalar("cos", Arguments(random, -10.0, 10.0), Cos4, [](double x) { return Cos(x); });
  ExpectLanesEqualScalar("exp", Arguments(random, -750.0, 720.0), Exp4, [](double x) { return Exp(x); });
  ExpectLanesEqualScalar("expm1", Arguments(random, -50.0, 720.0), Expm1_4, [](double x) { return Expm1(x); });
}

TEST(LaneMathTest, EveryPathGivesTheScalarBitsOfAtan2InEachLane) {
  RandomStream random(28);
  const std::vector<double> y = Arguments(random, -1.0, 1.0);
  std::vector<double> x = Arguments(random, -1.0, 1.0);
  std::reverse(x.begin(), x.end());  // the edge cases meet one another and random values
  x.resize(y.size(), 0.0);
  for (LaneMathPath path : Paths()) {
    int mismatches = 0;
    for (std::size_t i = 0; i < y.size(); i += 4) {
      const Lanes4 in_y{y[i], y[i + 1], y[i + 2], y[i + 3]};
      const Lanes4 in_x{x[i], x[i + 1], x[i + 2], x[i + 3]};
      const Lanes4 out = Atan2_4(path, in_y, in_x);
      for (int lane = 0; lane < 4; ++lane) {
        if (BitsOf(out[lane]) != BitsOf(Atan2(in_y[lane], in_x[lane])) && ++mismatches <= 3) {
          ADD_FAILURE() << "atan2 on " << LaneMathPathName(path) << ": (" << in_y[lane] << ", " << in_x[lane] << ")";
        }
      }
    }
    EXPECT_EQ(mismatches, 0) << "atan2 on " << LaneMathPathName(path);
  }
}

TEST(LaneMathTest, SimdPathIsChosenFromTheEnvironmentValue) {
  EXPECT_EQ(ChooseLaneMathPath("sse2"), LaneMathPath::kSse2);
  EXPECT_EQ(ChooseLaneMathPath("scalar"), LaneMathPath::kSse2);
  const LaneMathPath widest = LaneMathPathSupported(LaneMathPath::kAvx2) ? LaneMathPath::kAvx2 : LaneMathPath::kSse2;
  EXPECT_EQ(ChooseLaneMathPath(nullptr), widest);
  EXPECT_EQ(ChooseLaneMathPath("avx512"), widest);
}

// |value − exact| in units in the last place of the exact value's double neighbourhood (2^(e − 53) for
// exact = m 2^e, m ∈ [1/2, 1); 2^−1074 for subnormal results).
double UlpError(double value, long double exact) {
  int exponent = 0;
  std::frexp(static_cast<double>(exact), &exponent);
  const long double ulp = std::ldexp(1.0L, std::max(exponent - 53, -1074));
  return static_cast<double>(std::fabs(static_cast<long double>(value) - exact) / ulp);
}

struct Worst {
  double ulp = 0.0;
  double at = 0.0;
  void Take(double error, double x) {
    if (error > ulp) {
      ulp = error;
      at = x;
    }
  }
};

Worst WorstOver(const std::vector<double>& x, const std::function<double(double)>& f,
                const std::function<long double(long double)>& exact) {
  Worst worst;
  for (double v : x) worst.Take(UlpError(f(v), exact(v)), v);
  return worst;
}

std::vector<double> Grid(double low, double high, int count) {
  std::vector<double> x;
  for (int k = 0; k <= count; ++k) x.push_back(low + (high - low) * k / count);
  return x;
}

// ±x for x = 10^(−300 … 300) on a logarithmic grid, and the neighbours (±8 ulp) of each of `points`.
std::vector<double> Scales(const std::vector<double>& points) {
  std::vector<double> x;
  for (int k = -30000; k <= 30000; ++k) {
    x.push_back(std::pow(10.0, k / 100.0));
    x.push_back(-std::pow(10.0, k / 100.0));
  }
  for (double p : points) {
    double up = p, down = p;
    for (int k = 0; k < 8; ++k) {
      x.push_back(up = std::nextafter(up, kInfinity));
      x.push_back(down = std::nextafter(down, -kInfinity));
    }
  }
  return x;
}

TEST(LaneMathTest, AsinIsWithinItsBound) {
  std::vector<double> s = Grid(-1.0, 1.0, 2000000);
  for (double x : Scales({0.5, -0.5, 1.0, -1.0, 0.975, 0.0})) {
    if (std::abs(x) <= 1.0) s.push_back(x);
  }
  const Worst worst = WorstOver(s, Asin, [](long double v) { return std::asin(v); });
  std::cout << "asin: worst " << worst.ulp << " ulp at " << worst.at << "\n";
  EXPECT_LT(worst.ulp, kAsinBoundUlp);
  EXPECT_EQ(Asin(1.0), std::numbers::pi / 2);
  EXPECT_EQ(Asin(-1.0), -std::numbers::pi / 2);
  EXPECT_TRUE(std::signbit(Asin(-0.0)) && Asin(-0.0) == 0.0);
  EXPECT_TRUE(!std::signbit(Asin(0.0)) && Asin(0.0) == 0.0);
  EXPECT_TRUE(std::isnan(Asin(std::nextafter(1.0, 2.0))));
  EXPECT_TRUE(std::isnan(Asin(-kInfinity)));
  EXPECT_TRUE(std::isnan(Asin(kNan)));
}

TEST(LaneMathTest, AtanIsWithinItsBound) {
  std::vector<double> x = Grid(-4.0, 4.0, 2000000);
  const std::vector<double> scales = Scales({0.5, -0.5, 1.0, -1.0, 2.0, -2.0});  // the reduction's breakpoints
  x.insert(x.end(), scales.begin(), scales.end());
  const Worst worst = WorstOver(x, Atan, [](long double v) { return std::atan(v); });
  std::cout << "atan: worst " << worst.ulp << " ulp at " << worst.at << "\n";
  EXPECT_LT(worst.ulp, kAtanBoundUlp);
  EXPECT_EQ(Atan(kInfinity), std::atan(kInfinity));
  EXPECT_EQ(Atan(-kInfinity), std::atan(-kInfinity));
  EXPECT_TRUE(std::signbit(Atan(-0.0)) && Atan(-0.0) == 0.0);
  EXPECT_TRUE(std::isnan(Atan(kNan)));
}

TEST(LaneMathTest, Atan2IsWithinItsBoundAllAroundTheCircleAndAcrossScales) {
  Worst worst;
  RandomStream random(29);
  for (int k = 0; k <= 400000; ++k) {
    // An angle on a grid around the circle, its direction rounded to doubles; a radius from 1e-300 to 1e300.
    const double angle = -std::numbers::pi + 2.0 * std::numbers::pi * k / 400000.0;
    const double radius = std::pow(10.0, random.Uniform(-300.0, 300.0));
    for (double r : {1.0, radius}) {
      const double y = r * std::sin(angle), x = r * std::cos(angle);
      worst.Take(UlpError(Atan2(y, x), std::atan2(static_cast<long double>(y), static_cast<long double>(x))), angle);
    }
  }
  std::cout << "atan2: worst " << worst.ulp << " ulp at angle " << worst.at << "\n";
  EXPECT_LT(worst.ulp, kAtan2BoundUlp);
}

TEST(LaneMathTest, Atan2KeepsTheSignedZerosAxesAndInfinitiesOfLibm) {
  for (double y : {0.0, -0.0, 1.0, -1.0, 3e-300, kInfinity, -kInfinity}) {
    for (double x : {0.0, -0.0, 1.0, -1.0, 5e300, kInfinity, -kInfinity}) {
      if (std::isinf(x) && std::isinf(y)) {
        EXPECT_TRUE(std::isnan(Atan2(y, x))) << y << ", " << x;  // stated in lane_math.h
        continue;
      }
      const double libm = std::atan2(y, x);
      EXPECT_LT(UlpError(Atan2(y, x), std::atan2(static_cast<long double>(y), static_cast<long double>(x))),
                kAtan2BoundUlp)
          << y << ", " << x;
      EXPECT_EQ(std::signbit(Atan2(y, x)), std::signbit(libm)) << y << ", " << x;
    }
  }
  EXPECT_TRUE(std::isnan(Atan2(kNan, 1.0)));
  EXPECT_TRUE(std::isnan(Atan2(1.0, kNan)));
}

TEST(LaneMathTest, CosIsWithinItsBound) {
  const Worst quarter = WorstOver(Grid(-std::numbers::pi / 4, std::numbers::pi / 4, 2000000), Cos,
                                  [](long double v) { return std::cos(v); });
  std::cout << "cos, |x| <= pi/4: worst " << quarter.ulp << " ulp at " << quarter.at << "\n";
  EXPECT_LT(quarter.ulp, kCosQuarterTurnBoundUlp);
  std::vector<double> x = Grid(-std::numbers::pi / 2, std::numbers::pi / 2, 2000000);  // the step's tilts
  const std::vector<double> wide = Grid(-1000.0, 1000.0, 2000000);
  x.insert(x.end(), wide.begin(), wide.end());
  std::vector<double> near_zeros;  // the doubles next to (2k + 1) π/2, k < 1000, where cos is smallest
  for (int k = 0; k < 1000; ++k) near_zeros.push_back((2 * k + 1) * (std::numbers::pi / 2));
  const std::vector<double> scales = Scales(near_zeros);
  for (double v : scales) {
    if (std::abs(v) <= 1e6) x.push_back(v);
  }
  const Worst worst = WorstOver(x, Cos, [](long double v) { return std::cos(v); });
  std::cout << "cos: worst " << worst.ulp << " ulp at " << worst.at << "\n";
  EXPECT_LT(worst.ulp, kCosBoundUlp);
  EXPECT_EQ(Cos(0.0), 1.0);
  EXPECT_EQ(Cos(-0.0), 1.0);
  EXPECT_TRUE(std::isnan(Cos(1.0001e6)));
  EXPECT_TRUE(std::isnan(Cos(kInfinity)));
  EXPECT_TRUE(std::isnan(Cos(kNan)));
}

TEST(LaneMathTest, ExpIsWithinItsBound) {
  std::vector<double> x = Grid(-745.0, 709.78, 2000000);
  const std::vector<double> small = Grid(-1.0, 1.0, 1000000);
  x.insert(x.end(), small.begin(), small.end());
  for (double v : Scales({0.0, 700.0, -700.0, 709.78, -708.0, -745.0})) {
    if (v >= -745.0 && v <= 709.78) x.push_back(v);
  }
  const Worst worst = WorstOver(x, Exp, [](long double v) { return std::exp(v); });
  std::cout << "exp: worst " << worst.ulp << " ulp at " << worst.at << "\n";
  EXPECT_LT(worst.ulp, kExpBoundUlp);
  EXPECT_EQ(Exp(0.0), 1.0);
  EXPECT_EQ(Exp(-0.0), 1.0);
  EXPECT_EQ(Exp(709.79), kInfinity);
  EXPECT_EQ(Exp(kInfinity), kInfinity);
  EXPECT_EQ(Exp(-745.2), 0.0);
  EXPECT_EQ(Exp(-kInfinity), 0.0);
  EXPECT_TRUE(std::isnan(Exp(kNan)));
}

TEST(LaneMathTest, Expm1IsWithinItsBound) {
  std::vector<double> x = Grid(-45.0, 709.78, 2000000);
  const std::vector<double> small = Grid(-1.0, 1.0, 1000000);
  x.insert(x.end(), small.begin(), small.end());
  for (double v : Scales({0.0, 0.34657359027997264, -0.34657359027997264, 700.0, 709.78, -40.0})) {
    if (v >= -45.0 && v <= 709.78) x.push_back(v);
  }
  const Worst worst = WorstOver(x, Expm1, [](long double v) { return std::expm1(v); });
  std::cout << "expm1: worst " << worst.ulp << " ulp at " << worst.at << "\n";
  EXPECT_LT(worst.ulp, kExpm1BoundUlp);
  EXPECT_TRUE(std::signbit(Expm1(-0.0)) && Expm1(-0.0) == 0.0);
  EXPECT_TRUE(!std::signbit(Expm1(0.0)) && Expm1(0.0) == 0.0);
  EXPECT_EQ(Expm1(-40.0), -1.0);
  EXPECT_EQ(Expm1(-kInfinity), -1.0);
  EXPECT_EQ(Expm1(709.79), kInfinity);
  EXPECT_TRUE(std::isnan(Expm1(kNan)));
}

// Splat puts the constant's own bits in every lane: a −0 stays −0 (the lanes' constants from a table, such as a
// failed rotor's row of an allocation case, sim/controller_lanes.cc, must be the scalar code's operands).
TEST(LaneMathTest, SplatKeepsTheBitsOfItsConstantIncludingNegativeZero) {
  using lane_math_internal::Bits;
  using lane_math_internal::LaneMathV2;
  using lane_math_internal::LaneMathV4;
  using lane_math_internal::Splat;
  for (const double c : {-0.0, 0.0, -1.5, std::numeric_limits<double>::infinity(), 4.9e-324}) {
    const LaneMathV2 two = Splat<LaneMathV2>(c);
    const LaneMathV4 four = Splat<LaneMathV4>(c);
    for (int i = 0; i < 2; ++i) EXPECT_EQ(Bits(two[i]), Bits(c)) << c;
    for (int i = 0; i < 4; ++i) EXPECT_EQ(Bits(four[i]), Bits(c)) << c;
    EXPECT_EQ(Bits(Splat<double>(c)), Bits(c)) << c;
  }
}

}  // namespace
}  // namespace uascma::lane_math
