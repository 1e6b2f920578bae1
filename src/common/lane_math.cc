// The four-lane forms of common/lane_math.h: the kernels of common/lane_math_kernels.h instantiated on two 2-wide
// vectors (the x86-64 baseline: SSE2) and, through a target attribute, on one 4-wide vector (AVX2). Compiled with
// -ffp-contract=off, out of the unity files and without the precompiled header (src/common/CMakeLists.txt; the same
// reasons as gnc/imm_lanes.cc), so that no multiply and add are fused on either path.
#include "uascma/common/lane_math.h"

#include <cstdlib>
#include <cstring>

namespace uascma::lane_math {
namespace {

using lane_math_internal::LaneMathV2;
using lane_math_internal::LaneMathV4;

UASCMA_LANE_MATH_INLINE LaneMathV2 LoadLow(const Lanes4& x) { return LaneMathV2{x[0], x[1]}; }
UASCMA_LANE_MATH_INLINE LaneMathV2 LoadHigh(const Lanes4& x) { return LaneMathV2{x[2], x[3]}; }
UASCMA_LANE_MATH_INLINE Lanes4 Join(LaneMathV2 low, LaneMathV2 high) { return {low[0], low[1], high[0], high[1]}; }
UASCMA_LANE_MATH_INLINE LaneMathV4 Load4(const Lanes4& x) {
  LaneMathV4 v;
  std::memcpy(&v, x.data(), sizeof(v));
  return v;
}
UASCMA_LANE_MATH_INLINE Lanes4 Store4(LaneMathV4 v) {
  Lanes4 x;
  std::memcpy(x.data(), &v, sizeof(v));
  return x;
}

// One function of one argument on both paths: KERNEL on two 2-wide vectors, and on one 4-wide vector.
#define UASCMA_LANE_MATH_UNARY(NAME, KERNEL)                                                      \
  Lanes4 NAME##Sse2(const Lanes4& x) {                                                            \
    return Join(lane_math_internal::KERNEL(LoadLow(x)), lane_math_internal::KERNEL(LoadHigh(x))); \
  }                                                                                               \
  __attribute__((target("avx2"))) Lanes4 NAME##Avx2(const Lanes4& x) {                            \
    return Store4(lane_math_internal::KERNEL(Load4(x)));                                          \
  }
UASCMA_LANE_MATH_UNARY(Asin, AsinKernel)
UASCMA_LANE_MATH_UNARY(Atan, AtanKernel)
UASCMA_LANE_MATH_UNARY(Cos, CosKernel)
UASCMA_LANE_MATH_UNARY(Exp, ExpKernel)
UASCMA_LANE_MATH_UNARY(Expm1, Expm1Kernel)
#undef UASCMA_LANE_MATH_UNARY

Lanes4 Atan2Sse2(const Lanes4& y, const Lanes4& x) {
  return Join(lane_math_internal::Atan2Kernel(LoadLow(y), LoadLow(x)),
              lane_math_internal::Atan2Kernel(LoadHigh(y), LoadHigh(x)));
}
__attribute__((target("avx2"))) Lanes4 Atan2Avx2(const Lanes4& y, const Lanes4& x) {
  return Store4(lane_math_internal::Atan2Kernel(Load4(y), Load4(x)));
}

// Whether the CPU (and its operating system) has AVX2, asked once, when the program starts.
bool DetectAvx2() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") != 0;
}
const bool kCpuHasAvx2 = DetectAvx2();
const LaneMathPath kDefaultLaneMathPath = ChooseLaneMathPath(std::getenv("UASCMA_SIMD"));  // after kCpuHasAvx2

bool UseAvx2(LaneMathPath path) { return path == LaneMathPath::kAvx2 && kCpuHasAvx2; }

}  // namespace

bool LaneMathPathSupported(LaneMathPath path) { return path == LaneMathPath::kSse2 || kCpuHasAvx2; }

LaneMathPath ChooseLaneMathPath(const char* requested) {
  if (requested != nullptr && (std::strcmp(requested, "scalar") == 0 || std::strcmp(requested, "sse2") == 0)) {
    return LaneMathPath::kSse2;
  }
  return kCpuHasAvx2 ? LaneMathPath::kAvx2 : LaneMathPath::kSse2;
}

LaneMathPath DefaultLaneMathPath() { return kDefaultLaneMathPath; }

const char* LaneMathPathName(LaneMathPath path) { return path == LaneMathPath::kAvx2 ? "avx2" : "sse2"; }

Lanes4 Asin4(LaneMathPath path, const Lanes4& s) { return UseAvx2(path) ? AsinAvx2(s) : AsinSse2(s); }
Lanes4 Atan4(LaneMathPath path, const Lanes4& x) { return UseAvx2(path) ? AtanAvx2(x) : AtanSse2(x); }
Lanes4 Atan2_4(LaneMathPath path, const Lanes4& y, const Lanes4& x) {
  return UseAvx2(path) ? Atan2Avx2(y, x) : Atan2Sse2(y, x);
}
Lanes4 Cos4(LaneMathPath path, const Lanes4& x) { return UseAvx2(path) ? CosAvx2(x) : CosSse2(x); }
Lanes4 Exp4(LaneMathPath path, const Lanes4& x) { return UseAvx2(path) ? ExpAvx2(x) : ExpSse2(x); }
Lanes4 Expm1_4(LaneMathPath path, const Lanes4& x) { return UseAvx2(path) ? Expm1Avx2(x) : Expm1Sse2(x); }

}  // namespace uascma::lane_math
