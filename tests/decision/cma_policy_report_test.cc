// What `uascma policy` reports of the CMA MDP (decision/cma_policy_report.h): the transition rows against the model's
// own rows, value iteration against policy iteration, the TSV and the policy file against the solved policy, and the
// quadrant view of a written file against the one of the policy solved here.
#include "uascma/decision/cma_policy_report.h"

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "uascma/common/files.h"

namespace uascma::decision {
namespace {

constexpr double kRowSumTolerance = 1e-9;       // dimensionless: a row printed to 10 significant digits sums to one
constexpr double kPrintedRelative = 1e-9;       // dimensionless: a number printed to 10 significant digits
constexpr double kSolverValueTolerance = 1e-6;  // value units: value iteration stops at a residual below 1e-10

std::vector<std::vector<std::string>> TsvFields(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    std::vector<std::string> fields;
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, '\t');) fields.push_back(cell);
    rows.push_back(std::move(fields));
  }
  return rows;
}

TEST(CmaPolicyReportTest, TransitionRowsAreTheModelsRowsAndSumToOne) {
  const FiniteMdp mdp = BuildCmaMdp({});
  for (ActionIndex a = 0; a < mdp.num_actions(); ++a) {
    std::map<std::string, double> row_sums;
    for (const auto& fields : TsvFields(TransitionRowsTsv(mdp, a))) {
      ASSERT_EQ(fields.size(), 3u);
      ASSERT_GE(mdp.FindState(fields[0]), 0) << fields[0];
      ASSERT_GE(mdp.FindState(fields[1]), 0) << fields[1];
      row_sums[fields[0]] += std::stod(fields[2]);
    }
    int available = 0;
    for (StateIndex s = 0; s < mdp.num_states(); ++s) {
      if (mdp.FindChoice(s, a) < 0) {
        EXPECT_EQ(row_sums.count(mdp.state_label(s)), 0u) << mdp.state_label(s);
        continue;
      }
      ++available;
      EXPECT_NEAR(row_sums[mdp.state_label(s)], 1.0, kRowSumTolerance) << mdp.state_label(s);
    }
    EXPECT_EQ(static_cast<int>(row_sums.size()), available) << mdp.action_name(a);
    EXPECT_GT(available, 0) << mdp.action_name(a);
  }
}

TEST(CmaPolicyReportTest, ValueAndPolicyIterationAgree) {
  const CmaSolution vi = SolveCma(CmaConfig{}, CmaSolveMethod::kValueIteration);
  const CmaSolution pi = SolveCma(CmaConfig{}, CmaSolveMethod::kPolicyIteration);
  EXPECT_EQ(vi.policy.action, pi.policy.action);
  for (StateIndex s = 0; s < vi.mdp.num_states(); ++s) {
    EXPECT_NEAR(vi.policy.value[s], pi.policy.value[s], kSolverValueTolerance) << vi.mdp.state_label(s);
  }
  EXPECT_EQ(vi.model_config.count("transition_counts"), 0u);
  EXPECT_EQ(vi.model_config.at("weights").size(), pi.model_config.at("weights").size());
}

TEST(CmaPolicyReportTest, TsvListsTheNonTerminalStatesWithTheirActionAndValue) {
  const CmaSolution solution = SolveCma(CmaConfig{}, CmaSolveMethod::kValueIteration);
  const auto rows = TsvFields(CmaPolicyTsv(solution));
  ASSERT_EQ(static_cast<int>(rows.size()), kCmaNumTupleStates);
  for (StateIndex s = 0; s < kCmaNumTupleStates; ++s) {
    ASSERT_EQ(rows[s].size(), 3u);
    EXPECT_EQ(rows[s][0], solution.mdp.state_label(s));
    EXPECT_EQ(rows[s][1], solution.mdp.action_name(solution.policy.action[s]));
    const double value = solution.policy.value[s];
    EXPECT_NEAR(std::stod(rows[s][2]), value, kPrintedRelative * std::abs(value)) << rows[s][0];
  }
}

TEST(CmaPolicyReportTest, AWrittenPolicyFileShowsTheSolvedPolicysQuadrants) {
  const CmaSolution solution = SolveCma(CmaConfig{}, CmaSolveMethod::kPolicyIteration);
  char pattern[] = "/tmp/cma_policy_report_test_XXXXXX";
  ASSERT_NE(::mkdtemp(pattern), nullptr);
  const std::filesystem::path file = std::filesystem::path(pattern) / "policy.json";
  WriteFileAtomically(file, CmaPolicyFileJson(solution));
  const CmaPolicyView view = LoadCmaPolicyView(file.string(), "");
  std::filesystem::remove_all(pattern);
  EXPECT_EQ(view.document.model_hash, ModelHash(solution.mdp));
  EXPECT_EQ(view.policy.action, solution.policy.action);
  const auto expected = CmaQuadrantView(solution.policy.action, solution.policy.value);
  ASSERT_EQ(view.rows.size(), expected.size());
  const nlohmann::json json = CmaPolicyViewJson(view);
  ASSERT_EQ(json.at("rows").size(), expected.size());
  for (std::size_t r = 0; r < expected.size(); ++r) {
    for (int q = 0; q < 4; ++q) {
      const nlohmann::json& cell = json["rows"][r][kQuadrantNames[q]];
      EXPECT_EQ(cell.at("state"), CmaStateLabel(expected[r].quadrants[q].state));
      EXPECT_EQ(cell.at("action"), solution.mdp.action_name(expected[r].quadrants[q].action));
    }
  }
  // The text: a heading, two header lines and a rule, then one line per row and a blank line between FS groups.
  const std::string text = CmaPolicyViewText(view, "policy.json");
  int lines = 0;
  for (char c : text) lines += c == '\n';
  EXPECT_EQ(lines, 2 + 3 + static_cast<int>(expected.size()) + 2);
  EXPECT_EQ(text.rfind("CMA policy policy.json (model " + view.document.model_hash + ", gamma 0.95)\n", 0), 0u);
}

TEST(CmaPolicyReportTest, TheVehicleModelIsShownWithItsOwnHash) {
  const CmaPolicyView view = LoadCmaPolicyView(kCmaVehiclePolicyName, "");
  EXPECT_EQ(view.document.model_hash, ModelHash(view.mdp));
  EXPECT_NE(view.document.model_hash, ModelHash(BuildCmaMdp({})));
  EXPECT_EQ(view.rows.size(), CmaQuadrantView(view.policy.action, view.policy.value).size());
}

}  // namespace
}  // namespace uascma::decision
