// Learning from the simulator: the cost of one Q-learning episode (§5.3.3, the one-mission setting of
// learning/cma_q_learning.h with the default campaign) and of its parts, and of one run of the transition
// estimation. Target: 10,000 episodes in at most 2 minutes on the 2-core machine, i.e. ≈ 24 ms of CPU per episode
// at --jobs 2. Counters: sim_s = simulated seconds per episode (epochs at 1 Hz).
#include <benchmark/benchmark.h>

#include <memory>

#include "uascma/campaign/sampler.h"
#include "uascma/learning/cma_q_learning.h"
#include "uascma/learning/transition_estimation.h"
#include "uascma/sim/flight.h"

namespace {

using namespace uascma;

learning::CmaQLearningOptions DefaultOptions() {
  learning::CmaQLearningOptions options;
  options.config.seed = 1;
  return options;
}

// One episode: the scenario draw, the flight model, the flight through the environment, ε = 0.01 on an all-zero
// table (NoOp greedy, as at the start of learning).
void BM_QLearningEpisode(benchmark::State& state) {
  const learning::CmaQLearningOptions options = DefaultOptions();
  const learning::QTable table(learning::NumQStates(options.state), decision::kCmaNumActions,
                               learning::QStateAvailability(options.state));
  std::int64_t episode = 0;
  double steps = 0.0;
  for (auto _ : state) {
    const learning::Episode e = learning::FlyCmaEpisode(options, episode++ % 64, table, 0.01);
    steps += static_cast<double>(e.steps.size());
    benchmark::DoNotOptimize(e.return_sum);
  }
  state.counters["sim_s"] = benchmark::Counter(steps, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_QLearningEpisode)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

// The parts outside the flight: drawing an episode's scenario, and building its flight model (LandPract database).
void BM_EpisodeScenario(benchmark::State& state) {
  const learning::CmaQLearningOptions options = DefaultOptions();
  std::int64_t episode = 0;
  for (auto _ : state) benchmark::DoNotOptimize(learning::EpisodeScenario(options, episode++ % 64).seed);
}
BENCHMARK(BM_EpisodeScenario)->Unit(benchmark::kMillisecond);

void BM_EpisodeFlightModel(benchmark::State& state) {
  const sim::Scenario scenario = learning::EpisodeScenario(DefaultOptions(), 0);
  for (auto _ : state) {
    auto model = std::make_shared<const sim::FlightModel>(scenario);
    benchmark::DoNotOptimize(model.get());
  }
}
BENCHMARK(BM_EpisodeFlightModel)->Unit(benchmark::kMillisecond);

// One run of `learn transitions`: the behaviour flight and a one-epoch branch per other available action.
void BM_TransitionRun(benchmark::State& state) {
  learning::TransitionEstimationOptions options;
  options.config.seed = 1;
  std::int64_t run = 0;
  for (auto _ : state) benchmark::DoNotOptimize(learning::CountRunTransitions(options, run++ % 16).Total());
}
BENCHMARK(BM_TransitionRun)->Unit(benchmark::kMillisecond)->Iterations(8);

}  // namespace

BENCHMARK_MAIN();
