// End-to-end tests of `uascma learn q`, `uascma learn transitions` and `uascma policy solve --transitions`
// (dissertation §5.3.3, §5.6): small runs, the files they write usable as policies, the same files for
// any --jobs, and bad input refused with exit code 2 and nothing written.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_runner.h"

namespace uascma {
namespace {

using testing_support::ExpectBadInput;
using testing_support::RunCli;
using testing_support::RunResult;
using testing_support::ScratchDir;
using testing_support::Slurp;

// One small Q-learning run and one small transition estimate for the whole suite.
class LearnCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scratch_ = new ScratchDir("learn_cli");
    const std::string dir = scratch_->path.string();
    q_ = RunCli("learn q --episodes 4 --batch 2 --jobs 2 --seed 5 --json --out " + dir + "/q2.json --curve " + dir +
                "/curve.csv");
    q_one_thread_ = RunCli("learn q --episodes 4 --batch 2 --jobs 1 --seed 5 --out " + dir + "/q1.json");
    transitions_ = RunCli("learn transitions --runs 1 --seed 2 --json --out " + dir + "/t.json");
    solve_ = RunCli("policy solve --model cma --transitions " + dir + "/t.json --out " + dir + "/tp.json");
  }
  static void TearDownTestSuite() {
    delete scratch_;
    scratch_ = nullptr;
  }
  static std::string File(const std::string& name) { return (scratch_->path / name).string(); }

  static ScratchDir* scratch_;
  static testing_support::RunResult q_, q_one_thread_, transitions_, solve_;
};
ScratchDir* LearnCli::scratch_ = nullptr;
testing_support::RunResult LearnCli::q_, LearnCli::q_one_thread_, LearnCli::transitions_, LearnCli::solve_;

TEST_F(LearnCli, QLearningWritesAPolicyTheOtherCommandsUse) {
  ASSERT_EQ(q_.exit_code, 0) << q_.err;
  const nlohmann::json summary = nlohmann::json::parse(q_.out);
  EXPECT_EQ(summary["episodes"], 4);
  EXPECT_GE(summary["states_visited"].get<int>(), 1);
  EXPECT_EQ(summary["learning_states"], 1728);
  EXPECT_EQ(testing_support::LineCount(Slurp(File("curve.csv"))), 5);  // header + 4 episodes
  const RunResult show = RunCli("policy show " + File("q2.json"));
  EXPECT_EQ(show.exit_code, 0) << show.err;
  const RunResult fly =
      RunCli(std::string("simulate ") + UASCMA_SOURCE_DIR + "/examples/nominal.yaml --policy " + File("q2.json"));
  EXPECT_EQ(fly.exit_code, 0) << fly.err;
}

TEST_F(LearnCli, QLearningIsTheSameForAnyNumberOfThreads) {
  ASSERT_EQ(q_one_thread_.exit_code, 0) << q_one_thread_.err;
  EXPECT_EQ(Slurp(File("q1.json")), Slurp(File("q2.json")));
}

TEST_F(LearnCli, TransitionsAreSolvedIntoAPolicyBoundToTheEstimatedModel) {
  ASSERT_EQ(transitions_.exit_code, 0) << transitions_.err;
  const nlohmann::json summary = nlohmann::json::parse(transitions_.out)["summary"];
  EXPECT_EQ(summary["flights"], 1);
  EXPECT_GT(summary["observed_rows"].get<int>(), 0);
  EXPECT_EQ(summary["observed_rows"].get<int>() + summary["unobserved_rows"].get<int>(),
            summary["available_rows"].get<int>());
  ASSERT_EQ(solve_.exit_code, 0) << solve_.err;
  EXPECT_EQ(RunCli("policy show " + File("tp.json")).exit_code, 0);
  // The policy records the counts it was solved on: altering them breaks the model hash.
  nlohmann::json policy = nlohmann::json::parse(Slurp(File("tp.json")));
  auto& first = policy["model_config"]["transition_counts"][0]["next"];
  first[first.begin().key()] = first.begin().value().get<int>() + 1000;
  std::ofstream(File("tampered.json")) << policy.dump();
  ExpectBadInput(RunCli("policy show " + File("tampered.json")), "model_hash");
}

TEST_F(LearnCli, BadInputExitsTwoAndWritesNothing) {
  const std::string out = File("never.json");
  ExpectBadInput(RunCli("learn q --episodes 0 --out " + out), "--episodes");
  ExpectBadInput(RunCli("learn q --episodes 5 --alpha 1.5 --out " + out), "--alpha");
  ExpectBadInput(RunCli("learn q --episodes 5 --seed -1 --out " + out), "--seed");
  ExpectBadInput(RunCli("learn q --episodes 5 --jobs 0 --out " + out), "--jobs");
  ExpectBadInput(RunCli("learn q --episodes 5 --state fine --out " + out), "--state");
  ExpectBadInput(RunCli("learn q --episodes 2 --campaign " + File("missing.yaml") + " --out " + out), "missing.yaml");
  ExpectBadInput(RunCli("learn transitions --runs 0 --out " + out), "--runs");
  ExpectBadInput(RunCli("learn transitions --runs 1 --exploration 2 --out " + out), "--exploration");
  ExpectBadInput(RunCli("policy solve --model cma --transitions " + File("missing.json") + " --out " + out),
                 "missing.json");
  std::ofstream(File("wrong-format.json")) << R"({"format": "something-else", "counts": []})";
  ExpectBadInput(RunCli("policy solve --model cma --transitions " + File("wrong-format.json") + " --out " + out),
                 "format");
  std::ofstream(File("bad-count.json"))
      << R"({"format": "uascma-cma-transitions/1", "counts": [{"state": "N,NF,MM1,G,RM1", "action": "NoOp",)"
      << R"( "next": {"C": 1.5}}]})";
  ExpectBadInput(RunCli("policy solve --model cma --transitions " + File("bad-count.json") + " --out " + out),
                 "counts[0].next.C");
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST_F(LearnCli, HelpStatesTheBounds) {
  const RunResult help = RunCli("learn q --help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("--episodes"), std::string::npos);
  EXPECT_NE(help.out.find("1 to 1e+07 episodes"), std::string::npos) << help.out;
  EXPECT_NE(RunCli("learn transitions --help").out.find("--exploration"), std::string::npos);
}

}  // namespace
}  // namespace uascma
