#include "uascma/sim/branching.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "flight_internal.h"
#include "uascma/common/error.h"
#include "uascma/sim/act.h"
#include "uascma/sim/emergency_planner.h"
#include "uascma/sim/epoch.h"
#include "uascma/sim/initial_state.h"

namespace uascma::sim {

using internal::SecondsSince;

// ---- policies flown together until they differ (§5.5) ------------------------------------------------------------
namespace {

// One epoch of the shared flight: StepEpoch's decision with each policy of `together` deciding on the same
// observation, into `decided`.
void DecideShared(const FlightModel& model, std::span<DecisionPolicy* const> policies,
                  const std::vector<std::size_t>& together, const RunOptions& options, FlightState& state,
                  FlightLog& log, std::vector<DecisionPolicy*>& sharing_policies,
                  std::vector<decision::CmaAction>& decided) {
  bool eod_distribution = log.record_telemetry;
  bool vehicle_beliefs = false;
  sharing_policies.clear();
  for (std::size_t k : together) {
    eod_distribution = eod_distribution || NeedsEodDistribution(policies[k], nullptr);
    vehicle_beliefs = vehicle_beliefs || policies[k]->ReadsVehicleBeliefs();
    sharing_policies.push_back(policies[k]);
  }
  state.decision.vehicle_beliefs = vehicle_beliefs;
  const DecisionInputs& inputs =
      BeginEpoch(model, state, options.battery_policy, &log, eod_distribution,
                 EpochEodPrecision(model, sharing_policies, options.battery_policy, &log, eod_distribution));
  decided.clear();
  for (std::size_t k : together) decided.push_back(policies[k]->Decide(inputs));
}

}  // namespace

// A flight of one policy (policies[k]), from a decision epoch before its Observe, flown on alone after the shared
// flight (FlyTogether). At namespace scope, with linkage: a coroutine's frame holds it.
namespace internal {
struct AloneFlight {
  std::size_t k;
  FlightState state;
  FlightLog log;
};
}  // namespace internal

FlightCoroutine FlyTogether(const FlightModel& model, std::span<DecisionPolicy* const> policies,
                            std::span<const EmergencyPlanner> planners, RunOptions options, EpochSteps& steps,
                            std::vector<SimResult>& results) {
  UASCMA_CHECK(planners.size() == policies.size(), "one planner (possibly empty) per policy");
  const std::size_t n = policies.size();
  results.assign(n, SimResult{});
  std::vector<double> wall_s(n, 0.0);
  std::vector<internal::AloneFlight> alone;

  FlightState state = MakeInitialState(model, model.scenario().seed);
  FlightLog log;
  log.record_telemetry = options.record_telemetry;
  std::vector<std::size_t> together(n);
  for (std::size_t k = 0; k < n; ++k) together[k] = k;
  std::vector<decision::CmaAction> decided;
  std::vector<DecisionPolicy*> sharing_policies;
  while (!state.done() && together.size() > 1) {
    const auto start = std::chrono::steady_clock::now();
    const std::size_t sharing = together.size();
    DecideShared(model, policies, together, options, state, log, sharing_policies, decided);
    std::vector<std::size_t> still;
    for (std::size_t i = 0; i < together.size(); ++i) {
      if (decided[i] == decision::CmaAction::kNoOp) still.push_back(together[i]);
    }
    const double shared_s = SecondsSince(start);
    for (std::size_t i = 0; i < together.size(); ++i) {
      wall_s[together[i]] += shared_s / static_cast<double>(sharing);
      if (decided[i] == decision::CmaAction::kNoOp) continue;
      // The branch: a copy of the state and the log, which has the same future bit for bit.
      const std::size_t k = together[i];
      internal::AloneFlight branch{k, state, log};
      const auto act_start = std::chrono::steady_clock::now();
      RecordEodAtAction(model, branch.state, decided[i]);
      Act(model, branch.state, decided[i], planners[k], &branch.log,
          policies[k]->Ranking(branch.state.decision.inputs));
      wall_s[k] += SecondsSince(act_start);
      co_await steps.ToNextEpoch(model, branch.state, &branch.log, &wall_s[k]);
      alone.push_back(std::move(branch));
    }
    together = std::move(still);
    if (together.empty()) break;
    Act(model, state, decision::CmaAction::kNoOp, planners[together.front()], &log);  // NoOp asks no planner
    double step_s = 0.0;
    co_await steps.ToNextEpoch(model, state, &log, &step_s);
    for (std::size_t k : together) wall_s[k] += step_s / static_cast<double>(together.size());
  }
  if (together.size() == 1) {
    alone.push_back({together.front(), std::move(state), std::move(log)});
  } else {
    // The flight ended while shared (or every policy branched): every policy still in it has the same result.
    for (std::size_t i = 0; i < together.size(); ++i) {
      const std::size_t k = together[i];
      results[k] = MakeSimResult(model, state, i + 1 == together.size() ? std::move(log) : log, policies[k]->name());
      results[k].wall_time_s = wall_s[k];
    }
  }
  // Each branch (and the last policy of the shared flight) on alone, as Run flies it.
  for (internal::AloneFlight& flight : alone) {
    const std::size_t k = flight.k;
    const Controllers controllers{policies[k], options.battery_policy, planners[k]};
    while (!flight.state.done()) {
      const auto start = std::chrono::steady_clock::now();
      DecideEpoch(model, flight.state, controllers, &flight.log);
      wall_s[k] += SecondsSince(start);
      co_await steps.ToNextEpoch(model, flight.state, &flight.log, &wall_s[k]);
    }
    results[k] = MakeSimResult(model, flight.state, std::move(flight.log), policies[k]->name());
    results[k].wall_time_s = wall_s[k];
  }
}

std::vector<SimResult> RunTogether(const FlightModel& model, std::span<DecisionPolicy* const> policies,
                                   std::span<const EmergencyPlanner> planners, const RunOptions& options) {
  EpochSteps steps(false);
  std::vector<SimResult> results;
  FlyTogether(model, policies, planners, options, steps, results).RunToEnd();
  return results;
}

// ---- flights that follow one vehicle (Ch. IV) ---------------------------------------------------------------------
SharingCounts FlyFollowing(const FlightModel& model, std::span<FlightState> states,
                           std::span<BatterySwitchPolicy* const> executors) {
  UASCMA_CHECK(executors.size() == states.size(), "one battery executor per flight");
  const std::size_t n = states.size();
  SharingCounts counts;
  std::vector<bool> alone(n, false);
  std::vector<FlightState*> followers;
  std::vector<std::size_t> follower_index;
  const std::unique_ptr<bool[]> stepped_flags(new bool[std::max<std::size_t>(n, 1)]());
  bool* stepped = stepped_flags.get();
  auto first_flying = [&states]() -> const FlightState* {
    for (const FlightState& state : states) {
      if (!state.done()) return &state;
    }
    return nullptr;
  };
  // Invariant: every flight still flying is at the same GNC step.
  for (const FlightState* flying = first_flying(); flying != nullptr; flying = first_flying()) {
    for (std::size_t k = 0; k < n; ++k) {
      if (!states[k].done()) DecideBattery(model, states[k], *executors[k]);
    }
    do {
      const std::int64_t next_step = flying->step + 1;
      // The group: the flights still flying together; its first one leads.
      std::size_t lead = n;
      followers.clear();
      follower_index.clear();
      for (std::size_t k = 0; k < n; ++k) {
        if (states[k].done() || alone[k]) continue;
        if (lead == n) {
          lead = k;
        } else {
          followers.push_back(&states[k]);
          follower_index.push_back(k);
        }
      }
      if (lead != n && !followers.empty()) {
        StepFollowing(model, states[lead], followers, std::span<bool>(stepped, followers.size()));
        for (std::size_t j = 0; j < followers.size(); ++j) {
          if (stepped[j])
            ++counts.shared_steps;
          else
            alone[follower_index[j]] = true;  // its pack caps a rotor differently: on its own from this step
        }
      }
      // Every flight not stepped yet (the leader of a group of one, those on their own) takes its step alone.
      for (std::size_t k = 0; k < n; ++k) {
        if (states[k].done() || states[k].step >= next_step) continue;
        Step(model, states[k]);
        if (k != lead) ++counts.alone_steps;
      }
      flying = first_flying();
    } while (flying != nullptr && !IsDecisionEpoch(model, *flying));
  }
  return counts;
}

// ---- branch points ------------------------------------------------------------------------------------------------
const FlightState& RequireBranchPoint(const FlightModel& model, const FlightState& state, std::string_view source) {
  if (!IsBranchPoint(model, state)) {
    throw InputError(std::string(source), "state", fmt::format("a state at a decision epoch, got step {}", state.step));
  }
  return state;
}

}  // namespace uascma::sim
