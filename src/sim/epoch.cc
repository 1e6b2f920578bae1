// The decision epoch of the kernel (epoch.h): Observe (guidance under a speed cap, EOD, RUL, margins, the abstract
// CMA state), BeginEpoch and StepEpoch; the actions (the CMA's Act, the battery executor's DecideBattery) are act.cc,
// the GNC step flight.cc.
#include "uascma/sim/epoch.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "flight_internal.h"
#include "pack_monitor.h"
#include "uascma/common/error.h"
#include "uascma/common/frames.h"
#include "uascma/decision/cma_abstraction.h"
#include "uascma/prognostics/eod_distribution.h"
#include "uascma/prognostics/eod_peak.h"
#include "uascma/prognostics/reach_margin.h"
#include "uascma/prognostics/rul_calibration.h"
#include "uascma/sim/act.h"
#include "uascma/sim/flight.h"
#include "uascma/sim/initial_state.h"
#include "uascma/sim/speed_cap.h"
#include "uascma/sim/vehicle_margin.h"

namespace uascma::sim {
namespace internal {  // flight_internal.h

// m/s: above this horizontal speed an emergency plan starts with a braking move (ours: below it the LQR absorbs
// the step to rest within a fraction of a metre).
constexpr double kBrakingSpeed = 0.5;

void AddAction(FlightState& state, FlightLog* log, decision::CmaAction action) {
  state.decision.last_action = action;
  if (log) log->actions.emplace_back(state.time_s, action);
}

void StartPlan(FlightState& state) {
  state.guidance.plan_start_s = state.time_s;
  state.decision.load_forecast.profile.reset();
  state.decision.load_forecast.have_last = false;
}

PlanStart StartFromHere(const FlightModel& model, const FlightState& state) {
  PlanStart start;
  start.p_W = state.vehicle.body.p_WB_W;
  start.v_horizontal_W = Eigen::Vector3d(state.vehicle.body.v_WB_W.x(), state.vehicle.body.v_WB_W.y(), 0.0);
  start.accel = model.scenario().limits.horizontal_accel;
  start.stop_W = planning::BrakingStop(start.p_W, start.v_horizontal_W, start.accel);
  start.brake = start.v_horizontal_W.norm() > kBrakingSpeed && !model.map().SegmentCollides(start.p_W, start.stop_W);
  return start;
}

bool ReplanCapped(const FlightModel& model, FlightState& state, planning::FlightPlan& out) {
  const PlanStart start = StartFromHere(model, state);
  const Eigen::Vector2d wind_NE = model.wind().MeanWind_W().head<2>();
  planning::FlightPlan rest =
      ReplanAtCappedSpeed(state.plan(model), state.time_s - state.guidance.plan_start_s, start.from_W(),
                          model.scenario().limits, wind_NE, state.guidance.speed_cap_mps);
  if (rest.empty()) return false;
  out = start.Then(std::move(rest));
  return true;
}

models::PackState SensedPack(const FlightModel& model, const FlightState& state) {
  models::PackState pack = state.power.pack;
  const double error = SocEstimateError(state.power.sensing, model.pack().cell(0, 0).capacity_as());
  for (auto& branch : pack.cells) {
    for (auto& cell : branch) cell.soc_fraction = std::clamp(cell.soc_fraction + error, 0.0, 1.0);
  }
  return pack;
}

prognostics::EodOptions EpochEodOptions(const FlightModel& model, const FlightState& state,
                                        const models::PackState& pack, double current_a) {
  if (model.options().eod_load != EodLoad::kForecast) return {};
  return prognostics::PeakSagEodOptions(model.pack(), pack, current_a, state.decision.load_forecast.PeakExcursionA());
}

}  // namespace internal

namespace {

using decision::CmaAction;
using internal::ActiveRotors;
using internal::AddEvent;
using internal::EpochEodOptions;
using internal::NeededS;
using internal::ObservedBatteryHealth;
using internal::ObservedPack;
using internal::PrognosisPack;
using internal::ReplanCapped;
using internal::StartPlan;
using internal::StoreEod;
using internal::ThrustCap;
using internal::UpdatePackMonitor;

// The profile of the executing plan for the rotors that fly it (docs/modelling-choices.md#eod-load-forecast).
void EnsureLoadProfile(const FlightModel& model, FlightState& state) {
  LoadForecastState& forecast = state.decision.load_forecast;
  const int rotors = ActiveRotors(state);
  if (forecast.profile && forecast.profile->active_rotors() == rotors) return;
  forecast.have_last = false;
  const bool original = !state.guidance.on_emergency_plan && !state.guidance.nominal_replanned;
  forecast.profile = original && rotors == models::kRotorCount
                         ? model.nominal_load_profile()
                         : std::make_shared<const LoadProfile>(state.plan(model), model.steady_load(), rotors);
}

// §4.4.2: at the first epoch after the allocation flies four rotors, the executing plan's rest is re-planned within
// what they can hold (SimOptions::cap_speed_after_isolation).
void CapSpeedAfterIsolation(const FlightModel& model, FlightState& state, FlightLog* log) {
  if (!model.options().cap_speed_after_isolation || state.faults.allocation_failure == models::kNoFailedMotor ||
      std::isfinite(state.guidance.speed_cap_mps) || !state.vehicle.airborne) {
    return;
  }
  state.guidance.speed_cap_mps = CalcAuthorityAirspeed(model, state, ActiveRotors(state));
  const bool original = !state.guidance.on_emergency_plan;
  const double original_elapsed = state.original_plan_elapsed_s();
  const double original_left = state.plan(model).TimeRemaining(state.time_s - state.guidance.plan_start_s);
  planning::FlightPlan capped;
  if (!ReplanCapped(model, state, capped)) return;
  AddEvent(log, state.time_s,
           fmt::format("speed capped at {:.1f} m/s airspeed (four rotors, §4.4.2): {:.0f} s left",
                       state.guidance.speed_cap_mps, capped.duration()));
  if (original) {
    state.guidance.replanned_nominal = std::move(capped);
    state.guidance.nominal_replanned = true;
    state.guidance.original_time_offset_s = original_elapsed;
    state.guidance.original_time_scale = state.guidance.replanned_nominal.duration() > 0.0
                                             ? original_left / state.guidance.replanned_nominal.duration()
                                             : 1.0;
  } else {
    state.guidance.emergency_plan = std::move(capped);
  }
  StartPlan(state);
}

// The constant current of the 1 Hz EOD (SimOptions::eod_load), from what the CMA reads (sim/sensing.h under noisy
// sensing).
double EodCurrent(const FlightModel& model, FlightState& state) {
  const bool noisy = model.options().noisy_sensing;
  const double load_a = noisy ? state.power.sensing.load_current_a : state.power.load_current_a;
  if (model.options().eod_load == EodLoad::kPresent) return load_a;
  EnsureLoadProfile(model, state);
  const double forecast = ForecastCurrent(
      state.decision.load_forecast, state.time_s - state.guidance.plan_start_s,
      noisy ? state.power.sensing.energy_wh : state.power.energy_wh, 1.0 / model.options().decision_rate_hz,
      noisy ? state.power.sensing.bus_voltage_v : state.power.bus_voltage_v, model.options().hotel_current_a);
  return forecast > 0.0 ? forecast : load_a;  // under a second of plan left: the present load
}

// The prognosis (§3.4.1, §5.3.2.1: "When a spalling fault in the motor is detected, t_RUL is calculated using Paris'
// Law"): the calibrated model's particle mean from the initial spall, computed once (its stream serves nothing else,
// so the value does not depend on when).
double PrognosisRul(const FlightModel& model, FlightState& state) {
  if (!state.decision.rul_at_onset_s) {
    const prognostics::MotorRulModel& rul = model.rul_model();
    state.decision.rul_at_onset_s =
        rul.PredictRulFromArea(rul.params().initial_area_mm2, state.vehicle.prognosis_random).mean_s;
  }
  return *state.decision.rul_at_onset_s;
}

// The vehicle-level prognosis (prognostics/rul_calibration.h): the fitted model's particle RULs from the initial spall,
// sorted, drawn once from their own stream (so `cma`'s prognosis and every other draw stay as they were).
const std::vector<double>& VehiclePrognosis(const FlightModel& model, FlightState& state) {
  std::vector<double>& particles = state.decision.vehicle_rul_at_onset_s;
  if (particles.empty()) {
    const prognostics::MotorRulModel& rul = model.vehicle_rul_model();
    RandomStream random(DeriveSeed(state.vehicle.seed, internal::kVehiclePrognosisStream));
    particles = rul.PredictRulFromArea(rul.params().initial_area_mm2, random).rul_s;
    std::sort(particles.begin(), particles.end());
  }
  return particles;
}

// The vehicle-level RUL `since_s` after the detection: the mean of the particles that have not jammed by then
// (prognostics::SurvivingRulMean; one epoch when none is left, docs/modelling-choices.md#vehicle-rul).
double VehicleRul(const FlightModel& model, FlightState& state, double since_s) {
  return prognostics::SurvivingRulMean(VehiclePrognosis(model, state), since_s, 1.0 / model.options().decision_rate_hz);
}

// §5.4's fault model: a spall in a flight with probability 0.5 (P(SF|NF) per simulated flight), its onset uniform over
// the nominal flight: the spall filter's prior.
constexpr double kSpallFaultProbability = 0.5;

// Noisy sensing: the spall indicator's reading, the point CMA's latched detection, the Bayes filter and b(NF, SF, JF).
void ObserveSpallIndicator(const FlightModel& model, FlightState& state, bool isolated, DecisionInputs& inputs,
                           FlightLog* log) {
  const SensingParams& params = model.options().sensing;
  DecisionState& decision = state.decision;
  const double t = state.time_s;
  const bool reading = ReadSpallIndicator(params, state.faults.spall.has_value(), decision.indicator_random);
  if (reading && !decision.spall_detected_s) {
    decision.spall_detected_s = t;
    AddEvent(log, t,
             state.faults.spall ? "spall indicator: spall (the point CMA's SF from now)"
                                : "spall indicator: spall, a false positive (the point CMA's SF from now)");
  }
  const double hazard = SpallOnsetHazard(kSpallFaultProbability, model.nominal_plan().duration(), t,
                                         1.0 / model.options().decision_rate_hz);
  decision.spall_probability = UpdateSpallProbability(PredictSpallProbability(decision.spall_probability, hazard),
                                                      reading, params.spall_false_positive, params.spall_miss);
  const double p_jammed =
      isolated ? 1.0 : (model.options().fault_detection ? 1.0 - state.faults.imm.ModeProbability(0) : 0.0);
  inputs.motor_health_belief = MotorHealthBelief(decision.spall_probability, p_jammed);
  const double since_s = decision.spall_detected_s ? t - *decision.spall_detected_s : 0.0;
  inputs.rul_if_spall_s = std::max(PrognosisRul(model, state) - since_s, 0.0);
  inputs.vehicle_rul_if_spall_s = VehicleRul(model, state, since_s);
}

// MH and the RUL: JF once a rotor is isolated; SF from the spall's onset (the truth), or under noisy sensing from the
// indicator's first "spall" (latched), the RUL counted down from then.
decision::MotorHealth ObserveMotorHealth(const FlightModel& model, FlightState& state, DecisionInputs& inputs,
                                         FlightLog* log) {
  const bool noisy = model.options().noisy_sensing;
  const bool isolated = state.faults.allocation_failure != 0 || state.faults.imm.isolated_rotor() != 0;
  if (noisy) ObserveSpallIndicator(model, state, isolated, inputs, log);
  if (isolated) {
    inputs.rul_s = inputs.vehicle_rul_s = 0.0;
    return decision::MotorHealth::kJF;
  }
  const std::optional<double> detected_s =
      noisy ? state.decision.spall_detected_s : (state.faults.spall ? state.faults.spall_onset_s : std::nullopt);
  if (!detected_s) {
    inputs.vehicle_rul_s = std::numeric_limits<double>::infinity();
    return decision::MotorHealth::kNF;
  }
  inputs.rul_s = std::max(PrognosisRul(model, state) - (state.time_s - *detected_s), 0.0);
  inputs.vehicle_rul_s = VehicleRul(model, state, state.time_s - *detected_s);
  return decision::MotorHealth::kSF;
}

// The EOD's distribution: prognostics::CalcPackEodDistribution at the forecast current with the load
// forecast's measured error of this epoch's cell (sim/eod_error_model.h): its 5/50/95 % quantiles and
// P(EOD < t_remaining + t_sf). Without uncertainty, a point at the EOD. Under noisy sensing (sim/sensing.h) the
// distribution is the sensed pack's (`pack`) and the SOC estimate's 1σ joins the error model's.
void ObserveEodDistribution(const FlightModel& model, FlightState& state, DecisionInputs& inputs,
                            const models::PackState& pack) {
  const double eod_s = inputs.eod_value().eod_s;
  prognostics::EodUncertainty uncertainty =
      model.eod_error_model().At({model.battery_health(), inputs.state.mh, model.scenario().wind.turbulence,
                                  inputs.flight_time_remaining_s, eod_s});
  const bool noisy = model.options().noisy_sensing;
  if (noisy) {
    uncertainty.soc_sigma = std::min(std::hypot(uncertainty.soc_sigma, CalcSocEstimateSigma(model, state)),
                                     prognostics::EodUncertainty::kSocSigmaBounds.high);
  }
  state.decision.eod_uncertainty = uncertainty;
  const double needed_s = NeededS(model, inputs);
  const bool point =
      uncertainty.load_log_sigma <= 0.0 && uncertainty.load_log_mean == 0.0 && (!noisy || uncertainty.soc_sigma <= 0.0);
  if (point || !(state.decision.eod_current_a > 0.0)) {
    state.decision.eod_distribution = {};
    state.decision.eod_distribution.point = state.decision.eod;
    inputs.eod_distribution = EodDistributionSummary{eod_s, eod_s, eod_s, eod_s < needed_s ? 1.0 : 0.0};
    return;
  }
  const prognostics::EodDistribution& distribution = state.decision.eod_distribution =
      prognostics::CalcPackEodDistribution(model.pack(), pack, state.decision.eod_current_a, uncertainty,
                                           EpochEodOptions(model, state, pack, state.decision.eod_current_a));
  inputs.eod_distribution =
      EodDistributionSummary{distribution.Quantile(0.05), distribution.Quantile(0.50), distribution.Quantile(0.95),
                             distribution.ProbabilityBefore(needed_s)};
}

}  // namespace

const DecisionInputs& Observe(const FlightModel& model, FlightState& state, FlightLog* log, bool eod_distribution,
                              EodPrecision precision) {
  // Guidance first: a vehicle flying on four rotors keeps to what they can hold (§4.4.2).
  CapSpeedAfterIsolation(model, state, log);
  // EOD at the expected load of the rest of the executing plan (docs/modelling-choices.md#eod-load-forecast) or at the
  // present current, the pack current low-passed with SimOptions::load_current_time_constant_s
  // (docs/modelling-choices.md#pack-eod).
  const double t = state.time_s;
  const bool noisy = model.options().noisy_sensing;
  const bool class_only = precision == EodPrecision::kReachMarginClass;
  UASCMA_CHECK(!class_only || (!noisy && !eod_distribution), "the EOD's class alone needs exact sensing");
  state.decision.eod_current_a = EodCurrent(model, state);
  DecisionInputs& inputs = state.decision.inputs;
  inputs.time_s = t;
  inputs.flight_time_remaining_s = state.plan(model).TimeRemaining(t - state.guidance.plan_start_s);
  // The pack-fault indicator first: a flagged pack is not counted on (PrognosisPack).
  UpdatePackMonitor(model, state);
  const models::PackState observed = ObservedPack(model, state);
  const double current_a = state.decision.eod_current_a;
  const prognostics::EodOptions eod_options = EpochEodOptions(model, state, observed, current_a);
  StoreEod(model, state,
           class_only
               ? prognostics::CalcPackEodBefore(model.pack(), observed, current_a, NeededS(model, inputs), eod_options)
               : prognostics::CalcPackEod(model.pack(), observed, current_a, eod_options));
  const decision::MotorHealth motor_health = ObserveMotorHealth(model, state, inputs, log);
  if (!noisy) {  // the beliefs of exact sensing: the point MH
    inputs.motor_health_belief = {0.0, 0.0, 0.0};
    inputs.motor_health_belief[static_cast<std::size_t>(motor_health)] = 1.0;
    if (motor_health == decision::MotorHealth::kSF) {
      inputs.rul_if_spall_s = inputs.rul_s;
      inputs.vehicle_rul_if_spall_s = inputs.vehicle_rul_s;
    }
  }
  inputs.motor_margin = prognostics::CalcMotorMargin(inputs.flight_time_remaining_s, inputs.rul_s);
  const bool isolated = motor_health == decision::MotorHealth::kJF;
  inputs.vehicle_motor_margin =
      ObserveVehicleMotorMargin(model, state, inputs, inputs.vehicle_rul_s, isolated, observed);
  inputs.vehicle_motor_margin_if_spall =
      motor_health == decision::MotorHealth::kSF ? inputs.vehicle_motor_margin
      : noisy && state.decision.vehicle_beliefs && !isolated
          ? ObserveVehicleMotorMargin(model, state, inputs, inputs.vehicle_rul_if_spall_s, false, observed)
          : 1.0;
  inputs.state =
      decision::AbstractCmaState(state.decision.flight_status, motor_health, ObservedBatteryHealth(model, state),
                                 ReachMarginAtLeast(inputs.eod), inputs.motor_margin);
  if (eod_distribution) {
    ObserveEodDistribution(model, state, inputs, observed);
  } else {
    state.decision.eod_uncertainty = {};
    state.decision.eod_distribution = {};
    inputs.eod_distribution.reset();
  }
  if (log) log->states.emplace_back(t, decision::CmaStateIndex(inputs.state));
  return inputs;
}

const DecisionInputs& BeginEpoch(const FlightModel& model, FlightState& state, BatterySwitchPolicy* battery,
                                 FlightLog* log, bool eod_distribution, EodPrecision precision) {
  const DecisionInputs& inputs = Observe(model, state, log, eod_distribution, precision);
  if (battery) DecideBattery(model, state, *battery, log);
  return inputs;
}

void RecordEodAtAction(const FlightModel& model, FlightState& state, CmaAction action) {
  if (action == CmaAction::kNoOp) return;
  CompleteEod(model, state);  // the planners and this record read the EOD's value
  if (state.decision.eod_at_first_action) return;
  DecisionInputs& inputs = state.decision.inputs;
  if (!inputs.eod_distribution) {  // the pack the epoch's EOD was computed from (Observe)
    ObserveEodDistribution(model, state, inputs, ObservedPack(model, state));
  }
  state.decision.eod_at_first_action =
      EodAtAction{inputs.time_s, inputs.eod_value().eod_s, inputs.eod_distribution_value()};
}

void StepEpoch(const FlightModel& model, FlightState& state, const Controllers& controllers, FlightLog* log) {
  if (state.done()) return;
  DecideEpoch(model, state, controllers, log);
  StepToNextEpoch(model, state, log);
}

void DecideEpoch(const FlightModel& model, FlightState& state, const Controllers& controllers, FlightLog* log) {
  UASCMA_CHECK(IsDecisionEpoch(model, state), "a decision epoch's decision starts at a decision epoch");
  const bool eod_distribution = NeedsEodDistribution(controllers.policy, log);
  state.decision.vehicle_beliefs = controllers.policy != nullptr && controllers.policy->ReadsVehicleBeliefs();
  DecisionPolicy* const policy[] = {controllers.policy};
  const DecisionInputs& inputs =
      BeginEpoch(model, state, controllers.battery, log, eod_distribution,
                 EpochEodPrecision(model, policy, controllers.battery, log, eod_distribution));
  const CmaAction action = controllers.policy ? controllers.policy->Decide(inputs) : CmaAction::kNoOp;
  RecordEodAtAction(model, state, action);
  // A NoOp never reads the ranking (Act returns before any substitution), so it is asked for only when acting: the
  // default ranking's one-time solve (DefaultCmaActionRanking) then waits for a flight that needs it.
  const bool ranked = controllers.policy != nullptr && action != CmaAction::kNoOp;
  Act(model, state, action, controllers.planner, log, ranked ? controllers.policy->Ranking(inputs) : ActionRanking{});
}

}  // namespace uascma::sim
