#include "runs_in_flight.h"

#include <algorithm>
#include <memory>
#include <utility>

#include "uascma/campaign/metrics.h"
#include "uascma/sim/lockstep.h"

namespace uascma::campaign {
namespace {

// A run in flight: its sampled scenario, its simulator and its flying coroutine (which refers to both).
struct Flying {
  SampledRun run;
  std::optional<sim::Simulator> simulator;
  std::optional<RunInFlight> flying;
};

}  // namespace

void FlyRunsInFlight(const CampaignConfig& config, const std::vector<CampaignPolicy>& policies,
                     const CampaignWorld& world, const TaskSource& next_task, const ExecuteOptions& options,
                     const CancellationToken& stop, const std::function<void()>& request_flush,
                     const std::function<void(std::vector<RunRecord>&&)>& hand_over) {
  const auto runs_in_flight = static_cast<std::size_t>(std::max(1, options.runs_in_flight));
  const int num_policies = static_cast<int>(policies.size());
  sim::EpochSteps steps(runs_in_flight > 1);
  std::vector<std::unique_ptr<Flying>> in_flight;  // after `steps`, which their coroutines refer to
  // A run that has ended (it may end at its start, without a step) hands its records over and leaves.
  auto hand_over_ended = [&] {
    for (auto it = in_flight.begin(); it != in_flight.end();) {
      RunInFlight& run = *(*it)->flying;
      run.coroutine().ThrowIfFailed();
      if (!run.coroutine().done()) {
        ++it;
        continue;
      }
      hand_over(run.Records());
      it = in_flight.erase(it);
    }
  };
  bool exhausted = false;
  while (true) {
    while (!exhausted && in_flight.size() < runs_in_flight && !stop.IsCancelled()) {
      // Waiting for runs other processes hold only with none of its own in flight (TaskSource).
      const bool may_wait = in_flight.empty();
      const std::optional<FlightTask> task = next_task(stop, request_flush, may_wait);
      if (!task) {
        exhausted = may_wait;
        break;
      }
      auto flying = std::make_unique<Flying>();
      flying->run = SampleRun(config, world, config.seed, task->run_index);
      flying->simulator.emplace(flying->run.scenario);  // built once, flown by every policy (paired)
      std::vector<const CampaignPolicy*> flown;
      for (int slot : task->slots) flown.push_back(&policies[slot]);
      // The run's policies fly one vehicle until their decisions differ (FlyRunTogether); RunInFlight keeps what it
      // needs of `flown` and the slots.
      flying->flying.emplace(*flying->simulator, flying->run, flown, task->slots, num_policies, options.planner_factory,
                             steps);
      flying->flying->coroutine().Resume();  // to its first steps
      in_flight.push_back(std::move(flying));
      hand_over_ended();
    }
    if (in_flight.empty()) break;
    steps.StepWaiting();
    hand_over_ended();
  }
}

}  // namespace uascma::campaign
