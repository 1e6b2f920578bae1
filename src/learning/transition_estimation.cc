#include "uascma/learning/transition_estimation.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <vector>

#include <fmt/format.h>

#include "uascma/campaign/sampler.h"
#include "uascma/common/cpu_time.h"
#include "uascma/common/error.h"
#include "uascma/common/parallel_for.h"
#include "uascma/decision/cma_abstraction.h"
#include "uascma/decision/policy_file.h"
#include "uascma/learning/cma_q_learning.h"
#include "uascma/sim/environment.h"

namespace uascma::learning {
namespace {

using decision::CmaAction;

const decision::Policy& BehaviourPolicy() {
  static const decision::Policy policy = decision::SolveDefaultCmaPolicy();
  return policy;
}

// The behaviour's action at an epoch (header): the CMA policy, or with probability `exploration` a random
// available action other than Terminate.
CmaAction BehaviourAction(const sim::Observation& observation, double exploration, RandomStream& random,
                          bool* explored) {
  *explored = false;
  if (exploration > 0.0 && random.Bernoulli(exploration)) {
    std::vector<CmaAction> choices;
    for (CmaAction a : {CmaAction::kNoOp, CmaAction::kLandAsap, CmaAction::kLandPract}) {
      if (decision::IsCmaActionAvailable(observation.flight_status, a)) choices.push_back(a);
    }
    *explored = true;
    return choices[random.UniformIndex(choices.size())];
  }
  const auto action = BehaviourPolicy().action[static_cast<std::size_t>(observation.state_index)];
  return static_cast<CmaAction>(action);
}

}  // namespace

bool TransitionEstimationOptions::IsValid(std::string* error) const {
  auto fail = [error](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (!config.IsValid(error)) return false;
  if (runs < 1) return fail(fmt::format("runs: expected >= 1, got {}", runs));
  if (jobs < 1) return fail(fmt::format("jobs: expected >= 1, got {}", jobs));
  if (!(exploration >= 0.0 && exploration <= 1.0)) {
    return fail(fmt::format("exploration: expected [0, 1], got {}", exploration));
  }
  return true;
}

decision::CmaTransitionCounts CountRunTransitions(const TransitionEstimationOptions& options, std::int64_t run,
                                                  TransitionEstimationSummary* summary) {
  return CountRunTransitions(options, campaign::BuildCampaignWorld(options.config), run, summary);
}

decision::CmaTransitionCounts CountRunTransitions(const TransitionEstimationOptions& options,
                                                  const campaign::CampaignWorld& world, std::int64_t run,
                                                  TransitionEstimationSummary* summary) {
  campaign::SampledRun sampled = campaign::SampleRun(options.config, world, options.config.seed, run);
  // The transitions of the MDP's own actions (§5.6): Terminate goes to T as the MDP has it, without the executor's
  // last-resort check (sim/termination.h), which replaces it in a flight that still reaches the ground.
  sampled.scenario.options.termination = sim::TerminationRule::kPolicy;
  auto model = std::make_shared<const sim::FlightModel>(sampled.scenario);
  sim::DecisionEnvironment flight(model);
  sim::DecisionEnvironment branch(model);
  RandomStream random(DeriveSeed(sampled.run_seed, kExplorationStream));
  decision::CmaTransitionCounts counts;
  TransitionEstimationSummary local;
  sim::Observation observation = flight.Reset(sampled.scenario.seed);
  while (!flight.done()) {
    const decision::StateIndex s = observation.state_index;
    bool explored = false;
    const CmaAction chosen = BehaviourAction(observation, options.exploration, random, &explored);
    for (int a = 0; a < decision::kCmaNumActions; ++a) {
      const auto action = static_cast<CmaAction>(a);
      if (action == chosen || !decision::IsCmaActionAvailable(observation.flight_status, action)) continue;
      branch.SetState(flight.state());
      const sim::EnvironmentStep step = branch.Step(action);
      counts.Add(s, a, step.observation.state_index);
      ++local.branches;
    }
    const sim::EnvironmentStep step = flight.Step(chosen);
    counts.Add(s, static_cast<decision::ActionIndex>(chosen), step.observation.state_index);
    ++local.epochs;
    local.explored += explored ? 1 : 0;
    observation = step.observation;
  }
  local.runs = 1;
  if (summary != nullptr) *summary = local;
  return counts;
}

decision::CmaTransitionCounts EstimateCmaTransitions(const TransitionEstimationOptions& options,
                                                     TransitionEstimationSummary* summary) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("transitions", "options", error);
  const auto wall_start = std::chrono::steady_clock::now();
  const double cpu_start = ProcessCpuSeconds();
  BehaviourPolicy();  // solved once before the threads start
  struct RunCounts {
    decision::CmaTransitionCounts counts;
    TransitionEstimationSummary summary;
  };
  ParallelOptions parallel;
  parallel.jobs = options.jobs;
  decision::CmaTransitionCounts counts;
  TransitionEstimationSummary total;
  const campaign::CampaignWorld world = campaign::BuildCampaignWorld(options.config);  // once for every run
  // Merged in run order: the integer sums are the same for any number of threads.
  const std::int64_t merged = ParallelFor(
      options.runs, parallel,
      [&options, &world](std::int64_t run) {
        RunCounts one;
        one.counts = CountRunTransitions(options, world, run, &one.summary);
        if (options.on_run_done) options.on_run_done(run);
        return one;
      },
      [&counts, &total](std::int64_t, RunCounts&& one) {
        counts.Merge(one.counts);
        total.runs += one.summary.runs;
        total.epochs += one.summary.epochs;
        total.branches += one.summary.branches;
        total.explored += one.summary.explored;
      });
  if (merged < options.runs) throw Cancelled();
  total.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  total.cpu_time_s = ProcessCpuSeconds() - cpu_start;
  if (summary != nullptr) *summary = total;
  return counts;
}

}  // namespace uascma::learning
