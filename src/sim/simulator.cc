#include "uascma/sim/simulator.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "uascma/common/error.h"

namespace uascma::sim {

SimResult MakeSimResult(const FlightModel& model, const FlightState& state, FlightLog log, const std::string& policy) {
  SimResult result;
  result.outcome = state.outcome;
  result.reason = state.reason;
  result.sim_time_s = state.time_s;
  result.seed = state.seed;
  result.policy = policy;
  result.plan_duration_s = model.nominal_plan().duration();
  result.spall_onset_s = state.spall_onset_s;
  result.jam_time_s = state.jam_time_s;
  result.isolation_time_s = state.isolation_time_s;
  result.isolated_rotor = state.imm.isolated_rotor();
  result.min_cell_voltage_v = state.min_cell_voltage_v;
  result.max_tracking_error = state.max_tracking_error;
  result.max_tilt = std::acos(std::clamp(state.min_cos_tilt, -1.0, 1.0));
  result.energy_wh = state.energy_wh;
  result.eod_load = EodLoadName(model.options().eod_load);
  result.substitution_epochs = state.substitution_epochs;
  result.substitutions = state.substitutions;
  result.speed_cap_mps = state.speed_cap_mps;
  log.events.push_back({state.time_s, fmt::format("{}: {}", OutcomeName(state.outcome), state.reason)});
  result.events = std::move(log.events);
  result.actions = std::move(log.actions);
  result.states = std::move(log.states);
  result.battery_switches = std::move(log.battery_switches);
  result.telemetry = std::move(log.telemetry);
  if (state.on_emergency_plan) {
    for (double s = 0; s <= state.emergency_plan.duration(); s += 1.0) {
      result.executed_plan_ref.push_back(state.emergency_plan.At(s).p_W);
    }
    result.emergency_plan = state.emergency_plan;
  }
  result.footprint_NE = state.footprint_NE;
  result.emergency_site = state.emergency_site;
  result.emergency_reach_margin = state.emergency_reach_margin;
  return result;
}

SimResult Simulator::Run(DecisionPolicy& policy, const EmergencyPlanner& planner, const RunOptions& options) const {
  const auto wall_start = std::chrono::steady_clock::now();
  FlightState state = MakeInitialState(model_, model_.scenario().seed);
  FlightLog log;
  log.record_telemetry = options.record_telemetry;
  const Controllers controllers{&policy, options.battery_policy, planner};
  while (!state.done()) StepEpoch(model_, state, controllers, &log);
  SimResult result = MakeSimResult(model_, state, std::move(log), policy.name());
  result.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return result;
}

namespace {

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

std::vector<SimResult> Simulator::RunTogether(std::span<DecisionPolicy* const> policies,
                                              std::span<const EmergencyPlanner> planners,
                                              const RunOptions& options) const {
  UASCMA_CHECK(planners.size() == policies.size(), "one planner (possibly empty) per policy");
  const std::size_t n = policies.size();
  std::vector<SimResult> results(n);
  std::vector<double> wall_s(n, 0.0);
  auto finish = [&](std::size_t k, const FlightState& state, FlightLog log) {
    results[k] = MakeSimResult(model_, state, std::move(log), policies[k]->name());
    results[k].wall_time_s = wall_s[k];
  };
  // A flight of one policy from a decision epoch, before its Observe, to its end: as Run flies it.
  auto fly_on = [&](std::size_t k, FlightState state, FlightLog log) {
    const auto start = std::chrono::steady_clock::now();
    const Controllers controllers{policies[k], options.battery_policy, planners[k]};
    while (!state.done()) StepEpoch(model_, state, controllers, &log);
    wall_s[k] += SecondsSince(start);
    finish(k, state, std::move(log));
  };

  FlightState state = MakeInitialState(model_, model_.scenario().seed);
  FlightLog log;
  log.record_telemetry = options.record_telemetry;
  std::vector<std::size_t> together(n);
  for (std::size_t k = 0; k < n; ++k) together[k] = k;
  std::vector<decision::CmaAction> decided;
  while (!state.done() && together.size() > 1) {
    // One epoch of the shared flight: StepEpoch with each policy deciding on the same observation.
    const auto start = std::chrono::steady_clock::now();
    const std::size_t sharing = together.size();
    const DecisionInputs& inputs = Observe(model_, state, &log);
    if (options.battery_policy) DecideBattery(model_, state, *options.battery_policy, &log);
    decided.clear();
    for (std::size_t k : together) decided.push_back(policies[k]->Decide(inputs));
    std::vector<std::size_t> still;
    for (std::size_t i = 0; i < together.size(); ++i) {
      if (decided[i] == decision::CmaAction::kNoOp) still.push_back(together[i]);
    }
    const double shared_s = SecondsSince(start);
    for (std::size_t i = 0; i < together.size(); ++i) {
      wall_s[together[i]] += shared_s / static_cast<double>(sharing);
      if (decided[i] == decision::CmaAction::kNoOp) continue;
      const std::size_t k = together[i];
      FlightState own = state;  // the branch: both copies have the same future bit for bit
      FlightLog own_log = log;
      const auto act_start = std::chrono::steady_clock::now();
      Act(model_, own, decided[i], planners[k], &own_log, policies[k]->Ranking(own.inputs));
      StepToNextEpoch(model_, own, &own_log);
      wall_s[k] += SecondsSince(act_start);
      fly_on(k, std::move(own), std::move(own_log));
    }
    together = std::move(still);
    if (together.empty()) return results;
    const auto step_start = std::chrono::steady_clock::now();
    Act(model_, state, decision::CmaAction::kNoOp, planners[together.front()], &log);  // NoOp asks no planner
    StepToNextEpoch(model_, state, &log);
    const double step_s = SecondsSince(step_start);
    for (std::size_t k : together) wall_s[k] += step_s / static_cast<double>(together.size());
  }
  if (together.size() == 1) {
    fly_on(together.front(), std::move(state), std::move(log));
    return results;
  }
  // The flight ended while shared: every policy still in it has the same result.
  for (std::size_t i = 0; i < together.size(); ++i) {
    finish(together[i], state, i + 1 == together.size() ? std::move(log) : log);
  }
  return results;
}

}  // namespace uascma::sim
