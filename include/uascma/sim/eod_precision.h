#pragma once
// How far a decision epoch propagates the pack's EOD (sim/epoch.h Observe): to its value, or only as far as the reach
// margin's class needs. RM0 ⇔ EOD < t_remaining + t_sf (docs/modelling-choices.md#margins), so a propagation may stop
// once it has passed t_remaining + t_sf without a crossing (prognostics::CalcPackEodBefore): the EOD is then at least
// that, RM1, and DecisionInputs::eod holds an EodLowerBound (sim/policy.h) until CompleteEod. A propagation that ends
// before is CalcPackEod's, bit for bit, and the abstract CMA state is the same either way: only a policy that reads the
// state alone may decide on a bound, and the epoch completes the value before anything else reads it.
#include <span>

#include "uascma/sim/policy.h"

namespace uascma::sim {

class FlightModel;
struct FlightState;
class BatterySwitchPolicy;
struct FlightLog;

enum class EodPrecision { kValue, kReachMarginClass };

// Whether an epoch needs the EOD's value or only its class: the class when no one reads the value unless a policy
// acts (policies that read only the CMA state, no battery executor, no telemetry, no distribution, exact sensing).
EodPrecision EpochEodPrecision(const FlightModel& model, std::span<DecisionPolicy* const> policies,
                               const BatterySwitchPolicy* battery, const FlightLog* log, bool eod_distribution);

// The EOD's value at this epoch where Observe propagated it only for the reach margin's class: the same CalcPackEod on
// the same pack and current, hence the value kValue gives, into DecisionState::eod and DecisionInputs::eod as an
// EodValue (the class cannot change: checked). Nothing when the value is there. Must be called at the epoch it
// completes (before any step). Act and RecordEodAtAction call it for every action but NoOp.
void CompleteEod(const FlightModel& model, FlightState& state);

}  // namespace uascma::sim
