#pragma once
// The one home for every way flights share a vehicle or branch from one another (flight.h's kernel underneath):
//
//   RunTogether        one scenario flown once per CMA policy, one flight while the policies agree (NoOp at every
//                      epoch so far), a branch (a copy of the state and the log) for each policy that first acts:
//                      a campaign's paired policies (§5.5, Simulator::RunTogether, campaign/metrics.h FlyRunTogether);
//   FlyFollowing       flights of one model flown with their own battery executors (Ch. IV's loop, Fig. 4.3), one
//                      vehicle while their packs cap the rotors alike (StepFollowing: the vehicle part shared, each
//                      its own power system), each on its own once its pack caps a rotor differently: the battery
//                      MDP's learning flights, its evaluation, the hindsight search (campaign/battery_flights.h);
//   RequireBranchPoint where a flight may be continued from a copy of its state (DecisionEnvironment::SetState, the
//                      transition estimation's branches, learning/transition_estimation.h).
//
// A flight flown together with others equals the same flight flown alone, bit for bit: the state is a value and the
// random streams are part of it (flight.h), so a copy taken at any moment has the copied flight's future.
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "uascma/sim/act.h"
#include "uascma/sim/emergency_planner.h"
#include "uascma/sim/flight.h"
#include "uascma/sim/lockstep.h"
#include "uascma/sim/policy.h"
#include "uascma/sim/simulator.h"

namespace uascma::sim {

// How the GNC steps of flights flown together were taken.
struct SharingCounts {
  std::int64_t shared_steps = 0;  // steps a flight took by following another's vehicle
  std::int64_t alone_steps = 0;   // steps of flights that had left their group
};

// Flies `states` (flights of `model` at the same GNC step, at a decision epoch) to their ends with the CMA's NoOp:
// at every epoch each flight still flying asks its battery executor (executors[k], DecideBattery), then the GNC
// steps to the next epoch. The flights still together fly one vehicle (the first of them leads, StepFollowing); one
// whose pack caps a rotor differently flies on alone with Step from that step. Fig. 4.3's loop has no CMA: Observe
// and a NoOp Act change nothing these flights read, so neither is called. Requires what StepFollowing requires (no
// modelled fault, no fault detector). Returns how the steps were taken.
SharingCounts FlyFollowing(const FlightModel& model, std::span<FlightState> states,
                           std::span<BatterySwitchPolicy* const> executors);

// Flies the model's scenario from its seed once for each policy and returns what Simulator::Run would return for each,
// bit for bit (wall_time_s apart), sharing the flight while the policies agree: the flights of policies that have
// chosen NoOp at every epoch so far are one flight; at the first epoch where a policy chooses anything else its flight
// is copied (FlightState and FlightLog are values) and goes on alone. planners[k] (empty: the map's) is policy k's;
// the battery executor of `options`, if any, is asked once per shared flight (it keeps no state). A shared stretch's
// wall time is split equally between its flights.
std::vector<SimResult> RunTogether(const FlightModel& model, std::span<DecisionPolicy* const> policies,
                                   std::span<const EmergencyPlanner> planners, const RunOptions& options = {});
// RunTogether as a coroutine (sim/lockstep.h) that asks `steps` for every GNC step and leaves the flights' results in
// `results` when it ends: RunTogether runs it with steps taken at once; a campaign thread keeps several in flight with
// their flights stepped in lockstep. `model`, the policies and planners the spans view, and `steps` and `results`
// must outlive the coroutine.
FlightCoroutine FlyTogether(const FlightModel& model, std::span<DecisionPolicy* const> policies,
                            std::span<const EmergencyPlanner> planners, RunOptions options, EpochSteps& steps,
                            std::vector<SimResult>& results);

// True when a flight of `model` may be continued from a copy of `state`: at a decision epoch (before its BeginEpoch)
// or finished.
inline bool IsBranchPoint(const FlightModel& model, const FlightState& state) {
  return state.done() || IsDecisionEpoch(model, state);
}
// `state` when it is a branch point; otherwise InputError naming `source`, the field "state" and the step.
const FlightState& RequireBranchPoint(const FlightModel& model, const FlightState& state, std::string_view source);

}  // namespace uascma::sim
