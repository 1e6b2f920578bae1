// What `uascma learn transitions` writes and prints (learning/transition_report.h): the file's summary, rows and
// ranking against counts made here, a row's total variation against the DDN row computed here, and no policy change
// without counts (the estimated model is then the DDN's).
#include "uascma/learning/transition_report.h"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "uascma/decision/cma_mdp.h"

namespace uascma::learning {
namespace {

using decision::ActionIndex;
using decision::CmaTransitionCounts;
using decision::StateIndex;

constexpr double kDivergenceTolerance = 1e-12;  // dimensionless: the same sum computed twice

int Lines(const std::string& text) {
  int lines = 0;
  for (char c : text) lines += c == '\n';
  return lines;
}

TEST(TransitionReportTest, NoCountsChangeNoAction) {
  const CmaTransitionCounts counts;
  const nlohmann::json document = CmaTransitionsDocument({}, counts, {}, TransitionRanking{});
  EXPECT_EQ(document.at("format"), decision::kCmaTransitionsFormat);
  EXPECT_TRUE(document.at("policy_changes").empty());
  EXPECT_TRUE(document.at("rows").empty());
  EXPECT_EQ(document.at("summary").at("observed_rows"), 0);
  EXPECT_EQ(document.at("summary").at("transitions"), 0);
  // Text: the counts (2 lines), the ranking's heading, no rows, the policy changes and the file (2 lines).
  EXPECT_EQ(Lines(CmaTransitionsSummaryText(document, TransitionRanking{}, "t.json")), 5);
}

TEST(TransitionReportTest, RowsAreComparedWithTheDdnAndRanked) {
  const decision::FiniteMdp ddn = decision::BuildCmaMdp({});
  const StateIndex start = decision::CmaStateIndex({});
  const auto noop = static_cast<ActionIndex>(decision::CmaAction::kNoOp);
  const auto land = static_cast<ActionIndex>(decision::CmaAction::kLandPract);
  const StateIndex crash = decision::CmaTerminalIndex(decision::CmaTerminal::kFL);
  CmaTransitionCounts counts;
  counts.Add(start, noop, crash, 40);  // every NoOp from the nominal state ends in FL: far from the DDN row
  counts.Add(start, land, start, 5);   // too few samples to be ranked with min_samples 30
  const TransitionRanking ranking{.top = 10, .min_samples = 30};
  const nlohmann::json document = CmaTransitionsDocument({}, counts, {}, ranking);
  EXPECT_EQ(document.at("summary").at("transitions"), 45);
  EXPECT_EQ(document.at("summary").at("observed_rows"), 2);
  ASSERT_EQ(document.at("rows").size(), 2u);
  ASSERT_EQ(document.at("largest_disagreements").size(), 1u);
  const nlohmann::json& row = document["largest_disagreements"][0];
  EXPECT_EQ(row.at("state"), ddn.state_label(start));
  EXPECT_EQ(row.at("action"), "NoOp");
  EXPECT_EQ(row.at("samples"), 40);
  // TV = 0.5 Σ |p_est − p_ddn| with p_est all on FL: 0.5 ((1 − p_ddn(FL)) + Σ_{n ≠ FL} p_ddn(n)) = 1 − p_ddn(FL).
  const double ddn_fl = decision::DenseRow(ddn, start, noop)[static_cast<std::size_t>(crash)];
  EXPECT_NEAR(row.at("total_variation").get<double>(), 1.0 - ddn_fl, kDivergenceTolerance);
  EXPECT_EQ(row.at("estimated").size(), 1u);
  const std::string text = CmaTransitionsSummaryText(document, ranking, "t.json");
  EXPECT_EQ(Lines(text), 6);
  EXPECT_NE(text.find("rows with >= 30 samples"), std::string::npos) << text;
  EXPECT_EQ(CmaTransitionsSummaryJson(document, "t.json").at("largest_disagreements_by_tv"), 1);
}

}  // namespace
}  // namespace uascma::learning
