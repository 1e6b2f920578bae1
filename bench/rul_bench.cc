// Motor RUL figures: the cost of what the simulator and the CMA call.
//  - "RUL now": 100 particles from the observed spall area (§3.4.1), once per 1 Hz CMA epoch;
//  - the Table 5.4 measurement: 1000 spall histories (§5.3.2.3);
//  - the calibration of the time per growth step (docs/modelling-choices.md#spall-growth-time-scale);
//  - one motor's spall → jam event advanced at the 200 Hz GNC rate from onset to jam.
#include <benchmark/benchmark.h>

#include "uascma/common/random.h"
#include "uascma/prognostics/motor_rul.h"

namespace {

using namespace uascma;
using namespace uascma::prognostics;

void BM_RulNowHundredParticles(benchmark::State& state) {
  const MotorRulModel model;
  RandomStream random(1);
  for (auto _ : state) benchmark::DoNotOptimize(model.PredictRulFromArea(0.01, random).mean_s);
}
BENCHMARK(BM_RulNowHundredParticles)->Unit(benchmark::kMicrosecond);

void BM_MeasureJamProbabilityThousandRuns(benchmark::State& state) {
  const MotorRulModel model;
  RandomStream random(1);
  for (auto _ : state) {
    benchmark::DoNotOptimize(model.MeasureJamProbability(1000, random).jam_probability_per_epoch);
  }
}
BENCHMARK(BM_MeasureJamProbabilityThousandRuns)->Unit(benchmark::kMillisecond);

void BM_CalibrateTimePerGrowthStep(benchmark::State& state) {
  for (auto _ : state) {
    benchmark::DoNotOptimize(CalibrateTimePerGrowthStep(SpallGrowthParams{}).time_per_growth_step_s);
  }
}
BENCHMARK(BM_CalibrateTimePerGrowthStep)->Unit(benchmark::kMillisecond);

void BM_SpallJamEventAt200Hz(benchmark::State& state) {
  const MotorRulModel model;
  std::uint64_t seed = 0;
  std::int64_t advances = 0;
  for (auto _ : state) {
    SpallJamEvent event(model, 0.0, seed++);
    while (!event.jammed()) {
      event.Advance(0.005);
      ++advances;
    }
    benchmark::DoNotOptimize(event.jam_time_s());
  }
  state.SetItemsProcessed(advances);  // items/s = Advance calls per second
}
BENCHMARK(BM_SpallJamEventAt200Hz)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
