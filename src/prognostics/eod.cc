// Battery end-of-discharge prognosis: exact segment-by-segment propagation (see eod.h for the method).
#include "uascma/prognostics/eod.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "eod_internal.h"
#include "eod_law.h"
#include "uascma/common/error.h"

namespace uascma::prognostics {

using eod_internal::BranchAt;
using eod_internal::CurrentLaw;
using eod_internal::Ended;
using eod_internal::EstimateTimeToCharge;
using eod_internal::EvaluateBranch;
using eod_internal::EvaluateBranchWith;
using eod_internal::IsFlatAt;
using eod_internal::RequireValid;
using eod_internal::TimeToCharge;
using models::BatteryPack;
using models::CellState;
using models::kBranchCount;
using models::kCellsPerBranch;
using models::kMaxRcPairs;
using models::PackState;
using models::PerBranch;
using models::SelfCorrectingCell;

namespace {

constexpr int kMaxLanes = kBranchCount * kCellsPerBranch;
constexpr int kMaxRates = kMaxLanes * kMaxRcPairs;
constexpr int kMaxSegments = 100000;         // a full discharge takes about one per OCV breakpoint and cell
constexpr double kSocSnap = 1e-12;           // SOC within this of a breakpoint is on it (≈ 1e-8 s of discharge)
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
Lane MakeLane(const SelfCorrectingCell& cell, const CellState& state, int branch, int index,
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
int SegmentFrom(const models::OcvTable& ocv, int k, double soc) {
  if (std::isnan(soc)) return ocv.SegmentForDischarge(soc);
  const double* z = ocv.soc_fraction().data();
  const int last = ocv.segment_count() - 1;
  while (k > 0 && soc <= z[k]) --k;
  while (k < last && soc > z[k + 1]) ++k;
  return k;
}

// The lane's OCV segment from its SOC; `from` a segment near it (the present one when it moves on).
void UpdateSegment(Lane& lane, std::optional<int> from = std::nullopt) {
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
double Slope(const Lane& lane, const CurrentLaw& law, const Eval& e) {
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
double UpperSlopeBound(const Lane& lane, const CurrentLaw& law, const Eval& e1, const Eval& e2) {
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

// The propagation shared by the cell and the pack EOD.
struct Problem {
  std::array<Lane, kMaxLanes> lanes;
  int lane_count = 0;
  PerBranch<int> lane_begin{}, lane_end{};  // lanes [begin, end) of each branch
  PerBranch<bool> on{};
  PerBranch<double> r0_ohm{};             // eq. 3.7
  std::array<double, kMaxRates> rates{};  // the distinct RC rates 1/(R_j C_j) of the lanes
  int rate_count = 0;

  void AddLane(const Lane& lane) {
    Lane& added = lanes[lane_count++] = lane;
    for (int j = 0; j < added.rc_count; ++j) {
      int slot = 0;
      while (slot < rate_count && rates[slot] != added.rc_rate_per_s[j]) ++slot;
      if (slot == rate_count) rates[rate_count++] = added.rc_rate_per_s[j];
      added.rc_slot[j] = slot;
    }
  }
};

EodResult Reached(EodStatus status, double eod_s, const Lane* lane, int segments, int evaluations) {
  EodResult result = Ended(status, eod_s);
  if (lane != nullptr) {
    result.limiting_branch = lane->branch;
    result.limiting_cell = lane->index;
  }
  result.segments = segments;
  result.voltage_evaluations = evaluations;
  return result;
}

// Eq. 3.3 as SelfCorrectingCell::CalcTerminalVoltage computes it (the same operations in the same order; the
// lane's rc_ohm is 0 beyond its pairs, as the cell's), from the lane's R0, which may be scaled.
double LaneTerminalVoltage(const Lane& lane, double current_a, double ocv_v) {
  const double s = current_a > 0.0 ? -1.0 : (current_a < 0.0 ? 1.0 : lane.state.hysteresis_sign);
  double v = ocv_v + lane.m0_v * s + lane.m_v * lane.state.hysteresis - lane.r0_ohm * current_a;
  for (int j = 0; j < kMaxRcPairs; ++j) v -= lane.rc_ohm[j] * lane.state.rc_current_a[j];
  return v;
}

// The present: the voltages with the present split (eqs. 3.4–3.5), the stored state, s = −sgn(i). A result
// when the EOD is decided before any propagation (no branch, already below the cut-off, no discharge).
std::optional<EodResult> CheckPresent(const Problem& problem, double total_current_a, const EodOptions& options) {
  if (!problem.on[0] && !problem.on[1]) return Reached(EodStatus::kNoBranchConnected, 0.0, nullptr, 0, 0);
  // OCV(z) on the lane's segment (UpdateSegment has found it): OcvTable::CalcVoltage's own expression.
  std::array<double, kMaxLanes> lane_ocv{};
  PerBranch<double> ocv_now{};
  for (int b = 0; b < kBranchCount; ++b) {
    for (int l = problem.lane_begin[b]; l < problem.lane_end[b]; ++l) {
      const Lane& lane = problem.lanes[l];
      lane_ocv[l] = lane.ocv->CalcVoltageOnSegment(lane.segment, lane.state.soc_fraction);
      ocv_now[b] += lane_ocv[l];
    }
  }
  const models::BranchSplit split_now =
      models::CalcBranchSplit(ocv_now, problem.r0_ohm, problem.on, std::max(total_current_a, 0.0));
  const Lane* lowest = nullptr;
  double lowest_v = std::numeric_limits<double>::infinity();
  for (int b = 0; b < kBranchCount; ++b) {
    if (!problem.on[b]) continue;
    for (int l = problem.lane_begin[b]; l < problem.lane_end[b]; ++l) {
      const Lane& lane = problem.lanes[l];
      const double current = total_current_a > 0.0 ? split_now.current_a[b] : total_current_a;
      const double v = LaneTerminalVoltage(lane, current, lane_ocv[l]);
      if (v < lowest_v) {
        lowest_v = v;
        lowest = &lane;
      }
    }
  }
  if (lowest_v <= options.cutoff_v) return Reached(EodStatus::kAlreadyBelowCutoff, 0.0, lowest, 0, 0);
  if (!(total_current_a > 0.0)) {
    return Reached(EodStatus::kNotReachedWithinHorizon, options.horizon_s, nullptr, 0, 0);
  }
  return std::nullopt;
}

// One segment of the propagation: the branch current laws, which branches conduct, and its length.
struct Segment {
  PerBranch<CurrentLaw> law{};
  PerBranch<bool> conducting{};
  double duration = 0.0;
  PerBranch<BranchAt> branch_end;  // read only where branch_end_known
  PerBranch<bool> branch_end_known = {false, false};
};

// What a segment starts from, summed over each switched-on branch's lanes in lane order: the branch OCV (eq. 3.6)
// and K_j = Σ η slope / Q on the present OCV segments, and the charge the branch delivers until its first cell
// reaches its lower breakpoint.
struct BranchSums {
  PerBranch<double> ocv_v{}, k{};
  PerBranch<double> charge_to_breakpoint = {kNone, kNone};

  // The lane's OCV and charge to its breakpoint (K changes only with a lane's segment: SumK).
  void Add(int b, const Lane& lane) {
    ocv_v[b] += lane.ocv_v;
    if (lane.segment == 0) return;  // the lowest line extends below the table
    charge_to_breakpoint[b] =
        std::min(charge_to_breakpoint[b], (lane.state.soc_fraction - lane.segment_start_soc) * lane.charge_per_soc_as);
  }

  void SumK(const Problem& problem, int b) {
    k[b] = 0.0;
    for (int l = problem.lane_begin[b]; l < problem.lane_end[b]; ++l) {
      k[b] += problem.lanes[l].slope_v * problem.lanes[l].eta_per_as;
    }
  }
};

Segment MakeSegment(const Problem& problem, const BranchSums& sums, double current, double negligible_a,
                    double remaining) {
  const PerBranch<double>& branch_ocv = sums.ocv_v;
  const PerBranch<double>& branch_k = sums.k;
  // The branch current laws on the present OCV segments, and the time a blocked diode opens.
  Segment segment;
  PerBranch<CurrentLaw>& law = segment.law;
  segment.duration = remaining;
  if (problem.on[0] && problem.on[1]) {
    const double r_sum = problem.r0_ohm[0] + problem.r0_ohm[1];
    double i0 = (branch_ocv[0] - branch_ocv[1] + current * problem.r0_ohm[1]) / r_sum;  // eqs. 3.4–3.5
    if (i0 < -negligible_a || i0 > current + negligible_a) {
      // One diode blocks: the active branch carries I until its E_a(t) − R_a I falls to the idle
      // branch's E_b (E_a falls at K_a I per second), when the blocked branch joins in.
      const int active = i0 < 0.0 ? 1 : 0;
      const int idle = 1 - active;
      law[active] = {current, 0.0, 0.0, 0.0};
      segment.conducting[active] = true;
      const double unblock_s =
          (branch_ocv[active] - problem.r0_ohm[active] * current - branch_ocv[idle]) / (branch_k[active] * current);
      segment.duration = std::min(segment.duration, std::max(unblock_s, 0.0));
    } else {
      // Both conduct: i⁰(t) = ī + Δ e^{−qt}, q = (K₀ + K₁)/(R₀ + R₁), ī = K₁ I/(K₀ + K₁) (eq.-3.4–3.7
      // split of affine branch OCVs; derivation in eod.h).
      i0 = std::clamp(i0, 0.0, current);
      const double k_sum = branch_k[0] + branch_k[1];
      const double mean0 = current * branch_k[1] / k_sum;
      const double delta0 = i0 - mean0;
      if (std::abs(delta0) <= negligible_a) {
        law[0] = {i0, 0.0, 0.0, 0.0};
        law[1] = {current - i0, 0.0, 0.0, 0.0};
      } else {
        const double rate = k_sum / r_sum;
        law[0] = {mean0, delta0, rate, 1.0 / rate};
        law[1] = {current - mean0, -delta0, rate, 1.0 / rate};
      }
      segment.conducting = {true, true};
    }
  } else {
    const int b = problem.on[0] ? 0 : 1;
    law[b] = {current, 0.0, 0.0, 0.0};
    segment.conducting[b] = true;
  }
  return segment;
}

// Every conducting branch at the segment's end whose end is not known yet. When both conduct, their laws share
// q (MakeSegment): one expm1(−q t) serves both (the same argument, hence the same value).
inline void EndBranches(Segment& segment) {
  const double t = segment.duration;
  double em1 = 0.0;
  bool have_em1 = false;
  for (int b = 0; b < kBranchCount; ++b) {
    if (!segment.conducting[b] || segment.branch_end_known[b]) continue;
    const CurrentLaw& law = segment.law[b];
    if (!IsFlatAt(law, t) && !have_em1) {
      em1 = std::expm1(-law.rate_per_s * t);
      have_em1 = true;
    }
    segment.branch_end[b] = EvaluateBranchWith(law, t, em1);
    segment.branch_end_known[b] = true;
  }
}

// The segment ends when the first cell of a conducting branch reaches its lower OCV breakpoint. Solve the
// branch whose second-order estimate comes first; the other needs solving only if it has drawn its charge by
// then.
void EndAtTheFirstBreakpoint(const BranchSums& sums, double remaining, const EodOptions& options, Segment& segment) {
  PerBranch<double> charge_to_breakpoint = {kNone, kNone};
  PerBranch<double> estimate_s = {kNone, kNone};
  for (int b = 0; b < kBranchCount; ++b) {
    if (!segment.conducting[b]) continue;
    charge_to_breakpoint[b] = sums.charge_to_breakpoint[b];
    if (charge_to_breakpoint[b] != kNone) estimate_s[b] = EstimateTimeToCharge(segment.law[b], charge_to_breakpoint[b]);
  }
  const int urgent = estimate_s[0] <= estimate_s[1] ? 0 : 1;
  for (int b : {urgent, 1 - urgent}) {
    if (charge_to_breakpoint[b] == kNone) continue;
    if (segment.duration < remaining) {
      EndBranches(segment);
      if (segment.branch_end[b].charge_as < charge_to_breakpoint[b]) continue;  // its breakpoint comes later
    }
    segment.duration = std::min(segment.duration, TimeToCharge(segment.law[b], charge_to_breakpoint[b], estimate_s[b],
                                                               options.time_tolerance_s));
    segment.branch_end_known = {false, false};  // the end moved
  }
}

struct Crossing {
  double first_s = kNone;
  const Lane* limiting = nullptr;
};

// The lane to the state `e` at its segment's end; on (or past) its lower breakpoint, onto the segment below
// (then true).
bool AdvanceLane(Lane& lane, const Eval& e) {
  lane.state.soc_fraction = e.soc;
  lane.state.hysteresis = e.hysteresis;
  lane.state.hysteresis_sign = -1.0;
  // The pairs one by one (1 ≤ rc_count ≤ 3): a loop here becomes a call to memcpy.
  static_assert(kMaxRcPairs == 3);
  lane.state.rc_current_a[0] = e.rc_current_a[0];
  if (lane.rc_count > 1) lane.state.rc_current_a[1] = e.rc_current_a[1];
  if (lane.rc_count > 2) lane.state.rc_current_a[2] = e.rc_current_a[2];
  lane.ocv_v = e.ocv_v;
  if (lane.segment > 0 && lane.state.soc_fraction - lane.segment_start_soc <= kSocSnap) {
    lane.state.soc_fraction = std::min(lane.state.soc_fraction, lane.segment_start_soc);
    UpdateSegment(lane, lane.segment);
    lane.ocv_v = LaneOcv(lane, lane.state.soc_fraction);
    return true;
  }
  return false;
}

// In one pass over the switched-on lanes: the first cut-off crossing of any conducting lane inside [0, duration]
// (each searched from its state at the segment's start), every lane to the segment's end (a lane blocked by its
// diode rests: its RC currents relax) and the sums the next segment starts from (`next` holds the present K). The RC
// terms are computed once per distinct rate. When a crossing is found the lanes' new states are not used.
Crossing CrossOrAdvance(Problem& problem, Segment& segment, const EodOptions& options, BranchSums& next,
                        int& evaluations) {
  std::array<RcAt, kMaxRates> rc_at;
  const CurrentLaw& shared_law = segment.conducting[0] ? segment.law[0] : segment.law[1];  // the laws share q
  for (int r = 0; r < problem.rate_count; ++r) rc_at[r] = MakeRcAt(problem.rates[r], shared_law, segment.duration);
  EndBranches(segment);
  // Each rate's RcQuotient, once for the branches with a transient (delta ≠ 0): when both have one they share q, t
  // and e^{−qt} (EndBranches' one expm1, or 1 at t = 0), hence the quotient.
  std::array<double, kMaxRates> quotients;
  for (int b = 0; b < kBranchCount; ++b) {
    if (!segment.conducting[b] || segment.law[b].delta_a == 0.0) continue;
    for (int r = 0; r < problem.rate_count; ++r) {
      quotients[r] = RcQuotient(problem.rates[r], segment.law[b], segment.branch_end[b], rc_at[r]);
    }
    break;
  }
  Crossing crossing;
  for (int b = 0; b < kBranchCount; ++b) {
    if (!problem.on[b]) continue;
    const CurrentLaw& law = segment.law[b];
    bool moved = false;  // some lane onto another OCV segment: K_b changes
    for (int l = problem.lane_begin[b]; l < problem.lane_end[b]; ++l) {
      Lane& lane = problem.lanes[l];
      if (!segment.conducting[b]) {  // e^{−a t} of MakeRcAt is the relaxation factor
        for (int j = 0; j < lane.rc_count; ++j) lane.state.rc_current_a[j] *= rc_at[lane.rc_slot[j]].decay;
        next.Add(b, lane);
        continue;
      }
      Eval end;
      Evaluate(lane, law, segment.branch_end[b], rc_at.data(), &end, quotients.data());
      // Most segments end far above the cut-off: the lower bound over the whole segment settles it.
      const double start_current = law.mean_a + law.delta_a;
      if (LowerBound(lane, start_current, lane.state.rc_current_a.data(), end) <= options.cutoff_v) {
        Search search{lane, law, options.cutoff_v, options.time_tolerance_s};
        Eval start;
        EvaluateStart(lane, law, &start);
        const double first = search.First(start, end);
        evaluations += search.evaluations;
        if (first < crossing.first_s) {
          crossing.first_s = first;
          crossing.limiting = &lane;
        }
      }
      moved = AdvanceLane(lane, end) || moved;
      next.Add(b, lane);
    }
    if (moved) next.SumK(problem, b);
  }
  return crossing;
}

EodResult Propagate(Problem& problem, double total_current_a, const EodOptions& options) {
  for (int l = 0; l < problem.lane_count; ++l) UpdateSegment(problem.lanes[l]);  // CheckPresent reads the segment
  if (const std::optional<EodResult> decided = CheckPresent(problem, total_current_a, options)) return *decided;
  const double current = total_current_a;
  const double negligible_a = 1e-9 * std::max(current, 1.0);
  BranchSums sums;
  for (int b = 0; b < kBranchCount; ++b) {
    for (int l = problem.lane_begin[b]; l < problem.lane_end[b]; ++l) {
      Lane& lane = problem.lanes[l];
      lane.ocv_v = LaneOcv(lane, lane.state.soc_fraction);
      if (problem.on[b]) sums.Add(b, lane);
    }
    if (problem.on[b]) sums.SumK(problem, b);
  }
  double t = 0.0;
  int evaluations = 0;
  for (int segment_count = 0;; ++segment_count) {
    UASCMA_CHECK(segment_count < kMaxSegments, "EOD propagation did not terminate");
    const double remaining = options.horizon_s - t;
    if (remaining <= 0.0) {
      return Reached(EodStatus::kNotReachedWithinHorizon, options.horizon_s, nullptr, segment_count, evaluations);
    }
    Segment segment = MakeSegment(problem, sums, current, negligible_a, remaining);
    EndAtTheFirstBreakpoint(sums, remaining, options, segment);
    sums = BranchSums{.ocv_v = {}, .k = sums.k};
    const Crossing crossing = CrossOrAdvance(problem, segment, options, sums, evaluations);
    if (crossing.limiting != nullptr) {
      return Reached(EodStatus::kReached, t + crossing.first_s, crossing.limiting, segment_count + 1, evaluations);
    }
    t += segment.duration;
  }
}

}  // namespace

EodResult CalcCellEod(const SelfCorrectingCell& cell, const CellState& state, double current_a,
                      const EodOptions& options) {
  RequireValid(options);
  Problem problem;
  problem.AddLane(MakeLane(cell, state, 0, 0));
  problem.lane_begin = {0, 1};
  problem.lane_end = {1, 1};
  problem.on = {true, false};
  problem.r0_ohm = {cell.params().r0_ohm, 0.0};
  if (current_a <= 0.0) {
    // No discharge: only "already below" can be said.
    if (cell.CalcTerminalVoltage(state, current_a) <= options.cutoff_v) {
      return Reached(EodStatus::kAlreadyBelowCutoff, 0.0, &problem.lanes[0], 0, 0);
    }
    return Reached(EodStatus::kNotReachedWithinHorizon, options.horizon_s, nullptr, 0, 0);
  }
  return Propagate(problem, current_a, options);
}

EodResult CalcPackEod(const BatteryPack& pack, const PackState& state, double total_current_a,
                      const EodOptions& options) {
  RequireValid(options);
  if (!(total_current_a >= 0.0 && std::isfinite(total_current_a))) {
    throw InputError("EOD", "total current", fmt::format("a finite discharge current >= 0 A, got {}", total_current_a));
  }
  Problem problem;
  for (int b = 0; b < kBranchCount; ++b) {
    problem.lane_begin[b] = problem.lane_count;
    for (int c = 0; c < kCellsPerBranch; ++c) {
      problem.AddLane(MakeLane(pack.cell(b, c), state.cells[b][c], b, c));
    }
    problem.lane_end[b] = problem.lane_count;
    problem.on[b] = state.branch_on[b];
    problem.r0_ohm[b] = pack.branch_r0_ohm(b);
  }
  return Propagate(problem, total_current_a, options);
}

namespace eod_internal {

std::optional<EodResult> CalcScaledPackEod(const BatteryPack& pack, const PackState& state, double total_current_a,
                                           const CellScaling& scaling, const EodOptions& options) {
  RequireValid(options);
  if (!(total_current_a >= 0.0 && std::isfinite(total_current_a))) {
    throw InputError("EOD", "total current", fmt::format("a finite discharge current >= 0 A, got {}", total_current_a));
  }
  auto positive = [](double x) { return std::isfinite(x) && x > 0.0; };  // CellParams::IsValid's test
  Problem problem;
  for (int b = 0; b < kBranchCount; ++b) {
    problem.lane_begin[b] = problem.lane_count;
    problem.r0_ohm[b] = 0.0;  // eq. 3.7, summed as BatteryPack's constructor sums it
    for (int c = 0; c < kCellsPerBranch; ++c) {
      const Lane lane = MakeLane(pack.cell(b, c), state.cells[b][c], b, c, scaling);
      if (!positive(lane.r0_ohm) || !positive(pack.cell(b, c).params().capacity_ah * scaling.capacity_factor)) {
        return std::nullopt;
      }
      problem.AddLane(lane);
      problem.r0_ohm[b] += lane.r0_ohm;
    }
    problem.lane_end[b] = problem.lane_count;
    problem.on[b] = state.branch_on[b];
  }
  return Propagate(problem, total_current_a, options);
}

}  // namespace eod_internal

}  // namespace uascma::prognostics
