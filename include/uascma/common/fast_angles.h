#pragma once
// Inline atan, atan2 and asin for the 200 Hz step (issue 27): the LQR's Euler angles and reference tilts, and the
// drag's flow incidence (models/rigid_body.cc, gnc/lqr.cc). libm's versions are calls of ~60-130 instructions each
// (five to seven per step); these are ~40, inlined.
//
// Method (ours): atan(t) for t = min(|y|, |x|) / max(|y|, |x|) ∈ [0, 1]; above tan(π/8) it is π/4 + atan((t − 1) /
// (t + 1)), so the kernel only sees |u| ≤ tan(π/8) ≈ 0.414, where atan(u) = u + u³ P(u²) with P of degree 10, fitted
// by least squares on Chebyshev nodes in 50-digit arithmetic (scripts/fit-fast-atan.py prints these coefficients).
// The fit's own relative error is 7e-18; what remains is the double rounding of the evaluation and of π/4, π/2, π.
// Bounds, checked against libm over dense grids (tests/common/fast_angles_test.cc):
//   |FastAtan2(y, x) − atan2(y, x)| ≤ 4.5e-16 rad (≤ 2 ulp of π) for finite (y, x),
//   |FastAtan(x) − atan(x)| ≤ 2.3e-16 rad,  |FastAsin(s) − asin(s)| ≤ 4.5e-16 rad for |s| ≤ 1.
// Results differ from libm's in the last bits, so a flight using them is not bit-identical to one using libm.
// FastAtan2(±0, +0) = ±0 and FastAtan2(±0, −0) = ±π as atan2; two infinite arguments give NaN (not used here).
#include <cmath>

namespace uascma {
namespace fast_angles_internal {

inline constexpr double kPi = 3.141592653589793;
inline constexpr double kHalfPi = 1.5707963267948966;
inline constexpr double kQuarterPi = 0.7853981633974483;
inline constexpr double kTanEighthPi = 0.41421356237309503;  // tan(π/8) = √2 − 1

// atan(u) for |u| ≤ tan(π/8): u + u³ P(u²).
inline double AtanKernel(double u) {
  const double w = u * u;
  double p = -0.01920252926841228;
  p = p * w + 0.039253696320618564;
  p = p * w - 0.05086254885823143;
  p = p * w + 0.05858311810501153;
  p = p * w - 0.06664531369805009;
  p = p * w + 0.07692184699371778;
  p = p * w - 0.0909090464769568;
  p = p * w + 0.11111111017100327;
  p = p * w - 0.1428571428469138;
  p = p * w + 0.19999999999995652;
  p = p * w - 0.3333333333333333;
  return u + u * w * p;
}

// atan(t) for t ∈ [0, 1].
inline double AtanUnit(double t) {
  if (t <= kTanEighthPi) return AtanKernel(t);
  return kQuarterPi + AtanKernel((t - 1.0) / (t + 1.0));
}

}  // namespace fast_angles_internal

// atan2(y, x) (rad, in [−π, π]) to the bound above.
inline double FastAtan2(double y, double x) {
  using namespace fast_angles_internal;
  const double ay = std::abs(y);
  const double ax = std::abs(x);
  double angle;
  if (ay == 0.0) {
    angle = 0.0;
  } else if (ay > ax) {
    angle = kHalfPi - AtanUnit(ax / ay);
  } else {
    angle = AtanUnit(ay / ax);
  }
  if (std::signbit(x)) angle = kPi - angle;
  return std::copysign(angle, y);
}

// atan(x) (rad, in (−π/2, π/2)).
inline double FastAtan(double x) {
  using namespace fast_angles_internal;
  const double ax = std::abs(x);
  const double angle = ax <= 1.0 ? AtanUnit(ax) : kHalfPi - AtanUnit(1.0 / ax);
  return std::copysign(angle, x);
}

// asin(s) (rad) for s ∈ [−1, 1]: the angle whose sine is s and cosine √((1 − s)(1 + s)).
inline double FastAsin(double s) { return FastAtan2(s, std::sqrt((1.0 - s) * (1.0 + s))); }

}  // namespace uascma
