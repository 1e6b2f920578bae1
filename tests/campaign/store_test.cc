// The SQLite results store: round trip, idempotent inserts, refusal of foreign files, and a full disk
// (PRAGMA max_page_count stands in for a small filesystem) that leaves every committed batch intact;
// exclusive creation, errors that name the user's path, and the claims that share a campaign between
// processes (live, dead, retired and foreign workers; version-1 files).
#include "uascma/campaign/store.h"
#include "uascma/campaign/sampler.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <unistd.h>

#include <sys/wait.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <limits>
#include <thread>

#include "campaign_test_support.h"
#include "store_test_support.h"
#include "uascma/common/error.h"

namespace uascma::campaign {
namespace {

using testing_support::IntegrityCheck;

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
  r.initial_cell_voltage_v = std::string("[4.1,4.1,4.1,4.0,4.0,4.0]");  // JSON columns hold JSON (CheckStore)
  r.actions = std::string("[]");
  r.run_seed = RunSeed(Header().seed, run_index);  // as the sampler draws it (CheckStore holds rows to it)
  r.distance_m = 0.1 + static_cast<double>(run_index) / 3.0;
  r.outcome = "completed";
  r.reason.resize(reason_bytes, 'x');
  r.fault_onset_s = run_index % 2 == 0 ? std::optional<double>(12.5) : std::nullopt;
  r.average_reward = -1.0 / 7.0;
  r.min_reward = -0.408;
  return r;
}

// Runs SQL on the file through its own connection (what another process would do).
void ExecuteSql(const std::filesystem::path& path, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr), SQLITE_OK);
  sqlite3_busy_timeout(db, 5000);
  char* error = nullptr;
  const int code = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error);
  EXPECT_EQ(code, SQLITE_OK) << (error != nullptr ? error : "") << "\n" << sql;
  sqlite3_free(error);
  sqlite3_close(db);
}

// The pid of a process that has ended and been reaped.
std::int64_t DeadPid() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  int status = 0;
  ::waitpid(child, &status, 0);
  return child;
}

// Files in `folder` whose name contains ".creating-" (creation temporaries).
int TemporaryFiles(const std::filesystem::path& folder) {
  int count = 0;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    count += entry.path().filename().string().find(".creating-") != std::string::npos ? 1 : 0;
  }
  return count;
}

std::vector<std::int64_t> Runs(std::initializer_list<std::int64_t> runs) { return runs; }

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

  // The first run of this campaign whose seed lies above INT64_MAX: its unsigned bit pattern must survive.
  std::int64_t high = 0;
  while (RunSeed(header.seed, high) <= static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) ++high;
  ASSERT_LT(high, header.runs_requested);
  std::vector<RunRecord> records = {Synthetic(0, "cma"), Synthetic(0, "noop"), Synthetic(1, "cma")};
  if (high > 1) records.push_back(Synthetic(high, "cma"));
  store.Insert(records);
  const std::vector<RunRecord> back = store.ReadRecords();
  ASSERT_EQ(back.size(), records.size());
  for (std::size_t i = 0; i < back.size(); ++i) {
    EXPECT_EQ(FirstDifference(back[i], records[i]), std::nullopt) << i;
    if (back[i].run_index == high) {
      EXPECT_EQ(back[i].run_seed, RunSeed(header.seed, high));  // the unsigned bit pattern survives
    }
  }
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
}

TEST(StoreTest, CreationErrorsNameTheUsersPathAndLeaveNoTemporaryFile) {
  TempDir dir;
  std::ofstream(dir.path / "plain.txt") << "a file, not a folder\n";
  struct Case {
    std::filesystem::path db;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {dir.path / "no" / "such" / "c.db", "does not exist"},
      {dir.path / "plain.txt" / "c.db", "is not a folder"},
      // A folder nobody can create files in, root included: SQLite's own error on the temporary file.
      {"/proc/uascma_store_test.db", "/proc/uascma_store_test.db"},
  };
  for (const Case& c : cases) {
    try {
      ResultsStore::Create(c.db, Header());
      ADD_FAILURE() << "created " << c.db;
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(c.db.string() + ": ", 0), 0u) << message;  // the user's path comes first
      EXPECT_NE(message.find(c.expected), std::string::npos) << message;
      EXPECT_EQ(message.find(".creating-"), std::string::npos) << message;  // never the temporary name
    }
  }
  EXPECT_EQ(TemporaryFiles(dir.path), 0);
  EXPECT_FALSE(std::filesystem::exists(dir.path / "no"));
}

TEST(StoreTest, OfConcurrentCreatorsExactlyOneCreates) {
  constexpr int kRounds = 10;
  constexpr int kThreads = 4;
  for (int round = 0; round < kRounds; ++round) {
    TempDir dir;
    const auto path = dir.path / "c.db";
    std::vector<CampaignHeader> headers;
    for (int t = 0; t < kThreads; ++t) {
      CampaignConfig config = testing_support::ShortConfig();
      config.seed = 100 + static_cast<std::uint64_t>(t);  // four different campaigns
      headers.push_back(MakeCampaignHeader(config, {NoOpCampaignPolicy()}));
    }
    std::atomic<int> created{0};
    std::atomic<int> winner{-1};
    std::atomic<bool> go{false};
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t) {
      threads.emplace_back([&, t] {
        while (!go.load()) std::this_thread::yield();
        if (auto store = ResultsStore::TryCreate(path, headers[t])) {
          ++created;
          winner = t;
        }
      });
    }
    go = true;
    for (auto& thread : threads) thread.join();
    ASSERT_EQ(created.load(), 1) << "round " << round;
    EXPECT_EQ(ResultsStore::Open(path).header().campaign_hash, headers[winner.load()].campaign_hash);
    EXPECT_EQ(IntegrityCheck(path), "ok");
    EXPECT_EQ(TemporaryFiles(dir.path), 0);
  }
}

TEST(StoreTest, AKilledCreatorsTemporaryFileIsRemovedByTheNextCreation) {
  TempDir dir;
  const WorkerIdentity me = ThisProcessIdentity();
  const std::string prefix = "c.db.creating-" + me.host + "-" + me.boot_id.substr(0, 8) + "-";
  const auto stale = dir.path / (prefix + std::to_string(DeadPid()) + "-0");
  const auto running = dir.path / (prefix + std::to_string(::getpid()) + "-7");  // a creator still at work
  std::ofstream(stale) << "half";
  std::ofstream(stale.string() + "-wal") << "half";
  std::ofstream(running) << "busy";
  ResultsStore::Create(dir.path / "c.db", Header());
  EXPECT_FALSE(std::filesystem::exists(stale));
  EXPECT_FALSE(std::filesystem::exists(stale.string() + "-wal"));
  EXPECT_TRUE(std::filesystem::exists(running));
}

TEST(StoreTest, ProcessLivenessTellsDeadZombieAndReusedPidsApart) {
  const WorkerIdentity me = ThisProcessIdentity();
  EXPECT_GT(me.start_ticks, 0);
  EXPECT_FALSE(me.boot_id.empty());
  EXPECT_TRUE(ProcessIsRunning(me.pid, me.start_ticks));
  EXPECT_TRUE(ProcessIsRunning(me.pid, 0));
  EXPECT_FALSE(ProcessIsRunning(me.pid, me.start_ticks + 1));  // the same pid, another process
  EXPECT_FALSE(ProcessIsRunning(DeadPid(), 0));
  const pid_t zombie = ::fork();
  if (zombie == 0) ::_exit(0);
  bool seen_dead = false;
  for (int i = 0; i < 500 && !seen_dead; ++i) {  // until the child has exited (it stays unreaped)
    seen_dead = !ProcessIsRunning(zombie, 0);
    if (!seen_dead) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  EXPECT_TRUE(seen_dead) << "a killed, unreaped child counts as running";
  int status = 0;
  ::waitpid(zombie, &status, 0);
}

TEST(StoreTest, ARunIsClaimedOnceAndFreedWhenItsWorkerStops) {
  TempDir dir;
  const auto path = dir.path / "c.db";
  ResultsStore::Create(path, Header());
  ResultsStore a = ResultsStore::Open(path);
  ResultsStore b = ResultsStore::Open(path);
  const std::int64_t worker_a = a.JoinAsWorker();
  const std::int64_t worker_b = b.JoinAsWorker();
  EXPECT_NE(worker_a, worker_b);
  EXPECT_EQ(a.JoinAsWorker(), worker_a);
  EXPECT_EQ(a.CountLiveWorkers(), 1);  // b

  const ClaimResult first = a.ClaimRuns(Runs({0, 1, 2}), 1);
  ASSERT_EQ(first.claimed.size(), 1u);
  EXPECT_EQ(first.claimed[0].run_index, 0);
  EXPECT_EQ(first.claimed[0].slots, (std::vector<int>{0, 1}));
  EXPECT_EQ(first.examined, 1u);
  EXPECT_EQ(a.ClaimHolder(0), worker_a);

  b.Insert({Synthetic(1, "cma"), Synthetic(1, "noop"), Synthetic(2, "cma")});  // run 1 done, run 2 half
  const ClaimResult second = b.ClaimRuns(Runs({0, 1, 2, 3}), 5);
  EXPECT_EQ(second.held, Runs({0}));  // a is alive
  ASSERT_EQ(second.claimed.size(), 2u);
  EXPECT_EQ(second.claimed[0].run_index, 2);
  EXPECT_EQ(second.claimed[0].slots, (std::vector<int>{1}));  // only noop is missing
  EXPECT_EQ(second.claimed[1].run_index, 3);
  EXPECT_EQ(second.examined, 4u);
  EXPECT_EQ(b.ClaimRuns(Runs({2}), 1).held, Runs({2}));  // its own claim is held too (another thread)

  a.Retire();  // a stopped (error or success) with run 0 unflown
  EXPECT_EQ(b.CountLiveWorkers(), 0);
  const ClaimResult taken = b.ClaimRuns(Runs({0}), 1);
  ASSERT_EQ(taken.claimed.size(), 1u);
  EXPECT_EQ(b.ClaimHolder(0), worker_b);

  // A worker whose store is closed (its process goes on) frees its claims as well.
  {
    ResultsStore c = ResultsStore::Open(path);
    c.JoinAsWorker();
    ASSERT_EQ(c.ClaimRuns(Runs({5}), 1).claimed.size(), 1u);
  }
  EXPECT_EQ(b.ClaimRuns(Runs({5}), 1).claimed.size(), 1u);
  EXPECT_EQ(IntegrityCheck(path), "ok");
}

TEST(StoreTest, ClaimsOfDeadAndForeignWorkers) {
  TempDir dir;
  const auto path = dir.path / "c.db";
  ResultsStore::Create(path, Header());
  const WorkerIdentity me = ThisProcessIdentity();
  const double now_s = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  const std::string hash = Header().campaign_hash;
  // Worker 1: a killed process of this machine. 2: a process of this machine still running (ourselves
  // under another worker row is not it: use pid 1, init, which always runs). 3: another machine, seen
  // a second ago. 4: another machine, silent for longer than the lease.
  ExecuteSql(path, fmt::format("INSERT INTO workers (id, host, boot_id, pid_namespace, pid, start_ticks, started_utc, "
                               "heartbeat_s) VALUES "
                               "(1, '{0}', '{1}', '{2}', {3}, 0, 'x', {4}), (2, '{0}', '{1}', '{2}', 1, 0, 'x', {4}), "
                               "(3, 'far', 'other-boot', 'pid:[1]', 77, 5, 'x', {5}), "
                               "(4, 'farther', 'other-boot', 'pid:[1]', 78, 5, 'x', {6});"
                               "INSERT INTO claims (campaign_hash, run_index, worker, claimed_s) VALUES "
                               "('{7}', 0, 1, 0), ('{7}', 1, 2, 0), ('{7}', 2, 3, 0), ('{7}', 3, 4, 0);",
                               me.host, me.boot_id, me.pid_namespace, DeadPid(), now_s - 1000.0, now_s - 1.0,
                               now_s - kClaimLeaseSeconds - 5.0, hash));
  ResultsStore store = ResultsStore::Open(path);
  // A live worker of another machine: joining is refused (WAL works within one machine only).
  try {
    store.JoinAsWorker();
    ADD_FAILURE() << "joined while another machine writes the file";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(path.string() + ": ", 0), 0u) << message;
    EXPECT_NE(message.find("one machine"), std::string::npos) << message;
    EXPECT_NE(message.find("'far'"), std::string::npos) << message;
  }
  ExecuteSql(path, "UPDATE workers SET retired = 1 WHERE id = 3");
  store.JoinAsWorker();
  const ClaimResult result = store.ClaimRuns(Runs({0, 1, 2, 3}), 10);
  EXPECT_EQ(result.held, Runs({1}));  // pid 1 runs
  ASSERT_EQ(result.claimed.size(), 3u);
  EXPECT_EQ(result.claimed[0].run_index, 0);  // dead pid
  EXPECT_EQ(result.claimed[1].run_index, 2);  // retired
  EXPECT_EQ(result.claimed[2].run_index, 3);  // lease lapsed
}

// What a waiting process says of the worker it waits for. A suspended process (SIGSTOP,
// as Ctrl-Z does) is named as stopped with the command that resumes it; a running one, an ended one and
// another machine's are told apart.
TEST(StoreTest, AWorkerIsDescribedByWhatItsProcessIsDoing) {
  TempDir dir;
  const auto path = dir.path / "c.db";
  ResultsStore::Create(path, Header());
  const pid_t stopped = ::fork();
  if (stopped == 0) {
    ::pause();
    ::_exit(0);
  }
  ASSERT_EQ(::kill(stopped, SIGSTOP), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(stopped, &status, WUNTRACED), stopped);
  ASSERT_TRUE(WIFSTOPPED(status));
  const WorkerIdentity me = ThisProcessIdentity();
  const std::int64_t dead = DeadPid();
  ExecuteSql(path, fmt::format("INSERT INTO workers (id, host, boot_id, pid_namespace, pid, start_ticks, started_utc, "
                               "heartbeat_s) VALUES "
                               "(1, '{0}', '{1}', '{2}', {3}, 0, 'x', 0), (2, '{0}', '{1}', '{2}', 1, 0, 'x', 0), "
                               "(3, '{0}', '{1}', '{2}', {4}, 0, 'x', 0), (4, 'far', 'other-boot', 'pid:[1]', 77, 5, "
                               "'x', 0);",
                               me.host, me.boot_id, me.pid_namespace, stopped, dead));
  const ResultsStore store = ResultsStore::Open(path);
  const std::string suspended = store.DescribeWorker(1);
  ::kill(stopped, SIGKILL);
  ::waitpid(stopped, &status, 0);
  EXPECT_NE(suspended.find(fmt::format("pid {} on this machine (stopped", stopped)), std::string::npos) << suspended;
  EXPECT_NE(suspended.find(fmt::format("kill -CONT {}", stopped)), std::string::npos) << suspended;
  EXPECT_EQ(store.DescribeWorker(2), "pid 1 on this machine (running)");
  EXPECT_EQ(store.DescribeWorker(3), fmt::format("pid {} on this machine (ended)", dead));
  EXPECT_EQ(store.DescribeWorker(4), "a process on host far (pid 77 there)");
  EXPECT_EQ(store.DescribeWorker(99), "worker 99 (no longer registered)");
}

TEST(StoreTest, AVersionOneFileIsReadAndRaisedWhenJoined) {
  TempDir dir;
  const auto path = dir.path / "c.db";
  ResultsStore::Create(path, Header()).Insert({Synthetic(0, "cma")});
  ExecuteSql(path, "DROP TABLE claims; DROP TABLE workers; PRAGMA user_version = 1;");
  ResultsStore store = ResultsStore::Open(path);
  EXPECT_EQ(store.CountFlights(), 1);
  EXPECT_EQ(store.CountLiveWorkers(), 0);
  EXPECT_EQ(store.ClaimHolder(0), 0);
  store.JoinAsWorker();
  const ClaimResult result = store.ClaimRuns(Runs({0}), 1);
  ASSERT_EQ(result.claimed.size(), 1u);
  EXPECT_EQ(result.claimed[0].slots, (std::vector<int>{1}));
  sqlite3* db = nullptr;
  sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* version = nullptr;
  sqlite3_prepare_v2(db, "PRAGMA user_version", -1, &version, nullptr);
  ASSERT_EQ(sqlite3_step(version), SQLITE_ROW);
  EXPECT_EQ(sqlite3_column_int(version, 0), kStoreSchemaVersion);
  sqlite3_finalize(version);
  sqlite3_close(db);
}

TEST(StoreTest, AFullDiskKeepsEveryCommittedBatch) {
  TempDir dir;
  const auto path = dir.path / "c.db";
  ResultsStore::Create(path, Header()).RecordRunsRequested(1000);  // every run below is one of the campaign's
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
