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
  flight.decisions = result.decisions;
  for (const auto& detected : result.fault_detected_s) {
    if (detected && (!flight.fault_detected_s || *detected < *flight.fault_detected_s))
      flight.fault_detected_s = detected;
  }
  return flight;
}

// "none" or the kind of the run's pack fault.
std::string PackFaultLabel(const BatteryEvaluationRun& run) {
  return run.params.pack_fault ? models::PackFaultKindName(run.params.pack_fault->kind) : "none";
}

BatteryPolicySummary SummariseFlights(const std::string& label, const std::vector<const BatteryPolicyFlight*>& flights,
                                      const std::vector<double>& fault_onsets_s) {
  BatteryPolicySummary out;
  out.label = label;
  std::vector<double> failure_times, charge_left, switches, delays;
  for (std::size_t i = 0; i < flights.size(); ++i) {
    const BatteryPolicyFlight* f = flights[i];
    out.table_isolations += f->decisions.table_isolations;
    out.guard_isolations += f->decisions.guard_isolations;
    out.table_fault_isolations += f->decisions.table_fault_isolations;
    out.guard_fault_isolations += f->decisions.guard_fault_isolations;
    out.failure_rows_held += f->decisions.failure_rows_held;
    if (f->fault_detected_s) {
      ++out.detections;
      const double onset_s = fault_onsets_s[i];  // NaN without a fault
      if (*f->fault_detected_s >= onset_s) delays.push_back(*f->fault_detected_s - onset_s);
    }
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
  out.median_detection_delay_s = Median(delays);
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
      {"max_switches", s.max_switches},
      {"table_isolations", s.table_isolations},
      {"guard_isolations", s.guard_isolations},
      {"table_fault_isolations", s.table_fault_isolations},
      {"guard_fault_isolations", s.guard_fault_isolations},
      {"failure_rows_held", s.failure_rows_held},
      {"pack_fault_detections", s.detections},
      {"median_detection_delay_s", EvaluationJsonNumber(s.median_detection_delay_s)}};
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

using RunFilter = std::function<bool(const BatteryEvaluationRun&)>;

bool EveryRun(const BatteryEvaluationRun&) { return true; }

// Policy k's summary over the runs `keep` accepts.
BatteryPolicySummary SummariseColumn(const BatteryEvaluation& evaluation, std::size_t k, const RunFilter& keep) {
  std::vector<const BatteryPolicyFlight*> flights;
  std::vector<double> onsets_s;
  for (const auto& run : evaluation.runs) {
    if (!keep(run)) continue;
    flights.push_back(&run.flights[k]);
    onsets_s.push_back(run.params.pack_fault ? run.params.pack_fault->onset_s : kEvaluationNaN);
  }
  return SummariseFlights(evaluation.labels[k], flights, onsets_s);
}

BatteryPairComparison ComparePolicies(const BatteryEvaluation& evaluation, std::size_t a, std::size_t b,
                                      const RunFilter& keep = EveryRun) {
  BatteryPairComparison cmp;
  cmp.first = evaluation.labels[a];
  cmp.second = evaluation.labels[b];
  for (const auto& run : evaluation.runs) {
    if (!keep(run)) continue;
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

// Split by pack fault: the fault-free flights, each kind flown, and every faulted flight ("any"), when any was drawn.
void SummariseByPackFault(BatteryEvaluation& out) {
  const bool any_fault = std::any_of(out.runs.begin(), out.runs.end(),
                                     [](const BatteryEvaluationRun& run) { return run.params.pack_fault.has_value(); });
  if (!any_fault) return;
  std::vector<std::pair<std::string, RunFilter>> groups = {
      {"none", [](const BatteryEvaluationRun& run) { return !run.params.pack_fault; }},
      {"any", [](const BatteryEvaluationRun& run) { return run.params.pack_fault.has_value(); }}};
  for (int k = 0; k < models::kPackFaultKindCount; ++k) {
    const std::string kind = models::PackFaultKindName(static_cast<models::PackFaultKind>(k));
    groups.emplace_back(kind, [kind](const BatteryEvaluationRun& run) { return PackFaultLabel(run) == kind; });
  }
  for (const auto& [label, keep] : groups) {
    BatteryFaultSummary group;
    group.fault = label;
    for (std::size_t k = 0; k < out.labels.size(); ++k) group.policies.push_back(SummariseColumn(out, k, keep));
    if (group.policies.front().runs == 0) continue;
    for (std::size_t a = 0; a < out.labels.size(); ++a) {
      for (std::size_t b = a + 1; b < out.labels.size(); ++b)
        group.comparisons.push_back(ComparePolicies(out, a, b, keep));
    }
    out.by_pack_fault.push_back(std::move(group));
  }
}

// The summaries of the flown runs: per policy overall and per context flown, and every pair compared.
void SummariseEvaluation(BatteryEvaluation& out) {
  const std::size_t n = out.labels.size();
  for (std::size_t k = 0; k < n; ++k) out.overall.push_back(SummariseColumn(out, k, EveryRun));
  for (int c = 0; c < decision::kBatteryNumContexts; ++c) {
    const BatteryContext context = decision::BatteryContextFromIndex(c);
    BatteryContextSummary group;
    group.context = context;
    for (std::size_t k = 0; k < n; ++k) {
      group.policies.push_back(SummariseColumn(
          out, k, [&context](const BatteryEvaluationRun& run) { return run.params.context() == context; }));
    }
    if (group.policies.front().runs > 0) out.by_context.push_back(std::move(group));
  }
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t b = a + 1; b < n; ++b) out.comparisons.push_back(ComparePolicies(out, a, b));
  }
  SummariseByPackFault(out);
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

namespace {

nlohmann::json ComparisonJson(const BatteryPairComparison& c) {
  return {{"policies", {c.first, c.second}},
          {"pairs", c.pairs},
          {"both_completed", c.both_completed},
          {"neither_completed", c.neither_completed},
          {"only_first_completed", c.only_first_completed},
          {"only_second_completed", c.only_second_completed},
          {"mcnemar_exact_p", c.exact_p}};
}

nlohmann::json PackFaultJson(const std::optional<models::PackFault>& fault) {
  if (!fault) return nullptr;
  return {{"kind", models::PackFaultKindName(fault->kind)},
          {"pack", fault->branch + 1},
          {"cell", fault->cell + 1},
          {"onset_s", fault->onset_s},
          {"resistance_ohm", fault->resistance_ohm}};
}

nlohmann::json ByPackFaultJson(const BatteryEvaluation& evaluation) {
  nlohmann::json groups = nlohmann::json::array();
  for (const auto& group : evaluation.by_pack_fault) {
    nlohmann::json per_policy = nlohmann::json::array(), comparisons = nlohmann::json::array();
    for (const auto& s : group.policies) per_policy.push_back(SummaryJson(s));
    for (const auto& c : group.comparisons) comparisons.push_back(ComparisonJson(c));
    groups.push_back({{"pack_fault", group.fault}, {"policies", per_policy}, {"paired_comparisons", comparisons}});
  }
  return groups;
}

}  // namespace

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
  for (const auto& c : evaluation.comparisons) comparisons.push_back(ComparisonJson(c));
  nlohmann::json json = {{"policies", evaluation.labels},
                         {"seed", evaluation.seed},
                         {"runs", evaluation.runs.size()},
                         {"confidence_level", kConfidenceLevel},
                         {"overall", overall},
                         {"by_context", contexts},
                         {"paired_comparisons", comparisons},
                         {"by_pack_fault", ByPackFaultJson(evaluation)},
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
                           {"energy_used_wh", f.energy_used_wh},
                           {"table_isolations", f.decisions.table_isolations},
                           {"guard_isolations", f.decisions.guard_isolations},
                           {"table_fault_isolations", f.decisions.table_fault_isolations},
                           {"guard_fault_isolations", f.decisions.guard_fault_isolations},
                           {"failure_rows_held", f.decisions.failure_rows_held},
                           {"fault_detected_s", f.fault_detected_s ? nlohmann::json(*f.fault_detected_s) : nullptr}});
      }
      runs.push_back({{"run", run.run},
                      {"context", decision::BatteryContextLabel(run.params.context())},
                      {"plan_duration_s", run.params.plan_duration_s},
                      {"pack_fault", PackFaultJson(run.params.pack_fault)},
                      {"flights", flights}});
    }
    json["runs_detail"] = runs;
  }
  return json;
}

namespace {

// The split by pack fault, the isolations by the table and by the guard, and the indicator's flags.
std::string PackFaultText(const BatteryEvaluation& evaluation) {
  std::string out;
  if (!evaluation.by_pack_fault.empty()) {
    out +=
        "\ncompleted per sudden pack fault (docs/modelling-choices.md#pack-faults), runs in brackets\nfault         ";
    for (const auto& label : evaluation.labels) out += fmt::format(" {:>13}", label);
    out += "\n";
    for (const auto& group : evaluation.by_pack_fault) {
      out += fmt::format("{:<14}", group.fault);
      for (const auto& s : group.policies) out += fmt::format(" {:>7}/{:<5}", s.completions, fmt::format("{}", s.runs));
      out += "\n";
    }
    for (const auto& group : evaluation.by_pack_fault) {
      if (group.fault != "none" && group.fault != "any") continue;
      out += fmt::format("paired, pack fault {}: only A / only B completed\n", group.fault);
      for (const auto& c : group.comparisons) {
        out += fmt::format("  {:<13} vs {:<13} {:>4} / {:<4} p = {:.4g}\n", c.first, c.second, c.only_first_completed,
                           c.only_second_completed, c.exact_p);
      }
    }
  }
  out +=
      "\nisolations (a pack taken out while both were in) by the table / by a guard, of them of a flagged pack; "
      "FAILURE epochs held\n";
  for (const auto& s : evaluation.overall) {
    out += fmt::format("  {:<13} {:>5} / {:<5} flagged {:>4} / {:<4} {:>5}\n", s.label, s.table_isolations,
                       s.guard_isolations, s.table_fault_isolations, s.guard_fault_isolations, s.failure_rows_held);
  }
  for (const auto& group : evaluation.by_pack_fault) {
    if (group.fault != "none" && group.fault != "any") continue;
    const BatteryPolicySummary& s = group.policies.front();  // the indicator under the first policy's switches
    out += fmt::format("pack-fault indicator ({} flights), pack fault {}: flagged {} of {}", s.label, group.fault,
                       s.detections, s.runs);
    out += group.fault == "any" ? fmt::format(", median delay {:.0f} s\n", s.median_detection_delay_s) : "\n";
  }
  return out;
}

}  // namespace

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
  out += PackFaultText(evaluation);
  out += fmt::format("\n{:.1f} s wall\n", evaluation.wall_time_s);
  return out;
}

}  // namespace uascma::campaign
