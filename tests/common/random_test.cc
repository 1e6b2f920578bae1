#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "uascma/common/random.h"

namespace uascma {
namespace {

double NormalCdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

// One million ziggurat normals against N(0, 1): moments and the CDF at several points, including the tail
// beyond r = 3.654 that the ziggurat samples separately. Tolerances are ~5 standard errors.
TEST(RandomStreamTest, ZigguratNormalsFollowTheStandardNormal) {
  constexpr int kSamples = 1'000'000;
  RandomStream random(2024);
  const std::vector<double> points = {-4.0, -3.654, -2.0, -1.0, -0.3, 0.0, 0.5, 1.5, 3.0, 3.8};
  std::vector<int> below(points.size(), 0);
  double sum = 0, sum_sq = 0, sum_4 = 0;
  for (int k = 0; k < kSamples; ++k) {
    const double x = random.Normal();
    sum += x;
    sum_sq += x * x;
    sum_4 += x * x * x * x;
    for (std::size_t p = 0; p < points.size(); ++p) below[p] += x < points[p] ? 1 : 0;
  }
  EXPECT_NEAR(sum / kSamples, 0.0, 5.0 / std::sqrt(kSamples));
  EXPECT_NEAR(sum_sq / kSamples, 1.0, 5.0 * std::sqrt(2.0 / kSamples));
  EXPECT_NEAR(sum_4 / kSamples, 3.0, 5.0 * std::sqrt(96.0 / kSamples));  // kurtosis of N(0,1)
  for (std::size_t p = 0; p < points.size(); ++p) {
    const double expected = NormalCdf(points[p]);
    const double standard_error = std::sqrt(expected * (1 - expected) / kSamples);
    EXPECT_NEAR(static_cast<double>(below[p]) / kSamples, expected, 5.0 * standard_error + 1e-7)
        << "at x = " << points[p];
  }
}

TEST(RandomStreamTest, SeedsReplayAndDerivedStreamsDiffer) {
  RandomStream a(7), b(7), c(DeriveSeed(7, 1));
  for (int k = 0; k < 1000; ++k) {
    const double x = a.Normal();
    ASSERT_EQ(x, b.Normal());  // bit-identical
    (void)c;
  }
  EXPECT_NE(RandomStream(DeriveSeed(7, 1)).Next(), RandomStream(DeriveSeed(7, 2)).Next());
  RandomStream u(3);
  for (int k = 0; k < 10000; ++k) {
    const double x = u.Uniform();
    ASSERT_GE(x, 0.0);
    ASSERT_LT(x, 1.0);
    ASSERT_LT(u.UniformIndex(7), 7u);
  }
}

// Normal()'s common path inline and the rest out of line draw what the single loop drew, bit for bit and
// word for word: the loop as it was, on a copy of the stream, over a million draws that take every path.
TEST(RandomStreamTest, ZigguratSplitDrawsAsTheSingleLoop) {
  const internal::Ziggurat& z = internal::TheZiggurat();
  int wedges = 0, tails = 0;
  auto single_loop = [&](RandomStream& r) {
    while (true) {
      const std::uint64_t bits = r.Next();
      const int layer = static_cast<int>(bits & 0xff);
      const double u = 2.0 * (static_cast<double>(static_cast<std::int64_t>(bits >> 11)) * 0x1.0p-53) - 1.0;
      const double x = u * z.x[layer];
      if (std::abs(x) < z.x[layer + 1]) return x;
      if (layer == 0) {
        ++tails;
        double tail, e2;
        do {
          tail = -std::log(1.0 - r.Uniform()) / internal::Ziggurat::kR;
          e2 = -std::log(1.0 - r.Uniform());
        } while (2.0 * e2 < tail * tail);
        return u < 0.0 ? -(internal::Ziggurat::kR + tail) : internal::Ziggurat::kR + tail;
      }
      ++wedges;
      const double y = z.f[layer] + r.Uniform() * (z.f[layer + 1] - z.f[layer]);
      if (y < std::exp(-0.5 * x * x)) return x;
    }
  };
  RandomStream split(2027), reference(2027);
  for (int i = 0; i < 1000000; ++i) {
    const double a = split.Normal();
    const double b = single_loop(reference);
    ASSERT_EQ(std::bit_cast<std::uint64_t>(a), std::bit_cast<std::uint64_t>(b)) << "draw " << i;
  }
  EXPECT_EQ(split, reference);  // the same words consumed
  EXPECT_GT(wedges, 1000);
  EXPECT_GT(tails, 10);
}

}  // namespace
}  // namespace uascma
