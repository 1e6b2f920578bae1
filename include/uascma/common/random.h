#pragma once
// Explicit random streams (randomness is explicit): every stochastic call takes a RandomStream&, and every Monte
// Carlo run records the seed that replays it. The generator is xoshiro256** (Blackman & Vigna, "Scrambled
// linear pseudorandom number generators", 2021) seeded through SplitMix64; normals come from the
// ziggurat method with 256 layers (Marsaglia & Tsang, "The ziggurat method for generating random
// variables", J. Stat. Software 5(8), 2000): ~99 % of draws cost one 64-bit word and a multiply, which
// matters at seven normals per 200 Hz simulator step. Everything here is specified bit for bit, so a seed
// replays identically on every platform and compiler (unlike std::normal_distribution, whose algorithm is
// implementation-defined).
#include <array>
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

namespace internal {
struct Ziggurat;
inline const Ziggurat& TheZiggurat();  // defined below
}  // namespace internal

class RandomStream {
 public:
  explicit RandomStream(std::uint64_t seed = 0) { Seed(seed); }
  void Seed(std::uint64_t seed) {
    std::uint64_t state = seed;
    for (auto& word : s_) word = SplitMix64(state);
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
  double Uniform() { return static_cast<double>(static_cast<std::int64_t>(Next() >> 11)) * 0x1.0p-53; }
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
  // Standard normal N(0, 1) by the ziggurat method (see the file comment).
  [[gnu::always_inline]] double Normal();  // inlined: a handful of instructions for ~99 % of draws
  double Normal(double mean, double standard_deviation) { return mean + standard_deviation * Normal(); }
  // Equal streams draw the same numbers from here on (a flight state is compared whole, sim/flight.h).
  bool operator==(const RandomStream&) const = default;

 private:
  // Normal()'s draw when its first candidate falls outside its layer's rectangle (~1 % of draws): the tail or the
  // wedge for that candidate, then further candidates. Out of line, so that the common path inlines into its callers.
  double NormalOutsideRectangle(int layer, double u, double x);
  static std::uint64_t Rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t s_[4];
  // The ziggurat's table, found once per stream: a draw reads it through this pointer, without the guard check and
  // call of TheZiggurat's function-local static (~5 instructions a draw, seven draws per GNC step). The table itself
  // is still built at its first use, not when the program starts. Every stream points at the same table, so equal
  // streams compare equal.
  const internal::Ziggurat* ziggurat_ = &internal::TheZiggurat();
};

namespace internal {
// The 256-layer ziggurat of the standard normal: layer i ≥ 1 spans x ∈ [0, x[i]] between the heights
// f(x[i]) and f(x[i+1]) (f(x) = exp(−x²/2)); layer 0 is the base rectangle [0, r] × [0, f(r)] plus the tail
// beyond r, stretched to the same area v. x[256] = 0.
struct Ziggurat {
  static constexpr double kR = 3.6541528853610088;   // x[1], the start of the tail (256 layers)
  static constexpr double kArea = 4.92867323399e-3;  // v, the area of every layer
  std::array<double, 257> x{};
  std::array<double, 257> f{};
  [[gnu::noinline]] Ziggurat() {  // once per program: kept out of Normal()'s inlined path
    x[0] = kArea / std::exp(-0.5 * kR * kR);
    x[1] = kR;
    for (int i = 1; i < 255; ++i) x[i + 1] = std::sqrt(-2.0 * std::log(kArea / x[i] + std::exp(-0.5 * x[i] * x[i])));
    x[256] = 0.0;
    for (int i = 0; i < 257; ++i) f[i] = std::exp(-0.5 * x[i] * x[i]);
  }
};
inline const Ziggurat& TheZiggurat() {
  static const Ziggurat table;
  return table;
}

// One ziggurat candidate from 64 random bits: the layer (low 8 bits), u uniform in [-1, 1) (the high 53 bits) and
// x = u · x[layer].
struct ZigguratCandidate {
  int layer;
  double u, x;
};
inline ZigguratCandidate DrawZigguratCandidate(const Ziggurat& z, std::uint64_t bits) {
  const int layer = static_cast<int>(bits & 0xff);
  // bits >> 11 < 2^53 converts exactly through int64 (one instruction, unlike uint64 → double).
  const double u = 2.0 * (static_cast<double>(static_cast<std::int64_t>(bits >> 11)) * 0x1.0p-53) - 1.0;
  return {layer, u, u * z.x[layer]};
}
}  // namespace internal

inline double RandomStream::Normal() {
  const internal::Ziggurat& z = *ziggurat_;
  const internal::ZigguratCandidate c = internal::DrawZigguratCandidate(z, Next());
  if (std::abs(c.x) < z.x[c.layer + 1]) return c.x;  // inside the layer's rectangle: accept at once
  return NormalOutsideRectangle(c.layer, c.u, c.x);
}

[[gnu::noinline]] inline double RandomStream::NormalOutsideRectangle(int layer, double u, double x) {
  const internal::Ziggurat& z = *ziggurat_;
  while (true) {
    if (layer == 0) {
      // The tail beyond r (Marsaglia 1964): x = r + e1 / r with e1, e2 exponential, accept if 2 e2 > (e1/r)².
      double tail, e2;
      do {
        tail = -std::log(1.0 - Uniform()) / internal::Ziggurat::kR;
        e2 = -std::log(1.0 - Uniform());
      } while (2.0 * e2 < tail * tail);
      return u < 0.0 ? -(internal::Ziggurat::kR + tail) : internal::Ziggurat::kR + tail;
    }
    // The wedge between the rectangle and the curve: accept under f.
    const double y = z.f[layer] + Uniform() * (z.f[layer + 1] - z.f[layer]);
    if (y < std::exp(-0.5 * x * x)) return x;
    const internal::ZigguratCandidate c = internal::DrawZigguratCandidate(z, Next());  // the next candidate
    if (std::abs(c.x) < z.x[c.layer + 1]) return c.x;
    layer = c.layer;
    u = c.u;
    x = c.x;
  }
}

}  // namespace uascma
