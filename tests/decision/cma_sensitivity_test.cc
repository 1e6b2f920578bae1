// The reward-weight sweep of §5.3.2.5 (decision/cma_sensitivity.h): its steps, its weights and its changes against
// the base policy, checked against the quadrant view of policies solved here.
#include "uascma/decision/cma_sensitivity.h"

#include <cmath>
#include <cstddef>
#include <string>

#include <gtest/gtest.h>

#include "uascma/decision/solvers.h"

namespace uascma::decision {
namespace {

constexpr double kWeightSumTolerance = 1e-12;  // dimensionless: eq. 5.22's renormalised weights sum to one

std::vector<QuadrantRow> SolvedView(const CmaWeights& weights, double gamma) {
  ValueIterationOptions options;
  options.gamma = gamma;
  const Policy policy = SolveValueIteration(BuildCmaMdp(weights), options, nullptr);
  return CmaQuadrantView(policy.action, policy.value);
}

TEST(CmaSensitivityTest, StepsCoverTheRangeWithRenormalisedWeights) {
  const CmaConfig base;
  const auto steps = SweepCmaWeight(base, "MM", 0.0, 0.2, 0.05);
  ASSERT_EQ(steps.size(), 5u);  // 0, 0.05, …, 0.2: the last one kept
  for (std::size_t i = 0; i < steps.size(); ++i) {
    EXPECT_EQ(steps[i].value, 0.05 * static_cast<double>(i));  // from + i · step, bit for bit
    EXPECT_EQ(steps[i].weights.MM, steps[i].value);
    EXPECT_NEAR(steps[i].weights.Sum(), 1.0, kWeightSumTolerance);
  }
}

TEST(CmaSensitivityTest, TheBaseWeightChangesNothing) {
  const CmaConfig base;
  const auto steps = SweepCmaWeight(base, "MM", base.weights.MM, base.weights.MM, 0.01);
  ASSERT_EQ(steps.size(), 1u);
  EXPECT_TRUE(steps[0].changes.empty());
}

TEST(CmaSensitivityTest, ChangesAreTheQuadrantCellsWhoseActionDiffers) {
  const CmaConfig base;
  const auto steps = SweepCmaWeight(base, "MM", 0.0, 0.0, 0.01);  // Fig. 5.12: w_MM = 0
  ASSERT_EQ(steps.size(), 1u);
  const FiniteMdp mdp = BuildCmaMdp(base.weights);
  const auto before = SolvedView(base.weights, base.gamma);
  const auto after = SolvedView(steps[0].weights, base.gamma);
  std::size_t differing = 0;
  for (std::size_t r = 0; r < before.size(); ++r) {
    for (int q = 0; q < 4; ++q) {
      if (before[r].quadrants[q].action == after[r].quadrants[q].action) continue;
      ASSERT_LT(differing, steps[0].changes.size());
      const CmaPolicyChange& change = steps[0].changes[differing++];
      EXPECT_EQ(change.state, CmaStateLabel(after[r].quadrants[q].state));
      EXPECT_STREQ(change.quadrant, kQuadrantNames[q]);
      EXPECT_EQ(change.from, mdp.action_name(before[r].quadrants[q].action));
      EXPECT_EQ(change.to, mdp.action_name(after[r].quadrants[q].action));
    }
  }
  EXPECT_EQ(differing, steps[0].changes.size());
  EXPECT_GT(differing, 0u);  // §5.3.2.5: without w_MM the policy no longer lands in the nominal Quad II
}

TEST(CmaSensitivityTest, JsonAndTextListEveryStepAndChange) {
  const CmaConfig base;
  const auto steps = SweepCmaWeight(base, "MM", 0.0, 0.1, 0.05);
  std::size_t changes = 0;
  for (const CmaSensitivityStep& step : steps) changes += step.changes.size();
  ASSERT_GT(changes, 0u);  // w_MM = 0 changes the policy (the test above)
  const nlohmann::json json = CmaSensitivityJson(base, "MM", steps);
  EXPECT_EQ(json.at("weight"), "MM");
  ASSERT_EQ(json.at("steps").size(), steps.size());
  for (std::size_t i = 0; i < steps.size(); ++i) {
    EXPECT_EQ(json["steps"][i].at("value").get<double>(), steps[i].value);
    ASSERT_EQ(json["steps"][i].at("changes").size(), steps[i].changes.size());
    for (std::size_t k = 0; k < steps[i].changes.size(); ++k) {
      EXPECT_EQ(json["steps"][i]["changes"][k].at("to"), steps[i].changes[k].to);
    }
  }
  // The text: a heading, a line per step and a line per change.
  const std::string text = CmaSensitivityText("MM", 0.0, 0.1, steps);
  std::size_t lines = 0;
  for (char c : text) lines += c == '\n';
  EXPECT_EQ(lines, 1 + steps.size() + changes);
  EXPECT_EQ(text.rfind("Sweep of w_MM from 0 to 0.1 ", 0), 0u) << text;
}

}  // namespace
}  // namespace uascma::decision
