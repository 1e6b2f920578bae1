#include "uascma/campaign/metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>

#include <nlohmann/json.hpp>

#include "uascma/common/error.h"
#include "uascma/decision/cma_abstraction.h"
#include "uascma/sim/emergency_planner.h"

namespace uascma::campaign {
using decision::CmaAction;

decision::CmaAction RecordingPolicy::Decide(const sim::DecisionInputs& inputs) {
  const CmaAction action = inner_.Decide(inputs);
  decisions_.push_back({inputs.time_s, inner_.StateRead(inputs), action});
  return action;
}

RewardTrace CalcRewardTrace(const std::vector<EpochDecision>& decisions, sim::Outcome outcome,
                            const decision::CmaWeights& weights) {
  RewardTrace trace;
  trace.reward.reserve(decisions.size() + 1);
  for (const EpochDecision& d : decisions) trace.reward.push_back(decision::CmaEpochReward(weights, d.state, d.action));
  trace.reward.push_back(decision::CmaTerminalReward(weights, sim::TerminalStateOf(outcome)));
  trace.average =
      std::accumulate(trace.reward.begin(), trace.reward.end(), 0.0) / static_cast<double>(trace.reward.size());
  trace.minimum = *std::min_element(trace.reward.begin(), trace.reward.end());
  return trace;
}

RunRecord MakeRunRecord(const SampledRun& run, const std::string& policy, int slot, int num_policies,
                        const sim::SimResult& result, const std::vector<EpochDecision>& decisions) {
  const sim::Scenario& scenario = run.scenario;
  RunRecord r;
  r.flight_id = run.run_index * num_policies + slot;
  r.run_index = run.run_index;
  r.policy = policy;
  r.run_seed = run.run_seed;

  r.distance_m = run.distance_m;
  r.bearing_rad = run.bearing_rad;
  r.destination_north_m = scenario.mission.destination_NE.x();
  r.destination_east_m = scenario.mission.destination_NE.y();
  r.cruise_speed_mps = run.cruise_speed_mps;
  r.plan_duration_s = run.plan_duration_s;
  r.safety_margin_s = run.safety_margin_s;
  nlohmann::json voltages = nlohmann::json::array();
  r.initial_cell_voltage_min_v = std::numeric_limits<double>::infinity();
  for (const auto& pack : scenario.battery.initial_cell_voltage_v) {
    for (double v : pack) {
      voltages.push_back(v);
      r.initial_cell_voltage_min_v = std::min(r.initial_cell_voltage_min_v, v);
    }
  }
  r.initial_cell_voltage_v = voltages.dump();
  r.pack1_health = PackConditionName(run.pack_health[0]);
  r.pack2_health = PackConditionName(run.pack_health[1]);
  r.cell_health = CellHealthCode(scenario.battery.cell_health);
  r.battery_health = models::HealthClassName(static_cast<models::HealthClass>(static_cast<int>(run.battery_health)));
  r.ambient_temp_degf = scenario.battery.ambient_temp_degf;
  r.wind_speed_mps = scenario.wind.mean_speed;
  r.wind_direction_rad = scenario.wind.direction_rad;
  r.turbulence = models::TurbulenceCategoryName(scenario.wind.turbulence);
  r.fault = scenario.fault.enabled;
  r.fault_motor = scenario.fault.enabled ? scenario.fault.motor : 0;
  if (scenario.fault.enabled) r.fault_onset_s = scenario.fault.spall_onset_s;

  r.outcome = sim::OutcomeName(result.outcome);
  r.failure = sim::IsFailure(result.outcome);
  r.reason = result.reason;
  r.sim_time_s = result.sim_time_s;
  r.wall_time_s = result.wall_time_s;
  r.num_actions = static_cast<std::int64_t>(result.actions.size());
  nlohmann::json actions = nlohmann::json::array();
  for (const auto& [time, action] : result.actions) actions.push_back({time, decision::CmaActionName(action)});
  r.actions = actions.dump();
  for (const EpochDecision& d : decisions) {
    if (d.action != CmaAction::kNoOp) {
      r.first_emergency_action_s = d.time_s;
      r.first_emergency_action = decision::CmaActionName(d.action);
      r.first_action_state = decision::CmaStateLabel(d.state);
      break;
    }
  }
  r.substitution_epochs = result.substitution_epochs;
  r.substitutions = nlohmann::json(result.substitutions).dump();
  r.jam_time_s = result.jam_time_s;
  r.isolation_time_s = result.isolation_time_s;
  if (std::isfinite(result.speed_cap_mps)) r.speed_cap_mps = result.speed_cap_mps;
  r.min_cell_voltage_v = result.min_cell_voltage_v;
  r.energy_wh = result.energy_wh;
  r.end_reserve_s = result.end_reserve_s;
  if (result.eod_at_first_action) {
    const sim::EodDistributionSummary& d = result.eod_at_first_action->distribution;
    r.first_action_eod_p05_s = d.p05_s;
    r.first_action_eod_p50_s = d.p50_s;
    r.first_action_eod_p95_s = d.p95_s;
    r.first_action_eod_short_probability = d.short_probability;
  }
  r.max_tracking_error_m = result.max_tracking_error;
  r.max_tilt_rad = result.max_tilt;

  const RewardTrace trace = CalcRewardTrace(decisions, result.outcome);
  r.epochs = static_cast<std::int64_t>(trace.reward.size());
  r.average_reward = trace.average;
  r.min_reward = trace.minimum;
  return r;
}

RunRecord FlyRun(const sim::Simulator& simulator, const SampledRun& run, const CampaignPolicy& policy, int slot,
                 int num_policies, const PlannerFactory& planner_factory) {
  const std::array<const CampaignPolicy*, 1> one = {&policy};
  const std::array<int, 1> slots = {slot};
  return std::move(FlyRunTogether(simulator, run, one, slots, num_policies, planner_factory).front());
}

std::vector<RunRecord> FlyRunTogether(const sim::Simulator& simulator, const SampledRun& run,
                                      std::span<const CampaignPolicy* const> policies, std::span<const int> slots,
                                      int num_policies, const PlannerFactory& planner_factory) {
  sim::EpochSteps steps(false);
  RunInFlight flying(simulator, run, policies, slots, num_policies, planner_factory, steps);
  flying.coroutine().RunToEnd();
  return flying.Records();
}

RunInFlight::RunInFlight(const sim::Simulator& simulator, const SampledRun& run,
                         std::span<const CampaignPolicy* const> policies, std::span<const int> slots, int num_policies,
                         const PlannerFactory& planner_factory, sim::EpochSteps& steps)
    : run_(run), slots_(slots.begin(), slots.end()), num_policies_(num_policies) {
  UASCMA_CHECK(policies.size() == slots.size(), "one slot per policy");
  for (const CampaignPolicy* policy : policies) {
    names_.push_back(policy->name);
    decide_.push_back(MakeDecisionPolicy(*policy));
    recording_.push_back(std::make_unique<RecordingPolicy>(*decide_.back()));
    flying_.push_back(recording_.back().get());
    planners_.push_back(planner_factory ? planner_factory(simulator) : sim::EmergencyPlanner{});
  }
  sim::RunOptions options;
  options.record_telemetry = false;
  coroutine_ = sim::FlyTogether(simulator.model(), flying_, planners_, options, steps, results_);
}

std::vector<RunRecord> RunInFlight::Records() const {
  UASCMA_CHECK(coroutine_.done(), "a run's records once it has been flown");
  std::vector<RunRecord> records;
  for (std::size_t k = 0; k < names_.size(); ++k) {
    records.push_back(
        MakeRunRecord(run_, names_[k], slots_[k], num_policies_, results_[k], recording_[k]->decisions()));
  }
  return records;
}

}  // namespace uascma::campaign
