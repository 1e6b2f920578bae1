#pragma once
// Explicit random streams (style habit 7): every stochastic call takes a RandomStream&, and every Monte
// Carlo run records the seed that replays it. The generator is xoshiro256** (Blackman & Vigna, "Scrambled
// linear pseudorandom number generators", 2021) seeded through SplitMix64; normals come from the polar
// Marsaglia method. Everything here is specified bit for bit, so a seed replays identically on every
// platform and compiler (unlike std::normal_distribution, whose algorithm is implementation-defined).
#include <cmath>
#include <cstdint>

namespace uascma {

// SplitMix64 (Steele, Lea & Flood, 2014): seeds other generators and derives independent sub-seeds.
inline std::uint64_t SplitMix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// A seed for sub-stream `index` of `seed` (e.g. one per Monte Carlo run, or per model in a run), so
// streams never overlap by accident and a run replays from (seed, index) alone.
inline std::uint64_t DeriveSeed(std::uint64_t seed, std::uint64_t index) {
  std::uint64_t state = seed ^ (0xd1b54a32d192ed03ULL * (index + 1));
  SplitMix64(state);
  return SplitMix64(state);
}

class RandomStream {
 public:
  explicit RandomStream(std::uint64_t seed = 0) { Seed(seed); }
  void Seed(std::uint64_t seed) {
    std::uint64_t state = seed;
    for (auto& word : s_) word = SplitMix64(state);
    has_spare_normal_ = false;
  }
  // Satisfies UniformRandomBitGenerator, so it also works with <algorithm> shuffles.
  using result_type = std::uint64_t;
  static constexpr result_type min() { return 0; }
  static constexpr result_type max() { return ~result_type{0}; }
  result_type operator()() { return Next(); }

  std::uint64_t Next() {
    const std::uint64_t result = Rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = Rotl(s_[3], 45);
    return result;
  }
  // Uniform in [0, 1) with 53 random bits.
  double Uniform() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }
  double Uniform(double low, double high) { return low + (high - low) * Uniform(); }
  // Uniform integer in [0, n) (n > 0), by Lemire's multiply-shift with rejection.
  std::uint64_t UniformIndex(std::uint64_t n) {
    const std::uint64_t threshold = (0 - n) % n;
    while (true) {
      const __uint128_t product = static_cast<__uint128_t>(Next()) * n;
      if (static_cast<std::uint64_t>(product) >= threshold) return static_cast<std::uint64_t>(product >> 64);
    }
  }
  bool Bernoulli(double probability) { return Uniform() < probability; }
  // Standard normal N(0, 1), polar Marsaglia method (one spare kept).
  double Normal() {
    if (has_spare_normal_) {
      has_spare_normal_ = false;
      return spare_normal_;
    }
    double x, y, r2;
    do {
      x = 2.0 * Uniform() - 1.0;
      y = 2.0 * Uniform() - 1.0;
      r2 = x * x + y * y;
    } while (r2 >= 1.0 || r2 == 0.0);
    const double scale = std::sqrt(-2.0 * std::log(r2) / r2);
    spare_normal_ = y * scale;
    has_spare_normal_ = true;
    return x * scale;
  }
  double Normal(double mean, double standard_deviation) { return mean + standard_deviation * Normal(); }

 private:
  static std::uint64_t Rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t s_[4];
  double spare_normal_ = 0.0;
  bool has_spare_normal_ = false;
};

}  // namespace uascma
