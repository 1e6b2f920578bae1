#pragma once
// The branch current law of one segment of the EOD propagation (eod.h, eod.cc), i(t) = ī + Δ e^{−qt}: its value and
// the charge it has delivered at t, and the time at which it has delivered a given charge.
#include <cmath>
#include <cstdlib>

namespace uascma::prognostics::eod_internal {

// A branch current on one segment: i(t) = mean + delta · e^{−rate t}, A (rate in 1/s).
struct CurrentLaw {
  double mean_a = 0.0;
  double delta_a = 0.0;
  double rate_per_s = 0.0;
  double inverse_rate_s = 0.0;  // 1 / rate (unused when delta is 0)
};

// The branch-level quantities at time t, shared by the cells of the branch.
struct BranchAt {
  double t;
  double current_a;  // i(t)
  double e_rate;     // e^{−rate t}
  double charge_as;  // ∫₀ᵗ i = mean t + delta (1 − e^{−rate t}) / rate
};

// Whether the law is constant over [0, t] as EvaluateBranch sees it (no exponential to evaluate).
inline bool IsFlatAt(const CurrentLaw& law, double t) { return law.delta_a == 0.0 || t == 0.0; }

// i(t), e^{−rate t} and the charge at t, with em1 = expm1(−rate t) already computed (unused when IsFlatAt).
inline BranchAt EvaluateBranchWith(const CurrentLaw& law, double t, double em1) {
  if (IsFlatAt(law, t)) {
    const double current = law.mean_a + law.delta_a;
    return {t, current, 1.0, current * t};
  }
  return {t, law.mean_a + law.delta_a * (1.0 + em1), 1.0 + em1,
          law.mean_a * t - law.delta_a * em1 * law.inverse_rate_s};
}

// The same, computing em1.
inline BranchAt EvaluateBranch(const CurrentLaw& law, double t) {
  if (IsFlatAt(law, t)) return EvaluateBranchWith(law, t, 0.0);
  // One expm1 gives both e^{−qt} and 1 − e^{−qt} without cancellation.
  const double em1 = std::expm1(-law.rate_per_s * t);
  return {t, law.mean_a + law.delta_a * (1.0 + em1), 1.0 + em1,
          law.mean_a * t - law.delta_a * em1 * law.inverse_rate_s};
}

// The root of the second-order expansion i₀ t − ½ q Δ t² = charge (stable quadratic form), or the
// constant-current time when the expansion has none.
inline double EstimateTimeToCharge(const CurrentLaw& law, double charge_as) {
  const double i0 = law.mean_a + law.delta_a;
  const double half_curvature = 0.5 * law.rate_per_s * law.delta_a;
  const double discriminant = i0 * i0 - 4.0 * half_curvature * charge_as;
  return discriminant >= 0.0 ? 2.0 * charge_as / (i0 + std::sqrt(discriminant)) : charge_as / law.mean_a;
}

// Time at which a branch has delivered `charge_as` (the charge drawn increases with t): Halley steps from
// the second-order estimate, kept inside a bracket. One step at a time (Step, until done), so that several solves
// can be interleaved, each doing the same operations in the same order as alone.
struct ChargeTimeSolve {
  const CurrentLaw* law = nullptr;
  double charge_as = 0.0;
  double tolerance_s = 0.0;
  double lo = 0.0, hi = 0.0, t = 0.0;
  int iteration = 0;
  bool done = false;
  double result_s = 0.0;

  void Start(const CurrentLaw& solved_law, double charge, double estimate_s, double tolerance) {
    law = &solved_law;
    charge_as = charge;
    tolerance_s = tolerance;
    iteration = 0;
    done = false;
    if (solved_law.delta_a == 0.0) {
      Finish(charge / solved_law.mean_a);
      return;
    }
    // |delta (1 − e^{−qt})/q| ≤ |delta|/q bounds the transient's share, hence a bracket.
    lo = 0.0;
    hi = (charge + std::abs(solved_law.delta_a) * solved_law.inverse_rate_s) / solved_law.mean_a;
    t = estimate_s;
    if (!(t > lo && t < hi)) t = 0.5 * hi;
  }

  void Step() {
    if (iteration == kMaxIterations) return Finish(t);
    ++iteration;
    const BranchAt at = EvaluateBranch(*law, t);
    const double f = at.charge_as - charge_as;
    if (f > 0.0) {
      hi = t;
    } else {
      lo = t;
    }
    if (at.current_a > 0.0) {
      const double df = at.current_a;                                  // f' = i(t)
      const double d2f = -law->rate_per_s * law->delta_a * at.e_rate;  // f'' = di/dt
      const double step = 2.0 * f * df / (2.0 * df * df - f * d2f);    // Halley
      if (std::abs(step) <= 1e-3 * tolerance_s) return Finish(t - step);
      t -= step;
    }
    if (!(t > lo && t < hi)) t = 0.5 * (lo + hi);  // a step that leaves the bracket: bisect
    if (hi - lo <= 1e-3 * tolerance_s) Finish(t);
  }

 private:
  static constexpr int kMaxIterations = 100;
  void Finish(double time_s) {
    result_s = time_s;
    done = true;
  }
};

}  // namespace uascma::prognostics::eod_internal
