#pragma once
// A decision environment over the simulator, for learning and scripting (Gym's reset/step at the CMA's 1 Hz
// decision epoch): Reset(seed) flies nothing and returns the first observation; Step(action) executes a CMA action
// at the present epoch, flies to the next epoch (or the end of the flight) and returns the next observation, the
// reward R(S, A) of eqs. 5.20–5.29 for the state and the executed action (docs/modelling-choices.md#rewards,
// #executing-action-repeat), whether the flight ended and how. When it ends, the reward also holds the terminal state's
// own reward R(C), R(T) or R(FL) (decision/cma_abstraction.h CmaTerminalReward), so an episode's undiscounted return
// equals the campaign's reward trace of the same flight (campaign/metrics.h CalcRewardTrace).
//
// The environment is a thin shell over flight.h: state() is the whole FlightState, which can be copied and set
// back (SetState) to branch a flight from any epoch.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "uascma/decision/cma_mdp.h"
#include "uascma/sim/act.h"
#include "uascma/sim/emergency_planner.h"
#include "uascma/sim/flight.h"
#include "uascma/sim/simulator.h"

namespace uascma::sim {

struct EnvironmentOptions {
  decision::CmaWeights weights;                   // for R(S, A) (eqs. 5.28–5.29 by default)
  EmergencyPlanner planner;                       // empty: the map's LandPract/LandASAP planners
  BatterySwitchPolicy* battery_policy = nullptr;  // the 1 Hz battery executor; null: both packs on
  bool record = false;                            // keep the flight's events, actions and states (Result())
  bool record_telemetry = false;                  // … and its telemetry rows
  // Availability (docs/modelling-choices.md#action-availability): an action not available in the flight status (ELPRACT
  // offers NoOp, Terminate, LandASAP; ELASAP NoOp, Terminate) is refused with an InputError. Off, any action is taken,
  // and one equal to the executing emergency action is executed as NoOp (#executing-action-repeat).
  bool require_available_actions = true;
};

// What the decision module sees at an epoch: the abstract CMA state and the continuous quantities behind it.
struct Observation {
  double time_s = 0.0;
  decision::CmaState state;
  decision::StateIndex state_index = 0;           // CmaStateIndex, or the terminal's CmaTerminalIndex once done
  std::optional<decision::CmaTerminal> terminal;  // C, T or FL once the flight has ended
  decision::FlightStatus flight_status = decision::FlightStatus::kN;
  double reach_margin = 0.0;
  double motor_margin = 0.0;
  double eod_s = 0.0;
  double rul_s = 0.0;  // +∞ without a motor fault
  double flight_time_remaining_s = 0.0;
  bool operator==(const Observation&) const = default;  // every member, exactly
};

// A flight at a decision epoch, whole: its state (the random streams included, flight.h) and its log so far. Restore
// continues the flight from it as many times as wanted, each branch the flight it copied would have flown (as
// MuJoCo's mj_copyData gives a rollout's start; sim/branching.h RequireBranchPoint).
struct EnvironmentSnapshot {
  FlightState state;
  FlightLog log;
};

struct EnvironmentStep {
  Observation observation;
  double reward = 0.0;
  bool done = false;
  Outcome outcome = Outcome::kInProgress;
  decision::CmaAction executed = decision::CmaAction::kNoOp;  // after docs/modelling-choices.md#executing-action-repeat
};

class DecisionEnvironment {
 public:
  explicit DecisionEnvironment(const Scenario& scenario, EnvironmentOptions options = {});
  DecisionEnvironment(std::shared_ptr<const FlightModel> model, EnvironmentOptions options = {});

  // A new flight from `seed` (the scenario's seed replays Simulator::Run's flight).
  Observation Reset(std::uint64_t seed);
  // InputError before Reset, after the flight has ended, or for an unavailable action.
  EnvironmentStep Step(decision::CmaAction action);

  bool done() const { return state_.done(); }
  const Observation& observation() const { return observation_; }
  const FlightModel& model() const { return *model_; }
  const FlightState& state() const { return state_; }
  // Continue from a copy of a state taken at an epoch of this model's flights (InputError otherwise).
  void SetState(const FlightState& state);
  // The flight now (InputError before Reset), and the flight continued from one taken before (its log too).
  EnvironmentSnapshot Snapshot() const;
  void Restore(const EnvironmentSnapshot& snapshot);
  // The flight so far as a SimResult (its log when `record` is set).
  SimResult Result(const std::string& policy = "environment") const;

 private:
  Observation MakeObservation() const;

  std::shared_ptr<const FlightModel> model_;
  EnvironmentOptions options_;
  FlightState state_;
  FlightLog log_;
  Observation observation_;
  bool reset_ = false;
};

}  // namespace uascma::sim
