#pragma once
// The multi-rate hexacopter simulator of §5.4 (Fig. 5.15): GNC at 200 Hz (LQR → mixer → rotor lag →
// 6-DOF dynamics with drag and Dryden wind; IMM rotor-failure isolation; battery pack coupling), and at
// 1 Hz the battery EOD, the motor RUL, the abstract CMA state (decisions items 7–11) and the decision
// module, whose action swaps the executing plan.
//
// Model apart from state (style habit 5): a Simulator is immutable after construction and Run() takes
// the seed, so one Simulator serves many threads and every flight replays from (scenario, seed).
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "uascma/decision/cma_mdp.h"
#include "uascma/models/battery_pack.h"
#include "uascma/models/drag.h"
#include "uascma/models/mixer.h"
#include "uascma/models/propulsion.h"
#include "uascma/models/wind.h"
#include "uascma/planning/city_map.h"
#include "uascma/planning/emergency_landing.h"
#include "uascma/planning/flight_plan.h"
#include "uascma/prognostics/eod.h"
#include "uascma/prognostics/motor_rul.h"
#include "uascma/sim/imm.h"
#include "uascma/sim/lqr.h"
#include "uascma/sim/rigid_body.h"

namespace uascma::sim {

// A spall fault in one motor (§5.4): onset at a time, growth by the motor prognosis model until the
// spall crosses D_f and the rotor jams (its thrust goes to zero).
struct FaultSpec {
  bool enabled = false;
  int motor = 3;                 // 1…6 (Fig. 2.2 numbering)
  double spall_onset_s = 175.0;  // s after take-off
  // Growth speed of the simulated spall: seconds per Paris-law step. The prognosis default (calibrated to
  // Table 5.4) is used when absent; scenarios use faster growth (decisions item 15).
  std::optional<double> time_per_growth_step_s;
  // The prognosis's own time scale (§3.4.1): absent, the Table 5.4 calibration (decisions item 15), so a
  // fast-growing spall surprises it; set, the prognosis knows this motor's growth speed.
  std::optional<double> prognosis_time_per_growth_step_s;
};

struct BatterySpec {
  models::PerCell<double> initial_cell_voltage_v = {{{4.1, 4.1, 4.1}, {4.1, 4.1, 4.1}}};  // Table 4.4: 4.05–4.12
  models::PerCell<models::CellHealth> cell_health{};
  double ambient_temp_degf = models::kRoomTemperatureDegf;
};

// How the flight ends (decisions items 10–11).
enum class Outcome {
  kInProgress,
  kCompleted,          // landed at the end of the original plan
  kEmergencyLanding,   // landed at the end of an emergency plan
  kTerminated,         // Terminate: parachute and motors cut
  kFailedBattery,      // a cell reached the 3.3 V cut-off
  kFailedControl,      // attitude or tracking error beyond the bounds
  kFailedCollision,    // struck the ground (or a building) outside a landing
  kTimeout,            // still flying at the time limit (counted as a failure)
};
const char* OutcomeName(Outcome outcome);
bool IsFailure(Outcome outcome);

struct SimOptions {
  double gnc_rate_hz = 200.0;       // §4.3.2, §5.4
  double decision_rate_hz = 1.0;    // EOD, RUL, CMA: §5.4
  double telemetry_rate_hz = 10.0;  // rows per simulated second in the CSV
  double max_tilt = 1.2;            // rad (~69°): beyond it the flight is out of control (our bound)
  double max_tracking_error = 15.0; // m from the reference: out of control (our bound)
  double touchdown_speed = 1.5;     // m/s: faster ground contact is a crash (our bound)
  double time_limit_factor = 2.5;   // the flight times out at this × the original plan's duration + 60 s
  bool reconfiguration = true;      // switch to the quadcopter allocation when the IMM isolates a rotor
  bool sensor_noise = true;         // gyro and accelerometer noise for the IMM
  double hotel_current_a = 0.5;     // A: onboard computer, radio, sensors (our estimate; §4.3.2 calls it small)
  // Bus voltage at which the rotors reach their Table 2.2 maximum thrust; rotor thrust capacity scales
  // as (V_bus / V_ref)² (speed ∝ voltage, thrust ∝ speed²). Our estimate: a 3S pack at 3.7 V per cell.
  double reference_bus_voltage_v = 11.1;
  // s: the 1 Hz EOD prediction runs at the pack current low-passed with this time constant (our estimate:
  // long enough to ignore gusts and the take-off climb, short enough to see a rotor failure's extra load
  // within half a minute; the dissertation's EOD curves, Figs. 5.22 and 5.25, are smooth).
  double load_current_time_constant_s = 10.0;
  // s, t_sf of Table 4.4: the reach margin judges the plan with this much extra time,
  // RM = 1 − (t_remaining + t_sf) / t_EOD (the battery MDP's S1 ↔ EOD > RFD + t_sf, Table 4.1, carried to the
  // CMA). 0 by default; campaigns sample it in [5, 10] s.
  double safety_margin_s = 0.0;
  bool IsValid(std::string* error) const;
};

struct Scenario {
  std::string name = "default";
  // The city: buildings the vehicle can strike and the landing sites the emergency planners use. Shared
  // and immutable, so campaigns copy scenarios cheaply. Null: open ground, no sites.
  std::shared_ptr<const planning::CityMap> map;
  RigidBodyParams body;
  models::PropellerConfiguration configuration = models::PropellerConfiguration::kTractor;
  BatterySpec battery;
  models::WindParams wind;
  planning::DeliveryMission mission;
  planning::PlanLimits limits;
  FaultSpec fault;
  LqrOptions lqr;
  ImmParams imm;
  SimOptions options;
  std::uint64_t seed = 1;
};

// The 1 Hz view of the flight that a decision module sees (decisions items 7–11).
struct DecisionInputs {
  double time_s = 0.0;
  decision::CmaState state;
  double flight_time_remaining_s = 0.0;
  double eod_s = 0.0;
  double rul_s = 0.0;            // +∞ without a motor fault
  double reach_margin = 0.0;     // RM = 1 − t_remaining / t_EOD
  double motor_margin = 0.0;     // MM = 1 − t_remaining / t_RUL
};

// The pluggable decision module: called at 1 Hz, returns a CMA action.
class DecisionPolicy {
 public:
  virtual ~DecisionPolicy() = default;
  virtual decision::CmaAction Decide(const DecisionInputs& inputs) = 0;
  virtual std::string name() const = 0;
};

// Always NoOp: the baseline.
class NoOpPolicy final : public DecisionPolicy {
 public:
  decision::CmaAction Decide(const DecisionInputs&) override { return decision::CmaAction::kNoOp; }
  std::string name() const override { return "noop"; }
};

// A solved CMA policy: the action of the abstract state's row.
class TablePolicy final : public DecisionPolicy {
 public:
  TablePolicy(std::vector<decision::ActionIndex> action_per_state, std::string name);
  decision::CmaAction Decide(const DecisionInputs& inputs) override;
  std::string name() const override { return name_; }

 private:
  std::vector<decision::ActionIndex> action_;
  std::string name_;
};

// Emergency landing plans come from the planning layer (LandPract, LandASAP: the contingency-planning
// issue). Returns a plan from the current position to a site, or nothing when no site is reachable.
struct EmergencyRequest {
  decision::CmaAction action = decision::CmaAction::kLandPract;
  double time_s = 0.0;
  Eigen::Vector3d p_WB_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_WB_W = Eigen::Vector3d::Zero();
  double yaw = 0.0;        // rad
  int failed_motor = 0;    // the rotor the allocation has switched off (0: none): fewer rotors, less reach
  double eod_s = 0.0;
  double original_plan_elapsed_s = 0.0;  // how far along the nominal plan the vehicle is
};
struct EmergencyPlan {
  planning::FlightPlan plan;
  std::string site;  // a label of the landing site
  double reach_margin = 0.0;
  std::vector<Eigen::Vector2d> footprint_NE;  // LandASAP: the footprint's boundary in W (north, east), m
};
using EmergencyPlanner = std::function<std::optional<EmergencyPlan>(const EmergencyRequest&)>;

// One row of telemetry (SI units, frames in the names).
struct TelemetryRow {
  double t = 0;
  Eigen::Vector3d p_W, v_W, p_ref_W, euler;           // euler: roll, pitch, yaw (rad)
  Eigen::Vector3d drag_W, wind_W;
  Eigen::Vector4d wrench_cmd;                          // T, τx, τy, τz commanded
  Eigen::Vector4d wrench;                              // achieved by the rotors
  std::array<double, 6> rotor_thrust{}, rotor_current{};
  double pack_current = 0, bus_voltage = 0;
  std::array<double, 2> branch_current{};
  std::array<double, 6> cell_voltage{};
  double eod_s = 0, flight_time_remaining_s = 0, rul_s = 0, reach_margin = 0, motor_margin = 0;
  int cma_state = 0, action = 0, imm_mode = 0;
  double spall_area_mm2 = 0;
};

struct FlightEvent {
  double time_s = 0.0;
  std::string what;
};

struct SimResult {
  Outcome outcome = Outcome::kInProgress;
  std::string reason;
  double sim_time_s = 0.0;
  double wall_time_s = 0.0;
  std::uint64_t seed = 0;
  std::string policy;
  double plan_duration_s = 0.0;
  std::optional<double> spall_onset_s, jam_time_s, isolation_time_s;
  int isolated_rotor = 0;
  double min_cell_voltage_v = 0.0;
  double max_tracking_error = 0.0;   // m
  double max_tilt = 0.0;             // rad
  double energy_wh = 0.0;
  std::vector<FlightEvent> events;
  std::vector<std::pair<double, decision::CmaAction>> actions;  // (time, action) of every executed change
  std::vector<std::pair<double, decision::StateIndex>> states;  // CMA state at every epoch
  std::vector<TelemetryRow> telemetry;
  std::vector<Eigen::Vector3d> executed_plan_ref;                // for plotting: the emergency plans
  std::vector<Eigen::Vector2d> footprint_NE;  // the LandASAP footprint boundary, when one was planned
  std::string emergency_site;              // the site of the last emergency plan ("" when none)
  double emergency_reach_margin = 0.0;     // its RM when it was chosen
  double realtime_factor() const { return wall_time_s > 0 ? sim_time_s / wall_time_s : 0.0; }
};

struct RunOptions {
  bool record_telemetry = true;
};

// The emergency planners of the planning layer over the scenario's map: LandPract from a database built
// before flight on the nominal plan (5 checkpoints), LandASAP online inside the footprint (§5.3.2.2).
// Empty (no planner) when the map has no landing sites.
struct MapEmergencyPlanner {
  EmergencyPlanner planner;
  std::vector<Eigen::Vector3d> checkpoints_W;  // LandPract's checkpoints on the nominal plan
};
MapEmergencyPlanner MakeMapEmergencyPlanner(const Scenario& scenario, const planning::FlightPlan& nominal_plan,
                                            const models::DragTable& drag, const models::PropulsionParams& propulsion);

class Simulator {
 public:
  // Validates the scenario (InputError naming the field) and builds the immutable models, including the
  // LandPract database when the map has landing sites.
  explicit Simulator(const Scenario& scenario);

  // `planner` replaces the map's emergency planners when given.
  SimResult Run(DecisionPolicy& policy, const EmergencyPlanner& planner = {},
                const RunOptions& options = {}) const;

  const Scenario& scenario() const { return scenario_; }
  const planning::FlightPlan& nominal_plan() const { return nominal_plan_; }
  decision::BatteryHealth battery_health() const { return battery_health_; }

 private:
  Scenario scenario_;
  models::PropulsionParams propulsion_;
  models::ElectricalPowerTable electrical_power_;
  models::Mixer mixer_;
  models::DragTable drag_;
  models::WindModel wind_;
  models::BatteryPack pack_;
  prognostics::MotorRulModel rul_model_;      // the prognosis (calibrated to Table 5.4, decisions item 15)
  prognostics::MotorRulModel spall_truth_;    // the simulated spall (the scenario's growth speed)
  std::shared_ptr<const planning::CityMap> map_;
  LqrController controller_;
  planning::FlightPlan nominal_plan_;
  decision::BatteryHealth battery_health_;
  MapEmergencyPlanner map_planner_;

 public:
  const std::vector<Eigen::Vector3d>& checkpoints() const { return map_planner_.checkpoints_W; }
};

}  // namespace uascma::sim
