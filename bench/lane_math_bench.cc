// Our asin, atan, atan2, cos, exp and expm1 (common/lane_math.h) against glibc's, per evaluation (for lockstep:
// does evaluating four flights' functions in lanes pay?). For each function, 256 groups of 4 arguments drawn in the
// ranges the 200 Hz step uses, evaluated as
//   libm:      glibc's scalar function, 4 calls per group (the ifunc variant the CPU selects: _fma on this machine);
//   ours:      our scalar function (inlined), 4 per group;
//   sse2:      our kernel on two 2-wide vectors per group, inlined (the x86-64 baseline);
//   avx2:      our kernel on one 4-wide vector per group, inlined in a target("avx2") function;
//   dispatch:  the out-of-line Asin4(path, …) of lane_math.h on the default path (a call per group), its arguments
//              read in place from the table (structure of arrays). Copying them first into a local Lanes4 (two 16-byte
//              stores in the SSE2 caller, one 32-byte load in the AVX2 callee) stalled the load: measured 7.0 ns per
//              evaluation instead of 3.6 for asin and exp (store-to-load forwarding fails across the widths);
// in two patterns:
//   Throughput: the groups are independent (the out-of-order core overlaps consecutive evaluations);
//   Chain:      group k's arguments are table_k + 2^−20 · (group k − 1's results), so each lane is a dependent chain
//               (four independent chains for 4 lanes: four flights in lockstep, each waiting on its own last value);
//   Chain1:     (libm and ours only) one chain through all 1,024 arguments: a flight flown alone.
// Counters: ns per evaluation ("ns_per_eval"), and per group of 4 ("ns_per_4"); for Chain1, per evaluation.
// The file is compiled with -fno-tree-loop-vectorize (bench/CMakeLists.txt), so that the scalar loops stay scalar
// (one flight's step calls each function once, never in a loop the compiler could vectorise).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

#include "uascma/common/lane_math.h"
#include "uascma/common/random.h"

namespace {

using namespace uascma;
using lane_math::Lanes4;
using lane_math_internal::LaneMathV2;
using lane_math_internal::LaneMathV4;

constexpr int kGroups = 256;
constexpr int kValues = 4 * kGroups;
constexpr double kChainWeight = 0x1p-20;  // exact scaling: the chain's argument stays within 2^-19 of the table's

// The arguments of one function (x unused by the functions of one argument).
struct Table {
  std::vector<double> y = std::vector<double>(kValues);
  std::vector<double> x = std::vector<double>(kValues);
};

// The step's ranges (src/gnc/lqr.cc, src/models/rigid_body.cc, src/gnc/imm.cc, src/prognostics/eod.cc): asin of
// sin(pitch) (tilt ≤ 0.6 rad) and of the flow incidence, |.| ≤ 0.6; atan of the tilt references −a_x / (g − a_z), |.| ≲
// 1; atan2 of R_WB's entries (any angle on the unit circle); cos of a reference tilt within the 0.6 rad limit; exp of a
// likelihood exponent −q/2 (−10…0); expm1 of an EOD segment's −q t (−2…0).
// A function of one argument (x unused), its arguments uniform in [low, high].
#define UASCMA_UNARY_FUNCTION(NAME, LIBM, OURS, KERNEL, LANES, LOW, HIGH)                          \
  struct NAME {                                                                                    \
    static double Libm(double y, double) { return LIBM(y); }                                       \
    static double Ours(double y, double) { return lane_math::OURS(y); }                            \
    template <typename T>                                                                          \
    UASCMA_LANE_MATH_INLINE static T Kernel(T y, T) {                                              \
      return lane_math_internal::KERNEL(y);                                                        \
    }                                                                                              \
    static Lanes4 Dispatch(lane_math::LaneMathPath path, const Lanes4& y, const Lanes4&) {         \
      return lane_math::LANES(path, y);                                                            \
    }                                                                                              \
    static void Fill(RandomStream& random, double* y, double*) { *y = random.Uniform(LOW, HIGH); } \
  };
UASCMA_UNARY_FUNCTION(AsinFunction, std::asin, Asin, AsinKernel, Asin4, -0.6, 0.6)
UASCMA_UNARY_FUNCTION(AtanFunction, std::atan, Atan, AtanKernel, Atan4, -1.0, 1.0)
UASCMA_UNARY_FUNCTION(CosFunction, std::cos, Cos, CosKernel, Cos4, -0.6, 0.6)
UASCMA_UNARY_FUNCTION(ExpFunction, std::exp, Exp, ExpKernel, Exp4, -10.0, 0.0)
UASCMA_UNARY_FUNCTION(Expm1Function, std::expm1, Expm1, Expm1Kernel, Expm1_4, -2.0, 0.0)
#undef UASCMA_UNARY_FUNCTION
struct Atan2Function {
  static double Libm(double y, double x) { return std::atan2(y, x); }
  static double Ours(double y, double x) { return lane_math::Atan2(y, x); }
  template <typename T>
  UASCMA_LANE_MATH_INLINE static T Kernel(T y, T x) {
    return lane_math_internal::Atan2Kernel(y, x);
  }
  static Lanes4 Dispatch(lane_math::LaneMathPath path, const Lanes4& y, const Lanes4& x) {
    return lane_math::Atan2_4(path, y, x);
  }
  static void Fill(RandomStream& random, double* y, double* x) {
    const double angle = random.Uniform(-std::numbers::pi, std::numbers::pi);
    *y = std::sin(angle);
    *x = std::cos(angle);
  }
};

template <typename F>
const Table& TableOf() {
  static const Table table = [] {
    Table t;
    RandomStream random(27);
    for (int i = 0; i < kValues; ++i) F::Fill(random, &t.y[i], &t.x[i]);
    return t;
  }();
  return table;
}

UASCMA_LANE_MATH_INLINE LaneMathV2 Load2(const double* p) {
  LaneMathV2 v;
  std::memcpy(&v, p, sizeof(v));
  return v;
}
UASCMA_LANE_MATH_INLINE void Store2(LaneMathV2 v, double* p) { std::memcpy(p, &v, sizeof(v)); }
UASCMA_LANE_MATH_INLINE LaneMathV4 Load4(const double* p) {
  LaneMathV4 v;
  std::memcpy(&v, p, sizeof(v));
  return v;
}
UASCMA_LANE_MATH_INLINE void Store4(LaneMathV4 v, double* p) { std::memcpy(p, &v, sizeof(v)); }

enum Variant { kLibm, kOurs, kSse2, kAvx2, kDispatch };
constexpr const char* kVariantNames[] = {"libm", "ours", "sse2", "avx2", "dispatch"};

// ---- independent groups (not inlined into the benchmark loop, so that callgrind counts each variant apart) ----
template <typename F, bool kLibm>
__attribute__((noinline)) void ThroughputScalar(const Table& t, double* out) {
  for (int i = 0; i < kValues; ++i) out[i] = kLibm ? F::Libm(t.y[i], t.x[i]) : F::Ours(t.y[i], t.x[i]);
}
template <typename F>
__attribute__((noinline)) void ThroughputSse2(const Table& t, double* out) {
  for (int i = 0; i < kValues; i += 2) Store2(F::Kernel(Load2(&t.y[i]), Load2(&t.x[i])), out + i);
}
template <typename F>
__attribute__((target("avx2"), noinline)) void ThroughputAvx2(const Table& t, double* out) {
  for (int i = 0; i < kValues; i += 4) Store4(F::Kernel(Load4(&t.y[i]), Load4(&t.x[i])), out + i);
}
template <typename F>
__attribute__((noinline)) void ThroughputDispatch(const Table& t, double* out) {
  const lane_math::LaneMathPath path = lane_math::DefaultLaneMathPath();
  for (int i = 0; i < kValues; i += 4) {
    const Lanes4& y = *reinterpret_cast<const Lanes4*>(&t.y[i]);
    const Lanes4& x = *reinterpret_cast<const Lanes4*>(&t.x[i]);
    const Lanes4 r = F::Dispatch(path, y, x);
    std::memcpy(out + i, r.data(), sizeof(r));
  }
}

// ---- four dependent chains (group k's arguments depend on group k − 1's results) ----
template <typename F>
double ChainScalar(bool libm, const Table& t) {
  double v[4] = {0.0, 0.0, 0.0, 0.0};
  for (int i = 0; i < kValues; i += 4) {
    for (int lane = 0; lane < 4; ++lane) {
      const double y = t.y[i + lane] + v[lane] * kChainWeight;
      v[lane] = libm ? F::Libm(y, t.x[i + lane]) : F::Ours(y, t.x[i + lane]);
    }
  }
  return v[0] + v[1] + v[2] + v[3];
}
template <typename F>
double ChainSse2(const Table& t) {
  LaneMathV2 low{}, high{};
  for (int i = 0; i < kValues; i += 4) {
    low = F::Kernel(Load2(&t.y[i]) + low * kChainWeight, Load2(&t.x[i]));
    high = F::Kernel(Load2(&t.y[i + 2]) + high * kChainWeight, Load2(&t.x[i + 2]));
  }
  return low[0] + low[1] + high[0] + high[1];
}
template <typename F>
__attribute__((target("avx2"))) double ChainAvx2(const Table& t) {
  LaneMathV4 v{};
  for (int i = 0; i < kValues; i += 4) v = F::Kernel(Load4(&t.y[i]) + v * kChainWeight, Load4(&t.x[i]));
  return v[0] + v[1] + v[2] + v[3];
}
template <typename F>
double ChainDispatch(const Table& t) {
  const lane_math::LaneMathPath path = lane_math::DefaultLaneMathPath();
  Lanes4 v{};
  for (int i = 0; i < kValues; i += 4) {
    Lanes4 y, x;
    for (int lane = 0; lane < 4; ++lane) {
      y[lane] = t.y[i + lane] + v[lane] * kChainWeight;
      x[lane] = t.x[i + lane];
    }
    v = F::Dispatch(path, y, x);
  }
  return v[0] + v[1] + v[2] + v[3];
}
// One chain through every argument: a flight flown alone.
template <typename F>
double ChainOne(bool libm, const Table& t) {
  double v = 0.0;
  for (int i = 0; i < kValues; ++i) {
    const double y = t.y[i] + v * kChainWeight;
    v = libm ? F::Libm(y, t.x[i]) : F::Ours(y, t.x[i]);
  }
  return v;
}

// Counters in ns: a value v with kIsIterationInvariantRate | kInvert prints time / (v · iterations).
void Report(benchmark::State& state, int evaluations_per_iteration) {
  const auto kNsPer = benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert;
  state.counters["ns_per_eval"] = benchmark::Counter(evaluations_per_iteration * 1e-9, kNsPer);
  state.counters["ns_per_4"] = benchmark::Counter(evaluations_per_iteration / 4.0 * 1e-9, kNsPer);
  state.SetLabel(kVariantNames[state.range(0)]);
}

bool SkipWithoutAvx2(benchmark::State& state) {
  if (state.range(0) == kAvx2 && !lane_math::LaneMathPathSupported(lane_math::LaneMathPath::kAvx2)) {
    state.SkipWithError("this CPU lacks AVX2");
    return true;
  }
  return false;
}

template <typename F>
void BM_Throughput(benchmark::State& state) {
  if (SkipWithoutAvx2(state)) return;
  const Table& t = TableOf<F>();
  std::vector<double> out(kValues);
  for (auto _ : state) {
    switch (state.range(0)) {
      case kLibm:
        ThroughputScalar<F, true>(t, out.data());
        break;
      case kOurs:
        ThroughputScalar<F, false>(t, out.data());
        break;
      case kSse2:
        ThroughputSse2<F>(t, out.data());
        break;
      case kAvx2:
        ThroughputAvx2<F>(t, out.data());
        break;
      default:
        ThroughputDispatch<F>(t, out.data());
    }
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  Report(state, kValues);
}

template <typename F>
void BM_Chain(benchmark::State& state) {
  if (SkipWithoutAvx2(state)) return;
  const Table& t = TableOf<F>();
  for (auto _ : state) {
    double result;
    switch (state.range(0)) {
      case kLibm:
      case kOurs:
        result = ChainScalar<F>(state.range(0) == kLibm, t);
        break;
      case kSse2:
        result = ChainSse2<F>(t);
        break;
      case kAvx2:
        result = ChainAvx2<F>(t);
        break;
      default:
        result = ChainDispatch<F>(t);
    }
    benchmark::DoNotOptimize(result);
  }
  Report(state, kValues);
}

template <typename F>
void BM_Chain1(benchmark::State& state) {
  const Table& t = TableOf<F>();
  for (auto _ : state) {
    const double result = ChainOne<F>(state.range(0) == kLibm, t);
    benchmark::DoNotOptimize(result);
  }
  Report(state, kValues);
}

// ---- the step's mix: the transcendental calls of one 200 Hz step of one flight, four flights at a time ----
// Per flight and step (src/gnc/lqr.cc, src/models/rigid_body.cc; callgrind counts ~2.5 asin per step): roll =
// atan2(R21, R22), yaw = atan2(R10, R00), pitch = asin(−R20), one flow incidence asin, pitch_ref = atan(−a_x/G),
// roll_ref = atan(a_y cos(pitch_ref)/G): 7 calls, 6 independent chains but the reference tilt's atan → cos → atan. Each
// flight's next step depends on its last (its arguments are the table's plus 2^−20 times the sum of its last
// results), as a flight's state does; the four flights are independent. Counter: ns per flight-step (7 calls).
constexpr int kMixArguments = 8;  // R21, R22, R10, R00, −R20, incidence sine, −a_x/G, a_y/G
constexpr int kMixSteps = 256;

struct MixTable {
  std::vector<double> a = std::vector<double>(kMixSteps * kMixArguments * 4);  // [step][argument][flight]
};
const MixTable& MixTableOf() {
  static const MixTable table = [] {
    MixTable t;
    RandomStream random(31);
    for (int step = 0; step < kMixSteps; ++step) {
      for (int flight = 0; flight < 4; ++flight) {
        double* a = &t.a[step * kMixArguments * 4 + flight];
        const double roll = random.Uniform(-0.6, 0.6), pitch = random.Uniform(-0.6, 0.6);
        const double yaw = random.Uniform(-std::numbers::pi, std::numbers::pi);
        a[0] = std::sin(roll) * std::cos(pitch);  // R21, R22, R10, R00 and −R20 of a Z-Y-X attitude
        a[4] = std::cos(roll) * std::cos(pitch);
        a[8] = std::sin(yaw) * std::cos(pitch);
        a[12] = std::cos(yaw) * std::cos(pitch);
        a[16] = std::sin(pitch);
        a[20] = random.Uniform(-0.6, 0.6);
        a[24] = random.Uniform(-0.7, 0.7);
        a[28] = random.Uniform(-0.7, 0.7);
      }
    }
    return t;
  }();
  return table;
}

struct LibmMath {
  static double Atan2(double y, double x) { return std::atan2(y, x); }
  static double Asin(double x) { return std::asin(x); }
  static double Atan(double x) { return std::atan(x); }
  static double Cos(double x) { return std::cos(x); }
};
struct OurMath {
  template <typename T>
  UASCMA_LANE_MATH_INLINE static T Atan2(T y, T x) {
    return lane_math_internal::Atan2Kernel(y, x);
  }
  template <typename T>
  UASCMA_LANE_MATH_INLINE static T Asin(T x) {
    return lane_math_internal::AsinKernel(x);
  }
  template <typename T>
  UASCMA_LANE_MATH_INLINE static T Atan(T x) {
    return lane_math_internal::AtanKernel(x);
  }
  template <typename T>
  UASCMA_LANE_MATH_INLINE static T Cos(T x) {
    return lane_math_internal::CosKernel(x);
  }
};

// One step of the flights whose arguments are a[0], a[lanes], …, given their last results' sum `last`.
template <typename M, typename T, typename LoadFn>
UASCMA_LANE_MATH_INLINE T MixStep(LoadFn load, T last) {
  const T e = last * kChainWeight;
  const T roll = M::Atan2(load(0) + e, load(1));
  const T yaw = M::Atan2(load(2) + e, load(3));
  const T pitch = M::Asin(load(4) + e);
  const T incidence = M::Asin(load(5) + e);
  const T pitch_ref = M::Atan(load(6) + e);
  const T roll_ref = M::Atan(load(7) * M::Cos(pitch_ref));
  return ((roll + yaw) + (pitch + incidence)) + (pitch_ref + roll_ref);
}

template <typename M>
__attribute__((noinline)) double MixScalar(const MixTable& t) {
  double last[4] = {0.0, 0.0, 0.0, 0.0};
  for (int step = 0; step < kMixSteps; ++step) {
    for (int flight = 0; flight < 4; ++flight) {
      const double* a = &t.a[step * kMixArguments * 4 + flight];
      last[flight] = MixStep<M>([a](int k) { return a[4 * k]; }, last[flight]);
    }
  }
  return last[0] + last[1] + last[2] + last[3];
}
__attribute__((noinline)) double MixSse2(const MixTable& t) {
  LaneMathV2 low{}, high{};
  for (int step = 0; step < kMixSteps; ++step) {
    const double* a = &t.a[step * kMixArguments * 4];
    low = MixStep<OurMath>([a](int k) { return Load2(a + 4 * k); }, low);
    high = MixStep<OurMath>([a](int k) { return Load2(a + 4 * k + 2); }, high);
  }
  return low[0] + low[1] + high[0] + high[1];
}
__attribute__((target("avx2"), noinline)) double MixAvx2(const MixTable& t) {
  LaneMathV4 v{};
  for (int step = 0; step < kMixSteps; ++step) {
    const double* a = &t.a[step * kMixArguments * 4];
    v = MixStep<OurMath>(
        [a](int k) __attribute__((always_inline)) { return Load4(a + 4 * k); }, v);
  }
  return v[0] + v[1] + v[2] + v[3];
}

void BM_StepMix(benchmark::State& state) {
  if (SkipWithoutAvx2(state)) return;
  const MixTable& t = MixTableOf();
  for (auto _ : state) {
    double result;
    switch (state.range(0)) {
      case kLibm:
        result = MixScalar<LibmMath>(t);
        break;
      case kOurs:
        result = MixScalar<OurMath>(t);
        break;
      case kSse2:
        result = MixSse2(t);
        break;
      default:
        result = MixAvx2(t);
    }
    benchmark::DoNotOptimize(result);
  }
  state.counters["ns_per_flight_step"] = benchmark::Counter(
      4 * kMixSteps * 1e-9, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.SetLabel(kVariantNames[state.range(0)]);
}
BENCHMARK(BM_StepMix)->ArgName("variant")->DenseRange(kLibm, kAvx2);

#define UASCMA_LANE_MATH_BENCH(FUNCTION)                                                         \
  BENCHMARK_TEMPLATE(BM_Throughput, FUNCTION)->ArgName("variant")->DenseRange(kLibm, kDispatch); \
  BENCHMARK_TEMPLATE(BM_Chain, FUNCTION)->ArgName("variant")->DenseRange(kLibm, kDispatch);      \
  BENCHMARK_TEMPLATE(BM_Chain1, FUNCTION)->ArgName("variant")->DenseRange(kLibm, kOurs);
UASCMA_LANE_MATH_BENCH(AsinFunction)
UASCMA_LANE_MATH_BENCH(AtanFunction)
UASCMA_LANE_MATH_BENCH(Atan2Function)
UASCMA_LANE_MATH_BENCH(CosFunction)
UASCMA_LANE_MATH_BENCH(ExpFunction)
UASCMA_LANE_MATH_BENCH(Expm1Function)
#undef UASCMA_LANE_MATH_BENCH

}  // namespace

BENCHMARK_MAIN();
