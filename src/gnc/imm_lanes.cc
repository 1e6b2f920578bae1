// One IMM cycle over eight lanes (gnc/imm_lanes.h). The arithmetic is written once, as a template over two forms of
// eight lanes on GCC/Clang generic vectors: a pair of 4-wide vectors (compiled for the baseline x86-64, where the
// compiler splits each 4-wide operation into two SSE2 ones, and, through a target attribute, for AVX2) and one
// 8-wide vector (compiled for AVX-512). Only IEEE add, subtract, multiply, divide, square root and compare are used,
// lane by lane, plus integer adds and shifts on the bits of the exponential's scale factor; the file is compiled
// with -ffp-contract=off (src/gnc/CMakeLists.txt: AVX-512 has fused multiply-adds, which would round once where
// the others round twice), so every path gives the same bits. The order of every operation is the order of the
// Eigen expressions this replaced (imm.cc before the lanes), including Eigen's pairwise sum over 8 lanes.
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <span>
#include <type_traits>

#include "uascma/gnc/imm_lanes.h"

namespace uascma::gnc {
namespace {

typedef double LaneV2 __attribute__((vector_size(16)));
typedef double LaneV4 __attribute__((vector_size(32)));
typedef double LaneV8 __attribute__((vector_size(64)));
typedef std::uint64_t LaneU2 __attribute__((vector_size(16)));
typedef std::uint64_t LaneU4 __attribute__((vector_size(32)));
typedef std::uint64_t LaneU8 __attribute__((vector_size(64)));
typedef double LaneV4InMemory __attribute__((vector_size(32), aligned(8), may_alias));
typedef double LaneV8InMemory __attribute__((vector_size(64), aligned(8), may_alias));

#define UASCMA_LANES_INLINE inline __attribute__((always_inline))
#define UASCMA_LANES8_INLINE [[maybe_unused]] UASCMA_LANES_INLINE  // the 8-wide form: unused by Clang (below)

// Clang (the fuzzing and sanitizer builds) refuses 8-wide vectors between functions not all compiled for AVX-512,
// even inlined ones: it gets the SSE2 and AVX2 paths only.
#if defined(__clang__)
constexpr bool kWithAvx512 = false;
#else
constexpr bool kWithAvx512 = true;
#define UASCMA_IMM_AVX512 1
#endif

// Three forms of eight lanes: four 2-wide vectors (SSE2), two 4-wide ones (AVX2) and one 8-wide (AVX-512). Each
// form has its own shuffles, written in the widths its instruction set has (the compiler's splitting of wider
// shuffles for SSE2 goes through memory: measured, 3× the time of this form).
struct LaneQuad {
  LaneV2 a, b, c, d;  // lanes 0–1, 2–3, 4–5, 6–7
};
struct LanePair {
  LaneV4 lo, hi;  // lanes 0–3, 4–7
};

#define UASCMA_LANES_OPERATOR(op)                                                                                    \
  [[maybe_unused]] UASCMA_LANES_INLINE LaneQuad operator op(LaneQuad x, LaneQuad y) {                                \
    return {x.a op y.a, x.b op y.b, x.c op y.c, x.d op y.d};                                                         \
  }                                                                                                                  \
  [[maybe_unused]] UASCMA_LANES_INLINE LaneQuad operator op(LaneQuad x, double y) {                                  \
    return {x.a op y, x.b op y, x.c op y, x.d op y};                                                                 \
  }                                                                                                                  \
  [[maybe_unused]] UASCMA_LANES_INLINE LaneQuad operator op(double x, LaneQuad y) {                                  \
    return {x op y.a, x op y.b, x op y.c, x op y.d};                                                                 \
  }                                                                                                                  \
  [[maybe_unused]] UASCMA_LANES_INLINE LanePair operator op(LanePair x, LanePair y) {                                \
    return {x.lo op y.lo, x.hi op y.hi};                                                                             \
  }                                                                                                                  \
  [[maybe_unused]] UASCMA_LANES_INLINE LanePair operator op(LanePair x, double y) { return {x.lo op y, x.hi op y}; } \
  [[maybe_unused]] UASCMA_LANES_INLINE LanePair operator op(double x, LanePair y) { return {x op y.lo, x op y.hi}; }
UASCMA_LANES_OPERATOR(+)
UASCMA_LANES_OPERATOR(-)
UASCMA_LANES_OPERATOR(*)
UASCMA_LANES_OPERATOR(/)
#undef UASCMA_LANES_OPERATOR

UASCMA_LANES_INLINE LaneV2 Load2(const double* a) { return LaneV2{a[0], a[1]}; }
UASCMA_LANES_INLINE LaneV4 Load4(const double* a) { return *reinterpret_cast<const LaneV4InMemory*>(a); }
UASCMA_LANES_INLINE void Store2(LaneV2 v, double* a) { std::memcpy(a, &v, sizeof(v)); }
UASCMA_LANES_INLINE void Store4(LaneV4 v, double* a) { *reinterpret_cast<LaneV4InMemory*>(a) = v; }

template <typename L>
UASCMA_LANES_INLINE L LoadLanes(const ImmLaneArray& x) {
  const double* p = x.data();
  if constexpr (std::is_same_v<L, LaneQuad>) {
    return {Load2(p), Load2(p + 2), Load2(p + 4), Load2(p + 6)};
  } else if constexpr (std::is_same_v<L, LanePair>) {
    return {Load4(p), Load4(p + 4)};
  } else {
    return *reinterpret_cast<const LaneV8InMemory*>(p);
  }
}
UASCMA_LANES_INLINE void StoreLanes(LaneQuad v, ImmLaneArray* x) {
  Store2(v.a, x->data());
  Store2(v.b, x->data() + 2);
  Store2(v.c, x->data() + 4);
  Store2(v.d, x->data() + 6);
}
UASCMA_LANES_INLINE void StoreLanes(LanePair v, ImmLaneArray* x) {
  Store4(v.lo, x->data());
  Store4(v.hi, x->data() + 4);
}
UASCMA_LANES8_INLINE void StoreLanes(LaneV8 v, ImmLaneArray* x) { *reinterpret_cast<LaneV8InMemory*>(x->data()) = v; }

// The seven mode probabilities p_0…p_6 and, in the idle lane, p_6 again (its weights are 0 or replaced).
template <typename L>
UASCMA_LANES_INLINE L ProbabilityLanes(const std::array<double, 7>& p) {
  if constexpr (std::is_same_v<L, LaneQuad>) {
    return {Load2(p.data()), Load2(p.data() + 2), Load2(p.data() + 4), LaneV2{p[6], p[6]}};
  } else {
    const LaneV4 first = Load4(p.data()), last = Load4(p.data() + 3);  // p_0…p_3, p_3…p_6
    if constexpr (std::is_same_v<L, LanePair>) {
      return {first, __builtin_shufflevector(last, last, 1, 2, 3, 3)};
    } else {
      return __builtin_shufflevector(first, last, 0, 1, 2, 3, 5, 6, 7, 7);
    }
  }
}
UASCMA_LANES_INLINE void StoreProbabilities(LaneQuad v, std::array<double, 7>* p) {
  Store2(v.a, p->data());
  Store2(v.b, p->data() + 2);
  Store2(v.c, p->data() + 4);
  (*p)[6] = v.d[0];
}
UASCMA_LANES_INLINE void StoreProbabilities(LanePair v, std::array<double, 7>* p) {
  Store4(v.lo, p->data());
  Store4(__builtin_shufflevector(v.lo, v.hi, 3, 4, 5, 6), p->data() + 3);
}
UASCMA_LANES8_INLINE void StoreProbabilities(LaneV8 v, std::array<double, 7>* p) {
  Store4(__builtin_shufflevector(v, v, 0, 1, 2, 3), p->data());
  Store4(__builtin_shufflevector(v, v, 3, 4, 5, 6), p->data() + 3);
}

// x_0 + x_1 + … + x_6 in that order (the idle lane left out).
UASCMA_LANES_INLINE double SumOfModes(LaneQuad x) {
  return x.a[0] + x.a[1] + x.b[0] + x.b[1] + x.c[0] + x.c[1] + x.d[0];
}
UASCMA_LANES_INLINE double SumOfModes(LanePair x) {
  return x.lo[0] + x.lo[1] + x.lo[2] + x.lo[3] + x.hi[0] + x.hi[1] + x.hi[2];
}
UASCMA_LANES8_INLINE double SumOfModes(LaneV8 x) { return x[0] + x[1] + x[2] + x[3] + x[4] + x[5] + x[6]; }

// (0, t_1, …, t_6, 0): rotor j's thrust in lane j.
template <typename L>
UASCMA_LANES_INLINE L RemovedThrustLanes(std::span<const double, 6> t) {
  if constexpr (std::is_same_v<L, LaneQuad>) {
    return {LaneV2{0.0, t[0]}, Load2(t.data() + 1), Load2(t.data() + 3), LaneV2{t[5], 0.0}};
  } else {
    const LaneV4 first = Load4(t.data()), last = Load4(t.data() + 2);  // t_1…t_4, t_3…t_6
    const LaneV4 zero{};
    if constexpr (std::is_same_v<L, LanePair>) {
      return {__builtin_shufflevector(first, zero, 4, 0, 1, 2), __builtin_shufflevector(last, zero, 1, 2, 3, 4)};
    } else {
      const LaneV8 lanes = __builtin_shufflevector(first, last, 0, 0, 1, 2, 5, 6, 7, 7);
      return __builtin_shufflevector(lanes, LaneV8{}, 8, 1, 2, 3, 4, 5, 6, 15);
    }
  }
}

UASCMA_LANES_INLINE double FirstLane(LaneQuad x) { return x.a[0]; }
UASCMA_LANES_INLINE double FirstLane(LanePair x) { return x.lo[0]; }
UASCMA_LANES8_INLINE double FirstLane(LaneV8 x) { return x[0]; }

// x with lane 0 replaced by lane 0 of `first`.
UASCMA_LANES_INLINE LaneQuad WithFirstLane(LaneQuad x, LaneQuad first) {
  return {__builtin_shufflevector(x.a, first.a, 2, 1), x.b, x.c, x.d};
}
UASCMA_LANES_INLINE LanePair WithFirstLane(LanePair x, LanePair first) {
  return {__builtin_shufflevector(x.lo, first.lo, 4, 1, 2, 3), x.hi};
}
UASCMA_LANES8_INLINE LaneV8 WithFirstLane(LaneV8 x, LaneV8 first) {
  return __builtin_shufflevector(x, first, 8, 1, 2, 3, 4, 5, 6, 7);
}
// x with lane 0 replaced by `first` and lane 7 by `last`.
UASCMA_LANES_INLINE LaneQuad WithEnds(LaneQuad x, double first, double last) {
  return {LaneV2{first, x.a[1]}, x.b, x.c, LaneV2{x.d[0], last}};
}
UASCMA_LANES_INLINE LanePair WithEnds(LanePair x, double first, double last) {
  return {__builtin_shufflevector(x.lo, LaneV4{} + first, 4, 1, 2, 3),
          __builtin_shufflevector(x.hi, LaneV4{} + last, 0, 1, 2, 7)};
}
UASCMA_LANES8_INLINE LaneV8 WithEnds(LaneV8 x, double first, double last) {
  const LaneV8 ends = LaneV8{first, last, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  return __builtin_shufflevector(x, ends, 8, 1, 2, 3, 4, 5, 6, 9);
}

UASCMA_LANES_INLINE LaneV2 SqrtV2(LaneV2 v) { return LaneV2{__builtin_sqrt(v[0]), __builtin_sqrt(v[1])}; }
UASCMA_LANES_INLINE LaneV4 SqrtV4(LaneV4 v) {
  return LaneV4{__builtin_sqrt(v[0]), __builtin_sqrt(v[1]), __builtin_sqrt(v[2]), __builtin_sqrt(v[3])};
}
UASCMA_LANES_INLINE LaneQuad SqrtLanes(LaneQuad v) { return {SqrtV2(v.a), SqrtV2(v.b), SqrtV2(v.c), SqrtV2(v.d)}; }
UASCMA_LANES_INLINE LanePair SqrtLanes(LanePair v) { return {SqrtV4(v.lo), SqrtV4(v.hi)}; }
UASCMA_LANES8_INLINE LaneV8 SqrtLanes(LaneV8 v) {
  return LaneV8{__builtin_sqrt(v[0]), __builtin_sqrt(v[1]), __builtin_sqrt(v[2]), __builtin_sqrt(v[3]),
                __builtin_sqrt(v[4]), __builtin_sqrt(v[5]), __builtin_sqrt(v[6]), __builtin_sqrt(v[7])};
}

// max(x, floor) lane by lane, as std::max(x, floor) (x unless x < floor).
template <typename V>
UASCMA_LANES_INLINE V AtLeastV(V x, double floor) {
  return x < floor ? V{} + floor : x;
}
UASCMA_LANES_INLINE LaneQuad AtLeast(LaneQuad x, double floor) {
  return {AtLeastV(x.a, floor), AtLeastV(x.b, floor), AtLeastV(x.c, floor), AtLeastV(x.d, floor)};
}
UASCMA_LANES_INLINE LanePair AtLeast(LanePair x, double floor) {
  return {AtLeastV(x.lo, floor), AtLeastV(x.hi, floor)};
}
UASCMA_LANES8_INLINE LaneV8 AtLeast(LaneV8 x, double floor) { return AtLeastV(x, floor); }

// ((x0 + x2) + (x4 + x6)) + ((x1 + x3) + (x5 + x7)), how Eigen (SSE2, 2-lane packets) summed an array of 8, in every
// lane: each lane adds the same pairs, in another order of operands (a + b and b + a are the same double).
UASCMA_LANES_INLINE LaneQuad SumInEveryLane(LaneQuad x) {
  const LaneV2 halves = (x.a + x.b) + (x.c + x.d);  // (x0 + x2) + (x4 + x6), (x1 + x3) + (x5 + x7)
  const LaneV2 sum = halves + __builtin_shufflevector(halves, halves, 1, 0);
  return {sum, sum, sum, sum};
}
UASCMA_LANES_INLINE LanePair SumInEveryLane(LanePair x) {
  const LaneV4 lower = x.lo + __builtin_shufflevector(x.lo, x.lo, 2, 3, 0, 1);  // x0 + x2, x1 + x3, …
  const LaneV4 upper = x.hi + __builtin_shufflevector(x.hi, x.hi, 2, 3, 0, 1);  // x4 + x6, x5 + x7, …
  const LaneV4 halves = lower + upper;
  const LaneV4 sum = halves + __builtin_shufflevector(halves, halves, 1, 0, 3, 2);
  return {sum, sum};
}
UASCMA_LANES8_INLINE LaneV8 SumInEveryLane(LaneV8 x) {
  const LaneV8 pairs = x + __builtin_shufflevector(x, x, 2, 3, 0, 1, 6, 7, 4, 5);
  const LaneV8 halves = pairs + __builtin_shufflevector(pairs, pairs, 4, 5, 6, 7, 0, 1, 2, 3);
  return halves + __builtin_shufflevector(halves, halves, 1, 0, 3, 2, 5, 4, 7, 6);
}

// The least of lanes 0…6 (the idle lane 7 is left out), in every lane.
template <typename V>
UASCMA_LANES_INLINE V MinV(V a, V b) {
  return a < b ? a : b;
}
UASCMA_LANES_INLINE LaneQuad MinOfModesInEveryLane(LaneQuad x) {
  const LaneV2 last = __builtin_shufflevector(x.d, x.d, 0, 0);  // lane 7 replaced by lane 6
  const LaneV2 least2 = MinV(MinV(x.a, x.c), MinV(x.b, last));
  const LaneV2 least = MinV(least2, __builtin_shufflevector(least2, least2, 1, 0));
  return {least, least, least, least};
}
UASCMA_LANES_INLINE LanePair MinOfModesInEveryLane(LanePair x) {
  const LaneV4 upper = __builtin_shufflevector(x.hi, x.hi, 0, 1, 2, 2);  // lane 7 replaced by lane 6
  const LaneV4 least4 = MinV(x.lo, upper);
  const LaneV4 least2 = MinV(least4, __builtin_shufflevector(least4, least4, 2, 3, 0, 1));
  const LaneV4 least = MinV(least2, __builtin_shufflevector(least2, least2, 1, 0, 3, 2));
  return {least, least};
}
UASCMA_LANES8_INLINE LaneV8 MinOfModesInEveryLane(LaneV8 x) {
  const LaneV8 modes = __builtin_shufflevector(x, x, 0, 1, 2, 3, 4, 5, 6, 6);  // lane 7 replaced by lane 6
  const LaneV8 least4 = MinV(modes, __builtin_shufflevector(modes, modes, 4, 5, 6, 7, 0, 1, 2, 3));
  const LaneV8 least2 = MinV(least4, __builtin_shufflevector(least4, least4, 2, 3, 0, 1, 6, 7, 4, 5));
  return MinV(least2, __builtin_shufflevector(least2, least2, 1, 0, 3, 2, 5, 4, 7, 6));
}

// e^x (contract and error bound in imm_lanes.h). x = n ln 2 + r with n = round(x / ln 2), |r| ≤ ln 2 / 2; e^r by
// its Taylor series to r^13 (the first term left out, r^14/14! < 6e-18 relative, 1/20 of an ulp); 2^n put into the
// exponent bits.
// ln 2 = 0.693147180559945309417232121458176568… is split as kLn2High, its leading 32 bits (so n·kLn2High is exact
// for |n| < 2^21), plus kLn2Low, the rest rounded to a double: x − n·kLn2High is exact and r is good to ~1e-17.
constexpr double kLn2High = 0x1.62e42feep-1;
constexpr double kLn2Low = 0x1.a39ef35793c76p-33;
constexpr double kLog2e = 0x1.71547652b82fep0;  // 1 / ln 2, rounded
// Adding 1.5·2^52 to v (|v| < 2^51) rounds it to an integer, kept in the low mantissa bits of the sum.
constexpr double kRoundingShift = 0x1.8p52;
constexpr double kExpLowest = -708.0;  // below, e^x < 3.3e-308 is returned as 0 (2^n would leave the normal range)
constexpr int kExpTerms = 14;          // 1/k! for k = 0…13
constexpr std::array<double, kExpTerms> kInverseFactorial = [] {
  std::array<double, kExpTerms> c{};
  double factorial = 1.0;  // exact: 13! < 2^53
  for (int k = 0; k < kExpTerms; ++k) {
    if (k > 0) factorial *= k;
    c[k] = 1.0 / factorial;
  }
  return c;
}();

template <typename V, typename U>
UASCMA_LANES_INLINE V ExpVector(V x) {
  const V shifted = x * kLog2e + kRoundingShift;  // 1.5·2^52 + n
  const V n = shifted - kRoundingShift;
  const V r = (x - n * kLn2High) - n * kLn2Low;
  // e^r = 1 + (r + r² T(r)), T = Σ_{k=2}^{13} r^{k−2}/k! in Estrin's scheme (pairs, then r², r⁴, r⁸): a chain of
  // five levels where Horner's has thirteen; the one rounding near 1 comes last.
  static_assert(kExpTerms == 14);
  const auto& c = kInverseFactorial;
  const V r2 = r * r;
  const V r4 = r2 * r2;
  const V r8 = r4 * r4;
  const V p0 = c[2] + c[3] * r, p1 = c[4] + c[5] * r, p2 = c[6] + c[7] * r;
  const V p3 = c[8] + c[9] * r, p4 = c[10] + c[11] * r, p5 = c[12] + c[13] * r;
  const V q0 = p0 + p1 * r2, q1 = p2 + p3 * r2, q2 = p4 + p5 * r2;
  const V tail = (q0 + q1 * r4) + q2 * r8;
  const V series = 1.0 + (r + r2 * tail);
  // n is in the low bits of `shifted`; shifted left by 52 it is n·2^52 (the leading bits fall off), which added to
  // the bits of e^r (in [0.7, 1.5)) multiplies it by 2^n while the result stays normal (x ≥ −708).
  const U scaled = reinterpret_cast<U>(series) + (reinterpret_cast<U>(shifted) << 52);
  const U below = reinterpret_cast<U>(x < kExpLowest);  // all ones where x < −708 (never for NaN)
  return reinterpret_cast<V>(scaled & ~below);
}

UASCMA_LANES_INLINE LaneQuad ExpLanes8(LaneQuad x) {
  return {ExpVector<LaneV2, LaneU2>(x.a), ExpVector<LaneV2, LaneU2>(x.b), ExpVector<LaneV2, LaneU2>(x.c),
          ExpVector<LaneV2, LaneU2>(x.d)};
}
UASCMA_LANES_INLINE LanePair ExpLanes8(LanePair x) {
  return {ExpVector<LaneV4, LaneU4>(x.lo), ExpVector<LaneV4, LaneU4>(x.hi)};
}
UASCMA_LANES8_INLINE LaneV8 ExpLanes8(LaneV8 x) { return ExpVector<LaneV8, LaneU8>(x); }

// Step 1, the mixing weights (the switching model is described in imm.cc).
template <typename L>
struct LaneMix {
  L predicted;     // c_j
  L from_nominal;  // μ_{0|j}; 0 in lane 0, 1 in the idle lane (which thus copies mode 0)
  L into_nominal;  // μ_{i|0}; 0 in the idle lane
};

template <typename L>
UASCMA_LANES_INLINE LaneMix<L> MixLanes(const ImmLaneModel& model, const std::array<double, 7>& p) {
  const double failure_total = p[1] + p[2] + p[3] + p[4] + p[5] + p[6];
  const L probability = ProbabilityLanes<L>(p);
  const L own = LoadLanes<L>(model.own_weight) * p[0];
  LaneMix<L> mix;
  mix.predicted = own + LoadLanes<L>(model.other_weight) * WithEnds(probability, failure_total, 1.0);
  mix.from_nominal = WithEnds(own / mix.predicted, 0.0, 1.0);
  mix.into_nominal = (LoadLanes<L>(model.into_nominal) * probability) / FirstLane(mix.predicted);
  return mix;
}

// Mixed rates and variances of one axis. For the two-term mixes of modes j ≥ 1 (d = r_0 − r_j):
//   mean = μ0 r_0 + μj r_j,  var = μ0 v_0 + μj v_j + μ0 μj d²   (μ0 + μj = 1);
// mode 0 mixes every mode: mean = Σ μ_{i|0} r_i, var = Σ μ_{i|0} (v_i + (r_i − mean)²).
template <typename L>
UASCMA_LANES_INLINE void MixAxis(const LaneMix<L>& mix, L from_self, L spread_weight, L r, L v, L* mixed_rate,
                                 L* mixed_variance) {
  const double r0 = FirstLane(r), v0 = FirstLane(v);
  const L d = r0 - r;
  const L mean0 = SumInEveryLane(mix.into_nominal * r);
  const L spread0 = r - mean0;
  const L variance0 = SumInEveryLane(mix.into_nominal * (v + spread0 * spread0));
  *mixed_rate = WithFirstLane(mix.from_nominal * r0 + from_self * r, mean0);
  *mixed_variance = WithFirstLane(mix.from_nominal * v0 + from_self * v + spread_weight * (d * d), variance0);
}

// Steps 2–4: prediction of every mode under its thrusts over dt, update with the gyro, mode probabilities
// ∝ c_j exp(−q_j / 2) / √det S_j (the exponent shifted by its least value; a floor keeps every mode alive).
template <typename L>
UASCMA_LANES_INLINE void StepLanes(const ImmLaneModel& model, std::span<const double, 6> t,
                                   std::span<const double, 3> gyro_B, double specific_force_z_B, double dt,
                                   ImmLaneState* state) {
  const LaneMix<L> mix = MixLanes<L>(model, state->probability);
  const L from_self = 1.0 - mix.from_nominal;
  const L spread_weight = mix.from_nominal * from_self;
  L mixed_rate[3], mixed_variance[3];
  for (int axis = 0; axis < 3; ++axis) {
    MixAxis(mix, from_self, spread_weight, LoadLanes<L>(state->rate[axis]), LoadLanes<L>(state->variance[axis]),
            &mixed_rate[axis], &mixed_variance[axis]);
  }
  // The believed wrench (T, τx, τy, τz) = M · thrusts, column after column; each mode's is less rotor j's share.
  LaneV4 wrench = *reinterpret_cast<const LaneV4InMemory*>(model.mixing_column[0].data()) * t[0];
  for (int rotor = 1; rotor < 6; ++rotor) {
    wrench = *reinterpret_cast<const LaneV4InMemory*>(model.mixing_column[rotor].data()) * t[rotor] + wrench;
  }
  const L removed = RemovedThrustLanes<L>(t);
  const L accel_innovation =
      specific_force_z_B + (wrench[0] - LoadLanes<L>(model.column[0]) * removed) * model.inverse_mass;
  L quadratic = (accel_innovation * accel_innovation) * model.inverse_accel_variance;
  const double process = model.angular_process_noise * dt * model.angular_process_noise * dt;
  // w_x' = w_x + dt (τ_x − (I_z − I_y) w_y w_z) / I_x, and cyclically; then the gyro update. Returns S.
  const auto predict_and_update = [&](int axis) __attribute__((always_inline)) {
    const L torque = wrench[1 + axis] - LoadLanes<L>(model.column[1 + axis]) * removed;
    const L gyroscopic = model.gyroscopic[axis] * mixed_rate[(axis + 1) % 3] * mixed_rate[(axis + 2) % 3];
    const L prior = mixed_rate[axis] + (dt / model.inertia[axis]) * (torque - gyroscopic);
    const L prior_variance = mixed_variance[axis] + process;
    const L innovation_variance = prior_variance + model.gyro_variance;
    const L inverse = 1.0 / innovation_variance;
    const L innovation = gyro_B[axis] - prior;
    const L gain = prior_variance * inverse;
    StoreLanes(prior + gain * innovation, &state->rate[axis]);
    StoreLanes(model.gyro_variance * gain, &state->variance[axis]);  // (1 − K) P = R K
    quadratic = quadratic + (innovation * innovation) * inverse;
    return innovation_variance;
  };
  const L innovation_variance_x = predict_and_update(0);
  const L innovation_variance_y = predict_and_update(1);
  const L variance_product = innovation_variance_x * innovation_variance_y * predict_and_update(2);
  const L least = MinOfModesInEveryLane(quadratic);
  const L likelihood = (mix.predicted / SqrtLanes(variance_product)) * ExpLanes8(-0.5 * (quadratic - least));
  const double total = SumOfModes(likelihood);
  const L probability = AtLeast(likelihood * (1.0 / total), 1e-12);
  StoreProbabilities(probability, &state->probability);
}

// The paths: one template, three instruction sets.
void StepSse2(const ImmLaneModel& model, std::span<const double, 6> thrusts, std::span<const double, 3> gyro_B,
              double specific_force_z_B, double dt, ImmLaneState* state) {
  StepLanes<LaneQuad>(model, thrusts, gyro_B, specific_force_z_B, dt, state);
}
__attribute__((target("avx2"))) void StepAvx2(const ImmLaneModel& model, std::span<const double, 6> thrusts,
                                              std::span<const double, 3> gyro_B, double specific_force_z_B, double dt,
                                              ImmLaneState* state) {
  StepLanes<LanePair>(model, thrusts, gyro_B, specific_force_z_B, dt, state);
}
#ifdef UASCMA_IMM_AVX512
__attribute__((target("avx512f"))) void StepAvx512(const ImmLaneModel& model, std::span<const double, 6> thrusts,
                                                   std::span<const double, 3> gyro_B, double specific_force_z_B,
                                                   double dt, ImmLaneState* state) {
  StepLanes<LaneV8>(model, thrusts, gyro_B, specific_force_z_B, dt, state);
}
#endif

void ExpSse2(const ImmLaneArray& x, ImmLaneArray* y) { StoreLanes(ExpLanes8(LoadLanes<LaneQuad>(x)), y); }
__attribute__((target("avx2"))) void ExpAvx2(const ImmLaneArray& x, ImmLaneArray* y) {
  StoreLanes(ExpLanes8(LoadLanes<LanePair>(x)), y);
}
#ifdef UASCMA_IMM_AVX512
__attribute__((target("avx512f"))) void ExpAvx512(const ImmLaneArray& x, ImmLaneArray* y) {
  StoreLanes(ExpLanes8(LoadLanes<LaneV8>(x)), y);
}
#endif

// What the CPU (and its operating system) supports, asked once, when the program starts.
struct CpuSimd {
  bool avx2 = false;
  bool avx512 = false;
};
CpuSimd DetectCpuSimd() {
  __builtin_cpu_init();
  return CpuSimd{__builtin_cpu_supports("avx2") != 0, kWithAvx512 && __builtin_cpu_supports("avx512f") != 0};
}
const CpuSimd kCpuSimd = DetectCpuSimd();

// `path`, or the best one below it that the CPU has.
SimdPath Supported(SimdPath path) {
  if (path == SimdPath::kAvx512 && !kCpuSimd.avx512) path = SimdPath::kAvx2;
  if (path == SimdPath::kAvx2 && !kCpuSimd.avx2) path = SimdPath::kSse2;
  return path;
}

}  // namespace

bool CpuSupports(SimdPath path) { return Supported(path) == path; }

SimdPath ChooseSimdPath(const char* requested) {
  if (requested != nullptr) {
    if (std::strcmp(requested, "scalar") == 0 || std::strcmp(requested, "sse2") == 0) return SimdPath::kSse2;
    if (std::strcmp(requested, "avx2") == 0) return Supported(SimdPath::kAvx2);
  }
  return Supported(SimdPath::kAvx512);
}

namespace {
const SimdPath kImmSimdPath = ChooseSimdPath(std::getenv("UASCMA_SIMD"));  // after kCpuSimd (same file)
}  // namespace

SimdPath ImmSimdPath() { return kImmSimdPath; }

const char* SimdPathName(SimdPath path) {
  switch (path) {
    case SimdPath::kAvx512:
      return "avx512";
    case SimdPath::kAvx2:
      return "avx2";
    case SimdPath::kSse2:
      break;
  }
  return "sse2";
}

void StepImmLanes(SimdPath path, const ImmLaneModel& model, std::span<const double, 6> thrusts,
                  std::span<const double, 3> gyro_B, double specific_force_z_B, double dt, ImmLaneState* state) {
  switch (Supported(path)) {  // a path the CPU lacks falls back (never an illegal instruction)
    case SimdPath::kAvx512:
#ifdef UASCMA_IMM_AVX512
      return StepAvx512(model, thrusts, gyro_B, specific_force_z_B, dt, state);
#endif
    case SimdPath::kAvx2:
      return StepAvx2(model, thrusts, gyro_B, specific_force_z_B, dt, state);
    case SimdPath::kSse2:
      break;
  }
  StepSse2(model, thrusts, gyro_B, specific_force_z_B, dt, state);
}

ImmLaneArray ExpLanes(SimdPath path, const ImmLaneArray& x) {
  ImmLaneArray y;
  switch (Supported(path)) {
    case SimdPath::kAvx512:
#ifdef UASCMA_IMM_AVX512
      ExpAvx512(x, &y);
      return y;
#endif
    case SimdPath::kAvx2:
      ExpAvx2(x, &y);
      return y;
    case SimdPath::kSse2:
      break;
  }
  ExpSse2(x, &y);
  return y;
}

}  // namespace uascma::gnc
