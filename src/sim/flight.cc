#include "uascma/sim/flight.h"
#include "uascma/sim/vehicle_file.h"

// The model and the GNC step of the kernel (flight.h): the vehicle's step, then the power system's; StepTogether
// steps flights in lanes; StepFollowing flies one vehicle for several power systems. The initial state is
// initial_state.cc, the decision epoch epoch.cc.
#include <algorithm>
#include <cmath>
#include <memory>
#include <span>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "flight_internal.h"
#include "uascma/common/error.h"
#include "uascma/common/frames.h"
#include "uascma/decision/cma_abstraction.h"
#include "uascma/models/rigid_body_lanes.h"
#include "uascma/prognostics/rul_calibration.h"
#include "uascma/sim/controller_lanes.h"
#include "uascma/sim/emergency_planner.h"
#include "uascma/sim/rotor_lanes.h"
#include "uascma/sim/vehicle_margin.h"

namespace uascma::sim {
namespace {

using internal::AddEvent;
using internal::kSpallStream;
using internal::MaxCollectiveThrust;
using internal::ThrustCap;

// m/s: below this reference speed the plan is at rest and the whole position error counts as cross-track (ours).
constexpr double kMovingReferenceSpeed = 0.1;

prognostics::SpallGrowthParams TruthGrowth(const FaultSpec& fault) {
  prognostics::SpallGrowthParams params;
  if (fault.time_per_growth_step_s) params.time_per_growth_step_s = *fault.time_per_growth_step_s;
  return params;
}

prognostics::SpallGrowthParams PrognosisGrowth(const FaultSpec& fault) {
  prognostics::SpallGrowthParams params;
  if (fault.prognosis_time_per_growth_step_s) params.time_per_growth_step_s = *fault.prognosis_time_per_growth_step_s;
  return params;
}

prognostics::SpallGrowthParams VehiclePrognosisGrowth(const FaultSpec& fault) {
  prognostics::SpallGrowthParams params;
  // The fit scales the truth's time per growth step by the mean jam time over the mean growth steps; at the top of
  // the scenario's bound (3600 s per step, an hour) that can pass the bound itself, where a spall takes days to
  // jam and no flight sees it: held at the bound there (ours).
  params.time_per_growth_step_s =
      std::min(prognostics::VehicleRulTimeScale(TruthGrowth(fault).time_per_growth_step_s).time_per_growth_step_s,
               prognostics::SpallGrowthParams::kTimePerGrowthStepBounds.high);
  return params;
}

const Scenario& Validated(const Scenario& scenario) {
  std::string error;
  if (!scenario.IsValid(&error)) throw InputError(scenario.name + ": " + error);
  return scenario;
}

// What one GNC step computed: the vehicle's signals (StepVehicle), then the power system's (StepPowerSystem), for
// the classification and telemetry.
struct StepSignals {
  planning::PlanReference reference;
  gnc::Wrench command;
  models::BodyWrench achieved;
  models::RotorThrusts thrust;
  models::RotorThrusts allocated;       // the allocation's rotor thrusts before the bus voltage's cap
  double thrust_cap = 0.0;              // N per rotor at this step's bus voltage
  gnc::TiltBoundOutcome tilt;  // the LQR's tilt bound (gnc::LimitTiltToThrust); the lanes fill `bounded` only
  std::array<double, 6> rotor_power{};  // W, electrical, per rotor
  std::array<double, 6> rotor_current{};
  Eigen::Vector3d wind_W = Eigen::Vector3d::Zero();
  models::BodyInputs body_inputs;
  models::PackOutputs pack_outputs;
  Eigen::Vector3d z_B_W;  // R_WB's third column, the body's z axis in W, after the step (the full R_WB: telemetry)
};

// ---- faults: spall onset and growth → jam (the truth) -------------------------------------------------------
void AdvanceFaults(const FlightModel& model, FlightState& state, FlightLog* log) {
  const FaultSpec& fault = model.scenario().fault;
  const double t = state.time_s;
  if (fault.enabled && !state.faults.spall && t >= fault.spall_onset_s) {
    state.faults.spall.emplace(model.spall_truth(), t, DeriveSeed(state.vehicle.seed, kSpallStream));
    state.faults.spall_onset_s = t;
    AddEvent(log, t, fmt::format("spall in motor {}", fault.motor));
  }
  if (state.faults.spall && state.faults.jammed_rotor == 0) {
    const prognostics::SpallJamStep s = state.faults.spall->Advance(t - state.faults.spall->time_s());
    if (s.jammed) {
      state.faults.jammed_rotor = fault.motor;
      state.faults.jam_time_s = s.jam_time_s;
      AddEvent(log, s.jam_time_s, fmt::format("motor {} jammed", state.faults.jammed_rotor));
    }
  }
}

double InverseBusVoltage(double bus_voltage_v) { return 1.0 / std::max(bus_voltage_v, 1.0); }

// ---- guidance and control: LQR → allocation → rotor lag, capped by the bus voltage -------------------------------
// The rotors' electrical power is the vehicle's; the current it draws is the power system's (StepPowerSystem).
// The plan's reference of this step.
void ReadReference(const FlightModel& model, FlightState& state, StepSignals& s) {
  s.reference = state.plan(model).At(state.time_s - state.guidance.plan_start_s, state.guidance.plan_cursor);
}

// The reference → the LQR's wrench → the allocation's rotor thrusts.
void ComputeControl(const FlightModel& model, const FlightState& state, StepSignals& s) {
  // Drag feed-forward while all six rotors fly. After a reconfiguration to the quadcopter the
  // bare DLQR flies on: with four rotors near their thrust cap, asking the ~0.4 rad tilt that cancels the drag
  // at 8-9 m/s drives the loop into slow saturated swings. Measured on the default campaign, 150 runs, seed 1:
  // largest tracking error 13.2 m without feed-forward, 23.8 m with it throughout (rotor-out flights), 9.8 m with
  // it while hexacopter; mean per health 2.2-3.0 m, 2.2-3.0 m and 1.5-2.0 m; outcomes identical in all three.
  planning::PlanReference target = s.reference;
  if (model.options().drag_feedforward && state.faults.allocation_failure == models::kNoFailedMotor) {
    const Eigen::Vector3d z_B_W = state.vehicle.body.q_WB.toRotationMatrix().col(2);
    target.a_W += gnc::CalcDragFeedForward(model.scenario().body, model.drag(), z_B_W, s.reference.v_W,
                                           model.wind().MeanWind_W());
  }
  s.command =
      model.controller().Compute(state.vehicle.body, target, MaxCollectiveThrust(model, state), &s.tilt);
  const models::AllocationResult allocation = model.mixer().Allocate(s.command, state.faults.allocation_failure);
  s.allocated = allocation.rotor_thrust;
}

// The allocated thrusts, capped at the bus voltage → rotor lag → thrust and electrical power → the achieved wrench.
void StepRotors(const FlightModel& model, FlightState& state, models::RotorThrusts& believed, StepSignals& s) {
  const double thrust_cap = ThrustCap(model, state.power.bus_voltage_v);
  s.thrust_cap = thrust_cap;
  StepRotorLanes({.propulsion = &model.propulsion(),
                  .lag = &model.rotor_lag(),
                  .power_table = &model.electrical_power(),
                  .allocated = s.allocated.data(),
                  .thrust_cap = thrust_cap,
                  .jammed_rotor = state.faults.jammed_rotor,
                  .believed = model.options().fault_detection},  // the believed rotors feed only the IMM
                 {.rotor_speed = state.vehicle.rotor_speed.data(),
                  .believed_speed = state.vehicle.believed_speed.data(),
                  .believed_thrust = believed.data(),
                  .thrust = s.thrust.data(),
                  .power = s.rotor_power.data()});
  s.achieved = model.healthy_mixing() * s.thrust;
}

// ---- 6-DOF with drag and Dryden wind ----------------------------------------------------------------------------
// The wind of this step and the body's inputs, held over it.
void StepWind(const FlightModel& model, VehicleState& vehicle, StepSignals& s) {
  const double dt = model.dt();
  const double altitude = -vehicle.body.p_WB_W.z();
  const double airspeed_estimate = (vehicle.body.v_WB_W - model.wind().MeanWind_W()).norm();
  s.wind_W = model.wind().Step(vehicle.wind, std::max(altitude, 0.0), airspeed_estimate, dt, vehicle.wind_random);
  s.body_inputs = models::BodyInputs{s.achieved(0), s.achieved.tail<3>(), s.wind_W};
}

void HoldOnGround(VehicleState& vehicle) {
  if (!vehicle.airborne && vehicle.body.p_WB_W.z() > 0.0) {  // resting on the ground before take-off
    vehicle.body.p_WB_W.z() = 0.0;
    vehicle.body.v_WB_W.z() = std::min(vehicle.body.v_WB_W.z(), 0.0);
  }
}

void StepBody(const FlightModel& model, VehicleState& vehicle, StepSignals& s) {
  StepWind(model, vehicle, s);
  vehicle.body = models::StepRigidBody(model.scenario().body, model.drag(), vehicle.body, s.body_inputs, model.dt());
  HoldOnGround(vehicle);
}

// ---- power: rotor currents → pack → bus voltage ------------------------------------------------------------------
// The pack's slow step: its state advanced with the charge each branch drew since the last one (a full slow step, or
// the part of one a flight ended in), and linearised anew.
// A pack fault switches on or off (models/pack_fault.h IsPackFaultOn) only at a slow step's start, where the pack's
// state is the present one, and the pack is linearised anew with it.
void UpdatePackFault(const FlightModel& model, PowerState& power, double time_s) {
  if (!model.pack().fault() || power.pack_substeps != 0) return;
  const bool on = models::IsPackFaultOn(*model.pack().fault(), time_s);
  if (on == power.pack.fault_on) return;
  power.pack.fault_on = on;
  power.pack_linear = model.pack().Linearise(power.pack);
}

void AdvancePack(const FlightModel& model, PowerState& power) {
  if (power.pack_substeps == 0) return;
  const bool full = power.pack_substeps == model.pack_substeps();
  power.pack = model.pack().Advance(power.pack, power.pack_charge_as, power.pack_substeps * model.dt(),
                                    full ? &model.pack_step() : nullptr);
  power.pack_linear = model.pack().Linearise(power.pack);
  power.pack_charge_as = {0.0, 0.0};
  power.pack_substeps = 0;
}

// Noisy sensing (sim/sensing.h): the power module's readings of this step's current and bus voltage, the error of the
// charge the CMA counts, the energy and the low-passed load it reads.
void SensePower(const FlightModel& model, PowerState& power) {
  PowerSensing& sensing = power.sensing;
  const SensingParams& params = model.options().sensing;
  const double current_a = ReadCurrent(params, sensing.errors, power.pack_current_a, sensing.random);
  sensing.bus_voltage_v = ReadBusVoltage(params, sensing.errors, power.bus_voltage_v, sensing.random);
  sensing.charge_error_as += (current_a - power.pack_current_a) * model.dt();
  sensing.charge_read_as += current_a * model.dt();
  sensing.energy_wh += sensing.bus_voltage_v * current_a * model.dt() / 3600.0;
  sensing.load_current_a += model.load_filter_gain() * (current_a - sensing.load_current_a);
}

// The rotors' electrical power (StepVehicle's) drawn at this power system's bus voltage, through its packs.
void StepPowerSystem(const FlightModel& model, PowerState& power, StepSignals& s, double time_s) {
  UpdatePackFault(model, power, time_s);
  const double inverse_bus_voltage = InverseBusVoltage(power.bus_voltage_v);
  double motors_current = 0.0;
  for (int i = 0; i < 6; ++i) {
    s.rotor_current[i] = s.rotor_power[i] * inverse_bus_voltage;
    motors_current += s.rotor_current[i];
  }
  power.pack_current_a = motors_current + model.options().hotel_current_a;
  power.load_current_a += model.load_filter_gain() * (power.pack_current_a - power.load_current_a);
  if (model.pack_substeps() == 1) {  // the pack's state at the GNC rate
    const models::PackStepResult pack_step =
        model.pack().StepWithOutputs(power.pack, power.pack_current_a, model.pack_step());
    power.pack = pack_step.next;
    s.pack_outputs = pack_step.outputs;
    for (int b = 0; b < models::kBranchCount; ++b) {
      power.branch_charge_as[b] += s.pack_outputs.split.current_a[b] * model.dt();
    }
  } else {
    // The outputs at this step's current from the pack's last slow step and the charge drawn since; then this
    // step's charge, and the slow step when its GNC steps are done (models/battery_pack.h PackLinearisation).
    model.pack().CalcLinearisedOutputs(power.pack, power.pack_linear, power.pack_charge_as,
                                       power.pack_substeps * model.dt(), power.pack_current_a, s.pack_outputs);
    for (int b = 0; b < models::kBranchCount; ++b) {
      power.pack_charge_as[b] += s.pack_outputs.split.current_a[b] * model.dt();
      power.branch_charge_as[b] += s.pack_outputs.split.current_a[b] * model.dt();
    }
    if (++power.pack_substeps == model.pack_substeps()) AdvancePack(model, power);
  }
  power.bus_voltage_v = s.pack_outputs.split.bus_voltage_v;
  power.energy_wh += power.bus_voltage_v * power.pack_current_a * model.dt() / 3600.0;
  power.min_cell_voltage_v = std::min(power.min_cell_voltage_v, s.pack_outputs.min_cell_voltage_v);
  if (model.options().noisy_sensing) SensePower(model, power);
}

// ---- rotor failure detection and isolation (IMM) ----------------------------------------------------------------
void StepImm(const FlightModel& model, FlightState& state, const models::RigidBodyState& previous,
             const models::RotorThrusts& believed, const StepSignals& s, FlightLog* log) {
  if (!model.options().fault_detection || state.faults.imm.isolated_rotor() != 0) return;
  const double dt = model.dt();
  const gnc::ImmParams& imm = model.scenario().imm;
  gnc::ImmMeasurement measurement;
  const Eigen::Vector3d specific_force_W =
      (state.vehicle.body.v_WB_W - previous.v_WB_W) / dt - Eigen::Vector3d(0, 0, kGravity);
  measurement.gyro_B = state.vehicle.body.w_WB_B;
  // (R_WBᵀ f)_z, in the order Eigen's product summed it: (z_x f_x + z_y f_y) + z_z f_z.
  measurement.specific_force_z_B =
      s.z_B_W.x() * specific_force_W.x() + s.z_B_W.y() * specific_force_W.y() + s.z_B_W.z() * specific_force_W.z();
  if (model.options().sensor_noise) {
    RandomStream& random = state.vehicle.sensor_random;
    measurement.gyro_B += imm.gyro_noise * Eigen::Vector3d(random.Normal(), random.Normal(), random.Normal());
    measurement.specific_force_z_B += imm.accel_noise * random.Normal();
  }
  if (model.options().noisy_sensing) {  // vibration beyond what the IMM assumes (sim/sensing.h)
    RandomStream& random = state.vehicle.vibration_random;
    const VibrationNoise& vibration = model.vibration_noise();
    measurement.gyro_B += vibration.gyro_sigma * Eigen::Vector3d(random.Normal(), random.Normal(), random.Normal());
    measurement.specific_force_z_B += vibration.accel_sigma * random.Normal();
  }
  state.faults.imm.Step(believed, measurement, dt);
  if (state.faults.imm.isolated_rotor() != 0) {
    const double now = state.time_s + dt;
    state.faults.isolation_time_s = now;
    const bool reconfigure = model.options().reconfiguration;
    AddEvent(log, now,
             fmt::format("IMM isolated rotor {}{}", state.faults.imm.isolated_rotor(),
                         reconfigure ? ": quadcopter allocation" : " (reconfiguration disabled)"));
    if (reconfigure) state.faults.allocation_failure = state.faults.imm.isolated_rotor();
  }
}

void RecordTelemetry(const FlightModel& model, const FlightState& state, const StepSignals& s, FlightLog& log) {
  TelemetryRow row;
  row.t = state.time_s + model.dt();
  row.p_W = state.vehicle.body.p_WB_W;
  row.v_W = state.vehicle.body.v_WB_W;
  row.p_ref_W = s.reference.p_W;
  row.euler = EulerFromRotation(state.vehicle.body.q_WB.toRotationMatrix());
  row.drag_W =
      models::CalcRigidBodyRates(model.scenario().body, model.drag(), state.vehicle.body, s.body_inputs).drag_W;
  row.wind_W = s.wind_W;
  row.wrench_cmd = s.command;
  row.wrench = s.achieved;
  for (int i = 0; i < 6; ++i) {
    row.rotor_thrust[i] = s.thrust[i];
    row.rotor_current[i] = s.rotor_current[i];
  }
  row.pack_current = state.power.pack_current_a;
  row.bus_voltage = state.power.bus_voltage_v;
  row.branch_current = {s.pack_outputs.split.current_a[0], s.pack_outputs.split.current_a[1]};
  for (int b = 0; b < 2; ++b) {
    for (int c = 0; c < 3; ++c) row.cell_voltage[3 * b + c] = s.pack_outputs.cell_voltage_v[b][c];
  }
  const DecisionInputs& inputs = state.decision.inputs;
  row.eod_s = state.decision.eod.eod_s;
  row.flight_time_remaining_s = inputs.flight_time_remaining_s;
  row.rul_s = inputs.rul_s;
  // The value: an epoch that records telemetry propagates it (EpochEodPrecision); a step logged after an epoch that
  // did not (a flight flown on with a log) shows that epoch's bound, as row.eod_s shows DecisionState::eod.
  row.reach_margin = ReachMarginAtLeast(inputs.eod);
  const EodDistributionSummary distribution = inputs.eod_distribution.value_or(EodDistributionSummary{});
  row.eod_p05_s = distribution.p05_s;
  row.eod_p50_s = distribution.p50_s;
  row.eod_p95_s = distribution.p95_s;
  row.eod_short_probability = distribution.short_probability;
  row.motor_health_belief = inputs.motor_health_belief;
  row.motor_margin = inputs.motor_margin;
  row.cma_state = decision::CmaStateIndex(inputs.state);
  row.action = state.decision.last_action ? static_cast<int>(*state.decision.last_action) : 0;
  row.imm_mode =
      state.faults.imm.isolated_rotor() != 0 ? state.faults.imm.isolated_rotor() : state.faults.imm.MapMode();
  row.spall_area_mm2 = state.faults.spall ? state.faults.spall->area_mm2() : 0.0;
  log.telemetry.push_back(row);
}

// ---- outcomes (docs/modelling-choices.md#terminate, #outcomes, outcome.h) -------------------------------------------
// The distance from the reference path: the position error less its component along the reference velocity (the
// schedule's lead or lag is not a loss of control); at rest on the plan, the whole error.
double CrossTrackError(const Eigen::Vector3d& error_W, const Eigen::Vector3d& v_ref_W) {
  const double speed = v_ref_W.norm();
  if (speed < kMovingReferenceSpeed) return error_W.norm();
  const Eigen::Vector3d along = v_ref_W / speed;
  return (error_W - error_W.dot(along) * along).norm();
}

// The running extremes after a step, and whether the vehicle has been airborne. The tilt enters through its cosine
// R_WB(2, 2) (acos is decreasing): the largest tilt is the acos of the smallest cosine, taken once at the end.
void UpdateExtremes(const FlightModel& model, VehicleState& vehicle, const StepSignals& s) {
  const double tracking_error = (vehicle.body.p_WB_W - s.reference.p_W).norm();
  vehicle.min_cos_tilt = std::min(vehicle.min_cos_tilt, s.z_B_W.z());
  vehicle.max_tracking_error = std::max(vehicle.max_tracking_error, tracking_error);
  if (-vehicle.body.p_WB_W.z() > model.options().outcome.airborne_height) vehicle.airborne = true;
}

// The plan's reference waits one step (its clock, time − plan start, stands still) when the LQR gave up track for
// altitude and the vehicle is behind the reference along the reference's velocity: the schedule gives way, not the
// path (docs/modelling-choices.md#thrust-priority).
void WaitWhileTiltBounded(const FlightModel& model, FlightState& state, const StepSignals& s) {
  if (!s.tilt.bounded || state.done()) return;
  if ((state.vehicle.body.p_WB_W - s.reference.p_W).dot(s.reference.v_W) < 0.0) {
    state.guidance.plan_start_s += model.dt();
  }
}

void AdvanceClock(const FlightModel& model, FlightState& state) {
  if (state.done()) AdvancePack(model, state.power);  // a finished flight's pack is its present state
  ++state.step;
  state.time_s = static_cast<double>(state.step) * model.dt();
}

void ClassifyStep(const FlightModel& model, FlightState& state, const StepSignals& s) {
  const double now = state.time_s + model.dt();
  const planning::FlightPlan& plan = state.plan(model);
  const OutcomeInputs inputs{
      // every field set once, in place
      .time_s = now,
      .p_WB_W = state.vehicle.body.p_WB_W,
      .v_WB_W = state.vehicle.body.v_WB_W,
      .cos_tilt = s.z_B_W.z(),
      .body_rate = state.vehicle.body.w_WB_B.norm(),
      .cross_track_error = CrossTrackError(state.vehicle.body.p_WB_W - s.reference.p_W, s.reference.v_W),
      .min_cell_voltage_v = s.pack_outputs.min_cell_voltage_v,
      .min_cell_branch = s.pack_outputs.min_cell_branch,
      .min_cell_index = s.pack_outputs.min_cell_index,
      .airborne = state.vehicle.airborne,
      .plan_time_remaining_s = plan.TimeRemaining(now - state.guidance.plan_start_s),
      .plan_end_W = plan.end_W(),
      .landing_radius = state.guidance.on_emergency_plan ? state.guidance.emergency_site_radius : 0.0,
      .on_original_plan = !state.guidance.on_emergency_plan,
      .emergency_site = state.guidance.emergency_site,
      .time_limit_s = model.time_limit_s()};
  OutcomeDecision decision = model.outcome_classifier().Classify(inputs, model.map());
  if (decision.outcome != Outcome::kInProgress) {
    state.outcome = decision.outcome;
    state.reason = std::move(decision.reason);
  }
}

}  // namespace

// ---- the model ----------------------------------------------------------------------------------------------------
namespace {

// The scenario's profile of the nominal plan when it was built from this plan and load model (the same arithmetic
// on the same inputs: the same numbers), else a new one.
std::shared_ptr<const LoadProfile> NominalLoadProfile(const Scenario& scenario, const planning::FlightPlan& plan,
                                                      const SteadyLoadModel& load) {
  const std::shared_ptr<const KeyedLoadProfile>& keyed = scenario.nominal_load_profile;
  if (keyed && keyed->plan == plan && keyed->body == scenario.body && keyed->configuration == scenario.configuration &&
      keyed->vehicle_hash == (scenario.vehicle ? scenario.vehicle->content_hash : std::string()) &&
      keyed->mean_wind_W == load.mean_wind_W) {
    return std::shared_ptr<const LoadProfile>(keyed, &keyed->profile);  // shares the scenario's ownership
  }
  return std::make_shared<const LoadProfile>(plan, load, models::kRotorCount);
}

// The scenario's packs with its pack fault, whose connector draws come from the flight's seed.
models::PackParams MakeFlightPackParams(const Scenario& scenario) {
  models::PackParams params =
      ScenarioPackParams(scenario, scenario.battery.cell_health, scenario.battery.ambient_temp_degf);
  params.fault = scenario.pack_fault;
  if (params.fault) params.fault->seed = DeriveSeed(scenario.seed, internal::kPackFaultSeedStream);
  return params;
}

}  // namespace

FlightModel::FlightModel(const Scenario& scenario)
    : scenario_(Validated(scenario)),
      propulsion_(ScenarioPropulsion(scenario)),
      electrical_power_(propulsion_),
      mixer_(ScenarioMixer(scenario)),
      drag_(ScenarioDrag(scenario)),
      wind_(scenario.wind, static_cast<int>(std::lround(scenario.options.gnc_rate_hz / scenario.options.wind_rate_hz))),
      pack_(MakeFlightPackParams(scenario)),
      rul_model_(PrognosisGrowth(scenario.fault)),
      spall_truth_(TruthGrowth(scenario.fault)),
      vehicle_rul_model_(VehiclePrognosisGrowth(scenario.fault)),
      map_(scenario.map ? scenario.map : std::make_shared<const planning::CityMap>()),
      controller_(scenario.body, scenario.lqr),
      nominal_plan_(scenario.route ? planning::MakeMissionPlan(*scenario.route, scenario.limits)
                                   : planning::MakeDeliveryPlan(scenario.mission, scenario.limits)),
      battery_health_(static_cast<decision::BatteryHealth>(
          // docs/modelling-choices.md#battery-health-label
          static_cast<int>(models::ClassifyHealth(scenario.battery.cell_health)))),
      map_planner_(MakeMapEmergencyPlanner(scenario_, nominal_plan_, drag_, propulsion_)),
      dt_(1.0 / scenario.options.gnc_rate_hz),
      steps_per_epoch_(static_cast<int>(std::lround(scenario.options.gnc_rate_hz / scenario.options.decision_rate_hz))),
      time_limit_s_(scenario.options.outcome.time_limit_factor * nominal_plan_.duration() +
                    scenario.options.outcome.time_limit_margin_s),
      rotor_lag_(propulsion_.motor_time_constant, dt_),
      pack_substeps_(static_cast<int>(std::lround(scenario.options.gnc_rate_hz / scenario.options.pack_rate_hz))),
      pack_step_(pack_.MakeFixedStep(pack_substeps_ * dt_)),
      load_filter_gain_(1.0 - std::exp(-dt_ / scenario.options.load_current_time_constant_s)),
      outcome_classifier_(scenario.options.outcome),
      steady_load_{&scenario_.body, &drag_, &electrical_power_, wind_.MeanWind_W()},
      nominal_load_profile_(NominalLoadProfile(scenario_, nominal_plan_, steady_load_)),
      vibration_noise_(CalcVibrationNoise(
          scenario.options.sensing,
          models::CalcRotorSpeedForThrust(propulsion_, scenario.body.mass * kGravity / models::kRotorCount),
          scenario.body.mass, scenario.body.inertia_diagonal.x(), mixer_.params().arm_length)) {
  quadcopter_max_level_airspeed_ = CalcMaxLevelAirspeedOnRotors(*this, models::kRotorCount - 2);
}

// ---- the steps ----------------------------------------------------------------------------------------------------
namespace {

// After the body's step: z_B, the IMM, the extremes.
void FinishVehicleStep(const FlightModel& model, FlightState& state, const models::RigidBodyState& previous,
                       const models::RotorThrusts& believed, StepSignals& s, FlightLog* log) {
  s.z_B_W = state.vehicle.body.q_WB.toRotationMatrix().col(2);
  StepImm(model, state, previous, believed, s, log);
  UpdateExtremes(model, state.vehicle, s);
}

// The vehicle's part of a GNC step: faults → LQR → allocation → rotor lag (capped at the power system's bus voltage)
// → 6-DOF → IMM → extremes. Changes the vehicle and the faults only; fills `s` with what the power step and the
// classification read. `s` is working memory kept from step to step: every member a step reads, it writes first.
void StepVehicle(const FlightModel& model, FlightState& state, FlightLog* log, StepSignals& s) {
  AdvanceFaults(model, state, log);
  models::RotorThrusts believed;
  ReadReference(model, state, s);
  ComputeControl(model, state, s);
  StepRotors(model, state, believed, s);
  const models::RigidBodyState previous = state.vehicle.body;
  StepBody(model, state.vehicle, s);
  FinishVehicleStep(model, state, previous, believed, s, log);
}

// True when the follower's bus voltage caps every rotor's command of this step as the lead's cap did, and the LQR's
// tilt bound, which reads the rotors' collective at the bus voltage, would have commanded the same wrench: the vehicle
// then flies alike under both power systems (the pack acts on the vehicle only through these two).
bool CapsAlike(const FlightModel& model, const FlightState& lead, const StepSignals& s, const FlightState& follower) {
  const double cap = ThrustCap(model, follower.power.bus_voltage_v);
  bool alike = true;
  for (int i = 0; i < 6; ++i) {
    alike = alike && std::clamp(s.allocated[i], 0.0, cap) == std::clamp(s.allocated[i], 0.0, s.thrust_cap);
  }
  return alike && s.tilt.SameWrenchAt(MaxCollectiveThrust(model, lead), MaxCollectiveThrust(model, follower));
}

// The power system's part of a GNC step, the telemetry, the classification and the clock.
void FinishStep(const FlightModel& model, FlightState& state, StepSignals& s, FlightLog* log) {
  StepPowerSystem(model, state.power, s, state.time_s);
  if (log && log->record_telemetry) {
    const double rate = model.options().telemetry_rate_hz;
    const int steps_per_row = std::max(1, static_cast<int>(std::lround(model.options().gnc_rate_hz / rate)));
    if (state.step % steps_per_row == 0) RecordTelemetry(model, state, s, *log);
  }
  ClassifyStep(model, state, s);
  WaitWhileTiltBounded(model, state, s);
  AdvanceClock(model, state);
}

// The lanes flight k of a lockstep group fills: its own, and every lane of the group's first flying flight's when it
// is that flight (a lane without a flight of its own then repeats valid inputs; its results are not read).
std::pair<int, int> LanesFilledBy(int k, int first_flying) {
  return k == first_flying ? std::pair{0, kControllerLanes} : std::pair{k, k + 1};
}

// A flight's inputs to the control in lanes, in lane `lane`.
void SetControlLane(ControllerLaneInputs& control, int lane, const models::RigidBodyState& body,
                    const planning::PlanReference& reference, const Eigen::Vector3d& mean_wind_W) {
  for (int i = 0; i < 3; ++i) {
    control.p_WB_W[i][lane] = body.p_WB_W[i];
    control.v_WB_W[i][lane] = body.v_WB_W[i];
    control.w_WB_B[i][lane] = body.w_WB_B[i];
    control.p_ref_W[i][lane] = reference.p_W[i];
    control.v_ref_W[i][lane] = reference.v_W[i];
    control.a_ref_W[i][lane] = reference.a_W[i];
    control.mean_wind_W[i][lane] = mean_wind_W[i];
  }
  for (int i = 0; i < 4; ++i) control.q_WB[i][lane] = body.q_WB.coeffs()[i];
}

// Step with working memory the caller keeps from step to step (constructing the signals zeroes ~0.8 kB).
void StepWith(const FlightModel& model, FlightState& state, FlightLog* log, StepSignals& s) {
  if (state.done()) return;
  StepVehicle(model, state, log, s);
  FinishStep(model, state, s, log);
}

void CheckGroup(std::span<const FlightModel* const> models, std::span<FlightState* const> states,
                std::span<FlightLog* const> logs) {
  UASCMA_CHECK(states.size() <= static_cast<std::size_t>(kControllerLanes) && logs.size() == states.size() &&
                   models.size() == states.size(),
               "at most four flights, one model and one log (or nullptr) each");
}

// StepTogether's working memory, kept by a caller that steps a group many times. Every lane and signal a step reads
// it writes first (LanesFilledBy fills every lane of the inputs), so nothing carries over from step to step.
struct LockstepScratch {
  std::array<StepSignals, kControllerLanes> s;
  std::array<models::RotorThrusts, kControllerLanes> believed;
  std::array<models::RigidBodyState, kControllerLanes> previous;
  ControllerLaneInputs control;
  ControllerLaneOutputs out;
  models::RigidBodyLanes bodies;
  models::BodyInputLanes inputs;
};

void StepTogetherWith(std::span<const FlightModel* const> models, std::span<FlightState* const> states,
                      std::span<FlightLog* const> logs, LockstepScratch& scratch) {
  CheckGroup(models, states, logs);
  const lane_math::LaneMathPath path = lane_math::DefaultLaneMathPath();
  const int n = static_cast<int>(states.size());
  auto& [s, believed, previous, control, out, bodies, inputs] = scratch;
  std::array<bool, kControllerLanes> flying{};
  // Faults and the reference flight by flight, then the control in lanes (sim/controller_lanes.h).
  int first_flying = -1;
  for (int k = 0; k < n; ++k) {
    const FlightModel& model = *models[k];
    FlightState& state = *states[k];
    flying[k] = !state.done();
    if (!flying[k]) continue;
    if (first_flying < 0) first_flying = k;
    AdvanceFaults(model, state, logs[k]);
    ReadReference(model, state, s[k]);
    for (auto [lane, end] = LanesFilledBy(k, first_flying); lane < end; ++lane) {
      SetControlLane(control, lane, state.vehicle.body, s[k].reference, model.wind().MeanWind_W());
      control.failed_motor[lane] = state.faults.allocation_failure;
      control.max_collective_thrust[lane] = MaxCollectiveThrust(model, state);
    }
  }
  if (first_flying < 0) return;
  const FlightModel& vehicle = *models[first_flying];  // every flight's (SharesVehicle)
  ComputeControllerLanes(path,
                         {&vehicle.controller(), &vehicle.mixer(), &vehicle.drag(), vehicle.options().drag_feedforward},
                         control, out);
  for (int k = 0; k < n; ++k) {
    if (!flying[k]) continue;
    for (int i = 0; i < 4; ++i) s[k].command[i] = out.command[i][k];
    s[k].tilt.bounded = out.tilt_bounded[k];
    for (int i = 0; i < models::kRotorCount; ++i) s[k].allocated[i] = out.allocated[i][k];
  }
  // The rotors and the wind alone, the rigid bodies in lanes.
  for (int k = 0; k < n; ++k) {
    if (!flying[k]) continue;
    const FlightModel& model = *models[k];
    FlightState& state = *states[k];
    StepRotors(model, state, believed[k], s[k]);
    previous[k] = state.vehicle.body;
    StepWind(model, state.vehicle, s[k]);
    for (auto [lane, end] = LanesFilledBy(k, first_flying); lane < end; ++lane) {
      bodies.Set(lane, state.vehicle.body);
      inputs.Set(lane, s[k].body_inputs);
    }
  }
  // libm's asin per lane, the table's interpolation in the lanes: DragAtSine's bits (models/rigid_body_lanes.h).
  models::StepRigidBodyLanes(path, vehicle.scenario().body, vehicle.drag(), bodies, inputs, vehicle.dt(),
                             models::LaneDragLookup::kLibmAsinTableInLanes);
  for (int k = 0; k < n; ++k) {
    if (!flying[k]) continue;
    const FlightModel& model = *models[k];
    FlightState& state = *states[k];
    state.vehicle.body = bodies.Get(k);
    HoldOnGround(state.vehicle);
    FinishVehicleStep(model, state, previous[k], believed[k], s[k], logs[k]);
    FinishStep(model, state, s[k], logs[k]);
  }
}

}  // namespace

void Step(const FlightModel& model, FlightState& state, FlightLog* log) {
  StepSignals s;
  StepWith(model, state, log, s);
}

void StepTogether(std::span<const FlightModel* const> models, std::span<FlightState* const> states,
                  std::span<FlightLog* const> logs) {
  LockstepScratch scratch;
  StepTogetherWith(models, states, logs, scratch);
}

void StepToNextEpoch(const FlightModel& model, FlightState& state, FlightLog* log) {
  if (state.done()) return;
  StepSignals s;
  do {
    StepWith(model, state, log, s);
  } while (!state.done() && !IsDecisionEpoch(model, state));
}

void StepTogetherToNextEpoch(std::span<const FlightModel* const> models, std::span<FlightState* const> states,
                             std::span<FlightLog* const> logs) {
  CheckGroup(models, states, logs);
  LockstepScratch scratch;
  std::array<const FlightModel*, kControllerLanes> stepping_models{};
  std::array<FlightState*, kControllerLanes> stepping_states{};
  std::array<FlightLog*, kControllerLanes> stepping_logs{};
  for (bool first_step = true;; first_step = false) {
    int stepping = 0;  // the flights that have not ended and, after the first step, not reached an epoch
    for (std::size_t k = 0; k < states.size(); ++k) {
      if (states[k]->done() || (!first_step && IsDecisionEpoch(*models[k], *states[k]))) continue;
      stepping_models[stepping] = models[k];
      stepping_states[stepping] = states[k];
      stepping_logs[stepping] = logs[k];
      ++stepping;
    }
    if (stepping == 0) return;
    if (stepping == 1) {
      StepWith(*stepping_models[0], *stepping_states[0], stepping_logs[0], scratch.s[0]);
    } else {
      StepTogetherWith(std::span(stepping_models.data(), stepping), std::span(stepping_states.data(), stepping),
                       std::span(stepping_logs.data(), stepping), scratch);
    }
  }
}

void StepFollowing(const FlightModel& model, FlightState& lead, std::span<FlightState* const> followers,
                   std::span<bool> stepped) {
  UASCMA_CHECK(followers.size() == stepped.size(), "one stepped flag per follower");
  UASCMA_CHECK(!model.scenario().fault.enabled && !model.options().fault_detection,
               "followers share a vehicle without faults and without the fault detector");
  std::fill(stepped.begin(), stepped.end(), false);
  if (lead.done()) return;
  // The vehicle steps once; the followers whose pack caps every rotor's command alike fly it this step.
  StepSignals s;
  StepVehicle(model, lead, nullptr, s);
  for (std::size_t k = 0; k < followers.size(); ++k) {
    const FlightState& f = *followers[k];
    stepped[k] = !f.done() && f.step == lead.step && CapsAlike(model, lead, s, f);
  }
  StepSignals own = s;
  StepPowerSystem(model, lead.power, own, lead.time_s);
  ClassifyStep(model, lead, own);
  const bool lead_flies_on = !lead.done();
  // Then each follower's power system, on the vehicle it shares.
  for (std::size_t k = 0; k < followers.size(); ++k) {
    if (!stepped[k]) continue;
    FlightState& f = *followers[k];
    own = s;
    StepPowerSystem(model, f.power, own, f.time_s);
    f.vehicle = lead.vehicle;
    // The classification sees the follower's own cells and the shared kinematics: while the leader flies on and the
    // follower's cells are above the cut-off, its classification is the leader's (in progress).
    const bool as_lead = lead_flies_on && own.pack_outputs.min_cell_voltage_v > models::kCutoffVoltage;
    if (!as_lead) ClassifyStep(model, f, own);
    WaitWhileTiltBounded(model, f, own);
    AdvanceClock(model, f);
  }
  WaitWhileTiltBounded(model, lead, s);
  AdvanceClock(model, lead);
}

}  // namespace uascma::sim
