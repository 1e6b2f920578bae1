#include "uascma/sim/simulator.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "flight_internal.h"
#include "uascma/common/error.h"
#include "uascma/sim/branching.h"
#include "uascma/sim/emergency_planner.h"
#include "uascma/sim/epoch.h"
#include "uascma/sim/initial_state.h"

namespace uascma::sim {
namespace {

// s: how long the true pack, as the flight left it, could still hover the vehicle (its EOD at the steady hover current
// of the rotors that fly: six, or four after an isolation, docs/modelling-choices.md#mixing-after-motor-failure, in the
// mean wind, plus the hotel load: I = P_hover / V_bus(I) + I_hotel). What the report's unnecessary landings compare
// with t_sf (campaign/statistics.h). 0 when the bus cannot carry the hover (no pack on, or past its power).
double EndReserveS(const FlightModel& model, const FlightState& state) {
  const double power_w = CalcSteadyRotorPower(model.steady_load(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                              internal::ActiveRotors(state));
  const double current_a =
      model.pack().CalcCurrentAtPower(state.power.pack, power_w, 0.0, model.options().hotel_current_a);
  return std::isfinite(current_a) ? prognostics::CalcPackEod(model.pack(), state.power.pack, current_a).eod_s : 0.0;
}

}  // namespace

SimResult MakeSimResult(const FlightModel& model, const FlightState& state, FlightLog log, const std::string& policy) {
  SimResult result;
  result.outcome = state.outcome;
  result.reason = state.reason;
  result.sim_time_s = state.time_s;
  result.seed = state.vehicle.seed;
  result.policy = policy;
  result.plan_duration_s = model.nominal_plan().duration();
  result.spall_onset_s = state.faults.spall_onset_s;
  result.jam_time_s = state.faults.jam_time_s;
  result.isolation_time_s = state.faults.isolation_time_s;
  result.isolated_rotor = state.faults.imm.isolated_rotor();
  result.min_cell_voltage_v = state.power.min_cell_voltage_v;
  result.max_tracking_error = state.vehicle.max_tracking_error;
  result.max_tilt = std::acos(std::clamp(state.vehicle.min_cos_tilt, -1.0, 1.0));
  result.energy_wh = state.power.energy_wh;
  result.end_reserve_s = EndReserveS(model, state);
  result.eod_at_first_action = state.decision.eod_at_first_action;
  result.eod_load = EodLoadName(model.options().eod_load);
  result.substitution_epochs = state.decision.substitution_epochs;
  result.substitutions = state.decision.substitutions;
  result.speed_cap_mps = state.guidance.speed_cap_mps;
  log.events.push_back({state.time_s, fmt::format("{}: {}", OutcomeName(state.outcome), state.reason)});
  result.events = std::move(log.events);
  result.actions = std::move(log.actions);
  result.states = std::move(log.states);
  result.battery_switches = std::move(log.battery_switches);
  result.telemetry = std::move(log.telemetry);
  if (state.guidance.on_emergency_plan) {
    for (double s = 0; s <= state.guidance.emergency_plan.duration(); s += 1.0) {
      result.executed_plan_ref.push_back(state.guidance.emergency_plan.At(s).p_W);
    }
    result.emergency_plan = state.guidance.emergency_plan;
  }
  result.footprint_NE = state.guidance.footprint_NE;
  result.emergency_site = state.guidance.emergency_site;
  result.emergency_reach_margin = state.guidance.emergency_reach_margin;
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
  result.wall_time_s = internal::SecondsSince(wall_start);
  return result;
}

std::vector<SimResult> Simulator::RunTogether(std::span<DecisionPolicy* const> policies,
                                              std::span<const EmergencyPlanner> planners,
                                              const RunOptions& options) const {
  return sim::RunTogether(model_, policies, planners, options);
}

}  // namespace uascma::sim
