#pragma once
// The simulator's kernel in MuJoCo's shape (mj_step(const mjModel*, mjData*)): an immutable FlightModel built
// once from a Scenario, a FlightState value that holds everything that changes during a flight, and the steps
// that advance it (§5.4, Fig. 5.15):
//
//   Step        one GNC step of 1 / gnc_rate_hz (5 ms), the vehicle's then the power system's: spall growth → LQR
//               → allocation → rotor lag → 6-DOF with drag and Dryden wind → IMM, then battery pack → outcome
//               (outcome.h);
//   Observe     at a decision epoch (1 Hz): battery EOD, motor RUL, the reach and motor margins and the
//               abstract CMA state (decision/cma_abstraction.h; sim/epoch.h);
//   Act         executes a CMA action chosen at that epoch (an emergency plan from the planner, or Terminate;
//               sim/act.h);
//   StepEpoch   BeginEpoch (Observe → the battery executor) → the CMA policy decides → Act → Step until the next
//               epoch or the end of the flight (sim/epoch.h).
//
// This header holds the model, the state and the GNC steps; a flight starts from MakeInitialState
// (sim/initial_state.h), and its emergency plans come from sim/emergency_planner.h.
//
// The state is made of parts (vehicle, power system, faults, decisions, guidance: see "the state" below), each a value
// with ==. Flights that share a vehicle or branch from one another are sim/branching.h.
//
// A FlightState can be copied at any moment and both copies flown on: they have the same future bit for bit
// (the random streams are part of the state). Nothing in the kernel reads a clock.
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "uascma/common/random.h"
#include "uascma/decision/cma_mdp.h"
#include "uascma/gnc/imm.h"
#include "uascma/gnc/lqr.h"
#include "uascma/models/battery_pack.h"
#include "uascma/models/drag.h"
#include "uascma/models/mixer.h"
#include "uascma/models/propulsion.h"
#include "uascma/models/rigid_body.h"
#include "uascma/models/rigid_body_lanes.h"
#include "uascma/models/wind.h"
#include "uascma/planning/city_map.h"
#include "uascma/planning/flight_plan.h"
#include "uascma/prognostics/eod.h"
#include "uascma/prognostics/eod_distribution.h"
#include "uascma/prognostics/motor_rul.h"
#include "uascma/prognostics/pack_fault_monitor.h"
#include "uascma/sim/emergency_planner.h"
#include "uascma/sim/eod_error_model.h"
#include "uascma/sim/load_forecast.h"
#include "uascma/sim/outcome.h"
#include "uascma/sim/policy.h"
#include "uascma/sim/scenario.h"
#include "uascma/sim/sensing.h"

namespace uascma::sim {

// ---- the model ------------------------------------------------------------------------------------------------
// Everything fixed for a flight, built once from the scenario (validated by Scenario::IsValid, InputError
// naming the field otherwise). Immutable: one model serves any number of flights on any number of threads.
class FlightModel {
 public:
  explicit FlightModel(const Scenario& scenario);

  const Scenario& scenario() const { return scenario_; }
  const SimOptions& options() const { return scenario_.options; }
  double dt() const { return dt_; }                         // s, the GNC step
  int steps_per_epoch() const { return steps_per_epoch_; }  // GNC steps per decision epoch
  double time_limit_s() const { return time_limit_s_; }
  const planning::FlightPlan& nominal_plan() const { return nominal_plan_; }
  decision::BatteryHealth battery_health() const { return battery_health_; }
  const std::vector<Eigen::Vector3d>& checkpoints() const { return map_planner_.checkpoints_W; }
  const EmergencyPlanner& map_planner() const { return map_planner_.planner; }
  const PointPlanner& map_point_planner() const { return map_planner_.to_point; }
  const models::PropulsionParams& propulsion() const { return propulsion_; }
  const models::ElectricalPowerTable& electrical_power() const { return electrical_power_; }
  const models::Mixer& mixer() const { return mixer_; }
  // The mixer's matrix with every rotor (the achieved wrench of the true rotors).
  const models::MixingMatrix& healthy_mixing() const { return mixer_.mixing_matrix(models::kNoFailedMotor); }
  const models::DragTable& drag() const { return drag_; }
  const models::WindModel& wind() const { return wind_; }
  const models::BatteryPack& pack() const { return pack_; }
  // The pack's slow step (SimOptions::pack_rate_hz): its length with its RC decay factors, in GNC steps.
  const models::BatteryPack::FixedStep& pack_step() const { return pack_step_; }
  int pack_substeps() const { return pack_substeps_; }
  const models::RotorSpeedLag& rotor_lag() const { return rotor_lag_; }
  const prognostics::MotorRulModel& rul_model() const { return rul_model_; }
  const prognostics::MotorRulModel& spall_truth() const { return spall_truth_; }
  // The prognosis the vehicle-level policies read: the time scale fitted to the simulated spall's jams
  // (prognostics/rul_calibration.h VehicleRulTimeScale at the scenario's growth speed).
  const prognostics::MotorRulModel& vehicle_rul_model() const { return vehicle_rul_model_; }
  // m/s: the level airspeed the quadcopter left after an isolation can hold at its tilt limit, before the gust
  // allowance (sim/vehicle_margin.h CalcMaxLevelAirspeedOnRotors, computed once).
  double quadcopter_max_level_airspeed() const { return quadcopter_max_level_airspeed_; }
  const planning::CityMap& map() const { return *map_; }
  const gnc::LqrController& controller() const { return controller_; }
  double load_filter_gain() const { return load_filter_gain_; }
  // The steady-flight load of a reference (sim/load_forecast.h), and the nominal plan's profile with six rotors.
  const SteadyLoadModel& steady_load() const { return steady_load_; }
  const std::shared_ptr<const LoadProfile>& nominal_load_profile() const { return nominal_load_profile_; }
  // The load forecast's measured error the 1 Hz EOD distribution uses: the scenario's, else the default table.
  const EodErrorModel& eod_error_model() const {
    return scenario_.eod_error_model ? *scenario_.eod_error_model : EodErrorModel::Default();
  }
  const OutcomeClassifier& outcome_classifier() const { return outcome_classifier_; }
  // SimOptions::noisy_sensing: the vibration noise of the IMM's samples at this vehicle's hover (sim/sensing.h).
  const VibrationNoise& vibration_noise() const { return vibration_noise_; }

 private:
  Scenario scenario_;
  models::PropulsionParams propulsion_;
  models::ElectricalPowerTable electrical_power_;
  models::Mixer mixer_;
  models::DragTable drag_;
  models::WindModel wind_;
  models::BatteryPack pack_;
  // the prognosis (calibrated to Table 5.4, docs/modelling-choices.md#spall-growth-time-scale)
  prognostics::MotorRulModel rul_model_;
  prognostics::MotorRulModel spall_truth_;        // the simulated spall (the scenario's growth speed)
  prognostics::MotorRulModel vehicle_rul_model_;  // vehicle_rul_model()
  std::shared_ptr<const planning::CityMap> map_;
  gnc::LqrController controller_;
  planning::FlightPlan nominal_plan_;
  decision::BatteryHealth battery_health_;
  MapEmergencyPlanner map_planner_;
  double dt_;
  int steps_per_epoch_;
  double time_limit_s_;
  models::RotorSpeedLag rotor_lag_;
  int pack_substeps_;
  models::BatteryPack::FixedStep pack_step_;
  double load_filter_gain_;
  OutcomeClassifier outcome_classifier_;
  SteadyLoadModel steady_load_;
  std::shared_ptr<const LoadProfile> nominal_load_profile_;
  VibrationNoise vibration_noise_;
  double quadcopter_max_level_airspeed_ = 0.0;  // quadcopter_max_level_airspeed()
};

// ---- the state ------------------------------------------------------------------------------------------------
// Everything that changes during one flight, in parts. Each part is a value with an exact operator== (every member,
// IEEE == on doubles, no tolerance): a snapshot, a branch or a shared vehicle is a copy of a part, never a list of
// fields, and a test compares whole parts.
//
//   vehicle    what a GNC step changes on the airframe and its air: body, rotors, wind, random streams, extremes;
//   power      the power system: the packs and their switches, the bus, the currents, the energy drawn;
//   faults     the truth (the spall and the jam) and what the IMM has isolated;
//   decision   the 1 Hz prognosis and decisions (Observe, Act, DecideBattery): EOD, RUL, the CMA's inputs and
//              flight status, the actions taken;
//   guidance   the executing plan: the nominal one (as planned, or re-planned at a capped speed) or an emergency
//              plan, and where it started.
// Flights that share a vehicle (sim/branching.h) share the vehicle part and each has its own power system.

// The vehicle: written by the GNC step (rotors → 6-DOF with drag and Dryden wind, sim/flight.cc StepVehicle).
struct VehicleState {
  models::RigidBodyState body;
  std::array<double, 6> rotor_speed{};     // rad/s, the true rotors (a jammed rotor is held at 0)
  std::array<double, 6> believed_speed{};  // rad/s, the commanded speeds through the lag model (what the IMM knows)
  bool airborne = false;                   // has been above OutcomeThresholds::airborne_height
  models::WindState wind;
  // Random streams (common/random.h DeriveSeed from `seed`): independent, so e.g. the wind does not change when the
  // sensor noise is switched off.
  std::uint64_t seed = 0;
  RandomStream wind_random, sensor_random, prognosis_random;
  RandomStream vibration_random;  // SimOptions::noisy_sensing: the vibration noise of the IMM's samples
  // Running extremes of the motion over the flight.
  double max_tracking_error = 0.0;  // m
  double min_cos_tilt = 1.0;        // the largest tilt is its acos
  bool operator==(const VehicleState&) const = default;
};

// The power system: written by the power step (rotor currents → pack → bus voltage) and the pack switches.
struct PowerState {
  // The pack as of its last slow step (SimOptions::pack_rate_hz), its linearisation there, and the charge each branch
  // has drawn in the GNC steps since (models/battery_pack.h PackLinearisation). At every decision epoch and at the
  // end of a flight the charge is 0: `pack` is the present state.
  models::PackState pack;
  models::PackLinearisation pack_linear;
  models::PerBranch<double> pack_charge_as{};
  int pack_substeps = 0;
  double bus_voltage_v = 0.0;
  double pack_current_a = 0.0;
  // low-passed pack current (the EOD load of docs/modelling-choices.md#pack-eod, SimOptions::eod_load)
  double load_current_a = 0.0;
  double energy_wh = 0.0;  // drawn from the packs since take-off
  // A·s each branch has delivered since take-off: a pack monitor's coulomb counters (prognostics/pack_fault_monitor.h)
  models::PerBranch<double> branch_charge_as{};
  double min_cell_voltage_v = 0.0;  // the lowest any cell has read
  PowerSensing sensing;             // SimOptions::noisy_sensing: what the CMA reads of it (sim/sensing.h)
  bool operator==(const PowerState&) const = default;
};

// Faults: the truth (the spall and the jam) and what the IMM has isolated.
struct FaultState {
  std::optional<prognostics::SpallJamEvent> spall;
  int jammed_rotor = 0;  // 1…6, 0: none
  gnc::ImmFilter imm;
  int allocation_failure = 0;  // the failed motor the allocation flies around (after isolation)
  std::optional<double> spall_onset_s, jam_time_s, isolation_time_s;
  bool operator==(const FaultState&) const = default;
};

// The EOD's distribution at the first epoch whose decided action was not NoOp: what the CMA's EOD said
// when it acted. Computed at that epoch for the record when the policy does not read the distribution itself.
struct EodAtAction {
  double time_s = 0.0;
  double eod_s = 0.0;  // the point EOD
  EodDistributionSummary distribution;
  bool operator==(const EodAtAction&) const = default;
};

// The pack-fault indicator as the CMA loop reads it (prognostics/pack_fault_monitor.h,
// docs/modelling-choices.md#pack-fault-cma): run at every decision epoch of a flight whose scenario carries a pack
// fault; in a flight without one its residuals stay at micro-volts, far below its thresholds (tested), so it never
// flags and is not run. The monitor is shared between copies of a state and replaced, never changed, at an update.
struct PackMonitorState {
  std::shared_ptr<const prognostics::PackFaultMonitor> monitor;  // null before the first epoch
  double updated_s = -1.0;                                       // the epoch it last read
  models::PerBranch<bool> flags{};                               // latched
  bool any() const { return flags[0] || flags[1]; }
  // Flights equal in what the monitor read: the same epochs, the same flags.
  bool operator==(const PackMonitorState& other) const { return updated_s == other.updated_s && flags == other.flags; }
};

// The 1 Hz prognosis and decisions (updated at each epoch by Observe, Act and DecideBattery).
struct DecisionState {
  std::optional<double> rul_at_onset_s;
  prognostics::EodResult eod;
  double eod_current_a = 0.0;  // the constant current the last EOD was propagated at
  // The EOD's distribution (DecisionInputs::eod_distribution) and the uncertainty it was propagated with: the load
  // forecast's measured error (eod_error_model.h). Default values when not computed.
  prognostics::EodUncertainty eod_uncertainty;
  prognostics::EodDistribution eod_distribution;
  std::optional<EodAtAction> eod_at_first_action;
  // the expected load of the rest of the plan (docs/modelling-choices.md#eod-load-forecast)
  LoadForecastState load_forecast;
  DecisionInputs inputs;
  decision::FlightStatus flight_status = decision::FlightStatus::kN;
  std::optional<decision::CmaAction> last_action;    // the last action that changed something
  std::optional<models::PackAction> battery_action;  // the battery executor's last action (none without one)
  // Actions that could not be carried out (docs/modelling-choices.md#unavailable-actions): epochs at which the chosen
  // action's planner found nothing and another action was taken, and each distinct "Chosen->Taken" pair in the order
  // first seen.
  int substitution_epochs = 0;
  std::vector<std::string> substitutions;
  // SimOptions::noisy_sensing: the spall indicator's stream, the first epoch it read "spall" (the point CMA's
  // detection, latched) and the Bayes filter's P(spall) (sim/sensing.h).
  RandomStream indicator_random;
  std::optional<double> spall_detected_s;
  double spall_probability = 0.0;
  // The vehicle-level prognosis's particle RULs from the initial spall, sorted (empty until first read; drawn once
  // from their own stream), and whether the epoch's policies read the vehicle-level beliefs
  // (DecisionPolicy::ReadsVehicleBeliefs; set by the epoch's caller before Observe).
  std::vector<double> vehicle_rul_at_onset_s;
  bool vehicle_beliefs = false;
  PackMonitorState pack_monitor;
  bool operator==(const DecisionState&) const = default;
};

// The executing plan: the nominal one (as planned, or re-planned at a capped speed) or an emergency plan.
struct GuidanceState {
  bool on_emergency_plan = false;
  planning::FlightPlan emergency_plan;
  // After a rotor is isolated (§4.4.2): the horizontal speed the reconfigured vehicle can hold (m/s; +inf before),
  // and the nominal plan's rest re-planned at it. original_time_offset_s and original_time_scale map the re-planned
  // nominal plan's time to the original plan's (for LandPract's checkpoints).
  double speed_cap_mps = std::numeric_limits<double>::infinity();
  bool nominal_replanned = false;
  planning::FlightPlan replanned_nominal;
  double original_time_offset_s = 0.0;
  double original_time_scale = 1.0;
  std::string emergency_site;
  double emergency_reach_margin = 0.0;
  double emergency_site_radius = 0.0;         // m
  std::vector<Eigen::Vector2d> footprint_NE;  // the last LandASAP footprint's boundary
  double plan_start_s = 0.0;                  // s, flight time at which the executing plan started
  planning::PlanCursor plan_cursor;           // where the GNC step last was on the executing plan (a cache)
  bool operator==(const GuidanceState&) const = default;
};

// A flight: its clock, its parts and how it ended. A value: copy it to snapshot or branch a flight.
struct FlightState {
  // Time: the GNC steps taken; time_s = step · dt.
  std::int64_t step = 0;
  double time_s = 0.0;

  VehicleState vehicle;
  PowerState power;
  FaultState faults;
  DecisionState decision;
  GuidanceState guidance;

  // How it ended (kInProgress while flying).
  Outcome outcome = Outcome::kInProgress;
  std::string reason;

  bool operator==(const FlightState&) const = default;

  const planning::FlightPlan& plan(const FlightModel& model) const {
    if (guidance.on_emergency_plan) return guidance.emergency_plan;
    return guidance.nominal_replanned ? guidance.replanned_nominal : model.nominal_plan();
  }
  // s along the original nominal plan (while on it).
  double original_plan_elapsed_s() const {
    return guidance.original_time_offset_s + guidance.original_time_scale * (time_s - guidance.plan_start_s);
  }
  bool done() const { return outcome != Outcome::kInProgress; }
};

// ---- what a flight leaves behind (optional) ---------------------------------------------------------------------
struct FlightEvent {
  double time_s = 0.0;
  std::string what;
};

// One row of telemetry (SI units, frames in the names).
struct TelemetryRow {
  double t = 0;
  Eigen::Vector3d p_W, v_W, p_ref_W, euler;  // euler: roll, pitch, yaw (rad)
  Eigen::Vector3d drag_W, wind_W;
  Eigen::Vector4d wrench_cmd;  // T, τx, τy, τz commanded
  Eigen::Vector4d wrench;      // achieved by the rotors
  std::array<double, 6> rotor_thrust{}, rotor_current{};
  double pack_current = 0, bus_voltage = 0;
  std::array<double, 2> branch_current{};
  std::array<double, 6> cell_voltage{};
  double eod_s = 0, flight_time_remaining_s = 0, rul_s = 0, reach_margin = 0, motor_margin = 0;
  double eod_p05_s = 0, eod_p50_s = 0, eod_p95_s = 0, eod_short_probability = 0;  // DecisionInputs' distribution
  std::array<double, 3> motor_health_belief{1.0, 0.0, 0.0};  // b(NF, SF, JF), DecisionInputs' (one-hot when exact)
  int cma_state = 0, action = 0, imm_mode = 0;
  double spall_area_mm2 = 0;
};

// The record a step appends to when given one: events, the executed actions, the CMA state at every epoch, and
// telemetry rows when record_telemetry is set.
struct FlightLog {
  bool record_telemetry = false;
  std::vector<FlightEvent> events;
  std::vector<std::pair<double, decision::CmaAction>> actions;  // (time, action) of every executed change
  std::vector<std::pair<double, decision::StateIndex>> states;  // CMA state at every epoch
  // (time, action) of every change of the battery executor's action, the first included (also an event each).
  std::vector<std::pair<double, models::PackAction>> battery_switches;
  std::vector<TelemetryRow> telemetry;
};

// ---- the steps --------------------------------------------------------------------------------------------------
// True at a decision epoch (every steps_per_epoch GNC steps, from step 0).
inline bool IsDecisionEpoch(const FlightModel& model, const FlightState& state) {
  return state.step % model.steps_per_epoch() == 0;
}

// One GNC step (1 / gnc_rate_hz). Sets state.outcome when the flight ends. No-op on a finished flight.
void Step(const FlightModel& model, FlightState& state, FlightLog* log = nullptr);

// Flights in lockstep: up to four flights one GNC step each, as Step steps each alone, bit for bit
// (tests/sim/step_together_test.cc): their control (feed-forward, LQR, allocation with six rotors or after an
// isolation: sim/controller_lanes.h) and their rigid bodies (models/rigid_body_lanes.h) on lanes, the rest (faults,
// reference, rotors, wind, IMM, power, classification) flight by flight, each with its own model. The models must share
// a vehicle (sim/lockstep.h SharesVehicle): the lanes read the first's. `logs`: one per flight, nullptr for none.
// Finished flights are left as they are.
void StepTogether(std::span<const FlightModel* const> models, std::span<FlightState* const> states,
                  std::span<FlightLog* const> logs);

// GNC steps until the next decision epoch or the end of the flight (StepEpoch after its Act). No-op on a finished
// flight.
void StepToNextEpoch(const FlightModel& model, FlightState& state, FlightLog* log = nullptr);

// StepToNextEpoch for up to four flights that share a vehicle (sim/lockstep.h SharesVehicle), each as if alone: every
// flight not yet ended takes one step, then steps on until it ends or reaches a decision epoch; the flights stepping
// at a step are stepped by StepTogether (or, one left, by Step). Finished flights are left as they are.
void StepTogetherToNextEpoch(std::span<const FlightModel* const> models, std::span<FlightState* const> states,
                             std::span<FlightLog* const> logs);

// One GNC step of `lead` and, with it, of flights that follow its vehicle (the battery MDP's flights, Ch. IV: one
// parameter draw flown with each pack action, sim/branching.h FlyFollowing): the vehicle steps once, then each
// power system. A follower is a flight of the same model at the same step with the leader's vehicle part (its power
// system, decisions and outcome its own). The pack acts on the vehicle only through the rotors' thrust cap
// (∝ V_bus²): while the cap treats every rotor's command alike under both packs, the follower flies the leader's
// vehicle bit for bit, so only its power system is stepped (and its outcome classified) and the vehicle part is the
// leader's. stepped[k] tells whether follower k was stepped; one whose cap binds differently this step is left as it
// was, a complete flight state, to be flown on alone with Step. Requires no modelled fault and no fault detector
// (SimOptions::fault_detection off, the Ch. IV loop). A flight flown this way equals the same flight flown alone
// with Step, every part (tests/sim/branching_test.cc).
void StepFollowing(const FlightModel& model, FlightState& lead, std::span<FlightState* const> followers,
                   std::span<bool> stepped);

}  // namespace uascma::sim
