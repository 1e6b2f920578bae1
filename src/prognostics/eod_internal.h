#pragma once
// What the exact EOD propagation (eod.cc) and the fixed-step references (eod_reference.cc) share.
#include <array>
#include <optional>
#include <span>

#include "uascma/prognostics/eod.h"

namespace uascma::prognostics::eod_internal {

// InputError "EOD options: …" unless options.IsValid().
void RequireValid(const EodOptions& options);
// A result of `status` at `eod_s`, with no limiting cell and no cost figures.
EodResult Ended(EodStatus status, double eod_s);

// Every cell's R0 and capacity scaled alike, as eod_distribution.cc's ScaledPack scales CellParams (the RC pairs,
// the OCV table, the rest unchanged); two R0 factors for a scaled pack scaled again (the cold class, then R0).
struct CellScaling {
  std::array<double, 2> r0_factors = {1.0, 1.0};  // R0 → R0 · r0_factors[0] · r0_factors[1], left to right
  double capacity_factor = 1.0;                   // capacity_ah → capacity_ah · capacity_factor
};

// CalcPackEod of the pack a BatteryPack built from the scaled CellParams would be, bit for bit, without
// building it (no OCV-table copies, no labels, no validation of the unchanged parameters). std::nullopt when a
// scaled R0 or capacity is not a positive finite number: building that pack reports the error.
std::optional<EodResult> CalcScaledPackEod(const models::BatteryPack& pack, const models::PackState& state,
                                           double total_current_a, const CellScaling& scaling,
                                           const EodOptions& options);

// One pack EOD of a batch: CalcScaledPackEod(pack, *state, current_a, scaling) (the default scaling: CalcPackEod's).
struct ScaledEodRequest {
  const models::PackState* state = nullptr;  // not owned
  double current_a = 0.0;
  CellScaling scaling;
};
inline constexpr std::size_t kMaxBatchedEods = 8;

// The EODs of up to kMaxBatchedEods requests, each bit for bit what its own call gives, computed together (their
// propagations advance in lockstep, so that the core overlaps their serial chains). False, with no result, when a
// request's call would not give one: a current not finite and >= 0, or a scaled R0 or capacity not a positive finite
// number (the caller then makes the calls one by one). InputError for invalid options.
bool CalcScaledPackEods(const models::BatteryPack& pack, std::span<const ScaledEodRequest> requests,
                        std::span<EodResult> results, const EodOptions& options);

}  // namespace uascma::prognostics::eod_internal
