#pragma once
// One decision epoch of the kernel (sim/flight.h, §5.4, Fig. 5.15), at 1 Hz: Observe (battery EOD, motor RUL, the
// reach and motor margins and the abstract CMA state, decision/cma_abstraction.h), the battery executor (sim/act.h
// DecideBattery), the CMA policy's decision, Act (sim/act.h), then the GNC steps to the next epoch (sim/flight.h
// StepToNextEpoch).
#include "uascma/decision/cma_mdp.h"
#include "uascma/sim/emergency_planner.h"
#include "uascma/sim/eod_precision.h"
#include "uascma/sim/flight.h"
#include "uascma/sim/policy.h"

namespace uascma::sim {

class BatterySwitchPolicy;  // sim/act.h

// What decides at an epoch: the CMA policy, optionally the battery executor, and the emergency planner (empty:
// the model's map planner).
struct Controllers {
  DecisionPolicy* policy = nullptr;
  BatterySwitchPolicy* battery = nullptr;
  EmergencyPlanner planner;
};

// At an epoch: EOD, RUL, margins and the abstract CMA state into state.decision.inputs (and the log's states), and with
// `eod_distribution` the EOD's distribution from the model's error table (DecisionInputs::eod_distribution).
// `precision` (sim/eod_precision.h): kReachMarginClass requires exact sensing and no distribution (both read the EOD's
// value).
const DecisionInputs& Observe(const FlightModel& model, FlightState& state, FlightLog* log = nullptr,
                              bool eod_distribution = true, EodPrecision precision = EodPrecision::kValue);

// The start of a decision epoch: Observe, then the battery executor decides (DecideBattery; none when `battery` is
// null). Returns the observed inputs the CMA policy decides on.
const DecisionInputs& BeginEpoch(const FlightModel& model, FlightState& state, BatterySwitchPolicy* battery,
                                 FlightLog* log = nullptr, bool eod_distribution = true,
                                 EodPrecision precision = EodPrecision::kValue);

// Whether an epoch computes the EOD's distribution: when the policy reads it or the log records telemetry.
inline bool NeedsEodDistribution(const DecisionPolicy* policy, const FlightLog* log) {
  return (policy && policy->ReadsEodDistribution()) || (log && log->record_telemetry);
}

// After the policy decided `action` at this epoch (after Observe, before Act): at the first action that is not NoOp,
// the EOD's distribution into DecisionState::eod_at_first_action (computed now if the epoch did not).
void RecordEodAtAction(const FlightModel& model, FlightState& state, decision::CmaAction action);

// One decision epoch: BeginEpoch (the EOD's distribution when NeedsEodDistribution), the policy decides (a null
// policy: NoOp), RecordEodAtAction, Act, then GNC steps to the next epoch or the end of the flight. Must be called at
// an epoch.
void StepEpoch(const FlightModel& model, FlightState& state, const Controllers& controllers, FlightLog* log = nullptr);
// StepEpoch before its steps: BeginEpoch, the decision, RecordEodAtAction, Act (a flight at an epoch, not done).
void DecideEpoch(const FlightModel& model, FlightState& state, const Controllers& controllers,
                 FlightLog* log = nullptr);

}  // namespace uascma::sim
