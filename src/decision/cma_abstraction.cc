#include "uascma/decision/cma_abstraction.h"

namespace uascma::decision {

ReachMargin ClassifyReachMargin(double reach_margin) {
  return reach_margin < 0.0 ? ReachMargin::kRM0 : ReachMargin::kRM1;
}

MotorMargin ClassifyMotorMargin(double motor_margin) {
  return motor_margin < 0.0 ? MotorMargin::kMM0 : MotorMargin::kMM1;
}

CmaState AbstractCmaState(FlightStatus flight_status, MotorHealth motor_health, BatteryHealth battery_health,
                          double reach_margin, double motor_margin) {
  return CmaState{flight_status, motor_health, ClassifyMotorMargin(motor_margin), battery_health,
                  ClassifyReachMargin(reach_margin)};
}

bool IsCmaActionAvailable(FlightStatus flight_status, CmaAction action) {
  switch (flight_status) {
    case FlightStatus::kN:
      return true;
    case FlightStatus::kElPract:
      return action != CmaAction::kLandPract;
    case FlightStatus::kElAsap:
      return action == CmaAction::kNoOp || action == CmaAction::kTerminate;
  }
  return false;
}

CmaAction EffectiveCmaAction(CmaAction chosen, FlightStatus flight_status) {
  const bool repeat = (chosen == CmaAction::kLandPract && flight_status == FlightStatus::kElPract) ||
                      (chosen == CmaAction::kLandAsap && flight_status == FlightStatus::kElAsap);
  return repeat ? CmaAction::kNoOp : chosen;
}

FlightStatus FlightStatusAfter(CmaAction action, FlightStatus flight_status) {
  if (action == CmaAction::kLandPract) return FlightStatus::kElPract;
  if (action == CmaAction::kLandAsap) return FlightStatus::kElAsap;
  return flight_status;
}

FactoredState FactoredCmaState(const CmaState& state) {
  FactoredState factored;
  factored.values = {static_cast<int>(state.fs), static_cast<int>(state.mh), static_cast<int>(state.mm),
                     static_cast<int>(state.bh), static_cast<int>(state.rm)};
  return factored;
}

FactoredState FactoredCmaState(CmaTerminal terminal) {
  FactoredState factored;
  factored.terminal = static_cast<int>(terminal);
  return factored;
}

double CmaEpochReward(const CmaWeights& weights, const CmaState& state, CmaAction chosen) {
  const CmaAction executed = EffectiveCmaAction(chosen, state.fs);
  return CmaReward(weights, FactoredCmaState(state), static_cast<ActionIndex>(executed));
}

double CmaTerminalReward(const CmaWeights& weights, CmaTerminal terminal) {
  const auto noop = static_cast<ActionIndex>(CmaAction::kNoOp);
  return CmaReward(weights, FactoredCmaState(terminal), noop) -
         CmaReward(weights, FactoredCmaState(CmaTerminal::kE), noop);
}

}  // namespace uascma::decision
