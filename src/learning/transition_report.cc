// What `uascma learn transitions` writes and prints (transition_report.h, §5.6).
#include "uascma/learning/transition_report.h"

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "uascma/campaign/config.h"
#include "uascma/decision/cma_mdp.h"
#include "uascma/decision/policy_file.h"
#include "uascma/decision/solvers.h"

namespace uascma::learning {
namespace {

using decision::CmaTransitionCounts;
using decision::FiniteMdp;
using decision::RowDivergence;
using decision::StateIndex;

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
          {"estimated", Distribution(decision::EstimatedRow(counts, d.state, d.action), ddn)},
          {"ddn", Distribution(decision::DenseRow(ddn, d.state, d.action), ddn)}};
}

// The states whose optimal action differs between the DDN model and the estimated one (γ = 0.95,
// docs/modelling-choices.md#discount).
nlohmann::json PolicyChanges(const FiniteMdp& ddn, const FiniteMdp& estimated) {
  decision::ValueIterationOptions vi;
  const decision::Policy a = decision::SolveValueIteration(ddn, vi);
  const decision::Policy b = decision::SolveValueIteration(estimated, vi);
  nlohmann::json changes = nlohmann::json::array();
  for (StateIndex s = 0; s < decision::kCmaNumTupleStates; ++s) {
    if (a.action[static_cast<std::size_t>(s)] == b.action[static_cast<std::size_t>(s)]) continue;
    changes.push_back({{"state", ddn.state_label(s)},
                       {"ddn", ddn.action_name(a.action[static_cast<std::size_t>(s)])},
                       {"estimated", ddn.action_name(b.action[static_cast<std::size_t>(s)])}});
  }
  return changes;
}

// The `ranking.top` rows of the largest total variation among those of at least `ranking.min_samples` samples.
nlohmann::json LargestDisagreements(const std::vector<RowDivergence>& rows, const CmaTransitionCounts& counts,
                                    const FiniteMdp& ddn, const TransitionRanking& ranking) {
  std::vector<RowDivergence> ranked;
  for (const RowDivergence& d : rows) {
    if (d.samples >= ranking.min_samples) ranked.push_back(d);
  }
  std::stable_sort(ranked.begin(), ranked.end(), [](const RowDivergence& x, const RowDivergence& y) {
    return x.total_variation > y.total_variation;
  });
  ranked.resize(std::min<std::size_t>(ranked.size(), static_cast<std::size_t>(ranking.top)));
  nlohmann::json largest = nlohmann::json::array();
  for (const RowDivergence& d : ranked) largest.push_back(RowJson(d, counts, ddn));
  return largest;
}

}  // namespace

nlohmann::json CmaTransitionsDocument(const TransitionEstimationOptions& options, const CmaTransitionCounts& counts,
                                      const TransitionEstimationSummary& summary, const TransitionRanking& ranking) {
  const FiniteMdp ddn = decision::BuildCmaMdp(decision::CmaWeights{});
  decision::EstimatedCmaModelStats stats;
  const FiniteMdp estimated = decision::BuildEstimatedCmaMdp(decision::CmaWeights{}, counts, &stats);
  const std::vector<RowDivergence> rows = decision::CompareWithDdn(counts, ddn);
  nlohmann::json rows_json = nlohmann::json::array();
  for (const RowDivergence& d : rows) rows_json.push_back(RowJson(d, counts, ddn));
  return {{"format", decision::kCmaTransitionsFormat},
          {"provenance",
           {{"runs", options.runs},
            {"seed", std::to_string(options.config.seed)},
            {"campaign_config_hash", campaign::CampaignConfigHash(options.config)},
            {"exploration", options.exploration},
            {"unobserved_row_rule", "the DDN row of Tables 5.1-5.7 (decision/cma_estimated_model.h)"},
            {"divergence",
             {{"total_variation", "0.5 sum |p_est - p_ddn|"},
              {"kl_nats", "KL(p_est || p_ddn), both smoothed (p + 1e-6) / (1 + 112e-6)"},
              {"ranked_rows_min_samples", ranking.min_samples}}}}},
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
            {"estimated_model_hash", decision::ModelHash(estimated)}}},
          {"policy_changes", PolicyChanges(ddn, estimated)},
          {"largest_disagreements", LargestDisagreements(rows, counts, ddn, ranking)},
          {"rows", rows_json},
          {"counts", decision::CmaTransitionCountsToJson(counts)}};
}

nlohmann::json CmaTransitionsSummaryJson(const nlohmann::json& document, const std::string& out) {
  return {{"out", out},
          {"summary", document["summary"]},
          {"policy_changes", document["policy_changes"]},
          {"largest_disagreements_by_tv", document["largest_disagreements"].size()}};
}

std::string CmaTransitionsSummaryText(const nlohmann::json& document, const TransitionRanking& ranking,
                                      const std::string& out) {
  const nlohmann::json& s = document["summary"];
  std::string text = fmt::format(
      "counted {} transitions at 1 Hz over {} flights ({} epochs, {} one-epoch branches) in {:.1f} s\n"
      "{} of {} available rows observed (the others keep the DDN row)\n",
      s["transitions"].get<long long>(), s["flights"].get<long long>(), s["epochs"].get<long long>(),
      s["branches"].get<long long>(), s["wall_time_s"].get<double>(), s["observed_rows"].get<int>(),
      s["available_rows"].get<int>());
  text += fmt::format("largest disagreements with the DDN tables (rows with >= {} samples, by total variation):\n",
                      static_cast<long long>(ranking.min_samples));
  for (const nlohmann::json& row : document["largest_disagreements"]) {
    text += fmt::format("  {:<22} {:<10} n={:<7} TV {:.3f}  KL {:.3f} nats\n", row["state"].get<std::string>(),
                        row["action"].get<std::string>(), row["samples"].get<long long>(),
                        row["total_variation"].get<double>(), row["kl_nats"].get<double>());
  }
  text += fmt::format(
      "the MDP solved on the estimated rows picks another action than the DDN model's in {} of 108 "
      "states\nwrote {}\n",
      document["policy_changes"].size(), out);
  return text;
}

}  // namespace uascma::learning
