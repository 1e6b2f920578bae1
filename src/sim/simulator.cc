#include "uascma/sim/simulator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/frames.h"
#include "uascma/common/random.h"

namespace uascma::sim {
namespace {

using decision::CmaAction;
using decision::CmaState;
using decision::FlightStatus;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Independent random streams of one run (common/random.h DeriveSeed), so that e.g. the wind does not
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

decision::BatteryHealth ToCmaHealth(models::HealthClass health) {
  return static_cast<decision::BatteryHealth>(static_cast<int>(health));
}

}  // namespace

const char* OutcomeName(Outcome outcome) {
  switch (outcome) {
    case Outcome::kInProgress: return "in_progress";
    case Outcome::kCompleted: return "completed";
    case Outcome::kEmergencyLanding: return "emergency_landing";
    case Outcome::kTerminated: return "terminated";
    case Outcome::kFailedBattery: return "failed_battery";
    case Outcome::kFailedControl: return "failed_control";
    case Outcome::kFailedCollision: return "failed_collision";
    case Outcome::kTimeout: return "timeout";
  }
  return "unknown";
}

bool IsFailure(Outcome outcome) {
  return outcome == Outcome::kFailedBattery || outcome == Outcome::kFailedControl ||
         outcome == Outcome::kFailedCollision || outcome == Outcome::kTimeout;
}

bool SimOptions::IsValid(std::string* error) const {
  const struct { const char* name; double value; } positive[] = {
      {"gnc_rate_hz", gnc_rate_hz}, {"decision_rate_hz", decision_rate_hz},
      {"telemetry_rate_hz", telemetry_rate_hz}, {"max_tilt", max_tilt},
      {"max_tracking_error", max_tracking_error}, {"touchdown_speed", touchdown_speed},
      {"time_limit_factor", time_limit_factor}, {"reference_bus_voltage_v", reference_bus_voltage_v},
      {"load_current_time_constant_s", load_current_time_constant_s}};
  for (const auto& f : positive) {
    if (!(f.value > 0.0 && std::isfinite(f.value))) {
      if (error) *error = fmt::format("{}: expected a positive number, got {}", f.name, f.value);
      return false;
    }
  }
  const double ratio = gnc_rate_hz / decision_rate_hz;
  if (std::abs(ratio - std::round(ratio)) > 1e-9) {
    if (error) *error = "decision_rate_hz: expected to divide gnc_rate_hz";
    return false;
  }
  if (!(safety_margin_s >= 0.0 && std::isfinite(safety_margin_s))) {
    if (error) *error = "safety_margin_s: expected >= 0 s";
    return false;
  }
  if (!(hotel_current_a >= 0.0)) {
    if (error) *error = "hotel_current_a: expected >= 0 A";
    return false;
  }
  return true;
}

TablePolicy::TablePolicy(std::vector<decision::ActionIndex> action_per_state, std::string name)
    : action_(std::move(action_per_state)), name_(std::move(name)) {
  if (static_cast<int>(action_.size()) < decision::kCmaNumTupleStates) {
    throw InputError("policy", "states", "an action for each of the 108 CMA states");
  }
}

CmaAction TablePolicy::Decide(const DecisionInputs& inputs) {
  return static_cast<CmaAction>(action_[decision::CmaStateIndex(inputs.state)]);
}

Simulator::Simulator(const Scenario& scenario)
    : scenario_(scenario),
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
      nominal_plan_(planning::MakeDeliveryPlan(scenario.mission, scenario.limits)),
      battery_health_(ToCmaHealth(models::ClassifyHealth(scenario.battery.cell_health))),
      map_planner_(MakeMapEmergencyPlanner(scenario_, nominal_plan_, drag_, propulsion_)) {
  std::string error;
  if (!scenario.options.IsValid(&error)) throw InputError(scenario.name, "options", error);
  if (scenario.fault.enabled && (scenario.fault.motor < 1 || scenario.fault.motor > 6)) {
    throw InputError(scenario.name, "fault.motor", fmt::format("a motor 1..6, got {}", scenario.fault.motor));
  }
  if (scenario.fault.enabled && !(scenario.fault.spall_onset_s >= 0.0)) {
    throw InputError(scenario.name, "fault.spall_onset_s", "a time >= 0 s");
  }
  if (std::abs(scenario.lqr.dt * scenario.options.gnc_rate_hz - 1.0) > 1e-9) {
    throw InputError(scenario.name, "lqr.dt", "1 / options.gnc_rate_hz");
  }
}

MapEmergencyPlanner MakeMapEmergencyPlanner(const Scenario& scenario, const planning::FlightPlan& nominal_plan,
                                            const models::DragTable& drag, const models::PropulsionParams& propulsion) {
  if (!scenario.map || scenario.map->sites().empty()) return {};
  planning::LandingPathParams path;
  path.limits = scenario.limits;
  auto planner = std::make_shared<const planning::LandingPathPlanner>(*scenario.map, path);
  auto practical = std::make_shared<const planning::LandPractDatabase>(
      planning::LandPractDatabase::Build(*planner, nominal_plan));
  planning::LandAsapParams asap;
  asap.footprint.mass = scenario.body.mass;
  asap.footprint.drag_slope = planning::CruiseDragSlope(drag, scenario.limits.cruise_speed, scenario.body.mass);
  // A hovering vehicle's footprint of eqs. 5.10-5.11 is a point; LandASAP then plans as if it were cruising
  // (our choice: in the dissertation the action is taken in flight).
  asap.min_footprint_speed = scenario.limits.cruise_speed;
  const double rotor_max = propulsion.max_thrust;
  auto map = scenario.map;  // keeps the map alive as long as the planners
  MapEmergencyPlanner out;
  for (const auto& checkpoint : practical->checkpoints()) out.checkpoints_W.push_back(checkpoint.p_W);
  out.planner = [map, planner, practical, asap, rotor_max](const EmergencyRequest& r) -> std::optional<EmergencyPlan> {
    const planning::LandingRequest request{r.p_WB_W, r.v_WB_W, r.yaw, r.eod_s, r.original_plan_elapsed_s};
    planning::LandingResult result;
    if (r.action == CmaAction::kLandAsap) {
      planning::LandAsapParams params = asap;
      // After the failure rule only four rotors fly (§4.4.1).
      params.footprint.available_thrust = (r.failed_motor != 0 ? 4.0 : 6.0) * rotor_max;
      result = planning::PlanLandAsap(*planner, params, request);
    } else {
      result = practical->Plan(request);
    }
    if (!result.ok()) return std::nullopt;
    EmergencyPlan plan{std::move(result.plan), result.site_id, result.reach_margin, {}};
    if (r.action == CmaAction::kLandAsap) {
      for (const Eigen::Vector2d& p_H : result.footprint.region.Boundary(72)) {
        plan.footprint_NE.push_back(result.frame.ToWorld(p_H).head<2>());
      }
    }
    return plan;
  };
  return out;
}

SimResult Simulator::Run(DecisionPolicy& policy, const EmergencyPlanner& planner, const RunOptions& run) const {
  const auto wall_start = std::chrono::steady_clock::now();
  const Scenario& sc = scenario_;
  const SimOptions& opt = sc.options;
  const double dt = 1.0 / opt.gnc_rate_hz;
  const int steps_per_epoch = static_cast<int>(std::lround(opt.gnc_rate_hz / opt.decision_rate_hz));
  const int steps_per_row = std::max(1, static_cast<int>(std::lround(opt.gnc_rate_hz / opt.telemetry_rate_hz)));
  const double time_limit = opt.time_limit_factor * nominal_plan_.duration() + 60.0;

  RandomStream wind_random(DeriveSeed(sc.seed, kWindStream));
  RandomStream sensor_random(DeriveSeed(sc.seed, kSensorStream));
  RandomStream prognosis_random(DeriveSeed(sc.seed, kPrognosisStream));

  SimResult result;
  result.seed = sc.seed;
  result.policy = policy.name();
  result.plan_duration_s = nominal_plan_.duration();
  result.min_cell_voltage_v = kInfinity;

  // --- state of the flight -------------------------------------------------------------------------
  RigidBodyState body;
  body.p_WB_W = nominal_plan_.start_W();
  models::WindState wind_state = wind_.InitialState(0.0, wind_random);
  models::PackState pack_state = pack_.MakeRestingState(sc.battery.initial_cell_voltage_v);
  const models::RotorSpeedLag lag(propulsion_.motor_time_constant, dt);
  const models::BatteryPack::FixedStep pack_step_length = pack_.MakeFixedStep(dt);
  std::array<double, 6> rotor_speed{}, believed_speed{};
  const double hover_speed = models::CalcRotorSpeedForThrust(propulsion_, sc.body.mass * kGravity / 6.0);
  rotor_speed.fill(hover_speed);
  believed_speed.fill(hover_speed);
  ImmFilter imm(sc.imm, sc.body, mixer_.mixing_matrix(models::kNoFailedMotor));
  std::optional<prognostics::SpallJamEvent> spall;
  std::optional<double> rul_at_onset;
  int jammed_rotor = 0;         // the truth
  int allocation_failure = 0;   // the failed motor the allocation uses (after isolation)

  const planning::FlightPlan* plan = &nominal_plan_;
  planning::FlightPlan emergency_plan;
  std::string emergency_site;
  double plan_start = 0.0;
  FlightStatus flight_status = FlightStatus::kN;
  bool airborne = false;
  double bus_voltage = pack_.CalcOutputs(pack_state, 0.0).split.bus_voltage_v;
  // Until the first step has drawn real current, the 1 Hz prognosis sees the hover draw.
  double pack_current = opt.hotel_current_a +
                        6.0 * models::CalcElectricalPower(propulsion_, sc.body.mass * kGravity / 6.0) / bus_voltage;
  double load_current = pack_current;
  const double load_filter_gain = 1.0 - std::exp(-dt / opt.load_current_time_constant_s);
  prognostics::EodResult eod;
  DecisionInputs inputs;
  inputs.rul_s = kInfinity;
  Outcome outcome = Outcome::kInProgress;
  std::string reason;
  auto event = [&](double t, std::string what) { result.events.push_back({t, std::move(what)}); };

  // tilt > max_tilt ⇔ cos(tilt) < cos(max_tilt) for tilts in [0, π] (max_tilt > 0 is validated).
  const double cos_max_tilt = std::cos(std::min(opt.max_tilt, std::numbers::pi));
  double min_cos_tilt = 1.0;
  int step = 0;
  double t = 0.0;
  for (;; ++step) {
    t = step * dt;
    // ---- 1 Hz: prognosis, abstraction, decision ---------------------------------------------------
    if (step % steps_per_epoch == 0) {
      // EOD at the present current (decisions item 14), taken as the pack current low-passed with the
      // time constant of SimOptions::load_current_time_constant_s: the present load, not one gust-driven
      // 5 ms sample nor the few seconds of the take-off climb.
      eod = prognostics::CalcPackEod(pack_, pack_state, load_current);
      inputs.time_s = t;
      inputs.flight_time_remaining_s = plan->TimeRemaining(t - plan_start);
      inputs.eod_s = eod.eod_s;
      inputs.reach_margin = prognostics::CalcReachMargin(eod, inputs.flight_time_remaining_s + opt.safety_margin_s);
      decision::MotorHealth motor_health = decision::MotorHealth::kNF;
      if (allocation_failure != 0 || imm.isolated_rotor() != 0) {
        motor_health = decision::MotorHealth::kJF;
        inputs.rul_s = 0.0;
      } else if (spall) {
        // The prognosis (§3.4.1, §5.3.2.1: "When a spalling fault in the motor is detected, t_RUL is
        // calculated using Paris' Law"): the calibrated model's particle mean from the initial spall, computed
        // at detection, then counted down with the flight time.
        motor_health = decision::MotorHealth::kSF;
        if (!rul_at_onset) {
          rul_at_onset = rul_model_.PredictRulFromArea(rul_model_.params().initial_area_mm2, prognosis_random).mean_s;
        }
        inputs.rul_s = std::max(*rul_at_onset - (t - *result.spall_onset_s), 0.0);
      }
      inputs.motor_margin = prognostics::CalcMotorMargin(inputs.flight_time_remaining_s, inputs.rul_s);
      inputs.state = CmaState{flight_status, motor_health,
                              inputs.motor_margin < 0.0 ? decision::MotorMargin::kMM0 : decision::MotorMargin::kMM1,
                              battery_health_,
                              inputs.reach_margin < 0.0 ? decision::ReachMargin::kRM0 : decision::ReachMargin::kRM1};
      result.states.emplace_back(t, decision::CmaStateIndex(inputs.state));
      const CmaAction action = policy.Decide(inputs);
      // Decisions item 9: an action equal to the executing one is a no-op.
      const bool same = (action == CmaAction::kLandPract && flight_status == FlightStatus::kElPract) ||
                        (action == CmaAction::kLandAsap && flight_status == FlightStatus::kElAsap);
      if (action == CmaAction::kTerminate) {
        result.actions.emplace_back(t, action);
        outcome = Outcome::kTerminated;
        reason = fmt::format("Terminate in state {}", decision::CmaStateLabel(inputs.state));
        break;
      }
      if ((action == CmaAction::kLandPract || action == CmaAction::kLandAsap) && !same) {
        std::optional<EmergencyPlan> emergency;
        const EmergencyPlanner& emergency_planner = planner ? planner : map_planner_.planner;
        if (emergency_planner) {
          emergency = emergency_planner({action, t, body.p_WB_W, body.v_WB_W,
                                         EulerFromRotation(body.q_WB.toRotationMatrix()).z(), allocation_failure,
                                         eod.eod_s, plan == &nominal_plan_ ? t - plan_start : nominal_plan_.duration()});
        }
        if (emergency) {
          emergency_plan = std::move(emergency->plan);
          emergency_site = emergency->site;
          result.emergency_site = emergency->site;
          result.emergency_reach_margin = emergency->reach_margin;
          if (!emergency->footprint_NE.empty()) result.footprint_NE = emergency->footprint_NE;
          plan = &emergency_plan;
          plan_start = t;
          flight_status = action == CmaAction::kLandPract ? FlightStatus::kElPract : FlightStatus::kElAsap;
          result.actions.emplace_back(t, action);
          event(t, fmt::format("{}: emergency plan to {} ({:.0f} s, RM {:.2f})", decision::CmaActionName(action),
                               emergency->site, emergency_plan.duration(), emergency->reach_margin));
        } else if (result.actions.empty() || result.actions.back().second != action) {
          result.actions.emplace_back(t, action);
          event(t, fmt::format("{} requested: no emergency plan available, continuing", decision::CmaActionName(action)));
        }
      }
    }

    // ---- faults: spall onset and growth → jam (truth) ----------------------------------------------
    if (sc.fault.enabled && !spall && t >= sc.fault.spall_onset_s) {
      spall.emplace(spall_truth_, t, DeriveSeed(sc.seed, kSpallStream));
      result.spall_onset_s = t;
      event(t, fmt::format("spall in motor {}", sc.fault.motor));
    }
    if (spall && jammed_rotor == 0) {
      const prognostics::SpallJamStep s = spall->Advance(t - spall->time_s());
      if (s.jammed) {
        jammed_rotor = sc.fault.motor;
        result.jam_time_s = s.jam_time_s;
        event(s.jam_time_s, fmt::format("motor {} jammed", jammed_rotor));
      }
    }

    // ---- GNC at 200 Hz -------------------------------------------------------------------------------
    const planning::PlanReference reference = plan->At(t - plan_start);
    const Wrench command = controller_.Compute(body, reference);
    const models::AllocationResult allocation = mixer_.Allocate(command, allocation_failure);
    // The bus voltage caps each rotor's thrust: capacity ∝ (V_bus / V_ref)² below V_ref.
    const double voltage_ratio = std::min(1.0, bus_voltage / opt.reference_bus_voltage_v);
    const double thrust_cap = propulsion_.max_thrust * voltage_ratio * voltage_ratio;
    models::RotorThrusts thrust, believed;
    const double inverse_bus_voltage = 1.0 / std::max(bus_voltage, 1.0);
    double motors_current = 0.0;
    std::array<double, 6> rotor_current{};
    for (int i = 0; i < 6; ++i) {
      const double commanded = std::clamp(allocation.rotor_thrust[i], 0.0, thrust_cap);
      const double speed_command = models::CalcRotorSpeedForThrust(propulsion_, commanded);
      believed_speed[i] = lag.Step(believed_speed[i], speed_command);
      rotor_speed[i] = (i + 1 == jammed_rotor) ? 0.0 : lag.Step(rotor_speed[i], speed_command);
      thrust[i] = models::CalcRotorThrust(propulsion_, rotor_speed[i]);
      believed[i] = models::CalcRotorThrust(propulsion_, believed_speed[i]);
      rotor_current[i] = electrical_power_.Power(thrust[i]) * inverse_bus_voltage;
      motors_current += rotor_current[i];
    }
    const models::BodyWrench achieved = mixer_.mixing_matrix(models::kNoFailedMotor) * thrust;
    const double altitude = -body.p_WB_W.z();
    const double airspeed_estimate = (body.v_WB_W - wind_.MeanWind_W()).norm();
    const Eigen::Vector3d wind_W = wind_.Step(wind_state, std::max(altitude, 0.0), airspeed_estimate, dt, wind_random);
    BodyInputs body_inputs{achieved(0), achieved.tail<3>(), wind_W};
    const RigidBodyState previous = body;
    body = StepRigidBody(sc.body, drag_, body, body_inputs, dt);
    if (!airborne && body.p_WB_W.z() > 0.0) {  // resting on the ground before take-off
      body.p_WB_W.z() = 0.0;
      body.v_WB_W.z() = std::min(body.v_WB_W.z(), 0.0);
    }

    // ---- power: rotor currents → pack → bus voltage -------------------------------------------------
    pack_current = motors_current + opt.hotel_current_a;
    load_current += load_filter_gain * (pack_current - load_current);
    const models::PackStepResult pack_step = pack_.StepWithOutputs(pack_state, pack_current, pack_step_length);
    pack_state = pack_step.next;
    bus_voltage = pack_step.outputs.split.bus_voltage_v;
    result.energy_wh += bus_voltage * pack_current * dt / 3600.0;
    result.min_cell_voltage_v = std::min(result.min_cell_voltage_v, pack_step.outputs.min_cell_voltage_v);

    // ---- rotor failure detection and isolation (IMM) ------------------------------------------------
    const Eigen::Matrix3d R_WB = body.q_WB.toRotationMatrix();
    if (imm.isolated_rotor() == 0) {
      ImmMeasurement measurement;
      const Eigen::Vector3d specific_force_W = (body.v_WB_W - previous.v_WB_W) / dt - Eigen::Vector3d(0, 0, kGravity);
      measurement.gyro_B = body.w_WB_B;
      measurement.specific_force_z_B = (R_WB.transpose() * specific_force_W).z();
      if (opt.sensor_noise) {
        measurement.gyro_B += sc.imm.gyro_noise * Eigen::Vector3d(sensor_random.Normal(), sensor_random.Normal(),
                                                                  sensor_random.Normal());
        measurement.specific_force_z_B += sc.imm.accel_noise * sensor_random.Normal();
      }
      imm.Step(believed, measurement, dt);
      if (imm.isolated_rotor() != 0) {
        result.isolation_time_s = t + dt;
        result.isolated_rotor = imm.isolated_rotor();
        event(t + dt, fmt::format("IMM isolated rotor {}{}", imm.isolated_rotor(),
                                  opt.reconfiguration ? ": quadcopter allocation" : " (reconfiguration disabled)"));
        if (opt.reconfiguration) allocation_failure = imm.isolated_rotor();
      }
    }

    // ---- telemetry ------------------------------------------------------------------------------------
    // The tilt enters through its cosine R_WB(2, 2) (acos is decreasing): the largest tilt is the acos of
    // the smallest cosine, taken once at the end.
    const double cos_tilt = R_WB(2, 2);
    const double tracking_error = (body.p_WB_W - reference.p_W).norm();
    min_cos_tilt = std::min(min_cos_tilt, cos_tilt);
    result.max_tracking_error = std::max(result.max_tracking_error, tracking_error);
    if (run.record_telemetry && step % steps_per_row == 0) {
      TelemetryRow row;
      row.t = t + dt;
      row.p_W = body.p_WB_W;
      row.v_W = body.v_WB_W;
      row.p_ref_W = reference.p_W;
      row.euler = EulerFromRotation(R_WB);
      row.drag_W = CalcRigidBodyRates(sc.body, drag_, body, body_inputs).drag_W;
      row.wind_W = wind_W;
      row.wrench_cmd = command;
      row.wrench = achieved;
      for (int i = 0; i < 6; ++i) {
        row.rotor_thrust[i] = thrust[i];
        row.rotor_current[i] = rotor_current[i];
      }
      row.pack_current = pack_current;
      row.bus_voltage = bus_voltage;
      row.branch_current = {pack_step.outputs.split.current_a[0], pack_step.outputs.split.current_a[1]};
      for (int b = 0; b < 2; ++b) {
        for (int c = 0; c < 3; ++c) row.cell_voltage[3 * b + c] = pack_step.outputs.cell_voltage_v[b][c];
      }
      row.eod_s = eod.eod_s;
      row.flight_time_remaining_s = inputs.flight_time_remaining_s;
      row.rul_s = inputs.rul_s;
      row.reach_margin = inputs.reach_margin;
      row.motor_margin = inputs.motor_margin;
      row.cma_state = decision::CmaStateIndex(inputs.state);
      row.action = result.actions.empty() ? 0 : static_cast<int>(result.actions.back().second);
      row.imm_mode = imm.isolated_rotor() != 0 ? imm.isolated_rotor() : imm.MapMode();
      row.spall_area_mm2 = spall ? spall->area_mm2() : 0.0;
      result.telemetry.push_back(row);
    }

    // ---- outcomes (decisions item 11) -----------------------------------------------------------------
    const double now = t + dt;
    if (-body.p_WB_W.z() > 0.5) airborne = true;
    if (pack_step.outputs.min_cell_voltage_v <= models::kCutoffVoltage) {
      outcome = Outcome::kFailedBattery;
      reason = fmt::format("cell {} reached {:.3f} V", models::CellLabel(pack_step.outputs.min_cell_branch,
                                                                        pack_step.outputs.min_cell_index),
                           pack_step.outputs.min_cell_voltage_v);
      break;
    }
    if (cos_tilt < cos_max_tilt || tracking_error > opt.max_tracking_error) {
      outcome = Outcome::kFailedControl;
      reason = fmt::format("tilt {:.0f} deg, tracking error {:.1f} m", TiltAngle(R_WB) * kDegreesPerRadian,
                           tracking_error);
      break;
    }
    const double plan_left = plan->TimeRemaining(now - plan_start);
    const double altitude_now = -body.p_WB_W.z();
    const double end_altitude = -plan->end_W().z();
    const double to_end = (body.p_WB_W.head<2>() - plan->end_W().head<2>()).norm();
    const bool landing = to_end < 2.0 && plan_left < 5.0 && altitude_now - end_altitude < 0.5;
    if (airborne && landing && plan_left <= 0.0 && altitude_now - end_altitude < 0.3 && body.v_WB_W.norm() < 0.5) {
      outcome = plan == &nominal_plan_ ? Outcome::kCompleted : Outcome::kEmergencyLanding;
      reason = plan == &nominal_plan_ ? "landed at the destination of the original plan"
                                      : "landed at the emergency site " + emergency_site;
      break;
    }
    // Below the tallest roof the vehicle may strike a building (a touchdown on the site's own roof is a
    // landing, handled above).
    if (altitude_now < map_->max_building_height() + 0.5 && !landing) {
      const int building = map_->BuildingContaining(body.p_WB_W);
      if (building != planning::kNoBuilding) {
        outcome = Outcome::kFailedCollision;
        reason = fmt::format("struck building {} at {:.1f} m", map_->building(building).id, altitude_now);
        break;
      }
    }
    if (airborne && altitude_now <= 0.0) {
      const bool gentle = body.v_WB_W.z() <= opt.touchdown_speed;
      if (!gentle || !landing) {
        outcome = Outcome::kFailedCollision;
        reason = fmt::format("ground contact at {:.1f} m/s, {:.1f} m from the landing point", body.v_WB_W.z(), to_end);
        break;
      }
    }
    if (now >= time_limit) {
      outcome = Outcome::kTimeout;
      reason = fmt::format("still flying after {:.0f} s", now);
      break;
    }
  }
  result.max_tilt = std::acos(std::clamp(min_cos_tilt, -1.0, 1.0));
  result.outcome = outcome;
  result.reason = reason;
  result.sim_time_s = (step + 1) * dt;
  if (outcome == Outcome::kTerminated) result.sim_time_s = t;
  event(result.sim_time_s, fmt::format("{}: {}", OutcomeName(outcome), reason));
  if (plan != &nominal_plan_) {
    for (double s = 0; s <= emergency_plan.duration(); s += 1.0) result.executed_plan_ref.push_back(emergency_plan.At(s).p_W);
  }
  result.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return result;
}

}  // namespace uascma::sim
