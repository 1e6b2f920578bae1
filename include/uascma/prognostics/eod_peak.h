#pragma once
// The cut-off a current peak reaches before the energy is spent (docs/modelling-choices.md#eod-peak-sag).
//
// The EOD of eod.h propagates the cells at a constant current I and stops where a terminal voltage (eq. 3.3) reaches
// the cut-off v_c (3.3 V, §3.3.2.1). The speed controllers cut out at the first instant a cell reaches v_c, and the
// flight's current is not constant: gusts and the controller's corrections draw peaks above the mean. A peak of ΔI
// above the current I lasting seconds moves only the terms of eq. 3.3 that respond within seconds:
//   * the ohmic term, −R0 Δi;
//   * the RC pairs' currents i_Rj follow i with the time constant R_j C_j (Table 3.1: 9.9 mΩ × 51.5 kF ≈ 510 s),
//     so over a peak of seconds they stay where the mean current put them (their share is of order t/(R_j C_j));
//   * OCV(z) and the hysteresis move with the charge drawn, a peak's charge is ΔI · seconds: negligible.
// The branch split of a current step at fixed OCVs (eqs. 3.4–3.5 differentiated in I) gives the branch j that
// conducts the part Δi_j = ΔI · (1/R0^j) / Σ_k (1/R0^k) (eq. 3.7's branch resistances, over the conducting branches).
// So a cell c of branch j is at v_c during the peak exactly when, at the mean current, its voltage is at
//   v_c + R0_c · Δi_j.
// The EOD under peaks of ΔI is therefore the constant-current EOD with each cell's cut-off raised by R0_c · Δi_j. One
// cut-off serves all cells of eod.h's propagation: the largest raise over the conducting cells, exact for the cell
// with the largest R0 · Δi_j (the power-faded cell of a medium pack, which limits its EOD) and early by the rest for
// the others (cells that differ only by Table 3.1's cell-to-cell spread of R0 differ by millivolts).
#include "uascma/models/battery_pack.h"
#include "uascma/prognostics/eod.h"

namespace uascma::prognostics {

// V per cell: max over the cells of the branches that conduct at `current_a` (A, the EOD's constant current) of
// R0_c · Δi_j for a peak of `peak_a` (A) above it, split between the conducting branches as above. 0 for a peak ≤ 0
// or when no branch conducts.
double CalcPeakSagV(const models::BatteryPack& pack, const models::PackState& state, double current_a, double peak_a);

// `base` with its cut-off raised by CalcPeakSagV (at most to models::kCutoffVoltageBounds.high, 4.2 V: a cut-off
// there is reached at once).
EodOptions PeakSagEodOptions(const models::BatteryPack& pack, const models::PackState& state, double current_a,
                             double peak_a, const EodOptions& base = {});

}  // namespace uascma::prognostics
