#pragma once
// Our own asin, atan, atan2, cos, exp and expm1 (what stepping flights in lockstep needs): each as a scalar function
// and on four lanes, the lanes bit-identical to the scalar function of each lane's argument. A flight stepped in a lane
// beside three others (lockstep, structure of arrays) then computes exactly what it computes flown alone, provided
// the flight flown alone calls these scalar functions instead of libm's. The simulator's LQR takes its three attitude
// errors with one Atan2_4 (gnc/lqr.cc; adopting it re-based the fingerprints: these differ from libm in the last
// bit for some arguments); the rigid body's incidence still calls libm's asin.
//
// Lanes, on an instruction set chosen at run time (never a binary that fails on an older CPU): SSE2 (two 2-wide
// vectors; every x86-64) or AVX2 (one 4-wide vector). The environment variable UASCMA_SIMD, read once when the
// program starts, caps it as for the IMM (gnc/imm_lanes.h): "scalar" or "sse2" forces SSE2. No path uses a fused
// multiply-add, so every path gives the same bits (tests/common/lane_math_test.cc checks each against the scalar).
//
// Accuracy, in units in the last place (ulp) of the exact value, measured against a long-double reference over
// dense grids and edge cases (tests/common/lane_math_test.cc, which fails above the bound stated for each function).
// Methods: include/uascma/common/lane_math_kernels.h.
#include <array>

#include "uascma/common/lane_math_kernels.h"

namespace uascma::lane_math {

// asin(s) for s ∈ [−1, 1] (the LQR's pitch from R_WB, the drag's flow incidence): within 1 ulp (measured 0.88 on the
// grid, 0.90 on 2·10^7 random s); asin(±1) = ±π/2 rounded, asin(±0) = ±0; NaN for |s| > 1 or NaN.
inline double Asin(double s) { return lane_math_internal::AsinKernel(s); }

// atan(x) for every x (the LQR's reference tilts): within 1.5 ulp (measured 1.03 on the grid, 1.38 on 2·10^7 random x);
// atan(±∞) = ±π/2 rounded, atan(±0) = ±0, NaN → NaN.
inline double Atan(double x) { return lane_math_internal::AtanKernel(x); }

// atan2(y, x) in [−π, π] (the LQR's roll and yaw from R_WB): within 2 ulp for finite (y, x) (measured 1.47; 1.54 on
// 2·10^7 random pairs); signed zeros and axes as libm (atan2(±0, +0) = ±0, atan2(±0, −0) = ±π, atan2(±y, ±0) = ±π/2);
// NaN → NaN; one infinite argument as libm, two infinite arguments give NaN (libm: ±π/4, ±3π/4).
inline double Atan2(double y, double x) { return lane_math_internal::Atan2Kernel(y, x); }

// cos(x) for |x| ≤ 10^6 (the LQR's cos of the reference pitch, |x| ≤ its tilt limit, 0.6 rad by default): within
// 1 ulp for |x| ≤ π/4 (no reduction there; measured 0.75), within 2 ulp up to 1000 rad and next to the zeros of
// cos up to 1000 (measured 1.47); NaN for |x| > 10^6 (ours), ±∞ or NaN.
inline double Cos(double x) { return lane_math_internal::CosKernel(x); }

// e^x (the IMM's likelihoods, the pack's RC decays beyond their series, the EOD): within 1 ulp (measured 0.88; 0.93 on
// 2·10^7 random x) (normal results; below −708, subnormal results within 1 ulp of the subnormal grid); +∞ above, 0
// below −745.2; e^0 = 1 exactly; NaN → NaN.
inline double Exp(double x) { return lane_math_internal::ExpKernel(x); }

// e^x − 1 without cancellation near 0 (the pack's and the EOD's 1 − e^{−qt}): within 1.5 ulp (measured 1.36); expm1(±0)
// = ±0, −1 for x ≤ −40 (exactly the rounded value), +∞ above 709.78, NaN → NaN.
inline double Expm1(double x) { return lane_math_internal::Expm1Kernel(x); }

enum class LaneMathPath { kSse2, kAvx2 };

bool LaneMathPathSupported(LaneMathPath path);
// The path for a value of UASCMA_SIMD (nullptr: unset): "scalar" or "sse2" → SSE2; otherwise AVX2 if the CPU has it.
LaneMathPath ChooseLaneMathPath(const char* requested);
// ChooseLaneMathPath(getenv("UASCMA_SIMD")), decided when the program starts.
LaneMathPath DefaultLaneMathPath();
const char* LaneMathPathName(LaneMathPath path);  // "sse2", "avx2"

using Lanes4 = std::array<double, 4>;  // one argument (or result) per lane, e.g. per flight of a lockstep group

// The functions above on four lanes: lane i of the result is, bit for bit, the scalar function of lane i. A path the
// CPU lacks falls back to SSE2.
Lanes4 Asin4(LaneMathPath path, const Lanes4& s);
Lanes4 Atan4(LaneMathPath path, const Lanes4& x);
Lanes4 Atan2_4(LaneMathPath path, const Lanes4& y, const Lanes4& x);
Lanes4 Cos4(LaneMathPath path, const Lanes4& x);
Lanes4 Exp4(LaneMathPath path, const Lanes4& x);
Lanes4 Expm1_4(LaneMathPath path, const Lanes4& x);

}  // namespace uascma::lane_math
