// Campaign throughput (dissertation §5.5: 930 flights). The per-flight cost of dissertation-size flights,
// and the thread scaling of the runner on a fixed set of short flights. The whole timed campaign (CLI,
// threads and MPI ranks) is bench/campaign_scaling.sh.
#include <benchmark/benchmark.h>

#include "uascma/campaign/config.h"
#include "uascma/campaign/metrics.h"
#include "uascma/campaign/runner.h"
#include "uascma/campaign/sampler.h"

namespace {

using namespace uascma::campaign;

const CampaignPolicy& Cma() {
  static const CampaignPolicy policy = SolvedCmaPolicy();
  return policy;
}

void BM_SampleRun(benchmark::State& state) {
  const CampaignConfig config;
  const CampaignWorld world = BuildCampaignWorld(config.map);  // once per campaign (campaign/world.h)
  std::int64_t index = 0;
  for (auto _ : state) benchmark::DoNotOptimize(SampleRun(config, world, 1, index++));
}
BENCHMARK(BM_SampleRun);

// One dissertation-size flight (examples/campaign.yaml defaults) flown by the CMA policy; the run index
// cycles over the first `range(0)` runs of seed 1, so the mean covers a spread of missions.
void BM_FlyDissertationRun(benchmark::State& state) {
  const CampaignConfig config;
  const std::int64_t runs = state.range(0);
  const CampaignWorld world = BuildCampaignWorld(config.map);
  std::int64_t index = 0;
  double sim_s = 0.0;
  for (auto _ : state) {
    const SampledRun run = SampleRun(config, world, 1, index++ % runs);
    const uascma::sim::Simulator simulator(run.scenario);
    const RunRecord record = FlyRun(simulator, run, Cma(), 0, 1);
    sim_s += record.sim_time_s;
  }
  state.counters["flights/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["sim_s/flight"] = sim_s / static_cast<double>(state.iterations());
}
BENCHMARK(BM_FlyDissertationRun)->Arg(8)->Unit(benchmark::kMillisecond)->UseRealTime();

// 24 short runs × 2 policies on `range(0)` threads: the runner's scaling (ideal: time / jobs).
void BM_ExecuteShortFlights(benchmark::State& state) {
  CampaignConfig config;
  config.mission.distance_m = {20.0, 40.0};
  config.mission.cruise_speed_mps = {4.0, 9.0};
  config.mission.cruise_altitude_m = 5.0;
  config.mission.drop_hover_s = 2.0;
  config.battery.cold_probability = 0.0;
  config.runs = 24;
  const std::vector<CampaignPolicy> policies = {Cma(), NoOpCampaignPolicy()};
  const std::vector<FlightTask> tasks = MissingFlights(config.runs, policies, {});
  ExecuteOptions options;
  options.jobs = static_cast<int>(state.range(0));
  std::int64_t flights = 0;
  for (auto _ : state) {
    ExecuteFlights(config, policies, tasks, options,
                   [&flights](std::vector<RunRecord>&& batch) { flights += static_cast<std::int64_t>(batch.size()); });
  }
  state.counters["flights/s"] = benchmark::Counter(static_cast<double>(flights), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ExecuteShortFlights)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
