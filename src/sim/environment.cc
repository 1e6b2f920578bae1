#include "uascma/sim/environment.h"

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/decision/cma_abstraction.h"
#include "uascma/sim/act.h"
#include "uascma/sim/branching.h"
#include "uascma/sim/epoch.h"
#include "uascma/sim/initial_state.h"

namespace uascma::sim {

DecisionEnvironment::DecisionEnvironment(const Scenario& scenario, EnvironmentOptions options)
    : DecisionEnvironment(std::make_shared<const FlightModel>(scenario), std::move(options)) {}

DecisionEnvironment::DecisionEnvironment(std::shared_ptr<const FlightModel> model, EnvironmentOptions options)
    : model_(std::move(model)), options_(std::move(options)) {
  UASCMA_CHECK(model_ != nullptr, "a flight model");
  std::string error;
  if (!options_.weights.IsValid(&error)) throw InputError("environment", "weights", error);
}

Observation DecisionEnvironment::MakeObservation() const {
  Observation o;
  const DecisionInputs& inputs = state_.decision.inputs;
  o.time_s = inputs.time_s;
  o.state = inputs.state;
  o.flight_status = state_.decision.flight_status;
  o.reach_margin = inputs.eod_value().reach_margin;
  o.motor_margin = inputs.motor_margin;
  o.eod_s = inputs.eod_value().eod_s;
  o.rul_s = inputs.rul_s;
  o.flight_time_remaining_s = inputs.flight_time_remaining_s;
  if (state_.done()) {
    o.time_s = state_.time_s;
    o.terminal = TerminalStateOf(state_.outcome);
    o.state_index = decision::CmaTerminalIndex(*o.terminal);
  } else {
    o.state_index = decision::CmaStateIndex(o.state);
  }
  return o;
}

Observation DecisionEnvironment::Reset(std::uint64_t seed) {
  state_ = MakeInitialState(*model_, seed);
  log_ = FlightLog{};
  log_.record_telemetry = options_.record_telemetry;
  FlightLog* log = options_.record ? &log_ : nullptr;
  BeginEpoch(*model_, state_, options_.battery_policy, log, log && log->record_telemetry);
  reset_ = true;
  observation_ = MakeObservation();
  return observation_;
}

EnvironmentStep DecisionEnvironment::Step(decision::CmaAction action) {
  if (!reset_) throw InputError("environment", "step", "Reset before the first Step");
  if (state_.done()) throw InputError("environment", "step", "a flight in progress (it has ended: Reset)");
  if (options_.require_available_actions && !decision::IsCmaActionAvailable(state_.decision.flight_status, action)) {
    throw InputError(
        "environment", "action",
        fmt::format("an action available in flight status {} (docs/modelling-choices.md#action-availability), got {}",
                    static_cast<int>(state_.decision.flight_status), decision::CmaActionName(action)));
  }
  FlightLog* log = options_.record ? &log_ : nullptr;
  EnvironmentStep out;
  const decision::FlightStatus status = state_.decision.flight_status;
  out.reward = decision::CmaEpochReward(options_.weights, state_.decision.inputs.state, action);
  // The EOD when the first action other than NoOp is asked for, as a policy's flight records it (DecideEpoch): the
  // flight's summary then equals Simulator::Run's for the same actions.
  RecordEodAtAction(*model_, state_, action);
  // An action that cannot be carried out is replaced by the next-highest of the default CMA policy's Q
  // (docs/modelling-choices.md#unavailable-actions); `executed` says what flew.
  out.executed = decision::EffectiveCmaAction(Act(*model_, state_, action, options_.planner, log), status);
  StepToNextEpoch(*model_, state_, log);
  if (!state_.done()) {
    BeginEpoch(*model_, state_, options_.battery_policy, log, log && log->record_telemetry);
  } else {
    out.reward += decision::CmaTerminalReward(options_.weights, TerminalStateOf(state_.outcome));
  }
  observation_ = MakeObservation();
  out.observation = observation_;
  out.done = state_.done();
  out.outcome = state_.outcome;
  return out;
}

void DecisionEnvironment::SetState(const FlightState& state) {
  state_ = RequireBranchPoint(*model_, state, "environment");  // sim/branching.h
  reset_ = true;
  observation_ = MakeObservation();
}

EnvironmentSnapshot DecisionEnvironment::Snapshot() const {
  if (!reset_) throw InputError("environment", "snapshot", "Reset before the first Snapshot");
  return EnvironmentSnapshot{state_, log_};
}

void DecisionEnvironment::Restore(const EnvironmentSnapshot& snapshot) {
  SetState(snapshot.state);
  log_ = snapshot.log;
}

SimResult DecisionEnvironment::Result(const std::string& policy) const {
  return MakeSimResult(*model_, state_, log_, policy);
}

}  // namespace uascma::sim
