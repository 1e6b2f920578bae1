#pragma once
// The multi-rate hexacopter simulator of §5.4 (Fig. 5.15) as one call: a short loop of StepEpoch over the
// kernel of flight.h (GNC at 200 Hz: LQR → mixer → rotor lag → 6-DOF with drag and Dryden wind; IMM rotor-failure
// isolation; battery pack coupling; at 1 Hz the EOD, the motor RUL, the abstract CMA state and the decision
// module, whose action swaps the executing plan), and the flight's result.
//
// Model apart from state (a model apart from its state): a Simulator is immutable after construction and Run() takes
// the seed from the scenario, so one Simulator serves many threads and every flight replays from (scenario, seed). To
// step, snapshot or branch a flight, use flight.h directly (or environment.h for a decision-epoch interface).
#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "uascma/sim/act.h"
#include "uascma/sim/emergency_planner.h"
#include "uascma/sim/flight.h"
#include "uascma/sim/outcome.h"
#include "uascma/sim/policy.h"
#include "uascma/sim/scenario.h"

namespace uascma::sim {

struct SimResult {
  Outcome outcome = Outcome::kInProgress;
  std::string reason;
  double sim_time_s = 0.0;
  double wall_time_s = 0.0;  // measured by Run around the kernel (the only field that differs between replays)
  std::uint64_t seed = 0;
  std::string policy;
  double plan_duration_s = 0.0;
  std::optional<double> spall_onset_s, jam_time_s, isolation_time_s;
  int isolated_rotor = 0;
  double min_cell_voltage_v = 0.0;
  double max_tracking_error = 0.0;  // m
  double max_tilt = 0.0;            // rad
  double energy_wh = 0.0;
  // s: the true pack's EOD at the end of the flight at the vehicle's steady hover current (how long it could still
  // have hovered; 0 once a cell is at the cut-off).
  double end_reserve_s = 0.0;
  // The EOD's distribution when the CMA first acted (DecisionState::eod_at_first_action); none: it never did.
  std::optional<EodAtAction> eod_at_first_action;
  std::string eod_load;  // SimOptions::eod_load's name: what the 1 Hz EOD was propagated at
  // Unavailable actions (docs/modelling-choices.md#unavailable-actions): epochs at which the chosen action could not be
  // carried out and another was taken, and each distinct "Chosen->Taken" pair in the order first seen.
  int substitution_epochs = 0;
  std::vector<std::string> substitutions;
  double speed_cap_mps = 0.0;  // the airspeed cap after a rotor isolation (+inf: none, §4.4.2)
  std::vector<FlightEvent> events;
  std::vector<std::pair<double, decision::CmaAction>> actions;          // (time, action) of every executed change
  std::vector<std::pair<double, decision::StateIndex>> states;          // CMA state at every epoch
  std::vector<std::pair<double, models::PackAction>> battery_switches;  // the battery executor's changes
  std::vector<TelemetryRow> telemetry;
  std::vector<Eigen::Vector3d> executed_plan_ref;      // for plotting: the emergency plans
  std::optional<planning::FlightPlan> emergency_plan;  // the emergency plan flown at the end, when one was
  std::vector<Eigen::Vector2d> footprint_NE;           // the LandASAP footprint boundary, when one was planned
  std::string emergency_site;                          // the site of the last emergency plan ("" when none)
  double emergency_reach_margin = 0.0;                 // its RM when it was chosen
  double realtime_factor() const { return wall_time_s > 0 ? sim_time_s / wall_time_s : 0.0; }
};

struct RunOptions {
  bool record_telemetry = true;
  BatterySwitchPolicy* battery_policy = nullptr;  // the 1 Hz battery executor (Ch. IV); null: both packs on
};

// The result of a finished flight from its final state and log (the end-of-flight event appended to the log's).
SimResult MakeSimResult(const FlightModel& model, const FlightState& state, FlightLog log, const std::string& policy);

class Simulator {
 public:
  // Validates the scenario (InputError naming the field) and builds the immutable model, including the
  // LandPract database when the map has landing sites.
  explicit Simulator(const Scenario& scenario) : model_(scenario) {}

  // Flies the scenario from its seed. `planner` replaces the map's emergency planners when given.
  SimResult Run(DecisionPolicy& policy, const EmergencyPlanner& planner = {}, const RunOptions& options = {}) const;

  // sim/branching.h RunTogether over this simulator's model: each policy's Run, bit for bit (wall_time_s apart),
  // flown as one flight while the policies agree (a campaign's paired policies, §5.5).
  std::vector<SimResult> RunTogether(std::span<DecisionPolicy* const> policies,
                                     std::span<const EmergencyPlanner> planners, const RunOptions& options = {}) const;

  const FlightModel& model() const { return model_; }
  const Scenario& scenario() const { return model_.scenario(); }
  const planning::FlightPlan& nominal_plan() const { return model_.nominal_plan(); }
  decision::BatteryHealth battery_health() const { return model_.battery_health(); }
  const std::vector<Eigen::Vector3d>& checkpoints() const { return model_.checkpoints(); }

 private:
  FlightModel model_;
};

}  // namespace uascma::sim
