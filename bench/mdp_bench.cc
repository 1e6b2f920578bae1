// MDP engine figures (issue: foundation and decision core):
//  - one Bellman sweep of a random sparse MDP, 10^5 states × 4 actions × 10 successors
//    (target ≤ 5 ms on one core; AI-Toolbox takes about 9 ms);
//  - solving the CMA MDP to a residual of 1e-10 (target < 1 ms).
#include <benchmark/benchmark.h>

#include "uascma/decision/cma_mdp.h"
#include "uascma/decision/random_mdp.h"
#include "uascma/decision/solvers.h"

namespace {

using namespace uascma::decision;

void BM_BellmanSweepRandomSparse(benchmark::State& state) {
  const int num_states = static_cast<int>(state.range(0));
  const FiniteMdp mdp = MakeRandomMdp(num_states, 4, 10, 2024);
  std::vector<double> in(static_cast<std::size_t>(num_states), 0.0), out;
  for (int i = 0; i < 5; ++i) {  // warm up to realistic values
    BellmanSweep(mdp, 0.95, in, out);
    in.swap(out);
  }
  for (auto _ : state) {
    benchmark::DoNotOptimize(BellmanSweep(mdp, 0.95, in, out));
    benchmark::ClobberMemory();
  }
  state.counters["transitions"] = static_cast<double>(mdp.num_transitions());
  state.SetItemsProcessed(state.iterations() * mdp.num_transitions());
}
BENCHMARK(BM_BellmanSweepRandomSparse)->Arg(10000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);

void BM_SolveCmaValueIteration(benchmark::State& state) {
  const FiniteMdp mdp = BuildCmaMdp({});
  SolverSummary summary;
  for (auto _ : state) {
    Policy policy = SolveValueIteration(mdp, {}, &summary);
    benchmark::DoNotOptimize(policy.value.data());
  }
  state.counters["sweeps"] = summary.iterations;
}
BENCHMARK(BM_SolveCmaValueIteration)->Unit(benchmark::kMicrosecond);

void BM_SolveCmaPolicyIteration(benchmark::State& state) {
  const FiniteMdp mdp = BuildCmaMdp({});
  for (auto _ : state) {
    Policy policy = SolvePolicyIteration(mdp, {});
    benchmark::DoNotOptimize(policy.value.data());
  }
}
BENCHMARK(BM_SolveCmaPolicyIteration)->Unit(benchmark::kMicrosecond);

void BM_BuildCmaMdp(benchmark::State& state) {
  for (auto _ : state) {
    FiniteMdp mdp = BuildCmaMdp({});
    benchmark::DoNotOptimize(mdp.probability().data());
  }
}
BENCHMARK(BM_BuildCmaMdp)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
