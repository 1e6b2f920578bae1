// uascma learn transitions — the CMA MDP's transition rows counted from simulated campaign flights (dissertation
// §5.6, §5.3.2.3; learning/transition_estimation.h), compared with the DDN tables of §5.3.2 and solved.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "bounded_option.h"
#include "commands.h"
#include "learn_options.h"
#include "output.h"
#include "uascma/campaign/config.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/common/progress.h"
#include "uascma/decision/cma_estimated_model.h"
#include "uascma/decision/policy_file.h"
#include "uascma/decision/solvers.h"
#include "uascma/learning/transition_estimation.h"

namespace uascma::cli {
namespace {

using namespace uascma::decision;

// Our bounds.
constexpr Bounds kRunBounds{1, 1e6, "runs"};
constexpr Bounds kTopBounds{0, 432, "rows"};
constexpr Bounds kMinSampleBounds{1, 1e9, "samples"};

struct TransitionOptions {
  std::int64_t runs = 300;
  std::string seed;
  int jobs = 1;
  std::string out, campaign_file;
  double exploration = 0.002;
  int top = 10;
  std::int64_t min_samples = 30;
  bool json = false;
};

nlohmann::json Distribution(const std::vector<double>& row, const FiniteMdp& mdp) {
  nlohmann::json out = nlohmann::json::object();
  for (std::size_t n = 0; n < row.size(); ++n) {
    if (row[n] > 0.0) out[mdp.state_label(static_cast<StateIndex>(n))] = row[n];
  }
  return out;
}

nlohmann::json RowJson(const RowDivergence& d, const CmaTransitionCounts& counts, const FiniteMdp& ddn) {
  return {{"state", ddn.state_label(d.state)},
          {"action", ddn.action_name(d.action)},
          {"samples", d.samples},
          {"total_variation", d.total_variation},
          {"kl_nats", d.kl_nats},
          {"estimated", Distribution(EstimatedRow(counts, d.state, d.action), ddn)},
          {"ddn", Distribution(DenseRow(ddn, d.state, d.action), ddn)}};
}

// The states whose optimal action differs between the DDN model and the estimated one (γ = 0.95,
// docs/modelling-choices.md#discount).
nlohmann::json PolicyChanges(const FiniteMdp& ddn, const FiniteMdp& estimated) {
  ValueIterationOptions vi;
  const Policy a = SolveValueIteration(ddn, vi);
  const Policy b = SolveValueIteration(estimated, vi);
  nlohmann::json changes = nlohmann::json::array();
  for (StateIndex s = 0; s < kCmaNumTupleStates; ++s) {
    if (a.action[static_cast<std::size_t>(s)] == b.action[static_cast<std::size_t>(s)]) continue;
    changes.push_back({{"state", ddn.state_label(s)},
                       {"ddn", ddn.action_name(a.action[static_cast<std::size_t>(s)])},
                       {"estimated", ddn.action_name(b.action[static_cast<std::size_t>(s)])}});
  }
  return changes;
}

nlohmann::json TransitionsDocument(const TransitionOptions& o, const learning::TransitionEstimationOptions& options,
                                   const CmaTransitionCounts& counts,
                                   const learning::TransitionEstimationSummary& summary) {
  const FiniteMdp ddn = BuildCmaMdp(CmaWeights{});
  EstimatedCmaModelStats stats;
  const FiniteMdp estimated = BuildEstimatedCmaMdp(CmaWeights{}, counts, &stats);
  std::vector<RowDivergence> rows = CompareWithDdn(counts, ddn);
  nlohmann::json rows_json = nlohmann::json::array();
  for (const RowDivergence& d : rows) rows_json.push_back(RowJson(d, counts, ddn));
  std::vector<RowDivergence> ranked;
  for (const RowDivergence& d : rows) {
    if (d.samples >= o.min_samples) ranked.push_back(d);
  }
  std::stable_sort(ranked.begin(), ranked.end(), [](const RowDivergence& x, const RowDivergence& y) {
    return x.total_variation > y.total_variation;
  });
  ranked.resize(std::min<std::size_t>(ranked.size(), static_cast<std::size_t>(o.top)));
  nlohmann::json largest = nlohmann::json::array();
  for (const RowDivergence& d : ranked) largest.push_back(RowJson(d, counts, ddn));
  return {{"format", kCmaTransitionsFormat},
          {"provenance",
           {{"runs", options.runs},
            {"seed", std::to_string(options.config.seed)},
            {"campaign_config_hash", campaign::CampaignConfigHash(options.config)},
            {"exploration", options.exploration},
            {"unobserved_row_rule", "the DDN row of Tables 5.1-5.7 (decision/cma_estimated_model.h)"},
            {"divergence",
             {{"total_variation", "0.5 sum |p_est - p_ddn|"},
              {"kl_nats", "KL(p_est || p_ddn), both smoothed (p + 1e-6) / (1 + 112e-6)"},
              {"ranked_rows_min_samples", o.min_samples}}}}},
          {"summary",
           {{"flights", summary.runs},
            {"epochs", summary.epochs},
            {"branches", summary.branches},
            {"explored_epochs", summary.explored},
            {"transitions", counts.Total()},
            {"available_rows", stats.available_rows},
            {"observed_rows", stats.observed_rows},
            {"unobserved_rows", stats.unobserved_rows},
            {"wall_time_s", summary.wall_time_s},
            {"cpu_time_s", summary.cpu_time_s},
            {"estimated_model_hash", ModelHash(estimated)}}},
          {"policy_changes", PolicyChanges(ddn, estimated)},
          {"largest_disagreements", largest},
          {"rows", rows_json},
          {"counts", CmaTransitionCountsToJson(counts)}};
}

void PrintTransitionsSummary(const TransitionOptions& o, const nlohmann::json& document) {
  if (o.json) {
    PrintJson({{"out", o.out},
               {"summary", document["summary"]},
               {"policy_changes", document["policy_changes"]},
               {"largest_disagreements_by_tv", document["largest_disagreements"].size()}});
    return;
  }
  const nlohmann::json& s = document["summary"];
  std::printf(
      "counted %lld transitions at 1 Hz over %lld flights (%lld epochs, %lld one-epoch branches) in %.1f s\n"
      "%d of %d available rows observed (the others keep the DDN row)\n",
      s["transitions"].get<long long>(), s["flights"].get<long long>(), s["epochs"].get<long long>(),
      s["branches"].get<long long>(), s["wall_time_s"].get<double>(), s["observed_rows"].get<int>(),
      s["available_rows"].get<int>());
  std::printf("largest disagreements with the DDN tables (rows with >= %lld samples, by total variation):\n",
              static_cast<long long>(o.min_samples));
  for (const nlohmann::json& row : document["largest_disagreements"]) {
    std::printf("  %-22s %-10s n=%-7lld TV %.3f  KL %.3f nats\n", row["state"].get<std::string>().c_str(),
                row["action"].get<std::string>().c_str(), row["samples"].get<long long>(),
                row["total_variation"].get<double>(), row["kl_nats"].get<double>());
  }
  std::printf(
      "the MDP solved on the estimated rows picks another action than the DDN model's in %zu of 108 "
      "states\nwrote %s\n",
      document["policy_changes"].size(), o.out.c_str());
}

}  // namespace

void AddLearnTransitions(CLI::App* learn) {
  auto o = std::make_shared<TransitionOptions>();
  CLI::App* command = learn->add_subcommand(
      "transitions",
      "Count the CMA MDP's 1 Hz transitions per action over campaign flights (every available action tried\n"
      "from every epoch the flights reach, on one-epoch branches), compare each row with the DDN tables of\n"
      "§5.3.2 and keep the counts. Solve with 'uascma policy solve --model cma --transitions T.json'");
  AddBoundedOption(command, "--runs", o->runs, "Campaign flights", kRunBounds);
  AddSeedOption(command, "--seed", o->seed, "Master seed (default: the campaign's); flight r is campaign run r");
  AddBoundedOption(command, "--jobs", o->jobs, "Threads (the counts do not depend on it)", kLearnJobBounds);
  command->add_option("--out", o->out, "Transitions JSON to write")->required();
  command->add_option("--campaign", o->campaign_file, "Campaign YAML: the distribution of missions, faults, health");
  AddBoundedOption(command, "--exploration", o->exploration,
                   "Per-epoch probability that the flight takes a random non-Terminate action (ours: 0.002)",
                   kLearnProbabilityBounds);
  AddBoundedOption(command, "--top", o->top, "Largest disagreements to list", kTopBounds);
  AddBoundedOption(command, "--min-samples", o->min_samples, "Rows with fewer samples are not ranked",
                   kMinSampleBounds);
  command->add_flag("--json", o->json, "Print the summary as JSON");
  command->callback([o] {
    learning::TransitionEstimationOptions options;
    options.config = ResolveLearningCampaign(o->campaign_file, o->seed);
    options.runs = o->runs;
    options.jobs = o->jobs;
    options.exploration = o->exploration;
    learning::TransitionEstimationSummary summary;
    CmaTransitionCounts counts;
    {
      ProgressBar bar(o->runs, "learn transitions");
      options.on_run_done = [&bar](std::int64_t) { bar.Advance(); };
      counts = learning::EstimateCmaTransitions(options, &summary);
      bar.Finish();
    }
    const nlohmann::json document = TransitionsDocument(*o, options, counts, summary);
    WriteFileAtomically(o->out, document.dump(1) + "\n");
    PrintTransitionsSummary(*o, document);
  });
}

}  // namespace uascma::cli
