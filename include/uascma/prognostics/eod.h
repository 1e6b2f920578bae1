#pragma once
// Battery End Of Discharge (EOD) prognosis, dissertation §3.3.2.1 and docs/modelling-choices.md#pack-eod:
// propagate each cell's Enhanced Self-Correcting model (eqs. 3.1–3.3) at the present constant total
// current until its terminal voltage reaches the cut-off (3.3 V); the pack EOD is the minimum over its
// cells; with both packs in parallel the branch currents follow eqs. 3.4–3.7 DURING the propagation.
//
// How it is computed (fast and exact, no fixed time step):
//  * Joint linear segments. OCV(z) is piecewise linear (ocv_table.h). While every discharging cell stays
//    inside one OCV segment, each branch OCV E_j (eq. 3.6) is affine in its cells' charge drawn, so the
//    split of eqs. 3.4–3.5 obeys a scalar linear ODE: with K_j = Σ_cells η·slope/Q (V per A·s) and
//    R_j of eq. 3.7,   di¹/dt = (K₂ I − (K₁ + K₂) i¹) / (R₁ + R₂),   i² = I − i¹.
//    Hence on a segment each branch current is EXACTLY  i(t) = ī + Δ·e^{−qt}  with
//    q = (K₁ + K₂)/(R₁ + R₂), ī¹ = K₂ I/(K₁ + K₂), Δ = i(0) − ī  (Δ = 0, q = 0 for a single branch).
//  * Under that current every cell state has a closed form: z (charge drawn = ī t + Δ(1 − e^{−qt})/q),
//    h (h + 1 decays with the charge drawn, eq. 3.2), i_R (first-order lag of i, eq. 3.1, driven by a
//    constant plus an exponential), hence the terminal voltage v(t) of eq. 3.3 (Plett form).
//  * The propagation jumps from one OCV breakpoint to the next (the time a branch reaches a breakpoint is
//    a scalar monotone root), and from a diode blocking/unblocking event to the next; no controller-rate
//    stepping. About 20 segments for a full discharge of the default table.
//  * Cut-off crossing inside a segment: v(t) need not be monotone (the RC voltage recovers after a current
//    drop; a branch current may fall). A rigorous lower bound of v on [t₁, t₂] (OCV and h are monotone,
//    i is monotone, i_R never exceeds max(i_R(t₁), max i)) prunes intervals with no crossing, and an
//    upper bound of dv/dt certifies monotone intervals, where a bracketed Newton iteration finds the
//    root to `time_tolerance_s`. Otherwise the interval is bisected, left half first, so the FIRST
//    crossing is returned (the ESCs cut out at the first one, docs/modelling-choices.md#outcomes).
//  This is the exact solution of the model the fixed-step simulator integrates (ZOH at its Δt), so the
//  two agree to O(Δt) (the fixed-step reference, eod_reference.h): tests require 0.5 % against Δt = 0.01 s and
//  measure ≤ 1.1e-5. Because the split is solved exactly on each segment, no "re-split every large step"
//  approximation (and no step-size tuning) is needed. Cost (bench/eod_bench.cc, one core, as measured when written):
//  about 2.1 µs for the default pack (both branches alike, ~18 segments), about 6 µs when the packs differ and a pack's
//  cells discharge out of step (~47 segments); the 10 ms fixed-step reference takes about 9 ms.
//
// Scope and conventions:
//  * Only switched-on branches count; a switched-off pack neither discharges nor limits the EOD.
//  * The current is held at its present value (the dissertation's constant-current EOD); the flight
//    plan's future load is not modelled here.
//  * Times are seconds from the given state. A crossing later than `horizon_s` is reported as
//    kNotReachedWithinHorizon with eod_s = horizon_s, a lower bound (e.g. a near-zero current).
//  * No allocation; the result is a plain struct (Python-bindable).
#include <optional>
#include <string>

#include "uascma/models/battery_cell.h"
#include "uascma/models/battery_pack.h"

namespace uascma::prognostics {

enum class EodStatus {
  kReached = 0,                  // a cell reaches the cut-off at eod_s
  kAlreadyBelowCutoff = 1,       // some connected cell is at or below the cut-off now: eod_s = 0
  kNotReachedWithinHorizon = 2,  // no crossing before horizon_s (or no discharge current): eod_s = horizon_s
  kNoBranchConnected = 3,        // both switches off: nothing can supply the bus, eod_s = 0
};
// "reached", "already_below_cutoff", "not_reached_within_horizon", "no_branch_connected".
const char* EodStatusName(EodStatus status);

struct EodOptions {
  double cutoff_v = models::kCutoffVoltage;  // per cell, 3.3 V (§3.3.2.1, docs/modelling-choices.md#outcomes)
  double horizon_s = 86400.0;                // one day: far beyond any flight of the vehicle
  // Plausible horizons: 1 s to one week (our bound; a week is ~700x the pack's hover endurance).
  static constexpr Bounds kHorizonBounds{1.0, 604800.0, "s"};
  double time_tolerance_s = 1e-6;  // root accuracy of the crossing time
  // cutoff_v within models::kCutoffVoltageBounds, horizon_s within kHorizonBounds, time_tolerance_s > 0;
  // writes the reason to *error on failure.
  bool IsValid(std::string* error) const;
};

struct EodResult {
  EodStatus status = EodStatus::kNotReachedWithinHorizon;
  double eod_s = 0.0;           // time until the first cell reaches the cut-off (see EodStatus)
  int limiting_branch = -1;     // pack index 0..1 of the limiting cell (−1 when none)
  int limiting_cell = -1;       // cell index 0..2 in its pack (−1 when none)
  int segments = 0;             // linear segments propagated (cost figure)
  int voltage_evaluations = 0;  // closed-form voltage evaluations in the crossing search (cost figure)

  // e.g. "reached: EOD 1234.5 s, limiting pack 2 cell 1 (21 segments)".
  std::string BriefReport() const;
  bool operator==(const EodResult&) const = default;
};

// EOD of one cell at a constant current (A, discharge > 0). A current ≤ 0 never discharges the cell:
// kNotReachedWithinHorizon unless the cell is already below the cut-off.
EodResult CalcCellEod(const models::SelfCorrectingCell& cell, const models::CellState& state, double current_a,
                      const EodOptions& options = {});

// EOD of the battery (two 3S packs, switches and diodes as in battery_pack.h) at a constant total
// discharge current ≥ 0 (A). Throws InputError for invalid options.
EodResult CalcPackEod(const models::BatteryPack& pack, const models::PackState& state, double total_current_a,
                      const EodOptions& options = {});

// CalcPackEod's result, or std::nullopt once its propagation has passed `bound_s` (s) without a cell reaching the
// cut-off: CalcPackEod's EOD is then at least bound_s. The same segments in the same order as CalcPackEod, so a result
// is CalcPackEod's bit for bit; only the segments that start at or after bound_s are left out. For a decision that asks
// only whether the EOD falls short of bound_s: the reach margin's class, RM0 ⇔ EOD < t_flight (sim/epoch.cc).
std::optional<EodResult> CalcPackEodBefore(const models::BatteryPack& pack, const models::PackState& state,
                                           double total_current_a, double bound_s, const EodOptions& options = {});

// RM = 1 − t_flight / t_EOD (docs/modelling-choices.md#margins). RM ≥ 0 ⇔ the remaining flight time fits in the EOD.
// With t_flight ≤ 0, RM = 1; with t_EOD = 0 and t_flight > 0, RM = −∞. A kNotReachedWithinHorizon result
// uses eod_s = horizon_s, so the answer is conservative.
double CalcReachMargin(const EodResult& eod, double flight_time_remaining_s);
// t_flight ≤ t_EOD (equivalently CalcReachMargin(…) ≥ 0).
bool IsFlightTimeReachable(const EodResult& eod, double flight_time_remaining_s);

}  // namespace uascma::prognostics
