#include "uascma/campaign/battery_evaluation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/parallel_for.h"

namespace uascma::campaign {
namespace {

using decision::BatteryContext;

constexpr double kEvaluationNaN = std::numeric_limits<double>::quiet_NaN();

double Median(std::vector<double> values) {
  if (values.empty()) return kEvaluationNaN;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

double Mean(const std::vector<double>& values) {
  if (values.empty()) return kEvaluationNaN;
  double sum = 0.0;
  for (double v : values) sum += v;
  return sum / static_cast<double>(values.size());
}

nlohmann::json EvaluationJsonNumber(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

BatteryPolicyFlight SummarisePolicyFlight(const BatteryFlightResult& result) {
  BatteryPolicyFlight flight;
  flight.outcome = result.outcome;
  flight.end_time_s = result.end_time_s;
  flight.switches = CountSwitches(result);
  flight.charge_left_ah = result.charge_left_ah[0] + result.charge_left_ah[1];
  flight.energy_used_wh = result.energy_used_wh;
  return flight;
}

BatteryPolicySummary SummariseFlights(const std::string& label,
                                      const std::vector<const BatteryPolicyFlight*>& flights) {
  BatteryPolicySummary out;
  out.label = label;
  std::vector<double> failure_times, charge_left, switches;
  for (const BatteryPolicyFlight* f : flights) {
    ++out.runs;
    if (f->completed()) {
      ++out.completions;
      charge_left.push_back(f->charge_left_ah);
    } else {
      ++out.failures;  // every outcome but completion: the battery flights fail only on the battery (Table 4.1)
      failure_times.push_back(f->end_time_s);
    }
    switches.push_back(f->switches);
    out.max_switches = std::max(out.max_switches, f->switches);
  }
  out.completion_wilson = WilsonInterval(out.completions, out.runs);
  out.median_failure_time_s = Median(failure_times);
  out.mean_charge_left_ah = Mean(charge_left);
  out.median_switches = Median(switches);
  out.mean_switches = Mean(switches);
  return out;
}

nlohmann::json SummaryJson(const BatteryPolicySummary& s) {
  return {
      {"policy", s.label},
      {"runs", s.runs},
      {"completions", s.completions},
      {"failures", s.failures},
      {"completion_rate",
       s.runs > 0 ? EvaluationJsonNumber(static_cast<double>(s.completions) / static_cast<double>(s.runs)) : nullptr},
      {"completion_wilson_low", EvaluationJsonNumber(s.completion_wilson.low)},
      {"completion_wilson_high", EvaluationJsonNumber(s.completion_wilson.high)},
      {"median_failure_time_s", EvaluationJsonNumber(s.median_failure_time_s)},
      {"mean_charge_left_ah_completed", EvaluationJsonNumber(s.mean_charge_left_ah)},
      {"median_switches", EvaluationJsonNumber(s.median_switches)},
      {"mean_switches", EvaluationJsonNumber(s.mean_switches)},
      {"max_switches", s.max_switches}};
}

}  // namespace

// ================================ evaluation ======================================================
namespace {

// Run r: its flight drawn from Table 4.4, flown by every policy together (the same params value; each result
// bit-identical to the flight flown alone).
BatteryEvaluationRun FlyEvaluationRun(const std::vector<BatteryPolicySpec>& policies,
                                      const BatteryEvaluationOptions& options, std::int64_t r) {
  BatteryEvaluationRun run;
  run.run = r;
  run.params = SampleBatteryFlight(options.ranges, options.seed, r);
  std::vector<BatteryFlightController> controllers;
  for (const auto& p : policies) controllers.push_back(MakeBatteryController(p, run.params.context()));
  for (const auto& result : FlyBatteryFlights(run.params, controllers))
    run.flights.push_back(SummarisePolicyFlight(result));
  return run;
}

// Policy k's flights in the runs `keep` accepts.
std::vector<const BatteryPolicyFlight*> Column(const BatteryEvaluation& evaluation, std::size_t k,
                                               const std::function<bool(const BatteryEvaluationRun&)>& keep) {
  std::vector<const BatteryPolicyFlight*> flights;
  for (const auto& run : evaluation.runs) {
    if (keep(run)) flights.push_back(&run.flights[k]);
  }
  return flights;
}

BatteryPairComparison ComparePolicies(const BatteryEvaluation& evaluation, std::size_t a, std::size_t b) {
  BatteryPairComparison cmp;
  cmp.first = evaluation.labels[a];
  cmp.second = evaluation.labels[b];
  for (const auto& run : evaluation.runs) {
    const bool first = run.flights[a].completed(), second = run.flights[b].completed();
    ++cmp.pairs;
    if (first && second)
      ++cmp.both_completed;
    else if (!first && !second)
      ++cmp.neither_completed;
    else if (first)
      ++cmp.only_first_completed;
    else
      ++cmp.only_second_completed;
  }
  cmp.exact_p = CalcMcNemarTest(cmp.only_first_completed, cmp.only_second_completed).exact_p;
  return cmp;
}

// The summaries of the flown runs: per policy overall and per context flown, and every pair compared.
void SummariseEvaluation(BatteryEvaluation& out) {
  const std::size_t n = out.labels.size();
  for (std::size_t k = 0; k < n; ++k) {
    out.overall.push_back(
        SummariseFlights(out.labels[k], Column(out, k, [](const BatteryEvaluationRun&) { return true; })));
  }
  for (int c = 0; c < decision::kBatteryNumContexts; ++c) {
    const BatteryContext context = decision::BatteryContextFromIndex(c);
    BatteryContextSummary group;
    group.context = context;
    for (std::size_t k = 0; k < n; ++k) {
      group.policies.push_back(SummariseFlights(
          out.labels[k],
          Column(out, k, [&context](const BatteryEvaluationRun& run) { return run.params.context() == context; })));
    }
    if (group.policies.front().runs > 0) out.by_context.push_back(std::move(group));
  }
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t b = a + 1; b < n; ++b) out.comparisons.push_back(ComparePolicies(out, a, b));
  }
}

}  // namespace

BatteryEvaluation EvaluateBatteryPolicies(const std::vector<BatteryPolicySpec>& policies,
                                          const BatteryEvaluationOptions& options) {
  if (policies.empty()) throw InputError("--policies", "value", "at least one policy");
  if (options.runs < 1) throw InputError("--runs", "value", fmt::format("at least 1 flight, got {}", options.runs));
  if (options.jobs < 1) throw InputError("--jobs", "value", fmt::format("at least 1 thread, got {}", options.jobs));
  const auto start = std::chrono::steady_clock::now();
  BatteryEvaluation out;
  out.seed = options.seed;
  for (const auto& p : policies) out.labels.push_back(p.label);
  out.runs.reserve(static_cast<std::size_t>(options.runs));
  ParallelOptions parallel;
  parallel.jobs = options.jobs;
  // Runs kept in run order, whatever the number of threads.
  const std::int64_t merged = ParallelFor(
      options.runs, parallel, [&](std::int64_t r) { return FlyEvaluationRun(policies, options, r); },
      [&](std::int64_t, BatteryEvaluationRun&& run) {
        out.runs.push_back(std::move(run));
        if (options.on_run_done) options.on_run_done(static_cast<std::int64_t>(out.runs.size()));
      });
  if (merged < options.runs) throw Cancelled();
  SummariseEvaluation(out);
  out.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

nlohmann::json BatteryEvaluationJson(const BatteryEvaluation& evaluation, bool with_runs) {
  nlohmann::json overall = nlohmann::json::array(), contexts = nlohmann::json::array(),
                 comparisons = nlohmann::json::array();
  for (const auto& s : evaluation.overall) overall.push_back(SummaryJson(s));
  for (const auto& group : evaluation.by_context) {
    nlohmann::json per_policy = nlohmann::json::array();
    for (const auto& s : group.policies) per_policy.push_back(SummaryJson(s));
    contexts.push_back({{"context", decision::BatteryContextLabel(group.context)},
                        {"b1", decision::BatteryHealthName(group.context.b1)},
                        {"b2", decision::BatteryHealthName(group.context.b2)},
                        {"temperature", decision::TemperatureClassName(group.context.temperature)},
                        {"policies", per_policy}});
  }
  for (const auto& c : evaluation.comparisons) {
    comparisons.push_back({{"policies", {c.first, c.second}},
                           {"pairs", c.pairs},
                           {"both_completed", c.both_completed},
                           {"neither_completed", c.neither_completed},
                           {"only_first_completed", c.only_first_completed},
                           {"only_second_completed", c.only_second_completed},
                           {"mcnemar_exact_p", c.exact_p}});
  }
  nlohmann::json json = {{"policies", evaluation.labels},
                         {"seed", evaluation.seed},
                         {"runs", evaluation.runs.size()},
                         {"confidence_level", kConfidenceLevel},
                         {"overall", overall},
                         {"by_context", contexts},
                         {"paired_comparisons", comparisons},
                         {"wall_time_s", evaluation.wall_time_s}};
  if (with_runs) {
    nlohmann::json runs = nlohmann::json::array();
    for (const auto& run : evaluation.runs) {
      nlohmann::json flights = nlohmann::json::array();
      for (const auto& f : run.flights) {
        flights.push_back({{"outcome", sim::OutcomeName(f.outcome)},
                           {"end_time_s", f.end_time_s},
                           {"switches", f.switches},
                           {"charge_left_ah", f.charge_left_ah},
                           {"energy_used_wh", f.energy_used_wh}});
      }
      runs.push_back({{"run", run.run},
                      {"context", decision::BatteryContextLabel(run.params.context())},
                      {"plan_duration_s", run.params.plan_duration_s},
                      {"flights", flights}});
    }
    json["runs_detail"] = runs;
  }
  return json;
}

std::string BatteryEvaluationText(const BatteryEvaluation& evaluation) {
  std::string out = fmt::format(
      "battery policies on {} paired flights of Table 4.4's draw (seed {}), every policy on the same flight\n\n",
      evaluation.runs.size(), evaluation.seed);
  out +=
      "policy        completed   95% Wilson        failed  median failure s  charge left Ah  switches "
      "median/mean/max\n";
  for (const auto& s : evaluation.overall) {
    out += fmt::format("{:<13} {:>4}/{:<5} [{:5.1f}%, {:5.1f}%]  {:>6}  {:>16.0f}  {:>14.3f}  {:>6.0f} / {:.1f} / {}\n",
                       s.label, s.completions, s.runs, 100.0 * s.completion_wilson.low,
                       100.0 * s.completion_wilson.high, s.failures, s.median_failure_time_s, s.mean_charge_left_ah,
                       s.median_switches, s.mean_switches, s.max_switches);
  }
  out += "\npaired completions (McNemar, exact two-sided p): only A completed / only B completed\n";
  for (const auto& c : evaluation.comparisons) {
    out +=
        fmt::format("  {:<13} vs {:<13} {:>4} / {:<4} both {:>4}, neither {:>4}   p = {:.4g}\n", c.first, c.second,
                    c.only_first_completed, c.only_second_completed, c.both_completed, c.neither_completed, c.exact_p);
  }
  out += "\ncompleted per health pair and temperature (Table 4.2), runs in brackets\ncontext    ";
  for (const auto& label : evaluation.labels) out += fmt::format(" {:>13}", label);
  out += "\n";
  for (const auto& group : evaluation.by_context) {
    out += fmt::format("{:<10} ", decision::BatteryContextLabel(group.context));
    for (const auto& s : group.policies) out += fmt::format(" {:>7}/{:<5}", s.completions, fmt::format("{}", s.runs));
    out += "\n";
  }
  out += fmt::format("\n{:.1f} s wall\n", evaluation.wall_time_s);
  return out;
}

}  // namespace uascma::campaign
