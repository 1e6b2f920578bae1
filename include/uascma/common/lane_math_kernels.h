#pragma once
// The kernels of common/lane_math.h, written once as templates over the value type T: double (the scalar
// functions), or a GCC/Clang generic vector of 2 or 4 doubles (the lanes). Every kernel uses only IEEE add,
// subtract, multiply, divide and square root, compares, and bit operations (abs, copysign, building 2^n), and a
// branch per lane is a select between two values each computed by the same function in every instantiation (the
// scalar form may branch instead, computing only the value it selects: asin, cos). So lane i of
// the vector form is, bit for bit, the scalar form of lane i's argument, provided no operation is contracted into a
// fused multiply-add: the x86-64 baseline and `target("avx2")` have none, and the files that instantiate the lanes
// are compiled with -ffp-contract=off as well (src/common/CMakeLists.txt, bench/, tests/).
//
// Method and coefficients: scripts/fit-lane-math.py derives the two fitted polynomials (atan, asin) and the split
// constants; exp, expm1 and cos use Taylor coefficients 1/k!, computed below. Polynomials are evaluated in Estrin's
// scheme (pairs, then powers w², w⁴, w⁸), whose chains are half as long as Horner's: the latency of a dependent
// chain of calls is what an earlier Horner-form atan/asin lost to glibc's.
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace uascma::lane_math_internal {

#define UASCMA_LANE_MATH_INLINE inline __attribute__((always_inline))

// The 4-wide helpers below pass 32-byte vectors by value; they are always inlined into AVX2 functions, so no such
// value crosses a call, and GCC's note that the ABI of such a call would differ without AVX is silenced here.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

typedef double LaneMathV2 __attribute__((vector_size(16)));  // 2 lanes: SSE2
typedef double LaneMathV4 __attribute__((vector_size(32)));  // 4 lanes: AVX2
typedef std::uint64_t LaneMathU2 __attribute__((vector_size(16)));
typedef std::uint64_t LaneMathU4 __attribute__((vector_size(32)));

// The bits of a value, and back: std::uint64_t for a double, a vector of them for a vector.
UASCMA_LANE_MATH_INLINE std::uint64_t Bits(double x) { return std::bit_cast<std::uint64_t>(x); }
UASCMA_LANE_MATH_INLINE LaneMathU2 Bits(LaneMathV2 x) { return reinterpret_cast<LaneMathU2>(x); }
UASCMA_LANE_MATH_INLINE LaneMathU4 Bits(LaneMathV4 x) { return reinterpret_cast<LaneMathU4>(x); }
UASCMA_LANE_MATH_INLINE double FromBits(std::uint64_t b) { return std::bit_cast<double>(b); }
UASCMA_LANE_MATH_INLINE LaneMathV2 FromBits(LaneMathU2 b) { return reinterpret_cast<LaneMathV2>(b); }
UASCMA_LANE_MATH_INLINE LaneMathV4 FromBits(LaneMathU4 b) { return reinterpret_cast<LaneMathV4>(b); }

// IEEE square root, correctly rounded (one sqrtsd/sqrtpd per value; -fno-math-errno in Release).
UASCMA_LANE_MATH_INLINE double Sqrt(double x) { return __builtin_sqrt(x); }
UASCMA_LANE_MATH_INLINE LaneMathV2 Sqrt(LaneMathV2 x) { return LaneMathV2{__builtin_sqrt(x[0]), __builtin_sqrt(x[1])}; }
UASCMA_LANE_MATH_INLINE LaneMathV4 Sqrt(LaneMathV4 x) {
  return LaneMathV4{__builtin_sqrt(x[0]), __builtin_sqrt(x[1]), __builtin_sqrt(x[2]), __builtin_sqrt(x[3])};
}

// The lanes [first, first + the width of T) of an array of per-lane values (one value per flight or body of a
// lockstep group, models/rigid_body_lanes.h, sim/controller_lanes.h), and back.
template <typename T, std::size_t N>
UASCMA_LANE_MATH_INLINE T LoadLanes(const std::array<double, N>& a, int first) {
  T v;
  std::memcpy(&v, a.data() + first, sizeof(T));
  return v;
}
template <typename T, std::size_t N>
UASCMA_LANE_MATH_INLINE void StoreLanes(std::array<double, N>& a, int first, T v) {
  std::memcpy(a.data() + first, &v, sizeof(T));
}

// The lanes of a value: 1 for a double, 2 or 4 for a vector; lane i of it, and lane i set.
template <typename T>
inline constexpr int kLaneCount = std::is_same_v<T, double> ? 1 : static_cast<int>(sizeof(T) / sizeof(double));
template <typename T>
UASCMA_LANE_MATH_INLINE double LaneOf(const T& v, int i) {
  if constexpr (std::is_same_v<T, double>) {
    return v;
  } else {
    return v[i];
  }
}
template <typename T>
UASCMA_LANE_MATH_INLINE void SetLane(T& v, int i, double x) {
  if constexpr (std::is_same_v<T, double>) {
    v = x;
  } else {
    v[i] = x;
  }
}
// True when a compare holds in every lane (a bool for a double; a mask of all-ones/all-zeros lanes for a vector).
UASCMA_LANE_MATH_INLINE bool AllLanes(bool m) { return m; }
template <typename M>
UASCMA_LANE_MATH_INLINE bool AllLanes(M mask) {
  for (int i = 0; i < static_cast<int>(sizeof(M) / sizeof(mask[0])); ++i) {
    if (!mask[i]) return false;
  }
  return true;
}

// A 3-vector's components, one vector of lanes each, and those of an array of per-lane values [component][lane].
template <typename T>
struct Lanes3 {
  T x, y, z;
};
template <typename T, std::size_t N>
UASCMA_LANE_MATH_INLINE Lanes3<T> LoadLanes3(const std::array<std::array<double, N>, 3>& a, int first) {
  return {LoadLanes<T>(a[0], first), LoadLanes<T>(a[1], first), LoadLanes<T>(a[2], first)};
}

// std::min and std::max by their definitions, lane by lane (the same operand chosen on ties, NaN and ±0):
// min(a, b) = b < a ? b : a; max(a, b) = a < b ? b : a. std::clamp is Clamp below.
template <typename T>
UASCMA_LANE_MATH_INLINE T Min(T a, T b) {
  return b < a ? b : a;
}
template <typename T>
UASCMA_LANE_MATH_INLINE T Max(T a, T b) {
  return a < b ? b : a;
}

// A constant in every lane, bit for bit (−0 included).
template <typename T>
UASCMA_LANE_MATH_INLINE T Splat(double c) {
  if constexpr (std::is_same_v<T, double>) {
    return c;
  } else {
    T v;
    for (int i = 0; i < static_cast<int>(sizeof(T) / sizeof(double)); ++i) v[i] = c;
    return v;
  }
}

// m ? a : b, lane by lane (m: a bool for double, a compare's all-ones/all-zeros mask for a vector).
template <typename M, typename T>
UASCMA_LANE_MATH_INLINE T Select(M m, T a, T b) {
  return m ? a : b;
}

inline constexpr std::uint64_t kSignBit = 0x8000000000000000ULL;

// |x| (the sign bit cleared, as std::fabs), and |magnitude| with the sign bit of `sign` (as std::copysign).
template <typename T>
UASCMA_LANE_MATH_INLINE T Abs(T x) {
  return FromBits(Bits(x) & ~kSignBit);
}
template <typename T>
UASCMA_LANE_MATH_INLINE T CopySign(T magnitude, T sign) {
  return FromBits((Bits(magnitude) & ~kSignBit) | (Bits(sign) & kSignBit));
}
// All ones (true) where the sign bit of x is set, −0 and NaNs with the bit included (as std::signbit).
UASCMA_LANE_MATH_INLINE bool SignBit(double x) { return (Bits(x) & kSignBit) != 0; }
template <typename T>
UASCMA_LANE_MATH_INLINE auto SignBit(T x) {
  return (Bits(x) & kSignBit) != 0;
}

// c[0] + c[1] w + … + c[N−1] w^(N−1) in Estrin's scheme: pairs c[2i] + c[2i+1] w, then pairs of pairs with w², …
template <typename T, std::size_t N>
UASCMA_LANE_MATH_INLINE T Estrin(const std::array<double, N>& c, T w) {
  static_assert(N >= 2 && N <= 16);
  constexpr std::size_t kPairs = (N + 1) / 2;
  std::array<T, kPairs> level;
  for (std::size_t i = 0; i < kPairs; ++i) {
    level[i] = 2 * i + 1 < N ? c[2 * i] + c[2 * i + 1] * w : Splat<T>(c[2 * i]);
  }
  T power = w * w;
  std::size_t count = kPairs;
  while (count > 1) {
    const std::size_t next = (count + 1) / 2;
    for (std::size_t i = 0; i < next; ++i)
      level[i] = 2 * i + 1 < count ? level[2 * i] + level[2 * i + 1] * power : level[2 * i];
    count = next;
    if (count > 1) power = power * power;
  }
  return level[0];
}

// sign_i / k_i! for k_i = first + step i, i = 0…N − 1; sign_0 = first_sign, and the signs alternate if `alternate`.
// The factorials are exact (17! < 2^53 · 2^15, its powers of 2 being exact), each coefficient rounded once.
template <std::size_t N>
constexpr std::array<double, N> InverseFactorials(int first, int step, double first_sign, bool alternate) {
  std::array<double, N> c{};
  double factorial = 1.0;  // done!
  int done = 1;
  for (std::size_t i = 0; i < N; ++i) {
    const int k = first + step * static_cast<int>(i);
    while (done < k) factorial *= ++done;
    c[i] = (alternate && i % 2 == 1 ? -first_sign : first_sign) / factorial;
  }
  return c;
}

// ---- atan, atan2 -------------------------------------------------------------------------------------------------
// atan(u) = u + u³ P(u²) on |u| ≤ 1/2; P of degree 11 (scripts/fit-lane-math.py; the fit's relative error 1.9e-17).
inline constexpr std::array<double, 12> kAtanP = {-0.33333333333333326, 0.19999999999991946,  -0.14285714284161036,
                                                  0.11111110993533425,  -0.09090904478307565, 0.07692200457455081,
                                                  -0.06665076103480587, 0.058666698188609624, -0.051583442406897405,
                                                  0.04286039309906242,  -0.02899485437704136, 0.011182897447526905};
inline constexpr double kQuarterPiHigh = 0x1.921fb54442d18p-1;  // π/4 rounded (50 significant bits: 3·it is exact)
inline constexpr double kQuarterPiLow = 0x1.1a62633145c07p-55;  // π/4 − kQuarterPiHigh

// atan2(ay, ax) for ay, ax ≥ 0 (or NaN), then reflected: π − it where x_negative, and the sign of y. With
// a = min(ay, ax), b = max(ay, ax): atan(a/b) is atan(u), u = a/b ≤ 1/2, if a ≤ b/2, else π/4 + atan(u) with
// u = (a − b)/(a + b) ∈ (−1/3, 0], whose numerator is exact there (b/2 < a ≤ b; one division either way); above the
// diagonal the angle is π/2 − that, left of the axis π − that. So the angle is m π/4 + s atan(u), m ∈ {0…4}, s = ±1,
// summed as m π/4_high + (s u + (s u w P + m π/4_low)).
template <typename T, typename M>
UASCMA_LANE_MATH_INLINE T Atan2Reflected(T ay, T ax, M x_negative, T y) {
  const auto swap = ay > ax;
  const T a = Select(swap, ax, ay);
  const T b = Select(swap, ay, ax);
  const auto reduce = a > 0.5 * b;
  const T numerator = Select(reduce, a - b, a);
  const T sum = a + b;
  const T denominator = Select(reduce, sum, b);
  // 0/0 only for a = b = 0, the angle 0 (or π); a denominator of 1 there keeps the lane finite.
  const T u = numerator / Select(sum == 0.0, Splat<T>(1.0), denominator);
  const T m0 = Select(reduce, Splat<T>(1.0), Splat<T>(0.0));
  const T m1 = Select(swap, 2.0 - m0, m0);
  const T m = Select(x_negative, 4.0 - m1, m1);
  const T s1 = Select(swap, Splat<T>(-1.0), Splat<T>(1.0));
  const T s = Select(x_negative, -s1, s1);
  const T su = s * u;
  const T w = u * u;
  const T tail = su * (w * Estrin(kAtanP, w));
  const T angle = m * kQuarterPiHigh + (su + (tail + m * kQuarterPiLow));
  return CopySign(angle, y);
}

template <typename T>
UASCMA_LANE_MATH_INLINE T Atan2Kernel(T y, T x) {
  return Atan2Reflected(Abs(y), Abs(x), SignBit(x), y);
}

template <typename T>
UASCMA_LANE_MATH_INLINE T AtanKernel(T x) {
  return Atan2Reflected(Abs(x), Splat<T>(1.0), SignBit(Splat<T>(1.0)), x);
}

// ---- asin --------------------------------------------------------------------------------------------------------
// asin(r) = r + r³ P(r²) on 0 ≤ r ≤ 1/2; P of degree 12 (scripts/fit-lane-math.py; the fit's relative error 5e-18).
inline constexpr std::array<double, 13> kAsinP = {
    0.16666666666666669,  0.0749999999999834,    0.04464285714653523,  0.03038194412500875, 0.022372173467043486,
    0.017352380709839098, 0.01397138708310213,   0.011477517005507167, 0.01033337215296726, 0.005413184483715509,
    0.01751883397953867,  -0.015032162599250314, 0.028878362746452394};
inline constexpr double kHalfPiLow = 0x1.1a62633145c07p-54;  // π/2 − (π/2 rounded)

// |s| ≤ 1/2: asin(|s|) = |s| + |s| z P(z), z = s². Above: asin(|s|) = π/2 − 2 asin(r), r = √z, z = (1 − |s|)/2
// (exact), with r's rounding corrected as in fdlibm's e_asin.c: r_high = r with its 32 low bits cleared,
// c = (z − r_high²)/(r + r_high), asin = π/4 − ((2 r z P − (π/2_low − 2c)) − (π/4 − 2 r_high)). In lanes z is
// selected first and z P(z) evaluated once; both forms are then completed (the large one with a square root and a
// division) and each lane's own one selected. The scalar form branches and computes only its own z and form, with the
// same operations, hence the same bits.
template <typename T>
UASCMA_LANE_MATH_INLINE T AsinZp(T z) {
  return z * Estrin(kAsinP, z);
}
template <typename T>
UASCMA_LANE_MATH_INLINE T AsinOfSmall(T as, T zp) {  // |s| ≤ 1/2, zp = z P(z) with z = s²
  return as + as * zp;
}
template <typename T>
UASCMA_LANE_MATH_INLINE T AsinOfLarge(T z, T zp) {  // |s| > 1/2, zp = z P(z) with z = (1 − |s|)/2
  const T r = Sqrt(z);
  const T r_high = FromBits(Bits(r) & 0xffffffff00000000ULL);
  const T r_sum = r + r_high;
  const T c = (z - r_high * r_high) / Select(r_sum == 0.0, Splat<T>(1.0), r_sum);  // |s| = 1: r = 0, c = 0
  const T p = 2.0 * r * zp - (kHalfPiLow - 2.0 * c);
  const T q = kQuarterPiHigh - 2.0 * r_high;
  return kQuarterPiHigh - (p - q);
}

template <typename T>
UASCMA_LANE_MATH_INLINE T AsinKernel(T s) {
  const T as = Abs(s);
  if constexpr (std::is_same_v<T, double>) {
    if (as <= 0.5) {
      const T z = as * as;
      return CopySign(AsinOfSmall(as, AsinZp(z)), s);
    }
    const T z = (1.0 - as) * 0.5;  // NaN comes here, and stays NaN
    return CopySign(AsinOfLarge(z, AsinZp(z)), s);
  } else {
    const auto small = as <= 0.5;
    const T z = Select(small, as * as, (1.0 - as) * 0.5);
    const T zp = AsinZp(z);
    return CopySign(Select(small, AsinOfSmall(as, zp), AsinOfLarge(z, zp)), s);
  }
}

// ---- exp, expm1 --------------------------------------------------------------------------------------------------
// x = n ln 2 + r, n = round(x / ln 2) (adding 1.5·2^52 rounds to an integer kept in the sum's low bits), |r| ≤ ln 2/2;
// ln 2 = kLn2High (32 leading bits: a = x − n kLn2High is exact for |n| < 2^21) + kLn2Low, r = a − n kLn2Low rounded
// and r_low = (a − r) − n kLn2Low its rounding error. e^r − 1 = r + (r_low + r² Q(r)), Q(r) = Σ r^k/(k + 2)!,
// k = 0…11 (to r^13: the first term left out, r^14/14!, is 4e-18 relative, 1/50 of an ulp). expm1 sums
// 2^n (e^r − 1) + (2^n − 1) as ((2^n − 1) + 2^n r) + 2^n (r_low + r² Q): where n = 1 and r < 0 the leading sum,
// 1 + 2r, is exact and the cancellation (1 + 2r ≥ 0.3) costs nothing.
inline constexpr double kLn2High = 0x1.62e42feep-1;
inline constexpr double kLn2Low = 0x1.a39ef35793c76p-33;
inline constexpr double kLog2e = 0x1.71547652b82fep0;
inline constexpr double kRoundingShift = 0x1.8p52;
inline constexpr std::array<double, 12> kExpQ = InverseFactorials<12>(2, 1, 1.0, false);
// 2^n is built in the exponent bits, which hold normal numbers only: beyond ±700, 2^(n ∓ 64) is built and the result
// multiplied by 2^±64 at the end (one rounding, the only one, into the subnormals or to infinity).
inline constexpr double kExpScaledBeyond = 700.0;
inline constexpr std::uint64_t kExpScaleShift = std::uint64_t{64} << 52;
inline constexpr double kTwoTo64 = 0x1p64;
inline constexpr double kTwoToMinus64 = 0x1p-64;

// The reduction of x (clamped first: NaN passes, its compares being false), e^r − 1 in parts and the scale 2^n.
template <typename T>
struct ExpParts {
  T r;         // the reduced argument, rounded
  T tail;      // r_low + r² Q(r): e^r − 1 = r + tail
  T two_n;     // 2^n, or 2^(n − 64) above +700, 2^(n + 64) below −700
  T post;      // 1, or 2^64 above +700, 2^−64 below −700
  T post_inv;  // 1, or 2^−64 above +700, 2^64 below −700
};

template <typename T>
UASCMA_LANE_MATH_INLINE ExpParts<T> ExpReduce(T x) {
  const T shifted = x * kLog2e + kRoundingShift;  // 1.5·2^52 + n
  const T n = shifted - kRoundingShift;
  const T a = x - n * kLn2High;
  const T n_low = n * kLn2Low;
  ExpParts<T> parts;
  parts.r = a - n_low;
  parts.tail = ((a - parts.r) - n_low) + (parts.r * parts.r) * Estrin(kExpQ, parts.r);
  const auto upper = x > kExpScaledBeyond;
  const auto lower = x < -kExpScaledBeyond;
  // n·2^52 (the leading bits of the shifted sum fall off) added to the bits of 1.0 is 2^n.
  auto bits = Bits(Splat<T>(1.0)) + (Bits(shifted) << 52);
  bits = Select(upper, bits - kExpScaleShift, Select(lower, bits + kExpScaleShift, bits));
  parts.two_n = FromBits(bits);
  parts.post = Select(upper, Splat<T>(kTwoTo64), Select(lower, Splat<T>(kTwoToMinus64), Splat<T>(1.0)));
  parts.post_inv = Select(upper, Splat<T>(kTwoToMinus64), Select(lower, Splat<T>(kTwoTo64), Splat<T>(1.0)));
  return parts;
}

inline constexpr double kExpHighest = 710.0;   // e^710 > the largest double: +∞ from here on
inline constexpr double kExpLowest = -746.0;   // e^−746 < half the least subnormal: 0 from here on
inline constexpr double kExpm1Lowest = -40.0;  // e^−40 < 2^−54: expm1 = −1 from here on

// std::clamp(x, lowest, highest), lane by lane: x < lowest ? lowest : (highest < x ? highest : x).
template <typename T>
UASCMA_LANE_MATH_INLINE T Clamp(T x, double lowest, double highest) {
  return Select(x < lowest, Splat<T>(lowest), Select(x > highest, Splat<T>(highest), x));
}

template <typename T>
UASCMA_LANE_MATH_INLINE T ExpKernel(T x) {
  const ExpParts<T> e = ExpReduce(Clamp(x, kExpLowest, kExpHighest));
  const T result = ((1.0 + (e.r + e.tail)) * e.two_n) * e.post;
  return Select(x != x, x, result);  // NaN (any payload) stays NaN
}

// expm1 = 2^n (e^r − 1) + (2^n − 1), summed as above; n = 0 for |x| < ln 2/2, where it is r + tail. expm1(±0) = ±0.
template <typename T>
UASCMA_LANE_MATH_INLINE T Expm1Kernel(T x) {
  const ExpParts<T> e = ExpReduce(Clamp(x, kExpm1Lowest, kExpHighest));
  const T result = (((e.two_n - e.post_inv) + e.two_n * e.r) + e.two_n * e.tail) * e.post;
  return Select(x != x, x, Select(x == 0.0, x, result));
}

// ---- cos ---------------------------------------------------------------------------------------------------------
// |x| = n π/2 + r, n = round(|x| 2/π), r = ((|x| − n P1) − n P2) − n P3 (Cody and Waite: P1, P2 the leading 33 and
// next 33 bits of π/2, so n P1 and n P2 are exact for n < 2^20; P3 the rest), |r| ≤ π/4. sin r = r + r z S(z) and
// cos r = 1 − z/2 + z² C(z), z = r², by Taylor to r^17 and r^16 (the first terms left out, r^19/19! and r^18/18!,
// are below 1.1e-19 and 2e-18 relative); 1 − z/2 summed as w + ((1 − w) − z/2) (fdlibm's k_cos.c) with w = 1 − z/2.
// cos x = cos r, −sin r, −cos r, sin r for n mod 4 = 0, 1, 2, 3.
inline constexpr double kTwoOverPi = 0x1.45f306dc9c883p-1;
inline constexpr double kHalfPi1 = 0x1.921fb544p+0;
inline constexpr double kHalfPi2 = 0x1.0b4611a6p-34;
inline constexpr double kHalfPi3 = 0x1.3198a2e037073p-69;
inline constexpr double kCosLargest = 1e6;  // n < 2^20 (ours: far beyond what the step asks); above: NaN
inline constexpr std::array<double, 8> kSinS = InverseFactorials<8>(3, 2, -1.0, true);  // −1/3!, 1/5!, … 1/17!
inline constexpr std::array<double, 7> kCosC = InverseFactorials<7>(4, 2, 1.0, true);   // 1/4!, −1/6!, … 1/16!

template <typename T>
UASCMA_LANE_MATH_INLINE T SinOfReduced(T r, T z) {
  return r + (r * z) * Estrin(kSinS, z);
}
template <typename T>
UASCMA_LANE_MATH_INLINE T CosOfReduced(T z) {
  const T half_z = 0.5 * z;
  const T w = 1.0 - half_z;
  return w + (((1.0 - w) - half_z) + (z * z) * Estrin(kCosC, z));
}

// In lanes sin r and cos r are both computed and each lane's selected; the scalar form branches (the same bits).
template <typename T>
UASCMA_LANE_MATH_INLINE T CosKernel(T x) {
  const T ax = Abs(x);
  const T shifted = ax * kTwoOverPi + kRoundingShift;
  const T n = shifted - kRoundingShift;
  const auto quadrant = Bits(shifted);
  T value;
  if constexpr (std::is_same_v<T, double>) {
    // n = 0 (|x| ≲ π/4, the step's tilts): the reduction gives r = |x| exactly ((|x| − 0) − 0 − 0), taken directly.
    if (n == 0.0) return CosOfReduced(ax * ax);
    const T r = ((ax - n * kHalfPi1) - n * kHalfPi2) - n * kHalfPi3;
    const T z = r * r;
    value = (quadrant & 1) != 0 ? SinOfReduced(r, z) : CosOfReduced(z);
  } else {
    const T r = ((ax - n * kHalfPi1) - n * kHalfPi2) - n * kHalfPi3;
    const T z = r * r;
    value = Select((quadrant & 1) != 0, SinOfReduced(r, z), CosOfReduced(z));
  }
  const T result = Select(((quadrant + 1) & 2) != 0, -value, value);
  return Select(ax > kCosLargest, Splat<T>(__builtin_nan("")), result);
}

#pragma GCC diagnostic pop

}  // namespace uascma::lane_math_internal
