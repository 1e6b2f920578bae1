// A stop request (common/progress.h RequestStop: Ctrl-C in the CLI or Python) ends a campaign's flights early:
// no run starts after it, the runs under way finish with every policy (no half-flown pair), and every finished
// record reaches the sink.
#include <gtest/gtest.h>

#include <map>
#include <vector>

#include "campaign_test_support.h"
#include "uascma/campaign/runner.h"
#include "uascma/common/progress.h"

namespace uascma::campaign {
namespace {

const std::vector<CampaignPolicy>& Policies() {
  static const std::vector<CampaignPolicy> policies = {SolvedCmaPolicy(), NoOpCampaignPolicy()};
  return policies;
}

std::vector<RunRecord> FlyStoppingAfter(std::size_t records_before_stop) {
  CampaignConfig config = testing_support::ShortConfig();
  config.runs = 12;
  ExecuteOptions options;
  options.jobs = 1;
  options.flush_rows = 1;
  std::vector<RunRecord> records;
  ClearStopRequest();
  if (records_before_stop == 0) RequestStop();
  ExecuteFlights(config, Policies(), MissingFlights(config.runs, Policies(), {}), options,
                 [&](std::vector<RunRecord>&& batch) {
                   records.insert(records.end(), batch.begin(), batch.end());
                   if (records.size() >= records_before_stop) RequestStop();
                 });
  ClearStopRequest();
  return records;
}

TEST(RunnerStopTest, StopBeforeTheStartFliesNothing) { EXPECT_TRUE(FlyStoppingAfter(0).empty()); }

TEST(RunnerStopTest, StopMidwayKeepsWholeRunsAndEndsEarly) {
  const std::vector<RunRecord> records = FlyStoppingAfter(1);
  const std::size_t all = 12 * Policies().size();
  ASSERT_FALSE(records.empty());
  EXPECT_LT(records.size(), all);
  // One worker: the stop arrives while its first run is being handed over, so that run (and at most the next,
  // already taken) is finished with both policies, and no other.
  std::map<std::int64_t, int> per_run;
  for (const RunRecord& r : records) ++per_run[r.run_index];
  EXPECT_LE(per_run.size(), 2u);
  for (const auto& [run, flights] : per_run) EXPECT_EQ(flights, static_cast<int>(Policies().size())) << "run " << run;
}

}  // namespace
}  // namespace uascma::campaign
