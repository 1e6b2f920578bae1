#pragma once
// The runtime abstraction of the CMA state (§5.3.2.1, §5.4; docs/modelling-choices.md#action-availability, #margins,
// #battery-health-label, #executing-action-repeat): from the continuous quantities the simulator (or a vehicle)
// computes at 1 Hz to the abstract state the CMA policy reads, and the rules by which an action chosen in a state is
// executed. Pure functions, used alike by the simulator, the decision environment and the campaign's reward accounting.
//
//   RM = 1 − (t_remaining + t_sf) / t_EOD   → RM0 when RM < 0, else RM1   (#margins; prognostics::CalcReachMargin)
//   MM = 1 − t_remaining / t_RUL            → MM0 when MM < 0, else MM1   (#margins; prognostics::CalcMotorMargin)
//   MH: NF without a fault, SF once a spall is detected, JF once a rotor is isolated (jammed)
//   BH: the pack's composite health, constant in a flight (#battery-health-label)
//   FS: N on the original plan, ELASAP / ELPRACT while executing that emergency plan
#include "uascma/decision/cma_mdp.h"

namespace uascma::decision {

ReachMargin ClassifyReachMargin(double reach_margin);
MotorMargin ClassifyMotorMargin(double motor_margin);

CmaState AbstractCmaState(FlightStatus flight_status, MotorHealth motor_health, BatteryHealth battery_health,
                          double reach_margin, double motor_margin);

// Availability (docs/modelling-choices.md#action-availability): N → all four; ELPRACT → {NoOp, Terminate, LandASAP};
// ELASAP → {NoOp, Terminate}.
bool IsCmaActionAvailable(FlightStatus flight_status, CmaAction action);

// Repeats (docs/modelling-choices.md#executing-action-repeat): the policy is queried every epoch, but an emergency
// action equal to the one executing is executed as NoOp.
CmaAction EffectiveCmaAction(CmaAction chosen, FlightStatus flight_status);

// The flight status an emergency action starts (LandASAP → ELASAP, LandPract → ELPRACT); N otherwise.
FlightStatus FlightStatusAfter(CmaAction action, FlightStatus flight_status);

// The reward of one epoch, R(S, A) of eqs. 5.20–5.29 with A the action executed (#executing-action-repeat applied to
// `chosen`).
double CmaEpochReward(const CmaWeights& weights, const CmaState& state, CmaAction chosen);
// A terminal state's own reward R(S_end) = R(S_end, A) − R(E, A) (eq. 5.23: R(E) = w_E · 0, and R(A) cancels):
// what a flight earns for ending in C, T or FL.
double CmaTerminalReward(const CmaWeights& weights, CmaTerminal terminal);

// The factored form of a tuple or terminal state, features in the model's order [FS, MH, MM, BH, RM].
FactoredState FactoredCmaState(const CmaState& state);
FactoredState FactoredCmaState(CmaTerminal terminal);

}  // namespace uascma::decision
