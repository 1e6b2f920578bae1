// The headline experiment (dissertation §5.5.3, Figs. 5.30–5.31): every failure in a campaign comes
// from a modelled fault, and battery health drives the baseline's failures. Campaigns are seeded, so these are
// also regression tests of our published figures (README "Where we differ").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "uascma/campaign/runner.h"
#include "uascma/campaign/statistics.h"

namespace uascma::campaign {
namespace {

std::vector<RunRecord> Fly(const CampaignConfig& config) {
  const std::vector<CampaignPolicy> policies = {SolvedCmaPolicy(), NoOpCampaignPolicy()};
  ExecuteOptions options;
  options.jobs = 2;
  std::vector<RunRecord> records;
  ExecuteFlights(
      config, policies, MissingFlights(config.runs, policies, {}), options,
      [&records](std::vector<RunRecord>&& batch) { records.insert(records.end(), batch.begin(), batch.end()); });
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

// docs/modelling-choices.md#campaign-missions, #battery-health-draw: a plan a healthy pack flies with its safety
// margin, no motor fault — nothing fails, and with the 1 Hz EOD propagated at the expected load of the rest of the plan
// (docs/modelling-choices.md#eod-load-forecast) the CMA never lands or grounds such a flight (measured 0 of 600 at
// seeds 1 and 2; with the present current of docs/modelling-choices.md#pack-eod, 8 of 600 landed at seed 1).
TEST(HeadlineTest, HealthyPacksWithoutMotorFaultsNeverFailAndAreNeverLanded) {
  CampaignConfig config;
  config.runs = 150;
  config.battery.health_weights = {1.0, 0.0, 0.0};
  config.fault.probability = 0.0;
  const std::vector<RunRecord> records = Fly(config);
  ASSERT_EQ(records.size(), 300u);
  for (const RunRecord& r : records) {
    EXPECT_EQ(r.outcome, "completed") << r.policy << " run " << r.run_index << ": " << r.reason;
    EXPECT_EQ(r.first_emergency_action, "") << r.policy << " run " << r.run_index;
  }
}

// The default campaign of §5.5 (930 flights, seed 1).
TEST(HeadlineTest, DefaultCampaignFailsOnlyFromModelledFaultsAndHealthDrivesTheBaseline) {
  const CampaignConfig config;
  ASSERT_EQ(config.runs * 2, 930);
  const std::vector<RunRecord> records = Fly(config);
  ASSERT_EQ(records.size(), 930u);
  // A flight without a motor fault fails only on its battery (a degraded pack): no collision, no loss of control.
  // With a jam, guidance keeps the quadcopter within its authority (§4.4.2): no loss of control either. Every
  // emergency decision of the CMA executes a plan or records a substitution
  // (docs/modelling-choices.md#unavailable-actions).
  std::map<std::int64_t, const RunRecord*> noop;
  for (const RunRecord& r : records) {
    if (r.policy == "noop") noop[r.run_index] = &r;
  }
  int early_landings_in_good_health = 0, good_health = 0;
  for (const RunRecord& r : records) {
    EXPECT_NE(r.outcome, "failed_control") << r.policy << " run " << r.run_index << ": " << r.reason;
    if (r.failure && !r.fault) {
      EXPECT_EQ(r.outcome, "failed_battery") << r.policy << " run " << r.run_index << ": " << r.reason;
      EXPECT_NE(r.battery_health, "G") << r.policy << " run " << r.run_index << ": " << r.reason;
    }
    if (r.policy != "cma") continue;
    EXPECT_FALSE(r.failure) << "run " << r.run_index << ": " << r.reason;  // measured: 0 in every health group
    if (r.first_emergency_action_s) {
      EXPECT_TRUE(r.num_actions > 0 || r.substitution_epochs > 0) << r.run_index;
    }
    if (r.battery_health != "G") continue;
    ++good_health;
    const bool before_fault =
        !r.fault || (r.first_emergency_action_s && *r.first_emergency_action_s < *r.fault_onset_s);
    if (r.first_emergency_action_s && before_fault && noop.at(r.run_index)->outcome == "completed") {
      ++early_landings_in_good_health;
    }
  }
  // The CMA's landings in good health before any fault, in flights NoOp completed: at most 1 % (measured 0).
  EXPECT_LE(100 * early_landings_in_good_health, good_health);
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
