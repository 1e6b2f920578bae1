// The headline experiment (dissertation §5.5.3, Figs. 5.30–5.31; issue 11): every failure in a campaign comes
// from a modelled fault, and battery health drives the baseline's failures. Campaigns are seeded, so these are
// also regression tests of our published figures (README "Where we differ").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "uascma/campaign/runner.h"
#include "uascma/campaign/statistics.h"

namespace uascma::campaign {
namespace {

std::vector<RunRecord> Fly(const CampaignConfig& config) {
  const std::vector<CampaignPolicy> policies = {SolvedCmaPolicy(), NoOpCampaignPolicy()};
  ExecuteOptions options;
  options.jobs = 2;
  std::vector<RunRecord> records;
  ExecuteFlights(config, policies, MissingFlights(config.runs, policies, {}), options,
                 [&records](std::vector<RunRecord>&& batch) {
                   records.insert(records.end(), batch.begin(), batch.end());
                 });
  return records;
}

const GroupStatistics& Group(const std::vector<GroupStatistics>& groups, const std::string& policy,
                             const std::string& health) {
  const auto it = std::find_if(groups.begin(), groups.end(), [&](const GroupStatistics& g) {
    return g.policy == policy && g.battery_health == health;
  });
  EXPECT_NE(it, groups.end()) << policy << " " << health;
  return *it;
}

// Decisions items 19–20: a plan a healthy pack flies with its safety margin, no motor fault — nothing fails. The
// CMA's state is N,NF,MM1,G,RM1 unless its 1 Hz EOD, propagated at the present (10 s low-passed) current as
// decisions item 14 says, reads a gusty stretch of a long, fast or cold plan as the load of the rest of the flight
// and judges RM0: measured at seed 1, 1 of these 150 flights and 8 of 600 (1.3 %, all with plans above 0.81 of the
// healthy pack's endurance at 6–9 m/s in cold air or medium-moderate gusts) land on LandPract. Issue 11 asks for
// none; README "Where we differ" has the trade-off (a slower filter misses Scenario I's jam). This test holds the
// failures at zero and the false landings at the measured rate.
TEST(HeadlineTest, HealthyPacksWithoutMotorFaultsNeverFail) {
  CampaignConfig config;
  config.runs = 150;
  config.battery.health_weights = {1.0, 0.0, 0.0};
  config.fault.probability = 0.0;
  const std::vector<RunRecord> records = Fly(config);
  ASSERT_EQ(records.size(), 300u);
  int cma_landings = 0;
  for (const RunRecord& r : records) {
    EXPECT_FALSE(r.failure) << r.policy << " run " << r.run_index << ": " << r.outcome << ", " << r.reason;
    if (r.policy == "noop") {
      EXPECT_EQ(r.outcome, "completed") << "run " << r.run_index << ": " << r.reason;
    } else if (r.outcome != "completed") {
      EXPECT_EQ(r.outcome, "emergency_landing") << "run " << r.run_index << ": " << r.reason;
      EXPECT_EQ(r.first_emergency_action, "LandPract") << "run " << r.run_index;
      ++cma_landings;
    }
  }
  EXPECT_LE(cma_landings, 2) << "the CMA's false landings in healthy fault-free flights (measured: 1 of 150)";
}

// The default campaign of §5.5 (930 flights, seed 1).
TEST(HeadlineTest, DefaultCampaignFailsOnlyFromModelledFaultsAndHealthDrivesTheBaseline) {
  const CampaignConfig config;
  ASSERT_EQ(config.runs * 2, 930);
  const std::vector<RunRecord> records = Fly(config);
  ASSERT_EQ(records.size(), 930u);
  // A flight without a motor fault fails only on its battery (a degraded pack): no collision, no loss of control.
  for (const RunRecord& r : records) {
    if (r.failure && !r.fault) {
      EXPECT_EQ(r.outcome, "failed_battery") << r.policy << " run " << r.run_index << ": " << r.reason;
      EXPECT_NE(r.battery_health, "G") << r.policy << " run " << r.run_index << ": " << r.reason;
    }
  }
  const std::vector<GroupStatistics> groups = Summarise(records, {"cma", "noop"});
  // NoOp's failure rate rises G → M → P, each gap larger than the standard error of the difference.
  const Estimate g = Group(groups, "noop", "G").failure_rate, m = Group(groups, "noop", "M").failure_rate,
                 p = Group(groups, "noop", "P").failure_rate;
  EXPECT_GT(m.value - g.value, std::hypot(m.sem, g.sem)) << "G " << g.value << " M " << m.value;
  EXPECT_GT(p.value - m.value, std::hypot(p.sem, m.sem)) << "M " << m.value << " P " << p.value;
  // CMA fails in a small fraction of NoOp's poor-health failures (dissertation: 1.3 % against 71 %) …
  const GroupStatistics& cma_p = Group(groups, "cma", "P");
  const GroupStatistics& noop_p = Group(groups, "noop", "P");
  EXPECT_GT(noop_p.failures, 10);
  EXPECT_LE(cma_p.failures * 10, noop_p.failures);
  // … and completes fewer original plans in good health (Fig. 5.31: it lands on a spall's MM0).
  EXPECT_LT(Group(groups, "cma", "G").completion_rate.value, Group(groups, "noop", "G").completion_rate.value);
}

}  // namespace
}  // namespace uascma::campaign
