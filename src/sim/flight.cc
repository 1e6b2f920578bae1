#include "uascma/sim/flight.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/frames.h"
#include "uascma/decision/cma_abstraction.h"
#include "uascma/sim/speed_cap.h"

namespace uascma::sim {
namespace {

using decision::CmaAction;
using decision::FlightStatus;

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// m/s: below this reference speed the plan is at rest and the whole position error counts as cross-track (ours).
constexpr double kMovingReferenceSpeed = 0.1;
// m/s: above this horizontal speed an emergency plan starts with a braking move (ours: below it the LQR absorbs
// the step to rest within a fraction of a metre).
constexpr double kBrakingSpeed = 0.5;

// Independent random streams of one flight (common/random.h DeriveSeed), so that e.g. the wind does not
// change when the sensor noise is switched off.
enum Stream : std::uint64_t { kWindStream = 1, kSensorStream = 2, kSpallStream = 3, kPrognosisStream = 4 };

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

const Scenario& Validated(const Scenario& scenario) {
  std::string error;
  if (!scenario.IsValid(&error)) throw InputError(scenario.name + ": " + error);
  return scenario;
}

void AddEvent(FlightLog* log, double time_s, std::string what) {
  if (log) log->events.push_back({time_s, std::move(what)});
}

void AddAction(FlightState& state, FlightLog* log, CmaAction action) {
  state.last_action = action;
  if (log) log->actions.emplace_back(state.time_s, action);
}

// What one GNC step computed, for telemetry.
struct StepSignals {
  planning::PlanReference reference;
  gnc::Wrench command;
  models::BodyWrench achieved;
  models::RotorThrusts thrust;
  models::RotorThrusts allocated;        // the allocation's rotor thrusts before the bus voltage's cap
  double thrust_cap = 0.0;               // N per rotor at this step's bus voltage
  std::array<double, 6> rotor_power{};   // W, electrical, per rotor
  std::array<double, 6> rotor_current{};
  Eigen::Vector3d wind_W = Eigen::Vector3d::Zero();
  models::BodyInputs body_inputs;
  models::PackOutputs pack_outputs;
  Eigen::Matrix3d R_WB;
};

// ---- faults: spall onset and growth → jam (the truth) -------------------------------------------------------
void AdvanceFaults(const FlightModel& model, FlightState& state, FlightLog* log) {
  const FaultSpec& fault = model.scenario().fault;
  const double t = state.time_s;
  if (fault.enabled && !state.spall && t >= fault.spall_onset_s) {
    state.spall.emplace(model.spall_truth(), t, DeriveSeed(state.seed, kSpallStream));
    state.spall_onset_s = t;
    AddEvent(log, t, fmt::format("spall in motor {}", fault.motor));
  }
  if (state.spall && state.jammed_rotor == 0) {
    const prognostics::SpallJamStep s = state.spall->Advance(t - state.spall->time_s());
    if (s.jammed) {
      state.jammed_rotor = fault.motor;
      state.jam_time_s = s.jam_time_s;
      AddEvent(log, s.jam_time_s, fmt::format("motor {} jammed", state.jammed_rotor));
    }
  }
}

// The bus voltage caps each rotor's thrust: capacity ∝ (V_bus / V_ref)² below V_ref.
double ThrustCap(const FlightModel& model, double bus_voltage_v) {
  const double voltage_ratio = std::min(1.0, bus_voltage_v / model.options().reference_bus_voltage_v);
  return model.propulsion().max_thrust * voltage_ratio * voltage_ratio;
}

double InverseBusVoltage(double bus_voltage_v) { return 1.0 / std::max(bus_voltage_v, 1.0); }

// ---- guidance and control: LQR → allocation → rotor lag, capped by the bus voltage -------------------------------
void StepRotors(const FlightModel& model, FlightState& state, models::RotorThrusts& believed, double& motors_current,
                StepSignals& s) {
  const models::PropulsionParams& propulsion = model.propulsion();
  s.reference = state.plan(model).At(state.time_s - state.plan_start_s);
  // Drag feed-forward while all six rotors fly (issue 11 item 3). After a reconfiguration to the quadcopter the
  // bare DLQR flies on: with four rotors near their thrust cap, asking the ~0.4 rad tilt that cancels the drag
  // at 8-9 m/s drives the loop into slow saturated swings. Measured on the default campaign, 150 runs, seed 1:
  // largest tracking error 13.2 m without feed-forward, 23.8 m with it throughout (rotor-out flights), 9.8 m with
  // it while hexacopter; mean per health 2.2-3.0 m, 2.2-3.0 m and 1.5-2.0 m; outcomes identical in all three.
  planning::PlanReference target = s.reference;
  if (model.options().drag_feedforward && state.allocation_failure == models::kNoFailedMotor) {
    const Eigen::Vector3d z_B_W = state.body.q_WB.toRotationMatrix().col(2);
    target.a_W += gnc::CalcDragFeedForward(model.scenario().body, model.drag(), z_B_W, s.reference.v_W,
                                           model.wind().MeanWind_W());
  }
  s.command = model.controller().Compute(state.body, target);
  const models::AllocationResult allocation = model.mixer().Allocate(s.command, state.allocation_failure);
  s.allocated = allocation.rotor_thrust;
  const double thrust_cap = ThrustCap(model, state.bus_voltage_v);
  s.thrust_cap = thrust_cap;
  const double inverse_bus_voltage = InverseBusVoltage(state.bus_voltage_v);
  motors_current = 0.0;
  const bool detection = model.options().fault_detection;  // the believed rotors feed only the IMM
  for (int i = 0; i < 6; ++i) {
    const double commanded = std::clamp(allocation.rotor_thrust[i], 0.0, thrust_cap);
    const double speed_command = models::CalcRotorSpeedForThrust(propulsion, commanded);
    if (detection) {
      state.believed_speed[i] = model.rotor_lag().Step(state.believed_speed[i], speed_command);
      believed[i] = models::CalcRotorThrust(propulsion, state.believed_speed[i]);
    }
    state.rotor_speed[i] = (i + 1 == state.jammed_rotor) ? 0.0 : model.rotor_lag().Step(state.rotor_speed[i], speed_command);
    s.thrust[i] = models::CalcRotorThrust(propulsion, state.rotor_speed[i]);
    s.rotor_power[i] = model.electrical_power().Power(s.thrust[i]);
    s.rotor_current[i] = s.rotor_power[i] * inverse_bus_voltage;
    motors_current += s.rotor_current[i];
  }
  s.achieved = model.mixer().mixing_matrix(models::kNoFailedMotor) * s.thrust;
}

// ---- 6-DOF with drag and Dryden wind ----------------------------------------------------------------------------
void StepBody(const FlightModel& model, FlightState& state, StepSignals& s) {
  const double dt = model.dt();
  const double altitude = -state.body.p_WB_W.z();
  const double airspeed_estimate = (state.body.v_WB_W - model.wind().MeanWind_W()).norm();
  s.wind_W = model.wind().Step(state.wind, std::max(altitude, 0.0), airspeed_estimate, dt, state.wind_random);
  s.body_inputs = models::BodyInputs{s.achieved(0), s.achieved.tail<3>(), s.wind_W};
  state.body = models::StepRigidBody(model.scenario().body, model.drag(), state.body, s.body_inputs, dt);
  if (!state.airborne && state.body.p_WB_W.z() > 0.0) {  // resting on the ground before take-off
    state.body.p_WB_W.z() = 0.0;
    state.body.v_WB_W.z() = std::min(state.body.v_WB_W.z(), 0.0);
  }
}

// ---- power: rotor currents → pack → bus voltage ------------------------------------------------------------------
void StepPower(const FlightModel& model, FlightState& state, double motors_current, StepSignals& s) {
  const double dt = model.dt();
  state.pack_current_a = motors_current + model.options().hotel_current_a;
  state.load_current_a += model.load_filter_gain() * (state.pack_current_a - state.load_current_a);
  const models::PackStepResult pack_step = model.pack().StepWithOutputs(state.pack, state.pack_current_a, model.pack_step());
  state.pack = pack_step.next;
  s.pack_outputs = pack_step.outputs;
  state.bus_voltage_v = pack_step.outputs.split.bus_voltage_v;
  state.energy_wh += state.bus_voltage_v * state.pack_current_a * dt / 3600.0;
  state.min_cell_voltage_v = std::min(state.min_cell_voltage_v, pack_step.outputs.min_cell_voltage_v);
}

// ---- rotor failure detection and isolation (IMM) ----------------------------------------------------------------
void StepImm(const FlightModel& model, FlightState& state, const models::RigidBodyState& previous,
             const models::RotorThrusts& believed, const StepSignals& s, FlightLog* log) {
  if (!model.options().fault_detection || state.imm.isolated_rotor() != 0) return;
  const double dt = model.dt();
  const gnc::ImmParams& imm = model.scenario().imm;
  gnc::ImmMeasurement measurement;
  const Eigen::Vector3d specific_force_W = (state.body.v_WB_W - previous.v_WB_W) / dt - Eigen::Vector3d(0, 0, kGravity);
  measurement.gyro_B = state.body.w_WB_B;
  measurement.specific_force_z_B = (s.R_WB.transpose() * specific_force_W).z();
  if (model.options().sensor_noise) {
    RandomStream& random = state.sensor_random;
    measurement.gyro_B += imm.gyro_noise * Eigen::Vector3d(random.Normal(), random.Normal(), random.Normal());
    measurement.specific_force_z_B += imm.accel_noise * random.Normal();
  }
  state.imm.Step(believed, measurement, dt);
  if (state.imm.isolated_rotor() != 0) {
    const double now = state.time_s + dt;
    state.isolation_time_s = now;
    const bool reconfigure = model.options().reconfiguration;
    AddEvent(log, now, fmt::format("IMM isolated rotor {}{}", state.imm.isolated_rotor(),
                                   reconfigure ? ": quadcopter allocation" : " (reconfiguration disabled)"));
    if (reconfigure) state.allocation_failure = state.imm.isolated_rotor();
  }
}

void RecordTelemetry(const FlightModel& model, const FlightState& state, const StepSignals& s, FlightLog& log) {
  TelemetryRow row;
  row.t = state.time_s + model.dt();
  row.p_W = state.body.p_WB_W;
  row.v_W = state.body.v_WB_W;
  row.p_ref_W = s.reference.p_W;
  row.euler = EulerFromRotation(s.R_WB);
  row.drag_W = models::CalcRigidBodyRates(model.scenario().body, model.drag(), state.body, s.body_inputs).drag_W;
  row.wind_W = s.wind_W;
  row.wrench_cmd = s.command;
  row.wrench = s.achieved;
  for (int i = 0; i < 6; ++i) {
    row.rotor_thrust[i] = s.thrust[i];
    row.rotor_current[i] = s.rotor_current[i];
  }
  row.pack_current = state.pack_current_a;
  row.bus_voltage = state.bus_voltage_v;
  row.branch_current = {s.pack_outputs.split.current_a[0], s.pack_outputs.split.current_a[1]};
  for (int b = 0; b < 2; ++b) {
    for (int c = 0; c < 3; ++c) row.cell_voltage[3 * b + c] = s.pack_outputs.cell_voltage_v[b][c];
  }
  const DecisionInputs& inputs = state.inputs;
  row.eod_s = state.eod.eod_s;
  row.flight_time_remaining_s = inputs.flight_time_remaining_s;
  row.rul_s = inputs.rul_s;
  row.reach_margin = inputs.reach_margin;
  row.motor_margin = inputs.motor_margin;
  row.cma_state = decision::CmaStateIndex(inputs.state);
  row.action = state.last_action ? static_cast<int>(*state.last_action) : 0;
  row.imm_mode = state.imm.isolated_rotor() != 0 ? state.imm.isolated_rotor() : state.imm.MapMode();
  row.spall_area_mm2 = state.spall ? state.spall->area_mm2() : 0.0;
  log.telemetry.push_back(row);
}

// ---- outcomes (decisions items 10–11, outcome.h) ----------------------------------------------------------------
// The distance from the reference path: the position error less its component along the reference velocity (the
// schedule's lead or lag is not a loss of control); at rest on the plan, the whole error.
double CrossTrackError(const Eigen::Vector3d& error_W, const Eigen::Vector3d& v_ref_W) {
  const double speed = v_ref_W.norm();
  if (speed < kMovingReferenceSpeed) return error_W.norm();
  const Eigen::Vector3d along = v_ref_W / speed;
  return (error_W - error_W.dot(along) * along).norm();
}

// The running extremes after a step. The tilt enters through its cosine R_WB(2, 2) (acos is decreasing): the
// largest tilt is the acos of the smallest cosine, taken once at the end.
void UpdateExtremes(FlightState& state, const StepSignals& s) {
  const double tracking_error = (state.body.p_WB_W - s.reference.p_W).norm();
  state.min_cos_tilt = std::min(state.min_cos_tilt, s.R_WB(2, 2));
  state.max_tracking_error = std::max(state.max_tracking_error, tracking_error);
}

void AdvanceClock(const FlightModel& model, FlightState& state) {
  ++state.step;
  state.time_s = static_cast<double>(state.step) * model.dt();
}

void ClassifyStep(const FlightModel& model, FlightState& state, const StepSignals& s) {
  const OutcomeThresholds& thresholds = model.options().outcome;
  const double now = state.time_s + model.dt();
  if (-state.body.p_WB_W.z() > thresholds.airborne_height) state.airborne = true;
  const planning::FlightPlan& plan = state.plan(model);
  OutcomeInputs inputs;
  inputs.time_s = now;
  inputs.p_WB_W = state.body.p_WB_W;
  inputs.v_WB_W = state.body.v_WB_W;
  inputs.cos_tilt = s.R_WB(2, 2);
  inputs.body_rate = state.body.w_WB_B.norm();
  inputs.cross_track_error = CrossTrackError(state.body.p_WB_W - s.reference.p_W, s.reference.v_W);
  inputs.min_cell_voltage_v = s.pack_outputs.min_cell_voltage_v;
  inputs.min_cell_branch = s.pack_outputs.min_cell_branch;
  inputs.min_cell_index = s.pack_outputs.min_cell_index;
  inputs.airborne = state.airborne;
  inputs.plan_time_remaining_s = plan.TimeRemaining(now - state.plan_start_s);
  inputs.plan_end_W = plan.end_W();
  inputs.landing_radius = state.on_emergency_plan ? state.emergency_site_radius : 0.0;
  inputs.on_original_plan = !state.on_emergency_plan;
  inputs.emergency_site = state.emergency_site;
  inputs.time_limit_s = model.time_limit_s();
  OutcomeDecision decision = model.outcome_classifier().Classify(inputs, model.map());
  if (decision.outcome != Outcome::kInProgress) {
    state.outcome = decision.outcome;
    state.reason = std::move(decision.reason);
  }
}

}  // namespace

// ---- the model ----------------------------------------------------------------------------------------------------
FlightModel::FlightModel(const Scenario& scenario)
    : scenario_(Validated(scenario)),
      propulsion_(models::PropulsionParams::ForConfiguration(scenario.configuration)),
      electrical_power_(propulsion_),
      mixer_(models::MixerParams::ForPropulsion(propulsion_)),
      drag_(models::DragTable::Default(scenario.configuration)),
      wind_(scenario.wind),
      pack_(models::MakePackParams(scenario.battery.cell_health, scenario.battery.ambient_temp_degf)),
      rul_model_(PrognosisGrowth(scenario.fault)),
      spall_truth_(TruthGrowth(scenario.fault)),
      map_(scenario.map ? scenario.map : std::make_shared<const planning::CityMap>()),
      controller_(scenario.body, scenario.lqr),
      nominal_plan_(scenario.route ? planning::MakeMissionPlan(*scenario.route, scenario.limits)
                                   : planning::MakeDeliveryPlan(scenario.mission, scenario.limits)),
      battery_health_(static_cast<decision::BatteryHealth>(
          static_cast<int>(models::ClassifyHealth(scenario.battery.cell_health)))),  // decisions item 8
      map_planner_(MakeMapEmergencyPlanner(scenario_, nominal_plan_, drag_, propulsion_)),
      dt_(1.0 / scenario.options.gnc_rate_hz),
      steps_per_epoch_(static_cast<int>(std::lround(scenario.options.gnc_rate_hz / scenario.options.decision_rate_hz))),
      time_limit_s_(scenario.options.outcome.time_limit_factor * nominal_plan_.duration() +
                    scenario.options.outcome.time_limit_margin_s),
      rotor_lag_(propulsion_.motor_time_constant, dt_),
      pack_step_(pack_.MakeFixedStep(dt_)),
      load_filter_gain_(1.0 - std::exp(-dt_ / scenario.options.load_current_time_constant_s)),
      outcome_classifier_(scenario.options.outcome),
      steady_load_{&scenario_.body, &drag_, &electrical_power_, wind_.MeanWind_W()},
      nominal_load_profile_(std::make_shared<const LoadProfile>(nominal_plan_, steady_load_, models::kRotorCount)) {}

// ---- the state ----------------------------------------------------------------------------------------------------
FlightState MakeInitialState(const FlightModel& model, std::uint64_t seed) {
  const Scenario& sc = model.scenario();
  FlightState state;
  state.seed = seed;
  state.wind_random = RandomStream(DeriveSeed(seed, kWindStream));
  state.sensor_random = RandomStream(DeriveSeed(seed, kSensorStream));
  state.prognosis_random = RandomStream(DeriveSeed(seed, kPrognosisStream));
  state.body.p_WB_W = model.nominal_plan().start_W();
  state.wind = model.wind().InitialState(0.0, state.wind_random);
  state.pack = model.pack().MakeRestingState(sc.battery.initial_cell_voltage_v);
  const double hover_thrust = sc.body.mass * kGravity / 6.0;
  const double hover_speed = models::CalcRotorSpeedForThrust(model.propulsion(), hover_thrust);
  state.rotor_speed.fill(hover_speed);
  state.believed_speed.fill(hover_speed);
  state.imm = gnc::ImmFilter(sc.imm, sc.body, model.mixer().mixing_matrix(models::kNoFailedMotor));
  state.bus_voltage_v = model.pack().CalcOutputs(state.pack, 0.0).split.bus_voltage_v;
  // Until the first step has drawn real current, the 1 Hz prognosis sees the hover draw.
  state.pack_current_a = sc.options.hotel_current_a +
                         6.0 * models::CalcElectricalPower(model.propulsion(), hover_thrust) / state.bus_voltage_v;
  state.load_current_a = state.pack_current_a;
  state.inputs.rul_s = kInfinity;
  // The lowest cell voltage starts at the pack at rest (a flight that never takes off reports it; any step under
  // load reads lower).
  state.min_cell_voltage_v = model.pack().CalcOutputs(state.pack, 0.0).min_cell_voltage_v;
  return state;
}

// ---- the steps ----------------------------------------------------------------------------------------------------
void Step(const FlightModel& model, FlightState& state, FlightLog* log) {
  if (state.done()) return;
  AdvanceFaults(model, state, log);
  StepSignals s;
  models::RotorThrusts believed;
  double motors_current = 0.0;
  StepRotors(model, state, believed, motors_current, s);
  const models::RigidBodyState previous = state.body;
  StepBody(model, state, s);
  StepPower(model, state, motors_current, s);
  s.R_WB = state.body.q_WB.toRotationMatrix();
  StepImm(model, state, previous, believed, s, log);
  UpdateExtremes(state, s);
  if (log && log->record_telemetry) {
    const double rate = model.options().telemetry_rate_hz;
    const int steps_per_row = std::max(1, static_cast<int>(std::lround(model.options().gnc_rate_hz / rate)));
    if (state.step % steps_per_row == 0) RecordTelemetry(model, state, s, *log);
  }
  ClassifyStep(model, state, s);
  AdvanceClock(model, state);
}

void StepToNextEpoch(const FlightModel& model, FlightState& state, FlightLog* log) {
  if (state.done()) return;
  do {
    Step(model, state, log);
  } while (!state.done() && !IsDecisionEpoch(model, state));
}

void StepFollowing(const FlightModel& model, FlightState& lead, std::span<FlightState* const> followers,
                   std::span<bool> stepped) {
  UASCMA_CHECK(followers.size() == stepped.size(), "one stepped flag per follower");
  UASCMA_CHECK(!model.scenario().fault.enabled && !model.options().fault_detection,
               "followers share a vehicle without faults and without the fault detector");
  std::fill(stepped.begin(), stepped.end(), false);
  if (lead.done()) return;
  StepSignals s;
  models::RotorThrusts believed;
  double motors_current = 0.0;
  StepRotors(model, lead, believed, motors_current, s);
  // Followers whose pack caps every rotor's command alike fly the lead's trajectory this step.
  for (std::size_t k = 0; k < followers.size(); ++k) {
    const FlightState& f = *followers[k];
    if (f.done() || f.step != lead.step) continue;
    const double cap = ThrustCap(model, f.bus_voltage_v);
    bool alike = true;
    for (int i = 0; i < 6; ++i) {
      alike = alike && std::clamp(s.allocated[i], 0.0, cap) == std::clamp(s.allocated[i], 0.0, s.thrust_cap);
    }
    stepped[k] = alike;
  }
  StepBody(model, lead, s);
  StepPower(model, lead, motors_current, s);
  s.R_WB = lead.body.q_WB.toRotationMatrix();
  UpdateExtremes(lead, s);
  ClassifyStep(model, lead, s);
  const bool lead_flies_on = !lead.done();
  for (std::size_t k = 0; k < followers.size(); ++k) {
    if (!stepped[k]) continue;
    FlightState& f = *followers[k];
    // Its own power system, as StepRotors and StepPower would have it (the same operations in the same order) …
    const double inverse_bus_voltage = InverseBusVoltage(f.bus_voltage_v);
    double current = 0.0;
    for (int i = 0; i < 6; ++i) current += s.rotor_power[i] * inverse_bus_voltage;
    StepSignals own = s;
    StepPower(model, f, current, own);
    // … and everything Step changes on the vehicle, the lead's.
    f.body = lead.body;
    f.rotor_speed = lead.rotor_speed;
    f.believed_speed = lead.believed_speed;
    f.wind = lead.wind;
    f.wind_random = lead.wind_random;
    f.sensor_random = lead.sensor_random;
    f.min_cos_tilt = lead.min_cos_tilt;
    f.max_tracking_error = lead.max_tracking_error;
    // The classification sees the follower's own cells and the lead's kinematics: while the lead flies on and the
    // follower's cells are above the cut-off, its classification is the lead's (in progress).
    if (lead_flies_on && own.pack_outputs.min_cell_voltage_v > models::kCutoffVoltage) {
      f.airborne = lead.airborne;
    } else {
      ClassifyStep(model, f, own);
    }
    AdvanceClock(model, f);
  }
  AdvanceClock(model, lead);
}

namespace {

// Rotors the allocation flies: six, or four after the failure rule (decisions item 13).
int ActiveRotors(const FlightState& state) {
  return state.allocation_failure != models::kNoFailedMotor ? models::kRotorCount - 2 : models::kRotorCount;
}

// A new executing plan: the forecast's profile is rebuilt at the next epoch (its bias ratio carries on).
void StartPlan(FlightState& state) {
  state.plan_start_s = state.time_s;
  state.load_forecast.profile.reset();
  state.load_forecast.have_last = false;
}

// The profile of the executing plan for the rotors that fly it (decision 25).
void EnsureLoadProfile(const FlightModel& model, FlightState& state) {
  LoadForecastState& forecast = state.load_forecast;
  const int rotors = ActiveRotors(state);
  if (forecast.profile && forecast.profile->active_rotors() == rotors) return;
  forecast.have_last = false;
  const bool original = !state.on_emergency_plan && !state.nominal_replanned;
  forecast.profile = original && rotors == models::kRotorCount
                         ? model.nominal_load_profile()
                         : std::make_shared<const LoadProfile>(state.plan(model), model.steady_load(), rotors);
}

// m/s: the airspeed the reconfigured vehicle can hold less the gust allowance (sim/speed_cap.h), with the thrust the
// rotors give at the lowest bus voltage the flight can see, the cut-off's (3 cells × 3.3 V, decisions item 11): the
// cap then holds to the end of the flight.
double AuthorityAirspeed(const FlightModel& model, const FlightState& state) {
  const double weight = model.scenario().body.mass * kGravity;
  const double cutoff_bus_voltage_v = models::kCellsPerBranch * models::kCutoffVoltage;
  const double available = ActiveRotors(state) * ThrustCap(model, cutoff_bus_voltage_v);
  if (weight >= available) return 0.0;
  const double max_tilt = std::acos(std::sqrt(weight / available));  // models::CalcControlAuthority's square
  const models::WindParams& wind = model.scenario().wind;
  const double altitude = std::max(-state.body.p_WB_W.z(), model.scenario().mission.cruise_altitude);
  const models::DrydenIntensity gust =
      models::CalcDrydenIntensity(wind.turbulence, altitude, wind.medium_band_altitude);
  return std::max(0.0, CalcMaxLevelAirspeed(model.scenario().body, model.drag(), max_tilt) - gust.sigma_u);
}

// Where a plan made now starts (as an emergency plan does): a moving vehicle first brakes to rest at the plan's
// horizontal acceleration limit (FlightPlan::AfterBraking), and the plan starts where it stops, when the braking line
// is clear of buildings; otherwise from where it is.
struct PlanStart {
  Eigen::Vector3d p_W, v_horizontal_W, stop_W;
  double accel = 0.0;
  bool brake = false;
  Eigen::Vector3d from_W() const { return brake ? stop_W : p_W; }
  planning::FlightPlan Then(planning::FlightPlan plan) const {
    return brake ? planning::FlightPlan::AfterBraking(p_W, v_horizontal_W, accel, plan) : plan;
  }
};

PlanStart StartFromHere(const FlightModel& model, const FlightState& state) {
  PlanStart start;
  start.p_W = state.body.p_WB_W;
  start.v_horizontal_W = Eigen::Vector3d(state.body.v_WB_W.x(), state.body.v_WB_W.y(), 0.0);
  start.accel = model.scenario().limits.horizontal_accel;
  start.stop_W = planning::BrakingStop(start.p_W, start.v_horizontal_W, start.accel);
  start.brake = start.v_horizontal_W.norm() > kBrakingSpeed && !model.map().SegmentCollides(start.p_W, start.stop_W);
  return start;
}

// Re-plans the executing plan's rest at the capped speed, starting as an emergency plan does (StartFromHere). True
// when a plan was made.
bool ReplanCapped(const FlightModel& model, FlightState& state, planning::FlightPlan& out) {
  const PlanStart start = StartFromHere(model, state);
  const Eigen::Vector2d wind_NE = model.wind().MeanWind_W().head<2>();
  planning::FlightPlan rest = ReplanAtCappedSpeed(state.plan(model), state.time_s - state.plan_start_s, start.from_W(),
                                                  model.scenario().limits, wind_NE, state.speed_cap_mps);
  if (rest.empty()) return false;
  out = start.Then(std::move(rest));
  return true;
}

// §4.4.2: at the first epoch after the allocation flies four rotors, the executing plan's rest is re-planned within
// what they can hold (SimOptions::cap_speed_after_isolation).
void CapSpeedAfterIsolation(const FlightModel& model, FlightState& state, FlightLog* log) {
  if (!model.options().cap_speed_after_isolation || state.allocation_failure == models::kNoFailedMotor ||
      std::isfinite(state.speed_cap_mps) || !state.airborne) {
    return;
  }
  state.speed_cap_mps = AuthorityAirspeed(model, state);
  const bool original = !state.on_emergency_plan;
  const double original_elapsed = state.original_plan_elapsed_s();
  const double original_left = state.plan(model).TimeRemaining(state.time_s - state.plan_start_s);
  planning::FlightPlan capped;
  if (!ReplanCapped(model, state, capped)) return;
  AddEvent(log, state.time_s, fmt::format("speed capped at {:.1f} m/s airspeed (four rotors, §4.4.2): {:.0f} s left",
                                          state.speed_cap_mps, capped.duration()));
  if (original) {
    state.replanned_nominal = std::move(capped);
    state.nominal_replanned = true;
    state.original_time_offset_s = original_elapsed;
    state.original_time_scale = state.replanned_nominal.duration() > 0.0
                                    ? original_left / state.replanned_nominal.duration()
                                    : 1.0;
  } else {
    state.emergency_plan = std::move(capped);
  }
  StartPlan(state);
}

// The constant current of the 1 Hz EOD (SimOptions::eod_load).
double EodCurrent(const FlightModel& model, FlightState& state) {
  if (model.options().eod_load == EodLoad::kPresent) return state.load_current_a;
  EnsureLoadProfile(model, state);
  const double forecast =
      ForecastCurrent(state.load_forecast, state.time_s - state.plan_start_s, state.energy_wh,
                      1.0 / model.options().decision_rate_hz, state.bus_voltage_v, model.options().hotel_current_a);
  return forecast > 0.0 ? forecast : state.load_current_a;  // under a second of plan left: the present load
}

}  // namespace

const DecisionInputs& Observe(const FlightModel& model, FlightState& state, FlightLog* log) {
  // Guidance first: a vehicle flying on four rotors keeps to what they can hold (§4.4.2).
  CapSpeedAfterIsolation(model, state, log);
  // EOD at the expected load of the rest of the executing plan (decision 25) or at the present current, the pack
  // current low-passed with SimOptions::load_current_time_constant_s (decision 14).
  const double t = state.time_s;
  state.eod_current_a = EodCurrent(model, state);
  state.eod = prognostics::CalcPackEod(model.pack(), state.pack, state.eod_current_a);
  DecisionInputs& inputs = state.inputs;
  inputs.time_s = t;
  inputs.flight_time_remaining_s = state.plan(model).TimeRemaining(t - state.plan_start_s);
  inputs.eod_s = state.eod.eod_s;
  inputs.reach_margin =
      prognostics::CalcReachMargin(state.eod, inputs.flight_time_remaining_s + model.options().safety_margin_s);
  decision::MotorHealth motor_health = decision::MotorHealth::kNF;
  if (state.allocation_failure != 0 || state.imm.isolated_rotor() != 0) {
    motor_health = decision::MotorHealth::kJF;
    inputs.rul_s = 0.0;
  } else if (state.spall) {
    // The prognosis (§3.4.1, §5.3.2.1: "When a spalling fault in the motor is detected, t_RUL is calculated using
    // Paris' Law"): the calibrated model's particle mean from the initial spall, computed at detection, then
    // counted down with the flight time.
    motor_health = decision::MotorHealth::kSF;
    if (!state.rul_at_onset_s) {
      const prognostics::MotorRulModel& rul = model.rul_model();
      state.rul_at_onset_s = rul.PredictRulFromArea(rul.params().initial_area_mm2, state.prognosis_random).mean_s;
    }
    inputs.rul_s = std::max(*state.rul_at_onset_s - (t - *state.spall_onset_s), 0.0);
  }
  inputs.motor_margin = prognostics::CalcMotorMargin(inputs.flight_time_remaining_s, inputs.rul_s);
  inputs.state = decision::AbstractCmaState(state.flight_status, motor_health, model.battery_health(),
                                            inputs.reach_margin, inputs.motor_margin);
  if (log) log->states.emplace_back(t, decision::CmaStateIndex(inputs.state));
  return inputs;
}

namespace {

// True on the executing plan's last move when it is a vertical descent: the vehicle is landing at the plan's end.
bool OnFinalDescent(const planning::FlightPlan& plan, double t_plan) {
  if (plan.empty() || t_plan >= plan.duration()) return false;
  const auto& segments = plan.segments();
  const planning::PlanSegment& last = segments.back();
  const int segment = plan.At(t_plan).segment;
  const Eigen::Vector3d delta_W = last.end_W - last.start_W;
  return segment + 1 == static_cast<int>(segments.size()) && last.kind == planning::PlanSegment::Kind::kMove &&
         delta_W.z() > 0.0 && delta_W.head<2>().norm() < 1e-6;
}

// Asks the planner for an emergency plan for `action` and switches to it when there is one; otherwise says why not.
// On the executing plan's final descent no emergency plan is sought: the vehicle is already landing at the end of
// its plan, sooner than any emergency plan could (measured: a LandPract taken 1.4 s before a touchdown climbed away
// and failed the battery 5 ms later, in a flight whose NoOp twin completed).
bool TryEmergencyPlan(const FlightModel& model, FlightState& state, CmaAction action, const EmergencyPlanner& planner,
                      FlightLog* log, std::string* why) {
  const double t = state.time_s;
  const EmergencyPlanner& emergency_planner = planner ? planner : model.map_planner();
  if (!emergency_planner) {
    *why = "the map has no landing sites";
    return false;
  }
  const double t_plan = t - state.plan_start_s;
  if (OnFinalDescent(state.plan(model), t_plan)) {
    *why = fmt::format("on the final descent of the executing plan, {:.1f} s from its touchdown",
                       state.plan(model).TimeRemaining(t_plan));
    return false;
  }
  // The planners plan from where a moving vehicle comes to rest (StartFromHere).
  const PlanStart start = StartFromHere(model, state);
  const Eigen::Vector3d plan_velocity_W =
      start.brake ? Eigen::Vector3d(0.0, 0.0, state.body.v_WB_W.z()) : state.body.v_WB_W;
  const double original_elapsed =
      state.on_emergency_plan ? model.nominal_plan().duration() : state.original_plan_elapsed_s();
  EmergencyPlan emergency =
      emergency_planner({action, t, start.from_W(), plan_velocity_W, EulerFromRotation(state.body.q_WB.toRotationMatrix()).z(),
                         state.allocation_failure, state.eod.eod_s, original_elapsed});
  if (!emergency.ok()) {
    *why = emergency.message.empty() ? planning::LandingStatusName(emergency.status) : emergency.message;
    return false;
  }
  state.emergency_plan = start.Then(std::move(emergency.plan));
  state.emergency_site = emergency.site;
  state.emergency_reach_margin = emergency.reach_margin;
  state.emergency_site_radius = emergency.site_radius;
  if (!emergency.footprint_NE.empty()) state.footprint_NE = std::move(emergency.footprint_NE);
  state.on_emergency_plan = true;
  StartPlan(state);
  state.flight_status = decision::FlightStatusAfter(action, state.flight_status);
  AddAction(state, log, action);
  AddEvent(log, t, fmt::format("{}: emergency plan to {} ({:.0f} s, RM {:.2f})", decision::CmaActionName(action),
                               emergency.site, state.emergency_plan.duration(), emergency.reach_margin));
  // On four rotors the emergency plan too keeps to what they can hold (§4.4.2).
  planning::FlightPlan capped;
  if (std::isfinite(state.speed_cap_mps) && ReplanCapped(model, state, capped)) {
    state.emergency_plan = std::move(capped);
    StartPlan(state);
  }
  return true;
}

// Decisions item 28: `taken` replaces `chosen`, which could not be carried out (`why`).
void RecordSubstitution(FlightState& state, FlightLog* log, CmaAction chosen, CmaAction taken, const std::string& why) {
  ++state.substitution_epochs;
  const std::string pair = fmt::format("{}->{}", decision::CmaActionName(chosen), decision::CmaActionName(taken));
  if (std::find(state.substitutions.begin(), state.substitutions.end(), pair) == state.substitutions.end()) {
    state.substitutions.push_back(pair);
  }
  AddEvent(log, state.time_s, fmt::format("{} cannot be carried out ({}): {} instead (the next-highest Q)",
                                          decision::CmaActionName(chosen), why, decision::CmaActionName(taken)));
}

}  // namespace

CmaAction Act(const FlightModel& model, FlightState& state, CmaAction action, const EmergencyPlanner& planner,
              FlightLog* log, ActionRanking ranking) {
  // §5.5.3: "an emergency landing at t = 0 translates into not taking off" — any emergency action chosen before
  // take-off keeps the vehicle on the ground (decision 21).
  if (action != CmaAction::kNoOp && !state.airborne) {
    AddAction(state, log, action);
    state.outcome = Outcome::kGrounded;
    state.reason = fmt::format("{} chosen before take-off in state {}: the vehicle stays on the ground",
                               decision::CmaActionName(action), decision::CmaStateLabel(state.inputs.state));
    return action;
  }
  auto terminate = [&](CmaAction chosen) {
    AddAction(state, log, CmaAction::kTerminate);
    state.outcome = Outcome::kTerminated;
    state.reason = chosen == CmaAction::kTerminate
                       ? fmt::format("Terminate in state {}", decision::CmaStateLabel(state.inputs.state))
                       : fmt::format("Terminate in state {} ({} could not be carried out)",
                                     decision::CmaStateLabel(state.inputs.state), decision::CmaActionName(chosen));
    return CmaAction::kTerminate;
  };
  if (action == CmaAction::kTerminate) return terminate(action);
  // Decisions item 9: an action equal to the executing one is a no-op.
  if (decision::EffectiveCmaAction(action, state.flight_status) == CmaAction::kNoOp) return action;
  std::string why;
  if (TryEmergencyPlan(model, state, action, planner, log, &why)) return action;
  // Decisions item 28: the available action with the next-highest value that can be carried out now.
  if (ranking.empty()) ranking = DefaultCmaActionRanking(state.inputs.state);
  for (const decision::ActionIndex index : ranking) {
    const auto next = static_cast<CmaAction>(index);
    if (next == action || !decision::IsCmaActionAvailable(state.flight_status, next)) continue;
    if (next == CmaAction::kTerminate) {
      RecordSubstitution(state, log, action, next, why);
      return terminate(action);
    }
    if (decision::EffectiveCmaAction(next, state.flight_status) == CmaAction::kNoOp) {  // NoOp, or what executes
      RecordSubstitution(state, log, action, next, why);
      return next;
    }
    std::string next_why;
    if (TryEmergencyPlan(model, state, next, planner, log, &next_why)) {
      RecordSubstitution(state, log, action, next, why);
      return next;
    }
    why += "; " + std::string(decision::CmaActionName(next)) + ": " + next_why;
  }
  // NoOp and Terminate are available in every flight status (decisions item 3) and always carried out.
  UASCMA_CHECK(false, "a ranking that holds NoOp or Terminate");
  return CmaAction::kNoOp;
}

void SwitchPacks(FlightState& state, models::PackAction action) { state.pack.branch_on = models::SwitchesFor(action); }

void DecideBattery(const FlightModel& model, FlightState& state, BatterySwitchPolicy& policy, FlightLog* log) {
  const models::PackAction action = policy.Decide(model, state);
  if (state.battery_action != action) {
    state.battery_action = action;
    if (log) {
      log->battery_switches.emplace_back(state.time_s, action);
      AddEvent(log, state.time_s, fmt::format("battery: {}", models::PackActionName(action)));
    }
  }
  SwitchPacks(state, action);
}

void StepEpoch(const FlightModel& model, FlightState& state, const Controllers& controllers, FlightLog* log) {
  if (state.done()) return;
  UASCMA_CHECK(IsDecisionEpoch(model, state), "StepEpoch starts at a decision epoch");
  const DecisionInputs& inputs = Observe(model, state, log);
  if (controllers.battery) DecideBattery(model, state, *controllers.battery, log);
  const CmaAction action = controllers.policy ? controllers.policy->Decide(inputs) : CmaAction::kNoOp;
  Act(model, state, action, controllers.planner, log,
      controllers.policy ? controllers.policy->Ranking(inputs) : ActionRanking{});
  StepToNextEpoch(model, state, log);
}

}  // namespace uascma::sim
