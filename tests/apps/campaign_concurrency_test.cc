// Several `uascma campaign` processes on one SQLite database, as a user starts them from a
// second terminal, a job array or a retry loop: started at the same moment on a new database (the same
// campaign, and different ones), killed with SIGKILL and resumed, resumed twice at once. Every process
// either succeeds with every flight stored exactly once or exits 2 on one line naming the file; no
// flight is lost or flown twice; the rows equal those of an uninterrupted campaign (wall_time_s aside);
// PRAGMA integrity_check is ok; no temporary file is left behind.
#include "cli_runner.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "../campaign/campaign_test_support.h"
#include "../campaign/store_test_support.h"
#include "uascma/campaign/store.h"

extern char** environ;

namespace uascma {
namespace {

using campaign::ResultsStore;
using campaign::RunRecord;
using campaign::testing_support::IntegrityCheck;
using campaign::testing_support::StoredFlightsOrZero;
using testing_support::LineCount;
using testing_support::RunCli;
using testing_support::ScratchDir;
using testing_support::Slurp;

// Small campaigns keep the whole suite near half a minute on a shared 2-core machine: a process spends
// most of its ~0.2 s starting up, so several of them really do overlap on the database.
constexpr int kSmallRuns = 6;   // × 2 policies
constexpr int kLargeRuns = 40;  // × 2 policies: long enough to be killed in the middle
constexpr int kRounds = 20;

struct Child {
  pid_t pid = -1;
  std::filesystem::path out;
  std::filesystem::path err;
};

struct Finished {
  int exit_code = -1;  // -1 when killed by a signal
  bool killed = false;
  std::string out;
  std::string err;
};

Child Spawn(std::vector<std::string> args, const std::filesystem::path& base) {
  Child child;
  child.out = base.string() + ".out";
  child.err = base.string() + ".err";
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, child.out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&files, STDERR_FILENO, child.err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  const int code = posix_spawnp(&child.pid, argv[0], &files, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&files);
  EXPECT_EQ(code, 0) << args[0];
  return child;
}

Finished Wait(const Child& child) {
  int status = 0;
  ::waitpid(child.pid, &status, 0);
  Finished finished;
  finished.killed = WIFSIGNALED(status);
  finished.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  finished.out = Slurp(child.out);
  finished.err = Slurp(child.err);
  return finished;
}

// Temporary files of creations left in `folder`.
std::vector<std::string> Leftovers(const std::filesystem::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (name.find(".creating-") != std::string::npos) names.push_back(name);
  }
  return names;
}

void ExpectSameRows(const std::vector<RunRecord>& expected, const std::filesystem::path& db,
                    const std::string& context) {
  const std::vector<RunRecord> rows = ResultsStore::Open(db).ReadRecords();
  ASSERT_EQ(rows.size(), expected.size()) << context << ": a flight was lost or stored twice";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(campaign::FirstDifference(rows[i], expected[i]), std::nullopt)
        << context << ": row " << i << " (run " << rows[i].run_index << ", " << rows[i].policy << ")";
  }
  EXPECT_EQ(IntegrityCheck(db), "ok") << context;
}

class CampaignConcurrencyTest : public ::testing::Test {
 protected:
  // Uninterrupted reference campaigns, one process each.
  static void SetUpTestSuite() {
    dir_ = new ScratchDir("campaign_concurrency");
    std::ofstream(dir_->path / "short.yaml") << campaign::testing_support::ShortConfigYaml();
    references_ = new std::map<std::string, std::vector<RunRecord>>();
    for (const auto& [seed, runs] : {std::pair{11, kSmallRuns}, std::pair{12, kSmallRuns}, std::pair{11, kLargeRuns}}) {
      const std::string name = "reference-" + std::to_string(seed) + "-" + std::to_string(runs) + ".db";
      const auto result = RunCli(Join(Args(name, runs, seed)));
      ASSERT_EQ(result.exit_code, 0) << result.err;
      (*references_)[Key(seed, runs)] = ResultsStore::Open(Path(name)).ReadRecords();
    }
  }
  static void TearDownTestSuite() {
    delete references_;
    delete dir_;
  }
  static std::string Key(int seed, int runs) { return std::to_string(seed) + "/" + std::to_string(runs); }
  static const std::vector<RunRecord>& Reference(int seed, int runs) { return references_->at(Key(seed, runs)); }
  static std::filesystem::path Path(const std::string& name) { return dir_->path / name; }
  static std::vector<std::string> Args(const std::string& db, int runs, int seed) {
    return {UASCMA_CLI_PATH,
            "campaign",
            Path("short.yaml").string(),
            "--runs",
            std::to_string(runs),
            "--seed",
            std::to_string(seed),
            "--db",
            Path(db).string(),
            "--jobs",
            "1",
            "--json"};
  }
  static std::string Join(const std::vector<std::string>& args) {
    std::string line;
    for (std::size_t i = 1; i < args.size(); ++i) line += (i > 1 ? " " : "") + args[i];
    return line;
  }
  static std::vector<Finished> StartTogether(const std::vector<std::vector<std::string>>& commands,
                                             const std::string& name) {
    std::vector<Child> children;
    for (std::size_t i = 0; i < commands.size(); ++i) {
      children.push_back(Spawn(commands[i], Path(name + "-" + std::to_string(i))));
    }
    std::vector<Finished> finished;
    for (const Child& child : children) finished.push_back(Wait(child));
    return finished;
  }

  static ScratchDir* dir_;
  static std::map<std::string, std::vector<RunRecord>>* references_;
};
ScratchDir* CampaignConcurrencyTest::dir_ = nullptr;
std::map<std::string, std::vector<RunRecord>>* CampaignConcurrencyTest::references_ = nullptr;

TEST_F(CampaignConcurrencyTest, OneCampaignStartedTogetherFliesEachFlightOnce) {
  for (int round = 0; round < kRounds; ++round) {
    const std::string db = "same" + std::to_string(round) + ".db";
    const int processes = 2 + round % 3;
    const std::vector<Finished> finished =
        StartTogether(std::vector<std::vector<std::string>>(processes, Args(db, kSmallRuns, 11)), db);
    const std::string context = "round " + std::to_string(round) + " (" + std::to_string(processes) + " processes)";
    std::int64_t flown = 0;
    int succeeded = 0;
    for (const Finished& f : finished) {
      if (f.exit_code == 0) {
        ++succeeded;
        const nlohmann::json json = nlohmann::json::parse(f.out);
        flown += json["run"]["flights_flown"].get<std::int64_t>();
        EXPECT_EQ(json["campaign"]["complete_runs"], kSmallRuns) << context;  // a success saw every flight
      } else {
        // Started after the others had finished: the file exists and nobody runs it.
        ASSERT_EQ(f.exit_code, 2) << context << "\n" << f.err;
        EXPECT_EQ(LineCount(f.err), 1) << f.err;
        EXPECT_NE(f.err.find(Path(db).string()), std::string::npos) << f.err;
        EXPECT_NE(f.err.find("--resume"), std::string::npos) << f.err;
      }
    }
    EXPECT_GE(succeeded, 1) << context;
    EXPECT_EQ(flown, 2 * kSmallRuns) << context << ": flights flown twice or not at all";
    ExpectSameRows(Reference(11, kSmallRuns), Path(db), context);
  }
  EXPECT_EQ(Leftovers(dir_->path), std::vector<std::string>{});
}

TEST_F(CampaignConcurrencyTest, OfDifferentCampaignsStartedTogetherOneWinsAndTheOthersNameIt) {
  for (int round = 0; round < kRounds; ++round) {
    const std::string db = "mixed" + std::to_string(round) + ".db";
    const int processes = 2 + round % 3;
    std::vector<std::vector<std::string>> commands;
    std::vector<int> seeds;
    for (int i = 0; i < processes; ++i) {
      seeds.push_back((i + round) % 2 == 0 ? 11 : 12);  // both campaigns in every round
      commands.push_back(Args(db, kSmallRuns, seeds.back()));
    }
    const std::vector<Finished> finished = StartTogether(commands, db);
    const std::string context = "round " + std::to_string(round) + " (" + std::to_string(processes) + " processes)";
    const ResultsStore store = ResultsStore::Open(Path(db));
    const int winner = static_cast<int>(store.header().seed);
    const std::string winner_hash = store.header().campaign_hash;
    std::int64_t flown = 0;
    int succeeded = 0;
    for (std::size_t i = 0; i < finished.size(); ++i) {
      const Finished& f = finished[i];
      if (f.exit_code == 0) {
        ++succeeded;
        EXPECT_EQ(seeds[i], winner) << context;
        flown += nlohmann::json::parse(f.out)["run"]["flights_flown"].get<std::int64_t>();
        continue;
      }
      ASSERT_EQ(f.exit_code, 2) << context << "\n" << f.err;
      EXPECT_EQ(LineCount(f.err), 1) << f.err;
      EXPECT_NE(f.err.find(Path(db).string()), std::string::npos) << f.err;
      if (seeds[i] != winner) {
        EXPECT_NE(f.err.find("another campaign"), std::string::npos) << f.err;
        EXPECT_NE(f.err.find("(hash " + winner_hash), std::string::npos) << f.err;
      }
    }
    EXPECT_GE(succeeded, 1) << context;
    EXPECT_EQ(flown, 2 * kSmallRuns) << context;
    ExpectSameRows(Reference(winner, kSmallRuns), Path(db), context);
  }
  EXPECT_EQ(Leftovers(dir_->path), std::vector<std::string>{});
}

TEST_F(CampaignConcurrencyTest, AKilledProcessIsTakenOverAndResumeGivesTheUninterruptedRows) {
  // Passes 0-2 kill one of three processes (each position once); pass 3 kills all three.
  for (int round = 0; round < 4; ++round) {
    const std::string db = "killed" + std::to_string(round) + ".db";
    const std::string context = "round " + std::to_string(round);
    std::vector<std::string> args = Args(db, kLargeRuns, 11);
    args.insert(args.end(), {"--commit-every", "0.02"});
    std::vector<Child> children;
    for (int i = 0; i < 3; ++i) children.push_back(Spawn(args, Path(db + "-" + std::to_string(i))));
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (StoredFlightsOrZero(Path(db)) < 10 && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    for (int i = 0; i < 3; ++i) {
      if (round == 3 || i == round) ::kill(children[i].pid, SIGKILL);
    }
    bool any_succeeded = false;
    for (int i = 0; i < 3; ++i) {
      const Finished f = Wait(children[i]);
      if (round == 3 || i == round) continue;  // killed (or finished just before the signal)
      ASSERT_EQ(f.exit_code, 0) << context << ": a survivor failed\n" << f.err;
      any_succeeded = true;
    }
    if (any_succeeded) {
      // The survivors took the killed process's runs over (it is dead on this machine at once).
      EXPECT_EQ(StoredFlightsOrZero(Path(db)), 2 * kLargeRuns) << context;
    } else {
      EXPECT_LT(StoredFlightsOrZero(Path(db)), 2 * kLargeRuns) << context << ": the campaign ended before the kill";
    }
    const auto resumed = RunCli(Join(Args(db, kLargeRuns, 11)) + " --resume");
    ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
    const nlohmann::json json = nlohmann::json::parse(resumed.out);
    EXPECT_EQ(json["run"]["flights_before"].get<std::int64_t>() + json["run"]["flights_flown"].get<std::int64_t>(),
              2 * kLargeRuns);
    ExpectSameRows(Reference(11, kLargeRuns), Path(db), context);
  }
  EXPECT_EQ(Leftovers(dir_->path), std::vector<std::string>{});
}

TEST_F(CampaignConcurrencyTest, TwoResumesAtOnceFlyEachMissingFlightOnce) {
  constexpr int kPartRuns = 10;
  const auto part = RunCli(Join(Args("part.db", kPartRuns, 11)));
  ASSERT_EQ(part.exit_code, 0) << part.err;
  for (int round = 0; round < 3; ++round) {
    const std::string db = "resumed" + std::to_string(round) + ".db";
    std::filesystem::copy_file(Path("part.db"), Path(db));
    std::vector<std::string> args = Args(db, kLargeRuns, 11);
    args.push_back("--resume");
    const std::vector<Finished> finished = StartTogether({args, args}, db);
    const std::string context = "round " + std::to_string(round);
    std::int64_t flown = 0;
    for (const Finished& f : finished) {
      ASSERT_EQ(f.exit_code, 0) << context << "\n" << f.err;
      const nlohmann::json run = nlohmann::json::parse(f.out)["run"];
      flown += run["flights_flown"].get<std::int64_t>();
      // What each saw: stored before it started, flown by it, flown meanwhile by the other.
      EXPECT_EQ(run["flights_before"].get<std::int64_t>() + run["flights_flown"].get<std::int64_t>() +
                    run["flights_by_others"].get<std::int64_t>(),
                2 * kLargeRuns)
          << context;
    }
    EXPECT_EQ(flown, 2 * (kLargeRuns - kPartRuns)) << context << ": a missing flight was flown twice or not at all";
    ExpectSameRows(Reference(11, kLargeRuns), Path(db), context);
  }
}

TEST_F(CampaignConcurrencyTest, MpiRanksAndAPlainProcessShareOneDatabase) {
#ifndef UASCMA_TEST_WITH_MPI
  GTEST_SKIP() << "this build has no MPI (UASCMA_WITH_MPI=OFF)";
#else
  if (std::system("command -v mpirun > /dev/null 2>&1") != 0) GTEST_SKIP() << "mpirun is not installed";
  const std::string db = "mpi.db";
  // As root, Open MPI needs --allow-run-as-root; --oversubscribe starts more ranks than cores.
  std::vector<std::string> mpi = {"mpirun", "--allow-run-as-root", "--oversubscribe", "-n", "2"};
  const std::vector<std::string> args = Args(db, kLargeRuns, 11);
  mpi.insert(mpi.end(), args.begin(), args.end());
  const std::vector<Finished> finished = StartTogether({mpi, args}, db);
  std::int64_t flown = 0;
  for (const Finished& f : finished) {
    if (f.exit_code != 0) {  // only a start after the other had finished
      EXPECT_EQ(f.exit_code, 2) << f.err;
      EXPECT_NE(f.err.find("--resume"), std::string::npos) << f.err;
      continue;
    }
    flown += nlohmann::json::parse(f.out)["run"]["flights_flown"].get<std::int64_t>();
  }
  EXPECT_EQ(flown, 2 * kLargeRuns) << "flights flown twice or not at all";
  ExpectSameRows(Reference(11, kLargeRuns), Path(db), "mpirun and a plain process");
#endif
}

TEST_F(CampaignConcurrencyTest, ErrorsNameTheUsersPathAndLeaveNoFile) {
  // A folder that does not exist.
  const auto missing = Path("no-such-folder") / "c.db";
  const auto in_missing = RunCli(Join(Args("no-such-folder/c.db", 1, 11)));
  EXPECT_EQ(in_missing.exit_code, 2) << in_missing.err;
  EXPECT_EQ(LineCount(in_missing.err), 1) << in_missing.err;
  EXPECT_NE(in_missing.err.find(missing.string() + ": "), std::string::npos) << in_missing.err;
  EXPECT_FALSE(std::filesystem::exists(Path("no-such-folder")));

  // A folder the user cannot write (as root, the campaign runs as nobody through setpriv).
  const auto locked = Path("locked");
  std::filesystem::create_directories(locked);
  ::chmod(locked.c_str(), 0555);
  std::string prefix;
  if (::geteuid() == 0) {
    if (std::system("command -v setpriv > /dev/null 2>&1") != 0) GTEST_SKIP() << "root without setpriv";
    prefix = "setpriv --reuid=65534 --regid=65534 --clear-groups ";
  }
  const std::string shell = prefix + UASCMA_CLI_PATH + " " + Join(Args("locked/c.db", 1, 11)) + " >" +
                            Path("locked.out").string() + " 2>" + Path("locked.err").string();
  const int status = std::system(shell.c_str());
  const std::string err = Slurp(Path("locked.err"));
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2) << err;
  EXPECT_EQ(LineCount(err), 1) << err;
  EXPECT_NE(err.find((locked / "c.db").string() + ": "), std::string::npos) << err;
  EXPECT_EQ(err.find(".creating-"), std::string::npos) << err;
  EXPECT_TRUE(std::filesystem::is_empty(locked));
  ::chmod(locked.c_str(), 0755);
}

}  // namespace
}  // namespace uascma
