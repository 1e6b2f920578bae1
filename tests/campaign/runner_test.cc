// The campaign runner: the same rows for any number of threads, after a partial campaign and its
// resumption, and from a replay of one stored flight; another campaign's database is refused; several
// campaigns started at once on one database (threads of one process here; processes in
// tests/apps/campaign_concurrency_test.cc) fly each flight once.
#include "uascma/campaign/runner.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <thread>

#include "campaign_test_support.h"
#include "uascma/campaign/replay.h"
#include "uascma/common/error.h"

namespace uascma::campaign {
namespace {

struct RunnerTempDir : testing_support::TempDir {
  RunnerTempDir() : testing_support::TempDir("runner_test") {}
};

const std::vector<CampaignPolicy>& Policies() {
  static const std::vector<CampaignPolicy> policies = {SolvedCmaPolicy(), NoOpCampaignPolicy()};
  return policies;
}

std::vector<RunRecord> Fly(const CampaignConfig& config, int jobs, int runs_in_flight = 4) {
  ExecuteOptions options;
  options.jobs = jobs;
  options.runs_in_flight = runs_in_flight;
  options.flush_rows = 3;  // many small batches
  std::vector<RunRecord> records;
  ExecuteFlights(
      config, Policies(), MissingFlights(config.runs, Policies(), {}), options,
      [&records](std::vector<RunRecord>&& batch) { records.insert(records.end(), batch.begin(), batch.end()); });
  std::sort(records.begin(), records.end(),
            [](const RunRecord& a, const RunRecord& b) { return a.flight_id < b.flight_id; });
  return records;
}

void ExpectSameRows(const std::vector<RunRecord>& a, const std::vector<RunRecord>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(FirstDifference(a[i], b[i]), std::nullopt) << "row " << i << " (flight " << a[i].flight_id << ")";
  }
}

CampaignRequest Request(const CampaignConfig& config, const std::filesystem::path& db, bool resume) {
  CampaignRequest request;
  request.config = config;
  request.policies = Policies();
  request.db = db;
  request.resume = resume;
  request.execute.jobs = 2;
  return request;
}

TEST(MissingFlightsTest, SkipsStoredFlights) {
  const auto tasks = MissingFlights(3, Policies(), {{0, "cma"}, {0, "noop"}, {2, "noop"}, {7, "cma"}});
  ASSERT_EQ(tasks.size(), 2u);
  EXPECT_EQ(tasks[0].run_index, 1);
  EXPECT_EQ(tasks[0].slots, (std::vector<int>{0, 1}));
  EXPECT_EQ(tasks[1].run_index, 2);
  EXPECT_EQ(tasks[1].slots, (std::vector<int>{0}));
}

TEST(RunnerTest, ThreadCountAndRunsInFlightDoNotChangeTheResults) {
  CampaignConfig config = testing_support::ShortConfig();
  config.runs = 8;
  const auto one = Fly(config, 1);
  ASSERT_EQ(one.size(), 16u);
  ExpectSameRows(one, Fly(config, 2));
  ExpectSameRows(one, Fly(config, 4));
  // Runs flown one at a time, their steps alone, and several in flight per thread in lockstep.
  ExpectSameRows(one, Fly(config, 1, 1));
  ExpectSameRows(one, Fly(config, 2, 3));
  ExpectSameRows(one, Fly(config, 1, 8));
  // Paired: both policies fly the very same scenario of each run.
  for (std::size_t i = 0; i + 1 < one.size(); i += 2) {
    EXPECT_EQ(one[i].run_index, one[i + 1].run_index);
    EXPECT_EQ(one[i].run_seed, one[i + 1].run_seed);
    EXPECT_EQ(one[i].cell_health, one[i + 1].cell_health);
    EXPECT_DOUBLE_EQ(one[i].distance_m, one[i + 1].distance_m);
  }
}

TEST(RunnerTest, APartialCampaignResumedEqualsAnUninterruptedOne) {
  RunnerTempDir dir;
  CampaignConfig config = testing_support::ShortConfig();
  config.runs = 3;
  const CampaignOutcome first = RunCampaign(Request(config, dir.path / "resumed.db", false));
  EXPECT_EQ(first.flights_flown, 6);
  config.runs = 6;
  // Without --resume an existing database is refused.
  EXPECT_THROW(RunCampaign(Request(config, dir.path / "resumed.db", false)), InputError);
  const CampaignOutcome second = RunCampaign(Request(config, dir.path / "resumed.db", true));
  EXPECT_EQ(second.flights_before, 6);
  EXPECT_EQ(second.flights_flown, 6);
  const CampaignOutcome again = RunCampaign(Request(config, dir.path / "resumed.db", true));
  EXPECT_EQ(again.flights_flown, 0);  // nothing counted twice
  RunCampaign(Request(config, dir.path / "whole.db", false));
  const auto resumed = ResultsStore::Open(dir.path / "resumed.db").ReadRecords();
  ASSERT_EQ(resumed.size(), 12u);
  ExpectSameRows(resumed, ResultsStore::Open(dir.path / "whole.db").ReadRecords());
  EXPECT_EQ(ResultsStore::Open(dir.path / "resumed.db").header().runs_requested, 6);
}

TEST(RunnerTest, AnotherCampaignsDatabaseIsRefused) {
  RunnerTempDir dir;
  CampaignConfig config = testing_support::ShortConfig();
  config.runs = 1;
  RunCampaign(Request(config, dir.path / "c.db", false));
  CampaignConfig other = config;
  other.seed = config.seed + 1;
  try {
    RunCampaign(Request(other, dir.path / "c.db", true));
    ADD_FAILURE() << "a database of another campaign was accepted";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find((dir.path / "c.db").string()), std::string::npos) << message;
    EXPECT_NE(message.find("another campaign"), std::string::npos) << message;
  }
  CampaignRequest fewer_policies = Request(config, dir.path / "c.db", true);
  fewer_policies.policies = {NoOpCampaignPolicy()};
  EXPECT_THROW(RunCampaign(fewer_policies), InputError);
  EXPECT_EQ(ResultsStore::Open(dir.path / "c.db").CountFlights(), 2);
}

TEST(RunnerTest, AStoredFlightReplaysAlone) {
  RunnerTempDir dir;
  CampaignConfig config = testing_support::ShortConfig();
  config.runs = 3;
  RunCampaign(Request(config, dir.path / "c.db", false));
  for (const std::string id : {"0", "3", "2:cma", "1:noop"}) {
    const ReplayFlight flight = LoadReplay(dir.path / "c.db", id);
    EXPECT_EQ(FirstDifference(ReplayRun(flight), flight.recorded), std::nullopt) << id;
    EXPECT_EQ(flight.run.scenario.seed, SampleRun(config, config.seed, flight.recorded.run_index).scenario.seed);
  }
  EXPECT_EQ(LoadReplay(dir.path / "c.db", "3").recorded.policy, "noop");  // flight 3 = run 1, slot 1
  EXPECT_THROW(LoadReplay(dir.path / "c.db", "99"), InputError);
  EXPECT_THROW(LoadReplay(dir.path / "c.db", "1:greedy"), InputError);
  EXPECT_THROW(LoadReplay(dir.path / "c.db", "one"), InputError);
}

// Starts one RunCampaign per request at the same moment, each on its own thread; an InputError is
// kept as its message.
struct Started {
  std::optional<CampaignOutcome> outcome;
  std::string error;
};
std::vector<Started> RunAtOnce(const std::vector<CampaignRequest>& requests) {
  std::vector<Started> results(requests.size());
  std::atomic<bool> go{false};
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < requests.size(); ++i) {
    threads.emplace_back([&, i] {
      while (!go.load()) std::this_thread::yield();
      try {
        results[i].outcome = RunCampaign(requests[i]);
      } catch (const InputError& e) {
        results[i].error = e.what();
      }
    });
  }
  go = true;
  for (auto& thread : threads) thread.join();
  return results;
}

TEST(RunnerTest, CampaignsStartedTogetherShareTheWorkAndStoreEachFlightOnce) {
  RunnerTempDir dir;
  CampaignConfig config = testing_support::ShortConfig();
  config.runs = 6;
  RunCampaign(Request(config, dir.path / "whole.db", false));
  const auto whole = ResultsStore::Open(dir.path / "whole.db").ReadRecords();
  constexpr int kRounds = 4;
  for (int round = 0; round < kRounds; ++round) {
    const auto db = dir.path / ("shared" + std::to_string(round) + ".db");
    std::vector<CampaignRequest> requests;
    for (int i = 0; i < 3; ++i) {
      requests.push_back(Request(config, db, false));
      requests.back().execute.jobs = 1;
    }
    std::int64_t flown = 0;
    int succeeded = 0;
    for (const Started& started : RunAtOnce(requests)) {
      if (started.outcome) {
        ++succeeded;
        flown += started.outcome->flights_flown;
      } else {
        // Only a late start, after the others finished, may find a file without a live worker.
        EXPECT_NE(started.error.find("--resume"), std::string::npos) << started.error;
      }
    }
    EXPECT_GE(succeeded, 1);
    EXPECT_EQ(flown, 12) << "round " << round << ": a flight was flown twice or not at all";
    ExpectSameRows(whole, ResultsStore::Open(db).ReadRecords());
  }
}

TEST(RunnerTest, OfDifferentCampaignsStartedTogetherOneRunsAndTheOthersNameIt) {
  RunnerTempDir dir;
  CampaignConfig config = testing_support::ShortConfig();
  config.runs = 2;
  const auto db = dir.path / "c.db";
  std::vector<CampaignRequest> requests;
  for (int i = 0; i < 3; ++i) {
    CampaignConfig other = config;
    other.seed = config.seed + static_cast<std::uint64_t>(i);
    requests.push_back(Request(other, db, false));
  }
  const std::vector<Started> results = RunAtOnce(requests);
  int succeeded = 0;
  for (const Started& started : results) succeeded += started.outcome ? 1 : 0;
  ASSERT_EQ(succeeded, 1);
  const std::string hash = ResultsStore::Open(db).header().campaign_hash;
  for (const Started& started : results) {
    if (started.outcome) {
      EXPECT_EQ(started.outcome->campaign_hash, hash);
      EXPECT_EQ(started.outcome->flights_flown, 4);
    } else {
      EXPECT_NE(started.error.find("another campaign"), std::string::npos) << started.error;
      EXPECT_NE(started.error.find("(hash " + hash), std::string::npos) << started.error;
    }
  }
  EXPECT_EQ(ResultsStore::Open(db).CountFlights(), 4);
}

TEST(RunnerTest, AFailingSinkStopsTheWorkersAndIsRethrown) {
  CampaignConfig config = testing_support::ShortConfig();
  config.runs = 6;
  ExecuteOptions options;
  options.jobs = 2;
  options.flush_rows = 1;
  int calls = 0;
  EXPECT_THROW(ExecuteFlights(config, Policies(), MissingFlights(config.runs, Policies(), {}), options,
                              [&calls](std::vector<RunRecord>&&) {
                                ++calls;
                                throw std::runtime_error("disk on fire");
                              }),
               std::runtime_error);
  EXPECT_EQ(calls, 1);
}

}  // namespace
}  // namespace uascma::campaign
