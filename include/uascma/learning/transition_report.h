#pragma once
// What `uascma learn transitions` writes and prints (dissertation §5.6, §5.3.2.3): the transitions file, holding the
// counts of transition_estimation.h with their provenance, each observed row compared with the DDN tables of §5.3.2
// (decision/cma_estimated_model.h: CompareWithDdn), the rows that disagree most, and the states whose optimal action
// changes when the MDP is solved on the estimated rows; and its summary as JSON and text.
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "uascma/decision/cma_estimated_model.h"
#include "uascma/learning/transition_estimation.h"

namespace uascma::learning {

// Which rows the file ranks: the `top` largest total variations among the rows of at least `min_samples` samples.
struct TransitionRanking {
  int top = 10;
  std::int64_t min_samples = 30;
};

// The transitions file: {"format": kCmaTransitionsFormat, "provenance", "summary", "policy_changes",
// "largest_disagreements", "rows", "counts"}. The policy changes compare value iteration at γ = 0.95
// (docs/modelling-choices.md#discount) on the DDN rows and on the estimated ones, over the 108 non-terminal states.
nlohmann::json CmaTransitionsDocument(const TransitionEstimationOptions& options,
                                      const decision::CmaTransitionCounts& counts,
                                      const TransitionEstimationSummary& summary, const TransitionRanking& ranking);
// The summary of a document written to `out`, as `--json` prints it.
nlohmann::json CmaTransitionsSummaryJson(const nlohmann::json& document, const std::string& out);
// The same as text: the counts, the rows observed, the largest disagreements and the policy changes.
std::string CmaTransitionsSummaryText(const nlohmann::json& document, const TransitionRanking& ranking,
                                      const std::string& out);

}  // namespace uascma::learning
