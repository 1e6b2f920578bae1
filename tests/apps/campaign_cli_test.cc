// `uascma campaign` and `uascma report` as a user runs them: the same rows after a hard kill and a
// resume, under mpirun with 2 and 3 ranks (those of one thread), after a full disk; one-line errors that leave
// no database; the report of a hand-made database.
#include "cli_runner.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "../campaign/campaign_test_support.h"
#include "uascma/campaign/sampler.h"
#include "uascma/campaign/store.h"

extern char** environ;

namespace uascma {
namespace {

using campaign::ResultsStore;
using campaign::RunRecord;
using testing_support::LineCount;
using testing_support::RunCli;
using testing_support::ScratchDir;

constexpr int kRuns = 60;  // × 2 policies: ~1 s of flying on one thread

void ExpectSameRows(const std::filesystem::path& a, const std::filesystem::path& b) {
  const std::vector<RunRecord> rows_a = ResultsStore::Open(a).ReadRecords();
  const std::vector<RunRecord> rows_b = ResultsStore::Open(b).ReadRecords();
  ASSERT_EQ(rows_a.size(), rows_b.size()) << a << " vs " << b;
  for (std::size_t i = 0; i < rows_a.size(); ++i) {
    EXPECT_EQ(campaign::FirstDifference(rows_a[i], rows_b[i]), std::nullopt)
        << "row " << i << " (run " << rows_a[i].run_index << ", " << rows_a[i].policy << ")";
  }
}

std::int64_t StoredFlights(const std::filesystem::path& db) {
  std::error_code ec;
  if (!std::filesystem::exists(db, ec)) return 0;
  try {
    return ResultsStore::Open(db).CountFlights();
  } catch (const std::exception&) {
    return 0;  // being created
  }
}

class CampaignCliTest : public ::testing::Test {
 protected:
  // One uninterrupted reference campaign for the whole suite (2 threads).
  static void SetUpTestSuite() {
    dir_ = new ScratchDir("campaign_cli");
    std::ofstream(dir_->path / "short.yaml") << campaign::testing_support::ShortConfigYaml();
    const auto result = RunCli(Args("reference.db") + " --jobs 2 --json");
    ASSERT_EQ(result.exit_code, 0) << result.err;
    reference_json_ = new nlohmann::json(nlohmann::json::parse(result.out));
  }
  static void TearDownTestSuite() {
    delete reference_json_;
    delete dir_;
  }
  static std::filesystem::path Path(const std::string& name) { return dir_->path / name; }
  static std::string Args(const std::string& db) {
    return "campaign " + Path("short.yaml").string() + " --runs " + std::to_string(kRuns) + " --db " +
           Path(db).string();
  }

  static ScratchDir* dir_;
  static nlohmann::json* reference_json_;
};
ScratchDir* CampaignCliTest::dir_ = nullptr;
nlohmann::json* CampaignCliTest::reference_json_ = nullptr;

TEST_F(CampaignCliTest, JsonGivesRatesWithSemPerPolicyAndHealth) {
  const nlohmann::json& json = *reference_json_;
  EXPECT_EQ(json["run"]["flights_flown"], 2 * kRuns);
  std::int64_t runs = 0;
  for (const char* health : {"G", "M", "P"}) {
    const nlohmann::json& group = json["policies"]["noop"][health];
    runs += group["runs"].get<std::int64_t>();
    if (group["runs"].get<std::int64_t>() == 0) continue;
    const double p = group["failure_rate"].get<double>();
    EXPECT_NEAR(group["failure_rate_sem"].get<double>(), std::sqrt(p * (1 - p) / group["runs"].get<double>()), 1e-12);
    EXPECT_TRUE(group.contains("completion_rate_sem"));
    EXPECT_TRUE(group.contains("emergency_landing_rate"));
    EXPECT_TRUE(group.contains("termination_rate"));
    EXPECT_TRUE(group.contains("average_reward_sem"));
    EXPECT_TRUE(group.contains("min_reward"));
  }
  EXPECT_EQ(runs, kRuns);
  EXPECT_EQ(json["policies"]["cma"]["all"]["runs"], kRuns);
  EXPECT_EQ(json["campaign"]["name"], "short");
}

TEST_F(CampaignCliTest, AHardKillLosesNothingAndCountsNothingTwice) {
  const auto db = Path("killed.db");
  // Kill the campaign twice at different moments, then let it finish.
  for (const std::int64_t kill_after : {6, 50}) {
    const std::string runs = std::to_string(kRuns);
    std::vector<std::string> args = {UASCMA_CLI_PATH,  "campaign", Path("short.yaml").string(),
                                     "--runs",         runs,       "--db",
                                     db.string(),      "--jobs",   "1",
                                     "--commit-every", "0.02",     "--resume"};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t files;
    posix_spawn_file_actions_init(&files);
    posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&files, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
    pid_t pid = 0;
    ASSERT_EQ(posix_spawn(&pid, argv[0], &files, nullptr, argv.data(), environ), 0);
    posix_spawn_file_actions_destroy(&files);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (StoredFlights(db) < kill_after && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status)) << "the campaign ended before it could be killed; raise kRuns";
    const std::int64_t stored = StoredFlights(db);
    EXPECT_GE(stored, kill_after);
    EXPECT_LT(stored, 2 * kRuns);
  }
  const auto resumed = RunCli(Args("killed.db") + " --resume --json");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  const nlohmann::json json = nlohmann::json::parse(resumed.out);
  EXPECT_GT(json["run"]["flights_before"].get<std::int64_t>(), 0);
  EXPECT_EQ(json["run"]["flights_before"].get<std::int64_t>() + json["run"]["flights_flown"].get<std::int64_t>(),
            2 * kRuns);
  ExpectSameRows(Path("reference.db"), db);
}

TEST_F(CampaignCliTest, MpiRanksGiveTheSameRows) {
#ifndef UASCMA_TEST_WITH_MPI
  GTEST_SKIP() << "this build has no MPI (UASCMA_WITH_MPI=OFF)";
#else
  if (std::system("command -v mpirun > /dev/null 2>&1") != 0) GTEST_SKIP() << "mpirun is not installed";
  // The ranks' rows against one thread's as well as the suite's two-thread reference: a difference between the
  // reference and one thread would otherwise pass as the ranks agreeing with it.
  const auto serial = RunCli(Args("serial.db") + " --jobs 1");
  ASSERT_EQ(serial.exit_code, 0) << serial.err;
  ExpectSameRows(Path("serial.db"), Path("reference.db"));
  for (const int ranks : {2, 3}) {
    const std::string db = "mpi" + std::to_string(ranks) + ".db";
    // As root, Open MPI needs --allow-run-as-root; --oversubscribe starts more ranks than cores.
    const std::string command = "mpirun --allow-run-as-root --oversubscribe -n " + std::to_string(ranks) + " " +
                                std::string(UASCMA_CLI_PATH) + " " + Args(db) + " --json >" +
                                Path(db + ".out").string() + " 2>" + Path(db + ".err").string();
    const int status = std::system(command.c_str());
    ASSERT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 0) << testing_support::Slurp(Path(db + ".err"));
    const nlohmann::json json = nlohmann::json::parse(testing_support::Slurp(Path(db + ".out")));
    EXPECT_EQ(json["run"]["ranks"], ranks);
    EXPECT_EQ(json["run"]["flights_flown"], 2 * kRuns);
    ExpectSameRows(Path("serial.db"), Path(db));
  }
#endif
}

TEST_F(CampaignCliTest, AFullDiskIsAClearErrorAndResumeCompletes) {
  const auto db = Path("full.db");
  // A file-size limit (ulimit -f, KiB) stands in for a full disk: writes past it fail with EFBIG.
  const std::string command = "bash -c \"trap '' XFSZ; ulimit -f 48; exec " + std::string(UASCMA_CLI_PATH) + " " +
                              Args("full.db") + " --jobs 1 --commit-every 0.02\" >" + Path("full.out").string() +
                              " 2>" + Path("full.err").string();
  const int status = std::system(command.c_str());
  const std::string err = testing_support::Slurp(Path("full.err"));
  ASSERT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2) << err;
  // One error line. A slow run (the sanitizer build: 6 flights/s) may log a progress line before it (not a terminal:
  // a line per 5 % of the work, common/progress.h); those are not the error.
  std::istringstream lines(err);
  int error_lines = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.find(" elapsed, ") == std::string::npos) ++error_lines;
  }
  EXPECT_EQ(error_lines, 1) << err;
  EXPECT_NE(err.find(db.string()), std::string::npos) << err;
  EXPECT_NE(err.find("full"), std::string::npos) << err;
  const std::int64_t stored = StoredFlights(db);
  EXPECT_LT(stored, 2 * kRuns);
  const auto resumed = RunCli(Args("full.db") + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  ExpectSameRows(Path("reference.db"), db);
}

TEST_F(CampaignCliTest, BadInputIsExitTwoOnOneLineAndWritesNoDatabase) {
  struct Case {
    std::string arguments;
    std::string named;
  };
  std::ofstream(Path("typo.yaml")) << "wind:\n  sped_mps: [1, 2]\n";
  const std::vector<Case> cases = {
      {"campaign " + Path("missing.yaml").string() + " --db " + Path("bad.db").string(), "missing.yaml"},
      {"campaign " + Path("typo.yaml").string() + " --db " + Path("bad.db").string(), "wind.sped_mps"},
      {Args("bad.db") + " --policies cma,greedy", "--policies"},
      {Args("bad.db") + " --policies " + Path("missing-policy.json").string(), "missing-policy.json"},
      {Args("bad.db") + " --seed -3", "--seed"},
      {"report " + Path("missing.db").string(), "missing.db"},
  };
  for (const Case& c : cases) {
    const auto result = RunCli(c.arguments);
    EXPECT_EQ(result.exit_code, 2) << c.arguments << "\n" << result.err;
    EXPECT_EQ(LineCount(result.err), 1) << result.err;
    EXPECT_NE(result.err.find(c.named), std::string::npos) << result.err;
    EXPECT_FALSE(std::filesystem::exists(Path("bad.db"))) << c.arguments;
  }
}

TEST_F(CampaignCliTest, AnotherCampaignsDatabaseIsRefusedAndLeftAlone) {
  std::filesystem::copy_file(Path("reference.db"), Path("other.db"));
  const std::int64_t before = StoredFlights(Path("other.db"));
  const auto other_seed = RunCli(Args("other.db") + " --resume --seed 12");
  EXPECT_EQ(other_seed.exit_code, 2);
  EXPECT_EQ(LineCount(other_seed.err), 1) << other_seed.err;
  EXPECT_NE(other_seed.err.find(Path("other.db").string()), std::string::npos) << other_seed.err;
  EXPECT_NE(other_seed.err.find("another campaign"), std::string::npos) << other_seed.err;
  const auto no_resume = RunCli(Args("other.db"));
  EXPECT_EQ(no_resume.exit_code, 2);
  EXPECT_NE(no_resume.err.find("--resume"), std::string::npos) << no_resume.err;
  EXPECT_EQ(StoredFlights(Path("other.db")), before);
  ExpectSameRows(Path("reference.db"), Path("other.db"));
}

TEST_F(CampaignCliTest, APolicyFileFliesLikeThePolicyItHolds) {
  const auto solved = RunCli("policy solve --out " + Path("tuned.json").string());
  ASSERT_EQ(solved.exit_code, 0) << solved.err;
  const auto result = RunCli("campaign " + Path("short.yaml").string() + " --runs 4 --policies cma," +
                             Path("tuned.json").string() + " --db " + Path("file.db").string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const std::vector<RunRecord> rows = ResultsStore::Open(Path("file.db")).ReadRecords();
  ASSERT_EQ(rows.size(), 8u);
  for (std::size_t i = 0; i + 1 < rows.size(); i += 2) {
    EXPECT_EQ(rows[i].policy, "cma");
    EXPECT_EQ(rows[i + 1].policy, "tuned");  // named by the file stem
    RunRecord same = rows[i + 1];            // the file holds the default-weight policy: the same flight
    same.policy = rows[i].policy;
    same.flight_id = rows[i].flight_id;
    EXPECT_EQ(campaign::FirstDifference(rows[i], same), std::nullopt) << "run " << rows[i].run_index;
  }
}

TEST_F(CampaignCliTest, ReportOfAHandMadeDatabase) {
  const auto db = Path("hand.db");
  campaign::CampaignConfig config = campaign::testing_support::ShortConfig();
  config.runs = 2;
  {
    ResultsStore store = ResultsStore::Create(
        db, campaign::MakeCampaignHeader(config, {campaign::SolvedCmaPolicy(), campaign::NoOpCampaignPolicy()}));
    auto flight = [&config](std::int64_t run, const std::string& policy, const std::string& outcome, double reward) {
      RunRecord r;
      r.run_seed = campaign::RunSeed(config.seed, run);  // as the sampler draws it (the store check holds rows to it)
      r.battery_health = std::string("P");               // (a literal here trips GCC 12's -Wrestrict false positive)
      r.run_index = run;
      r.policy = policy;
      r.flight_id = 2 * run + (policy == "cma" ? 0 : 1);
      r.initial_cell_voltage_v = std::string("[4.1,4.1,4.1,4.1,4.1,4.1]");  // JSON columns hold JSON (store check)
      r.actions = std::string("[]");
      r.outcome = outcome;
      r.failure = outcome == "failed_battery";
      r.average_reward = reward;
      r.min_reward = reward - 0.5;
      return r;
    };
    store.Insert({flight(0, "cma", "emergency_landing", 0.2), flight(0, "noop", "failed_battery", -0.1),
                  flight(1, "cma", "completed", 0.3), flight(1, "noop", "failed_battery", -0.3)});
  }
  const auto json_run = RunCli("report " + db.string() + " --json");
  ASSERT_EQ(json_run.exit_code, 0) << json_run.err;
  const nlohmann::json json = nlohmann::json::parse(json_run.out);
  const nlohmann::json& cma = json["policies"]["cma"]["P"];
  const nlohmann::json& noop = json["policies"]["noop"]["P"];
  EXPECT_EQ(cma["runs"], 2);
  EXPECT_NEAR(cma["failure_rate"].get<double>(), 0.0, 1e-12);
  EXPECT_NEAR(cma["emergency_landing_rate"].get<double>(), 0.5, 1e-12);
  EXPECT_NEAR(cma["emergency_landing_rate_sem"].get<double>(), std::sqrt(0.25 / 2.0), 1e-12);
  EXPECT_NEAR(noop["failure_rate"].get<double>(), 1.0, 1e-12);
  EXPECT_NEAR(noop["average_reward"].get<double>(), -0.2, 1e-12);
  EXPECT_NEAR(noop["average_reward_sem"].get<double>(), 0.1, 1e-12);  // s = √0.02, s/√2 = 0.1
  EXPECT_EQ(json["policies"]["cma"]["G"]["runs"], 0);
  EXPECT_EQ(json["campaign"]["complete_runs"], 2);

  const auto text = RunCli("report " + db.string() + " --plots " + Path("plots").string());
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("noop       P        2   100.0 ±  0.0"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("dissertation  71.0 %"), std::string::npos) << text.out;
  for (const char* plot : {"failure_rate.png", "completion_rate.png", "rewards.png", "outcomes.png",
                           "failure_causes.png", "failure_fades.png"}) {
    EXPECT_TRUE(std::filesystem::exists(Path("plots") / plot)) << plot;
  }
}

}  // namespace
}  // namespace uascma
