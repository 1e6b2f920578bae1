// The decisions on beliefs (sim/belief_policy.h) per 1 Hz epoch, beside the point CMA's table look-up:
//  - "cma" (TablePolicy::Decide), "cma-risk" (RiskCmaPolicy::Decide: two states, the level from the Q-values) and
//    "cma-qmdp" (QmdpCmaPolicy::Decide: six states, four actions) on a belief spread over every MH and RM;
//  - one step of the spall indicator's Bayes filter (predict, update, b(NF, SF, JF)).
// What the issue bounds: the EOD distribution and the decision <= 50 µs per epoch; these are the decision's share.
#include <benchmark/benchmark.h>

#include <memory>

#include "uascma/sim/belief_policy.h"
#include "uascma/sim/policy.h"
#include "uascma/sim/sensing.h"

namespace {

using namespace uascma::sim;

// Mid-flight, N,NF,MM1,M,RM1 at the point, every belief component positive.
DecisionInputs SpreadInputs() {
  DecisionInputs inputs;
  inputs.state.bh = uascma::decision::BatteryHealth::kM;
  inputs.flight_time_remaining_s = 240.0;
  inputs.motor_health_belief = {0.6, 0.3, 0.1};
  inputs.eod_distribution = uascma::sim::EodDistributionSummary{.short_probability = 0.2};
  inputs.rul_if_spall_s = 180.0;
  return inputs;
}

void DecideWith(benchmark::State& state, const char* name) {
  const std::unique_ptr<DecisionPolicy> policy = MakePolicy(name, "bench");
  DecisionInputs inputs = SpreadInputs();
  policy->Decide(inputs);  // the Q-values and tables solved before timing
  for (auto _ : state) {
    inputs.time_s += 1.0;  // a new epoch (the QMDP ranking is recomputed)
    benchmark::DoNotOptimize(policy->Decide(inputs));
    benchmark::DoNotOptimize(policy->Ranking(inputs).data());
  }
}
void BM_DecideCma(benchmark::State& state) { DecideWith(state, "cma"); }
void BM_DecideCmaRisk(benchmark::State& state) { DecideWith(state, "cma-risk"); }
void BM_DecideCmaQmdp(benchmark::State& state) { DecideWith(state, "cma-qmdp"); }
BENCHMARK(BM_DecideCma)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_DecideCmaRisk)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_DecideCmaQmdp)->Unit(benchmark::kNanosecond);

void BM_SpallFilterStep(benchmark::State& state) {
  double p = 0.0;
  bool reading = false;
  for (auto _ : state) {
    p = UpdateSpallProbability(PredictSpallProbability(p, SpallOnsetHazard(0.5, 600.0, 100.0, 1.0)), reading,
                               1.0 / 3600.0, 0.5);
    reading = !reading;
    benchmark::DoNotOptimize(MotorHealthBelief(p, 0.01));
  }
}
BENCHMARK(BM_SpallFilterStep)->Unit(benchmark::kNanosecond);

}  // namespace

BENCHMARK_MAIN();
