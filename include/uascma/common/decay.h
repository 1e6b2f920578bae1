#pragma once
// e^{−x} and 1 − e^{−x} for x ≥ 0: the factor and the complement of an exact zero-order-hold step of a
// first-order lag, x = Δt/τ (RC pairs, hysteresis, Dryden filters). At the simulator's 5 ms step most of
// these arguments are 1e-5…1e-2, where a short Taylor polynomial is exact to rounding and costs a fifth of
// a libm exp call, and where 1 − e^{−x} computed as a difference would lose digits to cancellation.
#include <cmath>

namespace uascma {

struct ExpDecay {
  double factor = 1.0;      // e^{−x}
  double complement = 0.0;  // 1 − e^{−x}, without cancellation
};

// Below kExpDecaySeriesLimit the complement is the Taylor series x − x²/2! + … ± xⁿ/n! in Horner form,
// n = 5 for x < 1/1024, 6 for x < 1/128 (the usual cases at 5 ms), 8 for x < 1/32: the first omitted
// term relative to the sum, xⁿ/(n+1)!, stays below 1.2e-18, 4.5e-17 and 2.4e-18, under half an ulp
// (5.6e-17). Above the limit, libm's exp and expm1.
inline constexpr double kExpDecaySeriesLimit = 1.0 / 32.0;

inline ExpDecay CalcExpDecay(double x) {
  constexpr double k3 = 1.0 / 3, k5 = 1.0 / 5, k6 = 1.0 / 6, k7 = 1.0 / 7;
  if (x >= 0.0 && x < 1.0 / 1024.0) {
    const double c = x * (1 - x * 0.5 * (1 - x * k3 * (1 - x * 0.25 * (1 - x * k5))));
    return {1.0 - c, c};
  }
  if (x >= 0.0 && x < 1.0 / 128.0) {
    const double c = x * (1 - x * 0.5 * (1 - x * k3 * (1 - x * 0.25 * (1 - x * k5 * (1 - x * k6)))));
    return {1.0 - c, c};
  }
  if (x >= 0.0 && x < kExpDecaySeriesLimit) {
    const double c =
        x *
        (1 - x * 0.5 * (1 - x * k3 * (1 - x * 0.25 * (1 - x * k5 * (1 - x * k6 * (1 - x * k7 * (1 - x * 0.125)))))));
    return {1.0 - c, c};
  }
  return {std::exp(-x), -std::expm1(-x)};
}

}  // namespace uascma
