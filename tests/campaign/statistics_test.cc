// Campaign statistics (§5.5.3): the SEM formulas checked by hand and the summary of hand-made records.
#include "uascma/campaign/statistics.h"

#include <gtest/gtest.h>

#include <cmath>

namespace uascma::campaign {
namespace {

constexpr double kTolerance = 1e-12;

RunRecord Flight(const std::string& policy, const std::string& health, const std::string& outcome, double average,
                 double minimum) {
  RunRecord r;
  r.policy = policy;
  r.battery_health = health;
  r.outcome = outcome;
  r.failure = outcome.rfind("failed", 0) == 0 || outcome == "timeout";
  r.average_reward = average;
  r.min_reward = minimum;
  return r;
}

TEST(StatisticsTest, BinomialSemByHand) {
  // 3 failures in 10: p = 0.3, SEM = √(0.3 · 0.7 / 10) = √0.021 = 0.144913767…
  const Estimate e = EstimateRate(3, 10);
  EXPECT_NEAR(e.value, 0.3, kTolerance);
  EXPECT_NEAR(e.sem, 0.14491376746189438, kTolerance);
  // All or nothing: no spread.
  EXPECT_NEAR(EstimateRate(0, 7).sem, 0.0, kTolerance);
  EXPECT_NEAR(EstimateRate(7, 7).sem, 0.0, kTolerance);
  EXPECT_TRUE(std::isnan(EstimateRate(0, 0).value));
}

TEST(StatisticsTest, MeanSemByHand) {
  // {1, 2, 3, 6}: mean 3, s² = (4 + 1 + 0 + 9) / 3 = 14/3, SEM = √(14/3) / 2 = 1.0801234…
  const Estimate e = EstimateMean({1.0, 2.0, 3.0, 6.0});
  EXPECT_NEAR(e.value, 3.0, kTolerance);
  EXPECT_NEAR(e.sem, std::sqrt(14.0 / 3.0) / 2.0, kTolerance);
  EXPECT_NEAR(EstimateMean({2.5}).sem, 0.0, kTolerance);
  EXPECT_TRUE(std::isnan(EstimateMean({}).value));
}

std::vector<RunRecord> HandMadeCampaign() {
  return {
      // cma: P → 1 failure of 4, 1 completion, 1 emergency landing, 1 termination; G → 1 completion.
      Flight("cma", "P", "failed_battery", -0.1, -0.4),
      Flight("cma", "P", "completed", 0.2, 0.1),
      Flight("cma", "P", "emergency_landing", 0.3, 0.1),
      Flight("cma", "P", "terminated", 0.1, 0.0),
      Flight("cma", "G", "completed", 0.4, 0.2),
      // noop: P → 3 failures of 4 (one of each failure kind but control), G → 1 completion.
      Flight("noop", "P", "failed_battery", -0.2, -0.4),
      Flight("noop", "P", "failed_collision", -0.2, -0.4),
      Flight("noop", "P", "timeout", -0.1, -0.4),
      Flight("noop", "P", "completed", 0.3, 0.1),
      Flight("noop", "G", "completed", 0.4, 0.2),
  };
}

const GroupStatistics& Find(const std::vector<GroupStatistics>& groups, const std::string& policy,
                            const std::string& health) {
  for (const auto& g : groups) {
    if (g.policy == policy && g.battery_health == health) return g;
  }
  static GroupStatistics none;
  ADD_FAILURE() << "no group " << policy << " " << health;
  return none;
}

TEST(StatisticsTest, HandMadeCampaignGivesTheExpectedTable) {
  const auto groups = Summarise(HandMadeCampaign(), {"noop", "cma"});
  ASSERT_EQ(groups.size(), 8u);  // 2 policies × G, M, P, all
  EXPECT_EQ(groups.front().policy, "noop");  // the requested order
  const GroupStatistics& cma_p = Find(groups, "cma", "P");
  EXPECT_EQ(cma_p.runs, 4);
  EXPECT_NEAR(cma_p.failure_rate.value, 0.25, kTolerance);
  EXPECT_NEAR(cma_p.failure_rate.sem, std::sqrt(0.25 * 0.75 / 4.0), kTolerance);
  EXPECT_NEAR(cma_p.completion_rate.value, 0.25, kTolerance);
  EXPECT_NEAR(cma_p.emergency_landing_rate.value, 0.25, kTolerance);
  EXPECT_NEAR(cma_p.termination_rate.value, 0.25, kTolerance);
  EXPECT_NEAR(cma_p.average_reward.value, 0.125, kTolerance);
  EXPECT_NEAR(cma_p.min_reward.value, -0.05, kTolerance);
  const GroupStatistics& noop_p = Find(groups, "noop", "P");
  EXPECT_EQ(noop_p.failures, 3);
  EXPECT_NEAR(noop_p.failure_rate.value, 0.75, kTolerance);
  EXPECT_NEAR(noop_p.completion_rate.value, 0.25, kTolerance);
  const GroupStatistics& noop_m = Find(groups, "noop", "M");
  EXPECT_EQ(noop_m.runs, 0);
  EXPECT_TRUE(std::isnan(noop_m.failure_rate.value));
  const GroupStatistics& cma_all = Find(groups, "cma", "all");
  EXPECT_EQ(cma_all.runs, 5);
  EXPECT_NEAR(cma_all.completion_rate.value, 0.4, kTolerance);
  // Rates of a group sum to one.
  for (const auto& g : groups) {
    if (g.runs == 0) continue;
    EXPECT_NEAR(g.failure_rate.value + g.completion_rate.value + g.emergency_landing_rate.value +
                    g.termination_rate.value, 1.0, kTolerance);
  }
}

TEST(StatisticsTest, JsonAndTableCarryTheFigures) {
  const auto groups = Summarise(HandMadeCampaign(), {"cma", "noop"});
  const nlohmann::json json = StatisticsToJson(groups);
  EXPECT_EQ(json["policies"]["noop"]["P"]["runs"], 4);
  EXPECT_NEAR(json["policies"]["noop"]["P"]["failure_rate"].get<double>(), 0.75, kTolerance);
  EXPECT_NEAR(json["policies"]["noop"]["P"]["failure_rate_sem"].get<double>(), std::sqrt(0.75 * 0.25 / 4.0),
              kTolerance);
  EXPECT_TRUE(json["policies"]["cma"]["M"]["failure_rate"].is_null());
  EXPECT_NEAR(json["dissertation"]["poor_health_failure_rate"]["noop"].get<double>(), 0.71, kTolerance);
  const std::string table = StatisticsTable(groups);
  EXPECT_NE(table.find(" 75.0 ± 21.7"), std::string::npos) << table;  // noop P: 75 % ± 21.65 %
  EXPECT_NE(table.find("dissertation  71.0 %"), std::string::npos) << table;
}

}  // namespace
}  // namespace uascma::campaign
