// Judging battery policies: `battery evaluate` of 400 paired flights × 4 policies (useboth, pistar,
// rule:voltage, ours) must take ≤ 60 s on 2 cores. The policies come from a 600-flight model (seed 1, with the drop
// flights) solved both ways once, outside the timing; the flights are Table 4.4 draws of seed 2024 as the README's
// evaluation. Prints wall time (the benchmark's real time) and the process CPU seconds it took.
#include <benchmark/benchmark.h>

#include <ctime>
#include <memory>

#include "uascma/campaign/battery_evaluation.h"
#include "uascma/campaign/battery_flights.h"
#include "uascma/decision/battery_mdp_file.h"
#include "uascma/learning/battery_transition_estimation.h"

namespace {

using namespace uascma;

std::vector<campaign::BatteryPolicySpec> FourPolicies() {
  static const std::vector<campaign::BatteryPolicySpec> specs = [] {
    learning::BatteryLearningOptions learn_options;
    learn_options.runs = 600;
    learn_options.seed = 1;
    learn_options.jobs = 2;
    learn_options.drop_flights = true;
    const decision::BatteryModel model = learning::LearnBatteryModel(learn_options);
    campaign::BatteryPolicySpec useboth, pistar, rule, ours;
    useboth.label = "useboth";
    pistar.kind = campaign::BatteryPolicyKind::kPiStar;
    pistar.label = "pistar";
    pistar.policies = std::make_shared<decision::BatteryPolicySet>(decision::SolveBatteryPolicies(model));
    rule.kind = campaign::BatteryPolicyKind::kVoltageRule;
    rule.label = "rule:voltage";
    ours.kind = campaign::BatteryPolicyKind::kOurs;
    ours.label = "ours";
    ours.policies = std::make_shared<decision::BatteryPolicySet>(
        decision::SolveOursBatteryPolicies(model, campaign::OursBatteryDiscount()));
    return std::vector<campaign::BatteryPolicySpec>{useboth, pistar, rule, ours};
  }();
  return specs;
}

void BM_EvaluateFourPolicies(benchmark::State& state) {
  const auto policies = FourPolicies();
  campaign::BatteryEvaluationOptions options;
  options.runs = state.range(0);
  options.seed = 2024;
  options.jobs = 2;
  for (auto _ : state) {
    const std::clock_t cpu_start = std::clock();
    campaign::BatteryEvaluation evaluation = campaign::EvaluateBatteryPolicies(policies, options);
    const double cpu_s = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
    benchmark::DoNotOptimize(evaluation);
    state.counters["flights"] = static_cast<double>(options.runs * static_cast<std::int64_t>(policies.size()));
    state.counters["cpu_s"] = cpu_s;
    state.counters["target_wall_s"] = 60.0;
  }
}
BENCHMARK(BM_EvaluateFourPolicies)->Arg(400)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
