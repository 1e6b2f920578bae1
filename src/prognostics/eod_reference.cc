// Battery end-of-discharge: the fixed-step references the exact propagation (eod.cc) is checked against
// (eod_reference.h).
#include "uascma/prognostics/eod_reference.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <fmt/format.h>

#include "eod_internal.h"
#include "uascma/common/error.h"

namespace uascma::prognostics {

using eod_internal::Ended;
using eod_internal::RequireValid;
using models::BatteryPack;
using models::CellState;
using models::kBranchCount;
using models::kCellsPerBranch;
using models::PackState;
using models::SelfCorrectingCell;

// --- Fixed-step references ---------------------------------------------------------------------------
namespace {

void RequireStep(double dt_s) {
  if (!(dt_s > 0.0 && std::isfinite(dt_s))) {
    throw InputError("EOD reference", "dt_s", fmt::format("a positive step, got {}", dt_s));
  }
}

// The cut-off crossing between step k − 1 (voltage v_before) and step k (v_after ≤ cutoff), linearly
// interpolated, s.
double InterpolatedCrossingS(long long k, double dt_s, double v_before, double v_after, double cutoff_v) {
  const double fraction = v_before > v_after ? (v_before - cutoff_v) / (v_before - v_after) : 1.0;
  return (static_cast<double>(k - 1) + std::clamp(fraction, 0.0, 1.0)) * dt_s;
}

EodResult ReachedAtStep(double eod_s, int branch, int cell, long long steps) {
  EodResult result;
  result.status = EodStatus::kReached;
  result.eod_s = eod_s;
  result.limiting_branch = branch;
  result.limiting_cell = cell;
  result.segments = static_cast<int>(std::min<long long>(steps, std::numeric_limits<int>::max()));
  return result;
}

}  // namespace

EodResult SimulatePackEod(const BatteryPack& pack, const PackState& state, double total_current_a, double dt_s,
                          const EodOptions& options) {
  RequireValid(options);
  RequireStep(dt_s);
  models::PackOutputs previous = pack.CalcOutputs(state, total_current_a);
  if (!state.branch_on[0] && !state.branch_on[1]) return Ended(EodStatus::kNoBranchConnected, 0.0);
  EodResult result;
  if (previous.min_cell_voltage_v <= options.cutoff_v) {
    result.status = EodStatus::kAlreadyBelowCutoff;
    result.limiting_branch = previous.min_cell_branch;
    result.limiting_cell = previous.min_cell_index;
    return result;
  }
  if (!(total_current_a > 0.0)) return Ended(EodStatus::kNotReachedWithinHorizon, options.horizon_s);
  PackState s = state;
  const auto steps = static_cast<long long>(std::ceil(options.horizon_s / dt_s));
  for (long long k = 1; k <= steps; ++k) {
    const PackState previous_state = s;
    s = pack.Step(s, total_current_a, dt_s);
    const models::PackOutputs now = pack.CalcOutputs(s, total_current_a);
    if (now.min_cell_voltage_v <= options.cutoff_v) {
      // The earliest interpolated crossing among the cells that are at or below the cut-off.
      result = ReachedAtStep(std::numeric_limits<double>::infinity(), -1, -1, k);
      for (int b = 0; b < kBranchCount; ++b) {
        if (!s.branch_on[b]) continue;
        for (int c = 0; c < kCellsPerBranch; ++c) {
          // The cells' own voltages, as min_cell_voltage_v (a failed cell's reading is R_f i lower, pack_fault.h).
          const double now_v = pack.CalcCellOwnVoltage(s, now, b, c);
          if (now_v > options.cutoff_v) continue;
          const double crossing = InterpolatedCrossingS(
              k, dt_s, pack.CalcCellOwnVoltage(previous_state, previous, b, c), now_v, options.cutoff_v);
          if (crossing < result.eod_s) result = ReachedAtStep(crossing, b, c, k);
        }
      }
      return result;
    }
    previous = now;
  }
  return Ended(EodStatus::kNotReachedWithinHorizon, options.horizon_s);
}

EodResult SimulateCellEod(const SelfCorrectingCell& cell, const CellState& state, double current_a, double dt_s,
                          const EodOptions& options) {
  RequireValid(options);
  RequireStep(dt_s);
  double previous = cell.CalcTerminalVoltage(state, current_a);
  EodResult result;
  if (previous <= options.cutoff_v) {
    result.status = EodStatus::kAlreadyBelowCutoff;
    result.limiting_branch = 0;
    result.limiting_cell = 0;
    return result;
  }
  if (!(current_a > 0.0)) return Ended(EodStatus::kNotReachedWithinHorizon, options.horizon_s);
  CellState s = state;
  const auto steps = static_cast<long long>(std::ceil(options.horizon_s / dt_s));
  for (long long k = 1; k <= steps; ++k) {
    s = cell.Step(s, current_a, dt_s);
    const double v = cell.CalcTerminalVoltage(s, current_a);
    if (v <= options.cutoff_v) {
      return ReachedAtStep(InterpolatedCrossingS(k, dt_s, previous, v, options.cutoff_v), 0, 0, k);
    }
    previous = v;
  }
  return Ended(EodStatus::kNotReachedWithinHorizon, options.horizon_s);
}

}  // namespace uascma::prognostics
