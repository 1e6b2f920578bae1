#pragma once
// The CMA MDP under the vehicle-level reading of the motor margin (docs/modelling-choices.md#vehicle-motor-margin).
//
// Eq. 5.14 (§5.3.2.1) sets MM0 when the spalled motor's RUL is shorter than the rest of the flight or the motor has
// seized. The vehicle-level reading asks instead whether the VEHICLE can finish: MM0 when the hexacopter as it would
// be after the predicted jam (isolated to a quadcopter, §4.4, at its post-isolation speed cap, its pack's EOD at that
// vehicle's forecast load) could not fly the rest of the plan with the safety margin t_sf, or when the motor is
// seized and not yet isolated (sim/vehicle_margin.h). It is a second abstraction of the same MDP: states, actions,
// availability (docs/modelling-choices.md#action-availability), rewards (eqs. 5.20-5.29) and Tables 5.1-5.4, 5.6, 5.7
// are the DDN's. Table 5.5 changes only in its JF rows, derived as the DDN's are from what MM now means:
//   NF, SF rows   as printed (a spall's MM0 <-> MM1 moves are still those of a margin that a landing restores);
//   MM1, JF       -> MM1 with probability 1 for every action but Terminate: the isolated quadcopter can finish the
//                 plan, and no second motor fault is modelled (§5.3.2.1: "Once a spalling fault is observed, it is
//                 assumed not to occur in the remaining motors"); the battery's side is RM's (Table 5.3);
//   MM0, JF       the SF MM0 row as printed (0.995 / 0.9 / 0.89 stay MM0 under NoOp / LandASAP / LandPract): the
//                 quadcopter cannot finish, and only a shorter plan restores the margin, as it does for a spall.
// In the DDN's table a JF row always goes to MM0 (eq. 5.14: a seized motor), so JF,MM1 is unreachable there and its
// action carries no meaning; here it is the state of a jammed hexacopter that flies on as a quadcopter.
#include <vector>

#include "uascma/decision/cma_mdp.h"
#include "uascma/decision/factored_mdp.h"
#include "uascma/decision/finite_mdp.h"
#include "uascma/decision/solvers.h"

namespace uascma::decision {

// Table 5.5 with the JF rows above.
ConditionalTable CmaVehicleMotorMarginTable();
// MakeCmaFactoredModel with CmaVehicleMotorMarginTable in place of Table 5.5.
FactoredMdpBuilder MakeCmaVehicleFactoredModel();
FiniteMdp BuildCmaVehicleMdp(const CmaWeights& weights);
// The vehicle-level model with the dissertation's weights (eqs. 5.28-5.29) and gamma = 0.95
// (docs/modelling-choices.md#discount), solved by value iteration; `ranking` as SolveDefaultCmaPolicy's (per state,
// actions by decreasing Q).
Policy SolveCmaVehiclePolicy(std::vector<std::vector<ActionIndex>>* ranking = nullptr);

}  // namespace uascma::decision
