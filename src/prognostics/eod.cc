// Battery end-of-discharge prognosis: exact segment-by-segment propagation (see eod.h for the method).
#include "uascma/prognostics/eod.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <type_traits>

#include <fmt/format.h>

#include "eod_internal.h"
#include "eod_lane.h"
#include "eod_law.h"
#include "uascma/common/bounds.h"
#include "uascma/common/error.h"
#include "uascma/prognostics/reach_margin.h"

namespace uascma::prognostics {

using eod_internal::BranchAt;
using eod_internal::ChargeTimeSolve;
using eod_internal::CurrentLaw;
using eod_internal::Ended;
using eod_internal::EstimateTimeToCharge;
using eod_internal::Eval;
using eod_internal::Evaluate;
using eod_internal::EvaluateBranch;
using eod_internal::EvaluateBranchWith;
using eod_internal::EvaluateStart;
using eod_internal::IsFlatAt;
using eod_internal::kMaxLanes;
using eod_internal::kMaxRates;
using eod_internal::kNone;
using eod_internal::Lane;
using eod_internal::LaneOcv;
using eod_internal::LowerBound;
using eod_internal::MakeLane;
using eod_internal::MakeRcAt;
using eod_internal::RcAt;
using eod_internal::RcQuotient;
using eod_internal::RequireValid;
using eod_internal::Search;
using eod_internal::UpdateSegment;
using models::BatteryPack;
using models::CellState;
using models::kBranchCount;
using models::kCellsPerBranch;
using models::kMaxRcPairs;
using models::PackState;
using models::PerBranch;
using models::SelfCorrectingCell;

// --- the result and the options -------------------------------------------------------------------------
const char* EodStatusName(EodStatus status) {
  switch (status) {
    case EodStatus::kReached:
      return "reached";
    case EodStatus::kAlreadyBelowCutoff:
      return "already_below_cutoff";
    case EodStatus::kNotReachedWithinHorizon:
      return "not_reached_within_horizon";
    case EodStatus::kNoBranchConnected:
      return "no_branch_connected";
  }
  return "?";
}

bool EodOptions::IsValid(std::string* error) const {
  auto fail = [error](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (!CheckWithin(cutoff_v, models::kCutoffVoltageBounds, "cutoff_v", error)) return false;
  if (!CheckWithin(horizon_s, kHorizonBounds, "horizon_s", error)) return false;
  if (!(time_tolerance_s > 0.0)) return fail(fmt::format("time_tolerance_s: > 0, got {}", time_tolerance_s));
  return true;
}

std::string EodResult::BriefReport() const {
  std::string text = fmt::format("{}: EOD {:.6g} s", EodStatusName(status), eod_s);
  if (limiting_branch >= 0) text += ", limiting " + models::CellLabel(limiting_branch, limiting_cell);
  return text + fmt::format(" ({} segments)", segments);
}

double CalcReachMargin(const EodResult& eod, double flight_time_remaining_s) {
  return CalcReachMargin(eod.eod_s, flight_time_remaining_s, 0.0);
}

bool IsFlightTimeReachable(const EodResult& eod, double flight_time_remaining_s) {
  return flight_time_remaining_s <= eod.eod_s;
}

namespace eod_internal {

void RequireValid(const EodOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("EOD options: " + error);
}

EodResult Ended(EodStatus status, double eod_s) {
  EodResult result;
  result.status = status;
  result.eod_s = eod_s;
  return result;
}

}  // namespace eod_internal

// --- the exact propagation -------------------------------------------------------------------------------
namespace {

// The steps of a propagation's loop are inlined into both loops, a run alone (Propagate) and runs in lockstep
// (PropagateTogether).
#define UASCMA_EOD_INLINE inline __attribute__((always_inline))

constexpr int kMaxSegments = 100000;  // a full discharge takes about one per OCV breakpoint and cell
constexpr double kSocSnap = 1e-12;    // SOC within this of a breakpoint is on it (≈ 1e-8 s of discharge)

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

UASCMA_EOD_INLINE void MakeSegment(const Problem& problem, const BranchSums& sums, double current, double negligible_a,
                                   double remaining, Segment& segment) {
  const PerBranch<double>& branch_ocv = sums.ocv_v;
  const PerBranch<double>& branch_k = sums.k;
  // The branch current laws on the present OCV segments, and the time a blocked diode opens.
  segment.law = {};
  segment.conducting = {};
  segment.branch_end_known = {false, false};
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

struct Crossing {
  double first_s = kNone;
  const Lane* limiting = nullptr;
};

// The lane to the state `e` at its segment's end; on (or past) its lower breakpoint, onto the segment below
// (then true).
UASCMA_EOD_INLINE bool AdvanceLane(Lane& lane, const Eval& e) {
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
UASCMA_EOD_INLINE Crossing CrossOrAdvance(Problem& problem, Segment& segment, const EodOptions& options,
                                          BranchSums& next, int& evaluations) {
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

// Where a segment ends at the first breakpoint: each conducting branch's charge to its lower breakpoint and the
// estimated time to it. The branch whose estimate comes first (`urgent`) is solved first; the other needs solving
// only if it has drawn its charge by then.
struct BreakpointPlan {
  PerBranch<double> charge_as = {kNone, kNone};
  PerBranch<double> estimate_s = {kNone, kNone};
  int urgent = 0;
};

UASCMA_EOD_INLINE BreakpointPlan PlanBreakpoints(const BranchSums& sums, const Segment& segment) {
  BreakpointPlan plan;
  for (int b = 0; b < kBranchCount; ++b) {
    if (!segment.conducting[b]) continue;
    plan.charge_as[b] = sums.charge_to_breakpoint[b];
    if (plan.charge_as[b] != kNone) plan.estimate_s[b] = EstimateTimeToCharge(segment.law[b], plan.charge_as[b]);
  }
  plan.urgent = plan.estimate_s[0] <= plan.estimate_s[1] ? 0 : 1;
  return plan;
}

// Branch b's breakpoint time to be solved (then true, `solve` started): not when it has none, nor when the segment
// already ends (a diode event, the other branch's breakpoint) before the branch has drawn its charge.
UASCMA_EOD_INLINE bool StartBranchSolve(const BreakpointPlan& plan, int b, double remaining, const EodOptions& options,
                                        Segment& segment, ChargeTimeSolve& solve) {
  if (plan.charge_as[b] == kNone) return false;
  if (segment.duration < remaining) {
    EndBranches(segment);
    if (segment.branch_end[b].charge_as < plan.charge_as[b]) return false;  // its breakpoint comes later
  }
  solve.Start(segment.law[b], plan.charge_as[b], plan.estimate_s[b], options.time_tolerance_s);
  return true;
}

void EndBranchSolve(const ChargeTimeSolve& solve, Segment& segment) {
  segment.duration = std::min(segment.duration, solve.result_s);
  segment.branch_end_known = {false, false};  // the end moved
}

// The present and the sums the first segment starts from; a result when the EOD is decided already.
std::optional<EodResult> StartPropagation(Problem& problem, double total_current_a, const EodOptions& options,
                                          BranchSums& sums) {
  for (int l = 0; l < problem.lane_count; ++l) UpdateSegment(problem.lanes[l]);  // CheckPresent reads the segment
  if (std::optional<EodResult> decided = CheckPresent(problem, total_current_a, options)) return decided;
  for (int b = 0; b < kBranchCount; ++b) {
    for (int l = problem.lane_begin[b]; l < problem.lane_end[b]; ++l) {
      Lane& lane = problem.lanes[l];
      lane.ocv_v = LaneOcv(lane, lane.state.soc_fraction);
      if (problem.on[b]) sums.Add(b, lane);
    }
    if (problem.on[b]) sums.SumK(problem, b);
  }
  return std::nullopt;
}

// A propagation's loop state between two segments: one run goes alone (Propagate), several advance in lockstep
// (PropagateTogether).
struct Run {
  Run(double total_current_a, const EodOptions& eod_options) : current(total_current_a), options(&eod_options) {}

  Problem problem;
  double current = 0.0;
  const EodOptions* options = nullptr;
  double negligible_a = 0.0;
  BranchSums sums;
  double t = 0.0;
  int evaluations = 0;
  int segment_count = 0;
  double remaining = 0.0;
  Segment segment;
  BreakpointPlan plan;
  bool solving = false;  // the urgent branch's breakpoint solve started
  ChargeTimeSolve solve;
  std::optional<EodResult> result;  // set when the propagation ends
};

// The present and the sums of the run (its problem set up); its result when the EOD is decided already.
UASCMA_EOD_INLINE void StartRun(Run& run) {
  run.result = StartPropagation(run.problem, run.current, *run.options, run.sums);
  run.negligible_a = 1e-9 * std::max(run.current, 1.0);
}

// A segment up to the urgent branch's breakpoint solve (started, left to the caller), or the end.
UASCMA_EOD_INLINE void BeginSegment(Run& run) {
  UASCMA_CHECK(run.segment_count < kMaxSegments, "EOD propagation did not terminate");
  run.remaining = run.options->horizon_s - run.t;
  if (run.remaining <= 0.0) {
    run.result = Reached(EodStatus::kNotReachedWithinHorizon, run.options->horizon_s, nullptr, run.segment_count,
                         run.evaluations);
    return;
  }
  MakeSegment(run.problem, run.sums, run.current, run.negligible_a, run.remaining, run.segment);
  run.plan = PlanBreakpoints(run.sums, run.segment);
  run.solving = StartBranchSolve(run.plan, run.plan.urgent, run.remaining, *run.options, run.segment, run.solve);
}

// The rest of the segment: the urgent branch's solve done, the other branch's, the lanes to the segment's end or the
// crossing. The segment ends when the first cell of a conducting branch reaches its lower OCV breakpoint.
UASCMA_EOD_INLINE void FinishSegment(Run& run) {
  if (run.solving) EndBranchSolve(run.solve, run.segment);
  if (StartBranchSolve(run.plan, 1 - run.plan.urgent, run.remaining, *run.options, run.segment, run.solve)) {
    while (!run.solve.done) run.solve.Step();
    EndBranchSolve(run.solve, run.segment);
  }
  run.sums = BranchSums{.ocv_v = {}, .k = run.sums.k};
  const Crossing crossing = CrossOrAdvance(run.problem, run.segment, *run.options, run.sums, run.evaluations);
  if (crossing.limiting != nullptr) {
    run.result = Reached(EodStatus::kReached, run.t + crossing.first_s, crossing.limiting, run.segment_count + 1,
                         run.evaluations);
    return;
  }
  run.t += run.segment.duration;
  ++run.segment_count;
}

// One run (its problem, current and options set up) to its end, segment by segment; or, given `stop_s`, until a
// segment would start at or after stop_s (then nothing): every end the run could still reach (a crossing in a later
// segment, run.t + first ≥ run.t, or the horizon beyond run.t) is then at least stop_s.
std::optional<EodResult> PropagateUntil(Run& run, double stop_s) {
  StartRun(run);
  while (!run.result) {
    if (run.t >= stop_s && run.t < run.options->horizon_s) return std::nullopt;
    BeginSegment(run);
    if (run.result) break;
    if (run.solving) {
      while (!run.solve.done) run.solve.Step();
    }
    FinishSegment(run);
  }
  return run.result;
}

// One run (its problem, current and options set up) to its end, segment by segment.
EodResult Propagate(Run& run) { return *PropagateUntil(run, std::numeric_limits<double>::infinity()); }

// Propagate for each run, in lockstep: one segment of each in turn, their breakpoint solves (a serial chain of expm1
// calls and divisions each) interleaved step by step so that the core overlaps them. Each run makes the same
// operations in the same order as alone.
void PropagateTogether(std::span<Run* const> run_pointers) {
  for (Run* run : run_pointers) StartRun(*run);
  for (;;) {
    bool active = false;
    for (Run* run : run_pointers) {
      if (run->result) continue;
      BeginSegment(*run);
      active = true;
    }
    if (!active) return;
    for (bool stepping = true; stepping;) {
      stepping = false;
      for (Run* run : run_pointers) {
        if (run->result || !run->solving || run->solve.done) continue;
        run->solve.Step();
        stepping = true;
      }
    }
    for (Run* run : run_pointers) {
      if (!run->result) FinishSegment(*run);
    }
  }
}

// The pack's cells with their R0 and capacity scaled (CalcScaledPackEod's problem) and the branch R0 of eq. 3.7, summed
// as BatteryPack's constructor sums it; false when a scaled R0 or capacity is not a positive finite number. With the
// default scaling (every factor 1, exact) it is CalcPackEod's problem: the pack as built, its own branch R0.
bool SetUpScaledPack(Problem& problem, const BatteryPack& pack, const PackState& state,
                     const eod_internal::CellScaling& scaling) {
  auto positive = [](double x) { return std::isfinite(x) && x > 0.0; };  // CellParams::IsValid's test
  for (int b = 0; b < kBranchCount; ++b) {
    problem.lane_begin[b] = problem.lane_count;
    problem.r0_ohm[b] = 0.0;  // eq. 3.7, summed as BatteryPack's constructor sums it
    for (int c = 0; c < kCellsPerBranch; ++c) {
      const Lane lane = MakeLane(pack.cell(b, c), state.cells[b][c], b, c, scaling);
      if (!positive(lane.r0_ohm) || !positive(pack.cell(b, c).params().capacity_ah * scaling.capacity_factor)) {
        return false;
      }
      problem.AddLane(lane);
      problem.r0_ohm[b] += lane.r0_ohm;
    }
    problem.lane_end[b] = problem.lane_count;
    problem.on[b] = state.branch_on[b];
  }
  return true;
}

bool IsDischargeCurrent(double total_current_a) { return total_current_a >= 0.0 && std::isfinite(total_current_a); }

void RequireDischargeCurrent(double total_current_a) {
  if (!IsDischargeCurrent(total_current_a)) {
    throw InputError("EOD", "total current", fmt::format("a finite discharge current >= 0 A, got {}", total_current_a));
  }
}

}  // namespace

EodResult CalcCellEod(const SelfCorrectingCell& cell, const CellState& state, double current_a,
                      const EodOptions& options) {
  RequireValid(options);
  Run run(current_a, options);
  Problem& problem = run.problem;
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
  return Propagate(run);
}

EodResult CalcPackEod(const BatteryPack& pack, const PackState& state, double total_current_a,
                      const EodOptions& options) {
  // Propagate is PropagateUntil with no bound: the same segments to the end.
  return *CalcPackEodBefore(pack, state, total_current_a, std::numeric_limits<double>::infinity(), options);
}

std::optional<EodResult> CalcPackEodBefore(const BatteryPack& pack, const PackState& state, double total_current_a,
                                           double bound_s, const EodOptions& options) {
  RequireValid(options);
  RequireDischargeCurrent(total_current_a);
  Run run(total_current_a, options);
  UASCMA_CHECK(SetUpScaledPack(run.problem, pack, state, {}), "a built pack's cells have positive R0 and capacity");
  return PropagateUntil(run, bound_s);
}

namespace eod_internal {

std::optional<EodResult> CalcScaledPackEod(const BatteryPack& pack, const PackState& state, double total_current_a,
                                           const CellScaling& scaling, const EodOptions& options) {
  RequireValid(options);
  RequireDischargeCurrent(total_current_a);
  Run run(total_current_a, options);
  if (!SetUpScaledPack(run.problem, pack, state, scaling)) return std::nullopt;
  return Propagate(run);
}

bool CalcScaledPackEods(const BatteryPack& pack, std::span<const ScaledEodRequest> requests,
                        std::span<EodResult> results, const EodOptions& options) {
  RequireValid(options);
  UASCMA_CHECK(results.size() == requests.size(), "one result per request");
  // Storage for the runs (about 2 kB each), built only for the requests made.
  union RunSlot {
    RunSlot() {}
    Run run;
  };
  static_assert(std::is_trivially_destructible_v<Run>);
  std::array<RunSlot, kMaxBatchedEods> slots;
  std::array<Run*, kMaxBatchedEods> run_pointers{};
  UASCMA_CHECK(requests.size() <= slots.size(), "at most kMaxBatchedEods requests");
  for (std::size_t k = 0; k < requests.size(); ++k) {
    const ScaledEodRequest& request = requests[k];
    if (!IsDischargeCurrent(request.current_a)) return false;
    Run& run = *std::construct_at(&slots[k].run, request.current_a, options);
    run_pointers[k] = &run;
    if (!SetUpScaledPack(run.problem, pack, *request.state, request.scaling)) return false;
  }
  PropagateTogether(std::span<Run* const>(run_pointers.data(), requests.size()));
  for (std::size_t k = 0; k < requests.size(); ++k) results[k] = *run_pointers[k]->result;
  return true;
}

}  // namespace eod_internal

}  // namespace uascma::prognostics

#undef UASCMA_EOD_INLINE
