#pragma once
// The lane kernels of the exact EOD propagation (eod.cc): one discharging cell's constants and state, its
// closed-form state and voltage at a time of a segment, the bounds that prune the cut-off search, and the search.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include "eod_internal.h"
#include "eod_law.h"
#include "uascma/models/battery_pack.h"

namespace uascma::prognostics::eod_internal {

using models::CellState;
using models::kBranchCount;
using models::kCellsPerBranch;
using models::kMaxRcPairs;
using models::SelfCorrectingCell;

constexpr int kMaxLanes = kBranchCount * kCellsPerBranch;
constexpr int kMaxRates = kMaxLanes * kMaxRcPairs;
constexpr double kVoltageTolerance = 1e-10;  // V: a root this close to the cut-off is exact enough
// Hysteresis this close to its discharge limit −1 moves the voltage by less than this: left as is.
constexpr double kSettledHysteresisV = 1e-14;
constexpr double kNone = std::numeric_limits<double>::infinity();

// (1 − e^{−x}) / x, stable near x = 0 (where it is 1 − x/2 + x²/6 − …).
inline double Phi1(double x) {
  if (std::abs(x) < 1e-4) return 1.0 - x * (0.5 - x * (1.0 / 6.0));
  return -std::expm1(-x) / x;
}

// e^{−a t} and 1/(a − q) of one RC rate a at the evaluation time (shared by every cell with that rate;
// both packs use cells 1–3 of Table 3.1, and both branch laws of a segment share q).
struct RcAt {
  double decay;
  double inverse_gap_s;
};

inline RcAt MakeRcAt(double a, const CurrentLaw& law, double t) {
  const double gap = a - law.rate_per_s;
  return {std::exp(-a * t), gap != 0.0 ? 1.0 / gap : 0.0};
}

// One discharging cell: its model constants, its state at the start of the present segment and the OCV
// segment it is in.
struct Lane {
  const models::OcvTable* ocv = nullptr;  // not owned
  CellState state;
  int branch = 0;
  int index = 0;
  double eta_per_as = 0.0;         // η_discharge / Q, 1/(A·s): dz/dt = −eta_per_as · i
  double charge_per_soc_as = 0.0;  // Q / η_discharge, A·s per unit SOC
  double hysteresis_per_as = 0.0;  // η γ / Q, 1/(A·s): d(h + 1)/dt = −hysteresis_per_as · i · (h + 1)
  double r0_ohm = 0.0, m_v = 0.0, m0_v = 0.0;
  int rc_count = 0;
  std::array<double, kMaxRcPairs> rc_ohm{}, rc_rate_per_s{};
  std::array<int, kMaxRcPairs> rc_slot{};  // index of the rate in Problem::rates
  int segment = 0;                         // OCV segment (discharge direction) at the segment start
  double slope_v = 0.0;                    // dOCV/dz on it
  double segment_start_soc = 0.0;          // its lower breakpoint (none for segment 0: the line is extended)
  double segment_start_ocv_v = 0.0;        // OCV at that breakpoint
  double ocv_v = 0.0;                      // LaneOcv at the state's SOC (kept by Propagate for the branch sums)
};

// As battery_cell.cc converts the capacity: Q = capacity_ah · 3600 s/h.
constexpr double kSecondsPerHour = 3600.0;

// `scaling` gives the R0 and Q of the cell a pack rebuilt with scaled CellParams would hold, the same
// products in the same order: R0 · f₀ · f₁ (a factor 1 is exact) and (capacity_ah · f) · 3600.
inline Lane MakeLane(const SelfCorrectingCell& cell, const CellState& state, int branch, int index,
                     const eod_internal::CellScaling& scaling = {}) {
  Lane lane;
  lane.ocv = &cell.ocv();
  lane.state = state;
  lane.branch = branch;
  lane.index = index;
  const auto& p = cell.params();
  const double capacity_as = p.capacity_ah * scaling.capacity_factor * kSecondsPerHour;
  lane.eta_per_as = p.eta_discharge / capacity_as;
  lane.charge_per_soc_as = capacity_as / p.eta_discharge;
  lane.hysteresis_per_as = p.eta_discharge * p.hysteresis_gamma / capacity_as;
  lane.r0_ohm = p.r0_ohm * scaling.r0_factors[0] * scaling.r0_factors[1];
  lane.m_v = p.hysteresis_m_v;
  lane.m0_v = p.hysteresis_m0_v;
  lane.rc_count = p.rc_pair_count;
  for (int j = 0; j < p.rc_pair_count; ++j) {
    lane.rc_ohm[j] = p.rc[j].resistance_ohm;
    lane.rc_rate_per_s[j] = cell.rc_rate_per_s(j);
  }
  return lane;
}

// OcvTable::SegmentForDischarge(soc) walked to from segment k: both end at the one k with (k = 0 or soc > z_k) and
// (k = last or soc ≤ z_{k+1}) whatever they start from (the points strictly increase), so this is the table's
// answer; a NaN satisfies no comparison, so it is left to the table.
inline int SegmentFrom(const models::OcvTable& ocv, int k, double soc) {
  if (std::isnan(soc)) return ocv.SegmentForDischarge(soc);
  const double* z = ocv.soc_fraction().data();
  const int last = ocv.segment_count() - 1;
  while (k > 0 && soc <= z[k]) --k;
  while (k < last && soc > z[k + 1]) ++k;
  return k;
}

// The lane's OCV segment from its SOC; `from` a segment near it (the present one when it moves on).
inline void UpdateSegment(Lane& lane, std::optional<int> from = std::nullopt) {
  const auto& ocv = *lane.ocv;
  lane.segment =
      from ? SegmentFrom(ocv, *from, lane.state.soc_fraction) : ocv.SegmentForDischarge(lane.state.soc_fraction);
  lane.slope_v = ocv.segment_slope_v(lane.segment);
  lane.segment_start_soc = ocv.segment_start_soc(lane.segment);
  lane.segment_start_ocv_v = ocv.CalcVoltageOnSegment(lane.segment, lane.segment_start_soc);
}

// OCV on the lane's present segment line (kept in the lane: no table look-up in the inner loops).
inline double LaneOcv(const Lane& lane, double soc) {
  return lane.segment_start_ocv_v + lane.slope_v * (soc - lane.segment_start_soc);
}

// The closed-form state and voltage of a lane at time t of the segment.
struct Eval {
  double t;
  double v;          // terminal voltage, eq. 3.3 with s = −1
  double ocv_v;      // its first term, OCV(z) on the lane's segment line
  double v_rest;     // its terms before the currents', OCV(z) − M0 + M h (LowerBound continues from them)
  double current_a;  // i(t)
  double e_rate;     // e^{−rate t} of the current law
  double soc;
  double hysteresis;
  std::array<double, kMaxRcPairs> rc_current_a;
};

// (e^{−qt} − e^{−at}) / (a − q) for the RC rate a under the law (rc: MakeRcAt(a, law, at.t)): taken directly unless
// |a − q| t < 1e-4 (the difference of the exponentials then keeps at least 12 digits), else as
// e^{−min(a,q) t} · t · Phi1(|a − q| t), free of cancellation.
inline double RcQuotient(double a, const CurrentLaw& law, const BranchAt& at, const RcAt& rc) {
  const double gap = a - law.rate_per_s;
  return std::abs(gap) * at.t > 1e-4 ? (at.e_rate - rc.decay) * rc.inverse_gap_s
                                     : (gap > 0.0 ? at.e_rate : rc.decay) * at.t * Phi1(std::abs(gap) * at.t);
}

// `rc[lane.rc_slot[j]]` holds the RcAt of the lane's pair j at at.t; `quotients[lane.rc_slot[j]]`, when given, its
// RcQuotient (a function of the rate, q, t and e^{−qt} only).
inline void Evaluate(const Lane& lane, const CurrentLaw& law, const BranchAt& at, const RcAt* rc, Eval* e,
                     const double* quotients = nullptr) {
  e->t = at.t;
  e->current_a = at.current_a;
  e->e_rate = at.e_rate;
  // Coulomb counting.
  e->soc = lane.state.soc_fraction - lane.eta_per_as * at.charge_as;
  // dh/dt = −(η γ i / Q)(h + 1) for i ≥ 0: h + 1 decays with the charge drawn, whatever i(t) is.
  const double h_plus_1 = lane.state.hysteresis + 1.0;
  e->hysteresis = h_plus_1 * lane.m_v > kSettledHysteresisV
                      ? -1.0 + h_plus_1 * std::exp(-lane.hysteresis_per_as * at.charge_as)
                      : lane.state.hysteresis;
  e->ocv_v = LaneOcv(lane, e->soc);
  e->v_rest = e->ocv_v - lane.m0_v + lane.m_v * e->hysteresis;
  double v = e->v_rest - lane.r0_ohm * e->current_a;
  // di_R/dt = a (i − i_R), a = 1/(R C), driven by mean + delta e^{−qt}:
  //   i_R = mean + (i_R0 − mean) e^{−at} + delta a (e^{−qt} − e^{−at}) / (a − q).
  for (int j = 0; j < lane.rc_count; ++j) {
    const double a = lane.rc_rate_per_s[j];
    const int slot = lane.rc_slot[j];
    double i_r = law.mean_a + (lane.state.rc_current_a[j] - law.mean_a) * rc[slot].decay;
    if (law.delta_a != 0.0) {
      const double quotient = quotients != nullptr ? quotients[slot] : RcQuotient(a, law, at, rc[slot]);
      i_r += law.delta_a * a * quotient;
    }
    e->rc_current_a[j] = i_r;
    v -= lane.rc_ohm[j] * i_r;
  }
  e->v = v;
}

// The same at t = 0 (the lane's stored state).
inline void EvaluateStart(const Lane& lane, const CurrentLaw& law, Eval* e) {
  e->t = 0.0;
  e->current_a = law.mean_a + law.delta_a;
  e->e_rate = 1.0;
  e->soc = lane.state.soc_fraction;
  e->hysteresis = lane.state.hysteresis;
  e->ocv_v = LaneOcv(lane, e->soc);
  e->v_rest = e->ocv_v - lane.m0_v + lane.m_v * e->hysteresis;
  double v = e->v_rest - lane.r0_ohm * e->current_a;
  for (int j = 0; j < lane.rc_count; ++j) {
    e->rc_current_a[j] = lane.state.rc_current_a[j];
    v -= lane.rc_ohm[j] * e->rc_current_a[j];
  }
  e->v = v;
}

// dv/dt at an evaluated point.
inline double Slope(const Lane& lane, const CurrentLaw& law, const Eval& e) {
  double dv = -lane.slope_v * lane.eta_per_as * e.current_a -
              lane.m_v * lane.hysteresis_per_as * e.current_a * (e.hysteresis + 1.0) +
              lane.r0_ohm * law.rate_per_s * law.delta_a * e.e_rate;
  for (int j = 0; j < lane.rc_count; ++j) {
    dv -= lane.rc_ohm[j] * lane.rc_rate_per_s[j] * (e.current_a - e.rc_current_a[j]);
  }
  return dv;
}

// A lower bound of v on [t1, t2] from the current and i_R at t1 and the end point e2: OCV(z) and M h
// only fall, i(t) is monotone so it peaks at an end, and i_R (a lag of i) never exceeds
// max(i_R(t1), max i).
inline double LowerBound(const Lane& lane, double current1_a, const double* rc_current1_a, const Eval& e2) {
  const double i_max = std::max(current1_a, e2.current_a);
  double lb = e2.v_rest - lane.r0_ohm * i_max;  // = OCV(z₂) − M0 + M h₂ − R0 i_max
  for (int j = 0; j < lane.rc_count; ++j) lb -= lane.rc_ohm[j] * std::max(rc_current1_a[j], i_max);
  return lb;
}

// An upper bound of dv/dt on [e1.t, e2.t], term by term as in Slope(); negative ⇒ v strictly falls.
inline double UpperSlopeBound(const Lane& lane, const CurrentLaw& law, const Eval& e1, const Eval& e2) {
  const double i_min = std::min(e1.current_a, e2.current_a);
  const double i_max = std::max(e1.current_a, e2.current_a);
  double ub = -lane.slope_v * lane.eta_per_as * i_min -
              lane.m_v * lane.hysteresis_per_as * i_min * (e2.hysteresis + 1.0) +
              lane.r0_ohm * law.rate_per_s * law.delta_a * (law.delta_a > 0.0 ? e1.e_rate : e2.e_rate);
  for (int j = 0; j < lane.rc_count; ++j) {
    ub += lane.rc_ohm[j] * lane.rc_rate_per_s[j] * (std::max(e1.rc_current_a[j], i_max) - i_min);
  }
  return ub;
}

// s: the shortest interval the first-crossing search splits when its bounds cannot decide (a 1 Hz
// prognosis needs far less resolution; a root inside such an interval is still found to tolerance_s).
constexpr double kMinSubdivision_s = 1e-2;

// The first cut-off crossing of one lane inside a segment.
struct Search {
  const Lane& lane;
  const CurrentLaw& law;
  double cutoff_v;
  double tolerance_s;
  int evaluations = 0;

  Eval At(double t) {
    ++evaluations;
    std::array<RcAt, kMaxRates> rc;  // by rate slot
    for (int j = 0; j < lane.rc_count; ++j) rc[lane.rc_slot[j]] = MakeRcAt(lane.rc_rate_per_s[j], law, t);
    Eval e;
    Evaluate(lane, law, EvaluateBranch(law, t), rc.data(), &e);
    return e;
  }

  // The root of a strictly falling v on [a, b] with v(a) > cutoff ≥ v(b): Newton steps kept inside the
  // bracket, bisection when a step leaves it.
  double Root(Eval a, Eval b) {
    double t = a.t + (a.v - cutoff_v) / (a.v - b.v) * (b.t - a.t);  // secant start
    for (int iteration = 0; iteration < 100; ++iteration) {
      const Eval e = At(t);
      const double f = e.v - cutoff_v;
      if (std::abs(f) <= kVoltageTolerance) return t;
      if (f > 0.0) {
        a = e;
      } else {
        b = e;
      }
      const double dv = Slope(lane, law, e);
      if (dv < 0.0) {
        const double step = f / dv;  // Newton
        if (std::abs(step) <= tolerance_s) return t - step;
        t -= step;
      }
      if (!(t > a.t && t < b.t)) t = 0.5 * (a.t + b.t);  // a Newton step that leaves the bracket: bisect
      if (b.t - a.t <= tolerance_s) return t;
    }
    return b.t;
  }

  // The first t in [e1.t, e2.t] with v(t) ≤ cutoff, or kNone.
  double First(const Eval& e1, const Eval& e2) {
    if (e1.v <= cutoff_v) return e1.t;
    if (LowerBound(lane, e1.current_a, e1.rc_current_a.data(), e2) > cutoff_v) return kNone;
    if (UpperSlopeBound(lane, law, e1, e2) < 0.0) {  // monotone: at most one crossing
      return e2.v <= cutoff_v ? Root(e1, e2) : kNone;
    }
    // Where the bounds cannot decide, subdivide down to kMinSubdivision_s only: a voltage that grazes the
    // cut-off without the bounds separating it would otherwise be bisected to the root tolerance across the
    // whole segment (measured: seconds per call for some mixed-health packs).
    if (e2.t - e1.t <= std::max(tolerance_s, kMinSubdivision_s)) {
      return e2.v <= cutoff_v ? (e1.v > cutoff_v ? Root(e1, e2) : e1.t) : kNone;
    }
    const Eval middle = At(0.5 * (e1.t + e2.t));
    const double left = First(e1, middle);  // left half first: the FIRST crossing
    if (left != kNone) return left;
    if (middle.v <= cutoff_v) return middle.t;
    return First(middle, e2);
  }
};

}  // namespace uascma::prognostics::eod_internal
