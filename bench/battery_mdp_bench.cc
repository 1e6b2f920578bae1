// Battery-reconfiguration MDP (dissertation §4.3): solving every policy (target < 10 ms for the 18
// contexts) and learning from Monte Carlo flights (target ≤ 60 s for 5,000 flights on two cores).
#include <benchmark/benchmark.h>

#include "uascma/campaign/battery_flights.h"
#include "uascma/decision/battery_mdp_file.h"
#include "uascma/learning/battery_transition_estimation.h"

namespace {

using namespace uascma;

// A model learned from real flights once (600 flights, 2 threads), shared by the solve benchmark.
const decision::BatteryModel& LearnedModel() {
  static const decision::BatteryModel model = [] {
    learning::BatteryLearningOptions options;
    options.runs = 600;
    options.seed = 1;
    options.jobs = 2;
    return learning::LearnBatteryModel(options);
  }();
  return model;
}

// Building the 18 MDPs from counts and value iteration (γ = 0.95, residual 1e-10) on each.
void BM_SolveAllBatteryPolicies(benchmark::State& state) {
  const decision::BatteryModel& model = LearnedModel();
  for (auto _ : state) {
    decision::BatteryPolicySet set = decision::SolveBatteryPolicies(model);
    benchmark::DoNotOptimize(set);
  }
  state.counters["contexts"] = decision::kBatteryNumContexts;
}
BENCHMARK(BM_SolveAllBatteryPolicies)->Unit(benchmark::kMillisecond);

// Learning: `range(0)` flights on two threads (5,000 is the dissertation's count, §4.3.2).
void BM_LearnBatteryModel(benchmark::State& state) {
  learning::BatteryLearningOptions options;
  options.runs = state.range(0);
  options.seed = 7;
  options.jobs = 2;
  for (auto _ : state) {
    learning::BatteryLearningSummary summary;
    decision::BatteryModel model = learning::LearnBatteryModel(options, &summary);
    benchmark::DoNotOptimize(model);
    state.counters["flights"] = static_cast<double>(summary.flights);
    state.counters["parameter_draws"] = static_cast<double>(summary.parameter_draws);
  }
}
BENCHMARK(BM_LearnBatteryModel)->Arg(5000)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
