// The actions of a decision epoch (act.h): the battery executor's pack switches, and the CMA's executor (Act): an
// emergency plan, Terminate, or a substitute
// (docs/modelling-choices.md#unavailable-actions), with two run-time
// checks (docs/cma-safeguards.md):
// - an emergency plan is carried out only with a reach margin ≥ 0, the margin the CMA state will read once the plan
//   executes: the EOD at that plan's own expected load, RM by prognostics/reach_margin.h with t_sf
//   (docs/modelling-choices.md#one-reach-margin). A plan short of it is no plan: the next-best action is taken;
// - Terminate is carried out only as a last resort (sim/termination.h,
// docs/modelling-choices.md#terminate-last-resort).
#include "uascma/sim/act.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "flight_internal.h"
#include "pack_monitor.h"
#include "uascma/common/error.h"
#include "uascma/common/frames.h"
#include "uascma/decision/cma_abstraction.h"
#include "uascma/prognostics/eod.h"
#include "uascma/prognostics/reach_margin.h"
#include "uascma/sim/emergency_planner.h"
#include "uascma/sim/eod_precision.h"
#include "uascma/sim/flight.h"
#include "uascma/sim/termination.h"

namespace uascma::sim {

namespace {

using decision::CmaAction;
using internal::AddAction;
using internal::AddEvent;
using internal::StartPlan;

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

// s: the EOD of the executing plan as Observe computes it at the next epoch: the pack the CMA reads (the sensed one
// under noisy sensing), propagated at the plan's expected load (docs/modelling-choices.md#eod-load-forecast: its
// profile from plan time 0 for the rotors that fly it, the flight's bias ratio), or at the present load
// (SimOptions::eod_load present), with the epoch's cut-off under current peaks (internal::EpochEodOptions). Called
// once an emergency plan has just started (StartPlan).
double StartedPlanEodS(const FlightModel& model, const FlightState& state) {
  const bool noisy = model.options().noisy_sensing;
  double current_a = noisy ? state.power.sensing.load_current_a : state.power.load_current_a;
  if (model.options().eod_load == EodLoad::kForecast) {
    LoadForecastState forecast = state.decision.load_forecast;
    forecast.profile =
        std::make_shared<const LoadProfile>(state.plan(model), model.steady_load(), internal::ActiveRotors(state));
    forecast.have_last = false;
    const double forecast_a = ForecastCurrent(
        forecast, 0.0, noisy ? state.power.sensing.energy_wh : state.power.energy_wh,
        1.0 / model.options().decision_rate_hz, noisy ? state.power.sensing.bus_voltage_v : state.power.bus_voltage_v,
        model.options().hotel_current_a);
    if (forecast_a > 0.0) current_a = forecast_a;  // under a second of plan: the present load, as Observe
  }
  const models::PackState pack = internal::ObservedPack(model, state);
  return prognostics::CalcPackEod(model.pack(), pack, current_a,
                                  internal::EpochEodOptions(model, state, pack, current_a))
      .eod_s;
}

// Asks the planner for an emergency plan for `action` and switches to it when there is one whose reach margin with
// `safety_margin_s` (s) is ≥ 0; otherwise leaves the flight as it was and says why not (`why`). The margin is the
// one the CMA state reads once the plan executes: the plan as flown (after braking, re-planned at the capped speed on
// four rotors) against its own EOD (StartedPlanEodS). On the executing plan's final descent no emergency plan is
// sought: the vehicle is already landing at the end of its plan, sooner than any emergency plan could (measured: a
// LandPract taken 1.4 s before a touchdown climbed away and failed the battery 5 ms later, in a flight whose NoOp
// twin completed).
bool TryEmergencyPlan(const FlightModel& model, FlightState& state, CmaAction action, const EmergencyPlanner& planner,
                      FlightLog* log, double safety_margin_s, std::string* why) {
  const double t = state.time_s;
  const EmergencyPlanner& emergency_planner = planner ? planner : model.map_planner();
  if (!emergency_planner) {
    *why = "the map has no landing sites";
    return false;
  }
  const double t_plan = t - state.guidance.plan_start_s;
  if (OnFinalDescent(state.plan(model), t_plan)) {
    *why = fmt::format("on the final descent of the executing plan, {:.1f} s from its touchdown",
                       state.plan(model).TimeRemaining(t_plan));
    return false;
  }
  // The planners plan from where a moving vehicle comes to rest (StartFromHere).
  const internal::PlanStart start = internal::StartFromHere(model, state);
  const Eigen::Vector3d plan_velocity_W =
      start.brake ? Eigen::Vector3d(0.0, 0.0, state.vehicle.body.v_WB_W.z()) : state.vehicle.body.v_WB_W;
  const double original_elapsed =
      state.guidance.on_emergency_plan ? model.nominal_plan().duration() : state.original_plan_elapsed_s();
  EmergencyPlan emergency = emergency_planner(
      {action, t, start.from_W(), plan_velocity_W, EulerFromRotation(state.vehicle.body.q_WB.toRotationMatrix()).z(),
       state.faults.allocation_failure, state.decision.eod.eod_s, original_elapsed});
  if (!emergency.ok()) {
    *why = emergency.message.empty() ? planning::LandingStatusName(emergency.status) : emergency.message;
    return false;
  }
  // The plan as it would fly, then its margin; kept only when the margin holds.
  const GuidanceState guidance_before = state.guidance;
  const LoadForecastState forecast_before = state.decision.load_forecast;
  state.guidance.emergency_plan = start.Then(std::move(emergency.plan));
  state.guidance.on_emergency_plan = true;
  StartPlan(state);
  planning::FlightPlan capped;  // on four rotors the emergency plan too keeps to what they can hold (§4.4.2)
  if (std::isfinite(state.guidance.speed_cap_mps) && internal::ReplanCapped(model, state, capped)) {
    state.guidance.emergency_plan = std::move(capped);
    StartPlan(state);
  }
  const double flight_s = state.guidance.emergency_plan.duration();
  const double eod_s = StartedPlanEodS(model, state);
  const double reach_margin = prognostics::CalcReachMargin(eod_s, flight_s, model.options().safety_margin_s);
  if (prognostics::CalcReachMargin(eod_s, flight_s, safety_margin_s) < 0.0) {
    state.guidance = guidance_before;
    state.decision.load_forecast = forecast_before;
    *why = fmt::format("its plan to {} takes {:.0f} s{}, the EOD at its load {:.0f} s (RM {:.2f})", emergency.site,
                       flight_s, safety_margin_s > 0.0 ? fmt::format(" + t_sf {:.0f} s", safety_margin_s) : "", eod_s,
                       reach_margin);
    return false;
  }
  state.guidance.emergency_site = emergency.site;
  state.guidance.emergency_reach_margin = reach_margin;
  state.guidance.emergency_site_radius = emergency.site_radius;
  if (!emergency.footprint_NE.empty()) state.guidance.footprint_NE = std::move(emergency.footprint_NE);
  state.decision.flight_status = decision::FlightStatusAfter(action, state.decision.flight_status);
  AddAction(state, log, action);
  AddEvent(log, t,
           fmt::format("{}: emergency plan to {} ({:.0f} s, EOD {:.0f} s, RM {:.2f})", decision::CmaActionName(action),
                       emergency.site, flight_s, eod_s, reach_margin));
  return true;
}

// docs/modelling-choices.md#unavailable-actions: `taken` replaces `chosen`, which could not be carried out (`why`).
void RecordSubstitution(FlightState& state, FlightLog* log, CmaAction chosen, CmaAction taken, const std::string& why) {
  ++state.decision.substitution_epochs;
  const std::string pair = fmt::format("{}->{}", decision::CmaActionName(chosen), decision::CmaActionName(taken));
  if (std::find(state.decision.substitutions.begin(), state.decision.substitutions.end(), pair) ==
      state.decision.substitutions.end()) {
    state.decision.substitutions.push_back(pair);
  }
  AddEvent(log, state.time_s,
           fmt::format("{} cannot be carried out ({}): {} instead (the next-highest Q)",
                       decision::CmaActionName(chosen), why, decision::CmaActionName(taken)));
}

// Whether the executing plan brings the vehicle down before the EOD: it is on its final descent, or its rest fits in
// the epoch's EOD (at that plan's load; Observe, CompleteEod) without the safety margin.
bool ExecutingPlanReaches(const FlightModel& model, const FlightState& state, std::string* why) {
  const DecisionInputs& inputs = state.decision.inputs;
  if (OnFinalDescent(state.plan(model), state.time_s - state.guidance.plan_start_s)) return true;
  const double eod_s = inputs.eod_value().eod_s;
  if (inputs.flight_time_remaining_s <= eod_s) return true;
  *why += fmt::format("; the executing plan: {:.0f} s left, EOD {:.0f} s", inputs.flight_time_remaining_s, eod_s);
  return false;
}

// The first action of `ranking` but Terminate, available in the flight status, that brings the vehicle to the ground
// before the pack's EOD (sim/termination.h), switched to when it needs a plan; none when no action does (`why` then
// says what each found).
std::optional<CmaAction> ActionThatReaches(const FlightModel& model, FlightState& state,
                                           const EmergencyPlanner& planner, FlightLog* log, ActionRanking ranking,
                                           std::string* why) {
  for (const decision::ActionIndex index : ranking) {
    const auto next = static_cast<CmaAction>(index);
    if (next == CmaAction::kTerminate || !decision::IsCmaActionAvailable(state.decision.flight_status, next)) continue;
    if (decision::EffectiveCmaAction(next, state.decision.flight_status) == CmaAction::kNoOp) {
      if (ExecutingPlanReaches(model, state, why)) return next;
      continue;
    }
    std::string next_why;
    if (TryEmergencyPlan(model, state, next, planner, log, 0.0, &next_why)) return next;
    *why += fmt::format("; {}: {}", decision::CmaActionName(next), next_why);
  }
  return std::nullopt;
}

// Ends the flight with Terminate (docs/modelling-choices.md#terminate), chosen by the policy or reached as `chosen`'s
// next-best.
CmaAction TerminateFlight(FlightState& state, FlightLog* log, CmaAction chosen, const std::string& why) {
  AddAction(state, log, CmaAction::kTerminate);
  state.outcome = Outcome::kTerminated;
  const std::string label = decision::CmaStateLabel(state.decision.inputs.state);
  state.reason = chosen == CmaAction::kTerminate ? fmt::format("Terminate in state {}", label)
                                                 : fmt::format("Terminate in state {} ({} could not be carried out)",
                                                               label, decision::CmaActionName(chosen));
  if (!why.empty()) state.reason += fmt::format(": no other action reaches the ground ({})", why);
  return CmaAction::kTerminate;
}

// Terminate, chosen by the policy (`chosen` Terminate) or as the next-best of `chosen` (which could not be carried
// out: `why`), under SimOptions::termination (sim/termination.h).
CmaAction TerminateUnlessReachable(const FlightModel& model, FlightState& state, CmaAction chosen,
                                   const EmergencyPlanner& planner, FlightLog* log, ActionRanking ranking,
                                   const std::string& why) {
  const TerminationRule rule = model.options().termination;
  if (rule == TerminationRule::kPolicy) {
    if (chosen != CmaAction::kTerminate) RecordSubstitution(state, log, chosen, CmaAction::kTerminate, why);
    return TerminateFlight(state, log, chosen, "");
  }
  std::string reaches_why;
  const std::optional<CmaAction> reaches = ActionThatReaches(model, state, planner, log, ranking, &reaches_why);
  const std::string head = chosen == CmaAction::kTerminate ? "" : why + "; ";
  if (reaches) {
    // When the chosen action's own plan was short of t_sf only, it flies: what was replaced is the Terminate next.
    const CmaAction replaced = *reaches == chosen ? CmaAction::kTerminate : chosen;
    RecordSubstitution(state, log, replaced, *reaches,
                       head + fmt::format("Terminate is the last resort and {} reaches the ground before the EOD",
                                          decision::CmaActionName(*reaches)));
    return *reaches;
  }
  const std::string nothing = reaches_why.empty() ? "" : reaches_why.substr(2);  // without the leading "; "
  if (rule == TerminationRule::kNever) {
    RecordSubstitution(state, log, chosen, CmaAction::kNoOp, head + "termination is disarmed; " + nothing);
    return CmaAction::kNoOp;
  }
  if (chosen != CmaAction::kTerminate) RecordSubstitution(state, log, chosen, CmaAction::kTerminate, why);
  return TerminateFlight(state, log, chosen, nothing);
}

}  // namespace

CmaAction Act(const FlightModel& model, FlightState& state, CmaAction action, const EmergencyPlanner& planner,
              FlightLog* log, ActionRanking ranking) {
  if (action != CmaAction::kNoOp) CompleteEod(model, state);  // the planners and the checks read the EOD's value
  // §5.5.3: "an emergency landing at t = 0 translates into not taking off" — any emergency action chosen before
  // take-off keeps the vehicle on the ground (docs/modelling-choices.md#outcomes-refined).
  if (action != CmaAction::kNoOp && !state.vehicle.airborne) {
    AddAction(state, log, action);
    state.outcome = Outcome::kGrounded;
    state.reason = fmt::format("{} chosen before take-off in state {}: the vehicle stays on the ground",
                               decision::CmaActionName(action), decision::CmaStateLabel(state.decision.inputs.state));
    return action;
  }
  // The default ranking's one-time solve (DefaultCmaActionRanking) only when a ranking is read.
  const auto ranked = [&] { return ranking.empty() ? DefaultCmaActionRanking(state.decision.inputs.state) : ranking; };
  if (action == CmaAction::kTerminate) {
    return TerminateUnlessReachable(model, state, action, planner, log, ranked(), "");
  }
  // docs/modelling-choices.md#executing-action-repeat: an action equal to the executing one is a no-op.
  if (decision::EffectiveCmaAction(action, state.decision.flight_status) == CmaAction::kNoOp) return action;
  const double safety_margin_s = model.options().safety_margin_s;
  std::string why;
  if (TryEmergencyPlan(model, state, action, planner, log, safety_margin_s, &why)) return action;
  // docs/modelling-choices.md#unavailable-actions: the available action with the next-highest value that can be carried
  // out now.
  ranking = ranked();
  for (const decision::ActionIndex index : ranking) {
    const auto next = static_cast<CmaAction>(index);
    if (next == action || !decision::IsCmaActionAvailable(state.decision.flight_status, next)) continue;
    if (next == CmaAction::kTerminate)
      return TerminateUnlessReachable(model, state, action, planner, log, ranking, why);
    if (decision::EffectiveCmaAction(next, state.decision.flight_status) == CmaAction::kNoOp) {  // NoOp, or executing
      RecordSubstitution(state, log, action, next, why);
      return next;
    }
    std::string next_why;
    if (TryEmergencyPlan(model, state, next, planner, log, safety_margin_s, &next_why)) {
      RecordSubstitution(state, log, action, next, why);
      return next;
    }
    why += "; " + std::string(decision::CmaActionName(next)) + ": " + next_why;
  }
  // NoOp and Terminate are available in every flight status (docs/modelling-choices.md#action-availability) and always
  // carried out.
  UASCMA_CHECK(false, "a ranking that holds NoOp or Terminate");
  return CmaAction::kNoOp;
}

void SwitchPacks(FlightState& state, models::PackAction action) {
  state.power.pack.branch_on = models::SwitchesFor(action);
}

void DecideBattery(const FlightModel& model, FlightState& state, BatterySwitchPolicy& policy, FlightLog* log) {
  const models::PackAction action = policy.Decide(model, state);
  if (state.decision.battery_action != action) {
    state.decision.battery_action = action;
    if (log) {
      log->battery_switches.emplace_back(state.time_s, action);
      AddEvent(log, state.time_s, fmt::format("battery: {}", models::PackActionName(action)));
    }
  }
  SwitchPacks(state, action);
}

}  // namespace uascma::sim
