// A store is created whole or not at all even when the disk fills while its pages are
// moved from the write-ahead log into the file, and a damaged store (SQLite's integrity check, or the
// schema's own invariants) is named by CheckStore and refused by Open, so it is never reported on,
// resumed into or replayed from.
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "campaign_test_support.h"
#include "store_test_support.h"
#include "uascma/campaign/sampler.h"
#include "uascma/campaign/store.h"
#include "uascma/common/error.h"

namespace uascma::campaign {
namespace {

using testing_support::IntegrityCheck;

struct TempDir : testing_support::TempDir {
  TempDir() : testing_support::TempDir("store_check_test") {}
};

// ---- a disk that fills: an SQLite VFS that forwards to the default one, except that writes to a main
// database file at or beyond `main_file_room_bytes` fail with SQLITE_FULL (the -wal and -shm files are
// written normally). This is a full disk as SQLite meets it when the creation's checkpoint
// copies the committed pages from the -wal into the file: the -wal was written, the file cannot grow.
struct FaultyFile {
  sqlite3_file base;
  sqlite3_file* real;
  bool main_db;
};

sqlite3_vfs* g_real_vfs = nullptr;
sqlite3_int64 g_main_file_room_bytes = -1;  // < 0: no fault
sqlite3_io_methods g_methods{};

sqlite3_file* Real(sqlite3_file* file) { return reinterpret_cast<FaultyFile*>(file)->real; }

int FaultyWrite(sqlite3_file* file, const void* data, int amount, sqlite3_int64 offset) {
  const auto* faulty = reinterpret_cast<FaultyFile*>(file);
  if (faulty->main_db && g_main_file_room_bytes >= 0 && offset + amount > g_main_file_room_bytes) return SQLITE_FULL;
  return faulty->real->pMethods->xWrite(faulty->real, data, amount, offset);
}

int FaultyOpen(sqlite3_vfs*, sqlite3_filename name, sqlite3_file* file, int flags, int* out_flags) {
  auto* faulty = reinterpret_cast<FaultyFile*>(file);
  faulty->real = reinterpret_cast<sqlite3_file*>(faulty + 1);
  faulty->main_db = (flags & SQLITE_OPEN_MAIN_DB) != 0;
  faulty->base.pMethods = nullptr;
  const int code = g_real_vfs->xOpen(g_real_vfs, name, faulty->real, flags, out_flags);
  if (faulty->real->pMethods == nullptr) return code;
  // Every method forwards to the real file; only xWrite can fail.
  const sqlite3_io_methods* r = faulty->real->pMethods;
  g_methods.iVersion = r->iVersion;
  g_methods.xClose = [](sqlite3_file* f) { return Real(f)->pMethods->xClose(Real(f)); };
  g_methods.xRead = [](sqlite3_file* f, void* d, int n, sqlite3_int64 o) {
    return Real(f)->pMethods->xRead(Real(f), d, n, o);
  };
  g_methods.xWrite = FaultyWrite;
  g_methods.xTruncate = [](sqlite3_file* f, sqlite3_int64 s) { return Real(f)->pMethods->xTruncate(Real(f), s); };
  g_methods.xSync = [](sqlite3_file* f, int flags) { return Real(f)->pMethods->xSync(Real(f), flags); };
  g_methods.xFileSize = [](sqlite3_file* f, sqlite3_int64* s) { return Real(f)->pMethods->xFileSize(Real(f), s); };
  g_methods.xLock = [](sqlite3_file* f, int l) { return Real(f)->pMethods->xLock(Real(f), l); };
  g_methods.xUnlock = [](sqlite3_file* f, int l) { return Real(f)->pMethods->xUnlock(Real(f), l); };
  g_methods.xCheckReservedLock = [](sqlite3_file* f, int* o) {
    return Real(f)->pMethods->xCheckReservedLock(Real(f), o);
  };
  g_methods.xFileControl = [](sqlite3_file* f, int op, void* a) {
    return Real(f)->pMethods->xFileControl(Real(f), op, a);
  };
  g_methods.xSectorSize = [](sqlite3_file* f) { return Real(f)->pMethods->xSectorSize(Real(f)); };
  g_methods.xDeviceCharacteristics = [](sqlite3_file* f) { return Real(f)->pMethods->xDeviceCharacteristics(Real(f)); };
  g_methods.xShmMap = [](sqlite3_file* f, int p, int s, int e, void volatile** o) {
    return Real(f)->pMethods->xShmMap(Real(f), p, s, e, o);
  };
  g_methods.xShmLock = [](sqlite3_file* f, int o, int n, int fl) {
    return Real(f)->pMethods->xShmLock(Real(f), o, n, fl);
  };
  g_methods.xShmBarrier = [](sqlite3_file* f) { Real(f)->pMethods->xShmBarrier(Real(f)); };
  g_methods.xShmUnmap = [](sqlite3_file* f, int d) { return Real(f)->pMethods->xShmUnmap(Real(f), d); };
  g_methods.xFetch = [](sqlite3_file* f, sqlite3_int64 o, int n, void** p) {
    return Real(f)->pMethods->xFetch(Real(f), o, n, p);
  };
  g_methods.xUnfetch = [](sqlite3_file* f, sqlite3_int64 o, void* p) {
    return Real(f)->pMethods->xUnfetch(Real(f), o, p);
  };
  faulty->base.pMethods = &g_methods;
  return code;
}

// Installs the faulty VFS as SQLite's default for the lifetime of the object.
class FullDiskVfs {
 public:
  explicit FullDiskVfs(sqlite3_int64 main_file_room_bytes) {
    g_real_vfs = sqlite3_vfs_find(nullptr);
    vfs_ = *g_real_vfs;
    vfs_.zName = "uascma-full-disk-test";
    vfs_.szOsFile = static_cast<int>(sizeof(FaultyFile)) + g_real_vfs->szOsFile;
    vfs_.xOpen = FaultyOpen;
    g_main_file_room_bytes = main_file_room_bytes;
    sqlite3_vfs_register(&vfs_, 1);
  }
  ~FullDiskVfs() {
    sqlite3_vfs_unregister(&vfs_);
    sqlite3_vfs_register(g_real_vfs, 1);
    g_main_file_room_bytes = -1;
  }
  FullDiskVfs(const FullDiskVfs&) = delete;
  FullDiskVfs& operator=(const FullDiskVfs&) = delete;

 private:
  sqlite3_vfs vfs_{};
};

CampaignHeader Header() {
  return MakeCampaignHeader(testing_support::ShortConfig(), {SolvedCmaPolicy(), NoOpCampaignPolicy()});
}

// A flight row as the runner writes it (record.h): the JSON columns hold JSON.
RunRecord Flight(std::int64_t run_index, const std::string& policy) {
  RunRecord r;
  r.run_index = run_index;
  r.policy = policy;
  r.flight_id = run_index * 2 + (policy == "cma" ? 0 : 1);
  r.initial_cell_voltage_v = std::string("[4.1,4.1,4.1,4.0,4.0,4.0]");
  r.actions = std::string("[[0.0,\"NoOp\"]]");
  r.outcome = std::string("completed");
  r.run_seed = RunSeed(Header().seed, run_index);  // as the sampler draws it
  return r;
}

void ExecuteSql(const std::filesystem::path& path, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr), SQLITE_OK);
  char* error = nullptr;
  EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error), SQLITE_OK)
      << (error != nullptr ? error : "") << sql;
  sqlite3_free(error);
  sqlite3_close(db);
}

std::filesystem::path SoundStore(const std::filesystem::path& folder, const std::string& name) {
  const auto path = folder / name;
  ResultsStore store = ResultsStore::Create(path, Header());
  store.Insert({Flight(0, "cma"), Flight(0, "noop"), Flight(1, "cma"), Flight(1, "noop")});
  return path;
}

std::string AllProblems(const StoreCheckResult& result) {
  std::string text;
  for (const std::string& problem : result.problems) text += problem + "\n";
  return text;
}

TEST(StoreCheckTest, ACreationWhoseCheckpointMeetsAFullDiskLeavesNothing) {
  TempDir dir;
  const auto path = dir.path / "c.db";
  {
    // Room for the first page of the file only: the schema, campaign and policies pages stay in the -wal.
    FullDiskVfs full_disk(4096);
    try {
      ResultsStore::TryCreate(path, Header(), {}, true);
      ADD_FAILURE() << "created a store on a full disk";
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(path.string() + ": ", 0), 0u) << message;  // the user's path
      EXPECT_NE(message.find("full"), std::string::npos) << message;
      EXPECT_NE(message.find("nothing was created"), std::string::npos) << message;
      EXPECT_EQ(message.find(".creating-"), std::string::npos) << message;
    }
  }
  // Nothing at the user's path, nothing beside it: the corrected run (space freed) creates it afresh.
  EXPECT_FALSE(std::filesystem::exists(path));
  std::vector<std::string> left;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path)) left.push_back(entry.path().string());
  EXPECT_TRUE(left.empty()) << left.front();
  std::optional<ResultsStore> store = ResultsStore::TryCreate(path, Header(), {}, true);
  ASSERT_TRUE(store.has_value());
  EXPECT_EQ(store->header().policies.size(), 2u);
  EXPECT_EQ(IntegrityCheck(path), "ok");
}

TEST(StoreCheckTest, EveryRoomLeftOnTheDiskGivesAWholeStoreOrNone) {
  // From no room at all to more than the file needs: each creation either fails leaving nothing, or gives a
  // store that opens and checks clean.
  TempDir dir;
  int created = 0;
  for (sqlite3_int64 pages = 0; pages <= 16; ++pages) {
    const auto path = dir.path / ("c" + std::to_string(pages) + ".db");
    bool failed = false;
    {
      FullDiskVfs full_disk(pages * 4096);
      try {
        ResultsStore::TryCreate(path, Header());
      } catch (const InputError&) {
        failed = true;
      }
    }
    if (failed) {
      EXPECT_FALSE(std::filesystem::exists(path)) << pages << " pages of room";
    } else {
      ++created;
      EXPECT_TRUE(CheckStore(path).ok()) << pages << " pages of room\n" << AllProblems(CheckStore(path));
      EXPECT_NO_THROW(ResultsStore::Open(path)) << pages;
    }
  }
  EXPECT_GT(created, 0);  // the largest room holds the whole file
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path)) {
    files += entry.path().extension() == ".db" ? 1 : 0;
    EXPECT_EQ(entry.path().filename().string().find(".creating-"), std::string::npos) << entry.path();
  }
  EXPECT_EQ(files, created);
}

TEST(StoreCheckTest, ASoundStoreChecksClean) {
  TempDir dir;
  const auto path = SoundStore(dir.path, "c.db");
  const StoreCheckResult result = CheckStore(path);
  EXPECT_TRUE(result.ok()) << AllProblems(result);
  EXPECT_EQ(result.schema_version, kStoreSchemaVersion);
  EXPECT_EQ(result.flights, 4);
  EXPECT_EQ(result.policies, 2);
  EXPECT_EQ(result.runs_requested, 12);
  EXPECT_EQ(result.campaign_name, "short");
}

// Each damage is named by CheckStore (the expected words in one of its problems) and refused by Open with
// the user's path and the pointer to `uascma store check`.
TEST(StoreCheckTest, DamagedStoresAreNamedAndRefused) {
  struct Case {
    std::string name;
    std::string sql;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {"deleted policies row", "DELETE FROM policies WHERE slot = 1", "a policies row deleted"},
      {"added policies row",
       "INSERT INTO policies SELECT 2, 'extra', kind, source, hash, actions_json FROM policies WHERE slot = 1",
       "a policies row deleted, added or edited"},
      {"flight of a missing policy", "UPDATE runs SET policy = 'gone' WHERE run_index = 1 AND policy = 'noop'",
       "'gone' is not there"},
      {"text in a numeric column", "UPDATE runs SET energy_wh = 'lots' WHERE run_index = 0 AND policy = 'cma'",
       "energy_wh: a real number (the column's type), got text"},
      {"not JSON", "UPDATE runs SET actions = '[[0,' WHERE run_index = 0 AND policy = 'cma'", "actions: valid JSON"},
      {"JSON of the wrong shape", "UPDATE runs SET initial_cell_voltage_v = '[4.1]' WHERE run_index = 0",
       "a JSON list of 6 cell voltages"},
      {"text that is not UTF-8", "UPDATE runs SET reason = CAST(X'66FF6F' AS TEXT) WHERE run_index = 0",
       "reason: text in UTF-8, got 'f\\xFFo'"},
      {"flight_id out of step", "UPDATE runs SET flight_id = 99 WHERE run_index = 1 AND policy = 'cma'",
       "flight_id: run_index x 2 policies + slot 0 = 2, got 99"},
      {"run beyond the runs requested", "UPDATE campaign SET runs_requested = 1",
       "run_index: 0 to runs_requested - 1 = 0"},
      {"boolean out of range", "UPDATE runs SET failure = 5 WHERE run_index = 0 AND policy = 'cma'", "failure: 0 or 1"},
      {"edited configuration", "UPDATE campaign SET config_yaml = replace(config_yaml, 'seed: 11', 'seed: 12')",
       "config_hash: the hash of config_yaml"},
      {"no campaign row", "DELETE FROM campaign", "campaign: exactly one row"},
      {"claim of a missing worker", "INSERT INTO claims VALUES ((SELECT campaign_hash FROM campaign), 0, 77, 0)",
       "refers to a workers row that does not exist"},
      {"a flight of another campaign", "UPDATE runs SET campaign_hash = 'x' WHERE run_index = 1 AND policy = 'noop'",
       "campaign_hash: this campaign's hash"},
      {"a dropped column", "ALTER TABLE runs DROP COLUMN max_tilt_rad", "runs.max_tilt_rad"},
      // Rows that contradict themselves or the header.
      {"completed on a failed flight", "UPDATE runs SET failure = 1 WHERE run_index = 0 AND policy = 'cma'",
       "failure: 0 for the outcome 'completed', got 1 (the row contradicts itself)"},
      {"no outcome", "UPDATE runs SET outcome = 'won' WHERE run_index = 0 AND policy = 'cma'",
       "outcome: one of completed, "},
      {"negative energy", "UPDATE runs SET energy_wh = -3 WHERE run_index = 1 AND policy = 'cma'",
       "energy_wh: 0 or more, got -3"},
      {"negative cell voltage", "UPDATE runs SET min_cell_voltage_v = -0.5 WHERE run_index = 1 AND policy = 'noop'",
       "min_cell_voltage_v: 0 or more, got -0.5"},
      {"a run_seed that is not the sampler's", "UPDATE runs SET run_seed = 5 WHERE run_index = 1 AND policy = 'noop'",
       "run_seed: "},
      {"an edited header seed", "UPDATE campaign SET seed = 3", "campaign: seed: the seed of config_yaml"},
  };
  TempDir dir;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const auto path = SoundStore(dir.path, "damaged.db");
    ExecuteSql(path, c.sql);
    const StoreCheckResult result = CheckStore(path);
    EXPECT_FALSE(result.ok());
    EXPECT_NE(AllProblems(result).find(c.expected), std::string::npos) << AllProblems(result);
    try {
      ResultsStore::Open(path);
      ADD_FAILURE() << "a damaged store opened";
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(path.string() + ": database: ", 0), 0u) << message;
      EXPECT_NE(message.find("uascma store check " + path.string()), std::string::npos) << message;
    }
    std::filesystem::remove(path);
  }
}

// Runs `check` in a child process that cannot write `folder` and returns its exit code: as user nobody when this
// test runs as root (root may write any folder), else with the folder made read-only for the time of the call.
int InAFolderThatCannotBeWritten(const std::filesystem::path& folder, const std::function<int()>& check) {
  namespace fs = std::filesystem;
  const bool root = ::geteuid() == 0;
  if (!root) fs::permissions(folder, fs::perms::owner_read | fs::perms::owner_exec, fs::perm_options::replace);
  const pid_t child = ::fork();
  if (child == 0) {
    constexpr uid_t kNobody = 65534;
    if (root && (::setgid(kNobody) != 0 || ::setuid(kNobody) != 0)) ::_exit(90);
    ::_exit(check());
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  if (!root) fs::permissions(folder, fs::perms::owner_all, fs::perm_options::replace);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 99;
}

// A sound database in a folder its reader cannot write was "damaged" for store check, and report and --replay
// refused it: SQLite could not make its -shm there. It is read as an unchanging file, and said so.
TEST(StoreCheckTest, ASoundStoreInAFolderThatCannotBeWrittenIsReadNotCalledDamaged) {
  TempDir dir;
  const auto folder = dir.path / "read-only";
  std::filesystem::create_directories(folder);
  const auto path = SoundStore(folder, "c.db");
  ASSERT_FALSE(std::filesystem::exists(path.string() + "-wal"));  // closed: every flight in the main file
  // 0: read as immutable, sound, all four flights; 1-3: which expectation failed.
  const int check = InAFolderThatCannotBeWritten(folder, [&] {
    const StoreCheckResult result = CheckStore(path);
    if (!result.ok() || result.flights != 4) return 1;
    if (!result.read_immutable) return 2;
    StoreOptions read;
    read.read_only = true;
    const ResultsStore store = ResultsStore::Open(path, read);
    return store.read_immutable() && store.ReadRecords().size() == 4 ? 0 : 3;
  });
  EXPECT_EQ(check, 0);
  // Where the folder can be written nothing changes: the shared open, as before.
  const StoreCheckResult result = CheckStore(path);
  EXPECT_TRUE(result.ok()) << AllProblems(result);
  EXPECT_FALSE(result.read_immutable);
}

// A campaign resumed into a database in a folder this user cannot write stopped at SQLite's first statement with a
// message whose field was "configure" (the connection's settings) and SQLite's words only. It names the file and
// what cannot be written; the readers above still read it.
TEST(StoreCheckTest, AStoreThisUserCannotWriteIsRefusedForWritingNamingWhatCannotBeWritten) {
  TempDir dir;
  const auto folder = dir.path / "read-only";
  std::filesystem::create_directories(folder);
  const auto path = SoundStore(folder, "c.db");
  // 0: refused as expected; 1: opened for writing; 2-4: which expectation of the message failed.
  const int check = InAFolderThatCannotBeWritten(folder, [&] {
    try {
      const ResultsStore store = ResultsStore::Open(path);
      return 1;
    } catch (const InputError& e) {
      const std::string message = e.what();
      if (message.find("configure") != std::string::npos) return 2;
      if (message.rfind(path.string() + ": ", 0) != 0) return 3;
      return message.find("cannot be written") != std::string::npos ? 0 : 4;
    }
  });
  EXPECT_EQ(check, 0);
}

// A database renamed during a campaign ended with 0 rows in the renamed file (every flight in the -wal left at the
// old name) and a message that said only "an existing campaign database". The next batch finds it, stops, and the
// message says where the flights are; following it recovers every committed flight.
TEST(StoreCheckTest, ADatabaseRenamedDuringACampaignStopsItAndSaysHowToRecoverTheFlights) {
  TempDir dir;
  const auto path = dir.path / "c.db";
  const auto moved = dir.path / "moved.db";
  {
    ResultsStore store = ResultsStore::Create(path, Header());
    store.Insert({Flight(0, "cma"), Flight(0, "noop")});
    std::filesystem::rename(path, moved);
    try {
      store.Insert({Flight(1, "cma")});
      ADD_FAILURE() << "a batch was written into a moved database";
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(path.string() + ": file: the database this campaign opened, but it was renamed or "
                                              "deleted while the campaign ran",
                              0),
                0u)
          << message;
      EXPECT_NE(message.find(path.string() + "-wal"), std::string::npos) << message;
      EXPECT_NE(message.find("--resume"), std::string::npos) << message;
    }
  }
  // The recovery the message gives: the moved file back beside its -wal.
  std::filesystem::rename(moved, path);
  const StoreCheckResult result = CheckStore(path);
  EXPECT_TRUE(result.ok()) << AllProblems(result);
  EXPECT_EQ(result.flights, 2);
}

TEST(StoreCheckTest, AFileThatFailsSqlitesIntegrityCheckIsRefused) {
  TempDir dir;
  const auto path = SoundStore(dir.path, "c.db");
  ASSERT_EQ(IntegrityCheck(path), "ok");
  // Swap two bytes of an index's record area in the last page: the table and its index disagree, which
  // integrity_check finds and a plain read may not.
  ExecuteSql(path,
             "PRAGMA writable_schema = 1; "
             "UPDATE sqlite_master SET sql = replace(sql, 'flight_id)', 'run_index)') "
             "WHERE name = 'runs_by_flight'; PRAGMA writable_schema = 0;");
  ASSERT_NE(IntegrityCheck(path), "ok");
  const StoreCheckResult result = CheckStore(path);
  EXPECT_FALSE(result.ok());
  EXPECT_NE(AllProblems(result).find("SQLite integrity check"), std::string::npos) << AllProblems(result);
  EXPECT_THROW(ResultsStore::Open(path), InputError);
}

TEST(StoreCheckTest, BytesThatAreNotADatabaseAreAProblemNotACrash) {
  TempDir dir;
  const auto path = dir.path / "c.db";
  std::ofstream(path) << std::string(8192, 'x');
  const StoreCheckResult result = CheckStore(path);
  EXPECT_FALSE(result.ok());
  EXPECT_NE(AllProblems(result).find(path.string()), std::string::npos) << AllProblems(result);
  EXPECT_THROW(CheckStore(dir.path / "missing.db"), InputError);
}

}  // namespace
}  // namespace uascma::campaign
