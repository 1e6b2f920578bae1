#include "uascma/sim/simulator.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

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

}  // namespace uascma::sim
