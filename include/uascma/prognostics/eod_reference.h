#pragma once
// The fixed-step references of the battery end of discharge (eod.h; eod_reference.cc): the pack (or cell) model
// stepped at a fixed Δt with the branch split of eqs. 3.4–3.7 re-computed every step, as the simulator integrates
// it, the cut-off crossing interpolated linearly between steps. CalcPackEod and CalcCellEod solve the same model
// exactly; the references are what they are checked against (tests/prognostics/eod_test.cc, `uascma eod
// --reference-dt-s`), and are slow (µs per step).
#include "uascma/models/battery_cell.h"
#include "uascma/models/battery_pack.h"
#include "uascma/prognostics/eod.h"

namespace uascma::prognostics {

// The EOD of CalcPackEod (CalcCellEod) by the fixed-step reference at dt_s (s); InputError for invalid options or a
// step that is not a positive finite number.
EodResult SimulatePackEod(const models::BatteryPack& pack, const models::PackState& state, double total_current_a,
                          double dt_s, const EodOptions& options = {});
EodResult SimulateCellEod(const models::SelfCorrectingCell& cell, const models::CellState& state, double current_a,
                          double dt_s, const EodOptions& options = {});

}  // namespace uascma::prognostics
