#pragma once
// When the CMA may end a flight with Terminate (parachute, motors cut: docs/modelling-choices.md#terminate and
// #terminate-last-resort). The MDP ranks Terminate above NoOp in every RM0 state (from RM0, NoOp leads
// to FL with probability 1, Table 5.7), so a reach margin that is negative only because of the safety margin t_sf,
// or an emergency plan that cannot be made on the last metres of a descent, would end flights that reach the ground.
// Real autopilots guard their flight-termination action the same way: it is armed by a separate setting, and off it
// is never taken. The executor's check (sim/act.cc, docs/cma-safeguards.md):
//   kLastResort  Terminate (chosen, or reached as the next-best of docs/modelling-choices.md#unavailable-actions)
//                is carried out only when no other available action can bring the vehicle to the ground before
//                the pack's EOD: the executing plan (NoOp) when it is on its final descent or t_remaining ≤ t_EOD,
//                LandASAP or LandPract when their planner finds a plan whose flight time is ≤ t_EOD at that
//                plan's own load (RM ≥ 0 with t_sf = 0, prognostics/reach_margin.h). Otherwise the first such
//                action of the policy's ranking replaces it.
//   kPolicy      Terminate as the policy ranks it (the MDP's own choice, no check).
//   kNever       Terminate is never carried out (termination disarmed): the first action of the ranking that
//                reaches the ground as above, else the executing plan.
#include <string>

namespace uascma::sim {

enum class TerminationRule { kLastResort, kPolicy, kNever };

// "last-resort" | "policy" | "never".
const char* TerminationRuleName(TerminationRule rule);
// InputError naming `source` and `field` for any other text.
TerminationRule ParseTerminationRule(const std::string& text, const std::string& source, const std::string& field);

}  // namespace uascma::sim
