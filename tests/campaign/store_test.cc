// The SQLite results store: round trip, idempotent inserts, refusal of foreign files, and a full disk
// (PRAGMA max_page_count stands in for a small filesystem) that leaves every committed batch intact.
#include "uascma/campaign/store.h"

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "campaign_test_support.h"
#include "uascma/common/error.h"

namespace uascma::campaign {
namespace {

struct TempDir : testing_support::TempDir {
  TempDir() : testing_support::TempDir("store_test") {}
};

CampaignHeader Header() {
  return MakeCampaignHeader(testing_support::ShortConfig(), {SolvedCmaPolicy(), NoOpCampaignPolicy()});
}

RunRecord Synthetic(std::int64_t run_index, const std::string& policy, std::size_t reason_bytes = 8) {
  RunRecord r;
  r.battery_health = std::string("M");  // (assigning a literal here trips GCC 12's -Wrestrict false positive)
  r.run_index = run_index;
  r.policy = policy;
  r.flight_id = run_index * 2 + (policy == "cma" ? 0 : 1);
  r.run_seed = 0xffffffffffffff00ULL + static_cast<std::uint64_t>(run_index);  // above INT64_MAX
  r.distance_m = 0.1 + static_cast<double>(run_index) / 3.0;
  r.outcome = "completed";
  r.reason.resize(reason_bytes, 'x');
  r.fault_onset_s = run_index % 2 == 0 ? std::optional<double>(12.5) : std::nullopt;
  r.average_reward = -1.0 / 7.0;
  r.min_reward = -0.408;
  return r;
}

std::string IntegrityCheck(const std::filesystem::path& path) {
  sqlite3* db = nullptr;
  sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* statement = nullptr;
  sqlite3_prepare_v2(db, "PRAGMA integrity_check", -1, &statement, nullptr);
  std::string result = sqlite3_step(statement) == SQLITE_ROW
                           ? reinterpret_cast<const char*>(sqlite3_column_text(statement, 0))
                           : "no answer";
  sqlite3_finalize(statement);
  sqlite3_close(db);
  return result;
}

TEST(StoreTest, RecordsAndHeaderRoundTrip) {
  TempDir dir;
  const auto path = dir.path / "c.db";
  const CampaignHeader header = Header();
  ResultsStore store = ResultsStore::Create(path, header);
  EXPECT_EQ(store.header().campaign_hash, header.campaign_hash);
  EXPECT_EQ(store.header().seed, header.seed);
  ASSERT_EQ(store.header().policies.size(), 2u);
  EXPECT_EQ(store.header().policies[0].actions, header.policies[0].actions);
  EXPECT_EQ(store.header().policies[0].hash, header.policies[0].hash);
  EXPECT_EQ(CampaignConfigHash(store.config()), header.config_hash);

  const std::vector<RunRecord> records = {Synthetic(0, "cma"), Synthetic(0, "noop"), Synthetic(1, "cma")};
  store.Insert(records);
  const std::vector<RunRecord> back = store.ReadRecords();
  ASSERT_EQ(back.size(), 3u);
  for (std::size_t i = 0; i < back.size(); ++i) {
    EXPECT_EQ(FirstDifference(back[i], records[i]), std::nullopt) << i;
  }
  EXPECT_EQ(back[0].run_seed, records[0].run_seed);  // the unsigned bit pattern survives
  EXPECT_FALSE(back[1].fault_onset_s.has_value() != records[1].fault_onset_s.has_value());
  const auto one = store.ReadRecord(1, "cma");
  ASSERT_TRUE(one.has_value());
  EXPECT_EQ(one->flight_id, 2);
  EXPECT_TRUE(store.ReadRecordByFlightId(1).has_value());
  EXPECT_FALSE(store.ReadRecord(1, "noop").has_value());
}

TEST(StoreTest, InsertingAFlightTwiceChangesNothing) {
  TempDir dir;
  ResultsStore store = ResultsStore::Create(dir.path / "c.db", Header());
  store.Insert({Synthetic(0, "cma"), Synthetic(1, "cma")});
  RunRecord changed = Synthetic(1, "cma");
  changed.outcome = "failed_battery";
  store.Insert({changed, Synthetic(2, "cma")});  // (1, cma) is already there: left as it was
  EXPECT_EQ(store.CountFlights(), 3);
  EXPECT_EQ(store.ReadRecord(1, "cma")->outcome, "completed");
  EXPECT_EQ(store.StoredFlights().size(), 3u);
}

TEST(StoreTest, ForeignFilesAreRefusedByName) {
  TempDir dir;
  const auto path = dir.path / "c.db";
  ResultsStore::Create(path, Header());
  EXPECT_THROW(ResultsStore::Create(path, Header()), InputError);  // exists
  const auto text = dir.path / "notes.db";
  std::ofstream(text) << "this is not a database, just some text that is long enough to have a header\n";
  try {
    ResultsStore::Open(text);
    ADD_FAILURE() << "a text file opened as a store";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(text.string()), std::string::npos) << e.what();
  }
  EXPECT_THROW(ResultsStore::Open(dir.path / "missing.db"), InputError);
  // Creating in a folder that does not exist fails cleanly and leaves nothing behind.
  EXPECT_THROW(ResultsStore::Create(dir.path / "no" / "such" / "c.db", Header()), InputError);
}

TEST(StoreTest, AFullDiskKeepsEveryCommittedBatch) {
  TempDir dir;
  const auto path = dir.path / "c.db";
  ResultsStore::Create(path, Header());
  StoreOptions tiny;
  tiny.max_page_count = 40;  // 40 pages of 4 KiB: a few dozen rows with a 1 KiB reason each
  ResultsStore store = ResultsStore::Open(path, tiny);
  constexpr int kBatch = 10;
  int committed = 0;
  std::string message;
  std::vector<RunRecord> failed_batch;
  for (int batch = 0; batch < 100 && message.empty(); ++batch) {
    std::vector<RunRecord> records;
    for (int i = 0; i < kBatch; ++i) records.push_back(Synthetic(batch * kBatch + i, "cma", 1024));
    try {
      store.Insert(records);
      ++committed;
    } catch (const InputError& e) {
      message = e.what();
      failed_batch = records;
    }
  }
  ASSERT_FALSE(message.empty()) << "the page limit was never reached";
  EXPECT_GT(committed, 0);
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  EXPECT_NE(message.find("full"), std::string::npos) << message;
  EXPECT_EQ(store.CountFlights(), committed * kBatch);  // the failed batch left no row
  // Reopened without the limit: consistent, and the failed batch goes in.
  ResultsStore reopened = ResultsStore::Open(path);
  EXPECT_EQ(IntegrityCheck(path), "ok");
  EXPECT_EQ(reopened.CountFlights(), committed * kBatch);
  reopened.Insert(failed_batch);
  EXPECT_EQ(reopened.CountFlights(), (committed + 1) * kBatch);
}

}  // namespace
}  // namespace uascma::campaign
