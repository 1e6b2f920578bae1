// A stop request (common/progress.h RequestStop: Ctrl-C in the CLI or Python) ends a campaign's flights early:
// no run starts after it, the runs under way finish with every policy (no half-flown pair), and every finished
// record reaches the sink.
#include <gtest/gtest.h>

#include <map>
#include <vector>

#include "campaign_test_support.h"
#include "uascma/campaign/runner.h"
#include "uascma/common/progress.h"
#include "uascma/sim/emergency_planner.h"

namespace uascma::campaign {
namespace {

const std::vector<CampaignPolicy>& StopTestPolicies() {
  static const std::vector<CampaignPolicy> policies = {SolvedCmaPolicy(), NoOpCampaignPolicy()};
  return policies;
}

ExecuteOptions OneWorker() {
  ExecuteOptions options;
  options.jobs = 1;
  options.flush_rows = 1;
  return options;
}

TEST(RunnerStopTest, StopBeforeTheStartFliesNothing) {
  CampaignConfig config = testing_support::ShortConfig();
  config.runs = 12;
  std::vector<RunRecord> records;
  RequestStop();
  ExecuteFlights(config, StopTestPolicies(), MissingFlights(config.runs, StopTestPolicies(), {}), OneWorker(),
                 [&](std::vector<RunRecord>&& batch) { records.insert(records.end(), batch.begin(), batch.end()); });
  ClearStopRequest();
  EXPECT_TRUE(records.empty());
}

TEST(RunnerStopTest, StopMidwayKeepsWholeRunsAndEndsEarly) {
  // The stop is requested on the flying thread while its first run is being set up (the planner factory is called
  // once per flight there; it returns no planner, as the default does). A stop from the sink instead would race
  // with the flying thread: measured, a loaded machine let the flyer finish three runs before the collecting thread
  // handed the first one over.
  CampaignConfig config = testing_support::ShortConfig();
  config.runs = 12;
  ExecuteOptions options = OneWorker();
  options.planner_factory = [](const sim::Simulator&) {
    RequestStop();
    return sim::EmergencyPlanner{};
  };
  std::vector<RunRecord> records;
  ClearStopRequest();
  ExecuteFlights(config, StopTestPolicies(), MissingFlights(config.runs, StopTestPolicies(), {}), options,
                 [&](std::vector<RunRecord>&& batch) { records.insert(records.end(), batch.begin(), batch.end()); });
  ClearStopRequest();
  const std::size_t all = 12 * StopTestPolicies().size();
  ASSERT_FALSE(records.empty());
  EXPECT_LT(records.size(), all);
  // One worker: the run under way when the stop came is finished with both policies (and at most the next, if it
  // was already taken), and no other starts.
  std::map<std::int64_t, int> per_run;
  for (const RunRecord& r : records) ++per_run[r.run_index];
  EXPECT_LE(per_run.size(), 2u);
  for (const auto& [run, flights] : per_run)
    EXPECT_EQ(flights, static_cast<int>(StopTestPolicies().size())) << "run " << run;
}

}  // namespace
}  // namespace uascma::campaign
