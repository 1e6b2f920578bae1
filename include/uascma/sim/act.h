#pragma once
// The actions a decision epoch executes (sim/epoch.h): the CMA's (Act: an emergency plan, Terminate, or a substitute
// when the chosen action cannot be carried out) and the battery executor's (Ch. IV: BatterySwitchPolicy decides the
// pack switches, DecideBattery applies them).
#include "uascma/decision/cma_mdp.h"
#include "uascma/models/battery_pack.h"
#include "uascma/sim/emergency_planner.h"
#include "uascma/sim/flight.h"
#include "uascma/sim/policy.h"

namespace uascma::sim {

// Executes a CMA action chosen at the present epoch (after Observe): Terminate ends the flight; LandPract and
// LandASAP ask `planner` (empty: the model's map planner) for an emergency plan, and switch to it when there is
// one; an action equal to the executing one is a no-op (docs/modelling-choices.md#executing-action-repeat). When the
// planner finds nothing, the action cannot be carried out at this epoch
// (docs/modelling-choices.md#unavailable-actions): the next action of `ranking` (the state's actions by decreasing Q;
// empty: the default CMA policy's) that can be is taken instead, and the substitution is an event and counted in the
// state. Returns the action taken (NoOp and Terminate always can be).
decision::CmaAction Act(const FlightModel& model, FlightState& state, decision::CmaAction action,
                        const EmergencyPlanner& planner, FlightLog* log = nullptr, ActionRanking ranking = {});

// A 1 Hz battery executor (§4.3.2: the battery MDP's policy); its action takes effect at once
// (docs/modelling-choices.md#battery-mdp-policies).
class BatterySwitchPolicy {
 public:
  virtual ~BatterySwitchPolicy() = default;
  virtual models::PackAction Decide(const FlightModel& model, const FlightState& state) = 0;
};

// Sets the pack switches (Table 4.3); takes effect at the next step.
void SwitchPacks(FlightState& state, models::PackAction action);

// At an epoch (after Observe): the battery executor decides and the packs switch; a change of its action is
// logged (an event "battery: UseBatt1" and FlightLog::battery_switches).
void DecideBattery(const FlightModel& model, FlightState& state, BatterySwitchPolicy& policy, FlightLog* log = nullptr);

}  // namespace uascma::sim
