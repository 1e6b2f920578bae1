// End-to-end checks of `uascma` as a user runs it: exit codes, one-line errors, outputs.
#include "cli_runner.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace uascma {
namespace {

using testing_support::RunCli;
using testing_support::ScratchDir;

TEST(CliTest, VersionAndHelpExitZero) {
  EXPECT_EQ(RunCli("--version").exit_code, 0);
  const auto help = RunCli("--help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("policy"), std::string::npos);
  EXPECT_EQ(RunCli("policy solve --help").exit_code, 0);
  EXPECT_EQ(RunCli("policy sensitivity --help").exit_code, 0);
}

TEST(CliTest, UnknownCommandOrOptionIsExitTwoOnOneLine) {
  const auto result = RunCli("fly-to-the-moon");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
}

TEST(CliTest, TransitionsPrintEveryAvailableRowWithTerminals) {
  const auto result = RunCli("policy transitions --model cma --action LandASAP");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  std::map<std::string, double> row_sum;
  std::istringstream lines(result.out);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream fields(line);
    std::string state, next, probability;
    std::getline(fields, state, '\t');
    std::getline(fields, next, '\t');
    std::getline(fields, probability, '\t');
    row_sum[state] += std::stod(probability);
  }
  // LandASAP is available in N (36) and ELPRACT (36) states and in the 4 terminal states.
  EXPECT_EQ(row_sum.size(), 76u);
  for (const auto& [state, sum] : row_sum) EXPECT_NEAR(sum, 1.0, 1e-8) << state;
  EXPECT_EQ(row_sum.count("E"), 1u);
  EXPECT_EQ(row_sum.count("ELASAP,NF,MM1,G,RM1"), 0u);
}

TEST(CliTest, UnknownActionIsExitTwo) {
  const auto result = RunCli("policy transitions --model cma --action Hover");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("--action"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("Hover"), std::string::npos) << result.err;
}

TEST(CliTest, SolveTsvHas108StatesAndShowReadsTheJson) {
  const auto tsv = RunCli("policy solve --model cma --format tsv");
  ASSERT_EQ(tsv.exit_code, 0) << tsv.err;
  EXPECT_EQ(std::count(tsv.out.begin(), tsv.out.end(), '\n'), 108);
  EXPECT_NE(tsv.out.find("N,NF,MM0,G,RM0\tLandPract\t"), std::string::npos);

  ScratchDir dir("solve_show");
  const std::string policy = (dir.path / "p.json").string();
  ASSERT_EQ(RunCli("policy solve --model cma --out " + policy).exit_code, 0);
  const std::string png = (dir.path / "q.png").string();
  const auto show = RunCli("policy show " + policy + " --plot " + png);
  ASSERT_EQ(show.exit_code, 0) << show.err;
  EXPECT_NE(show.out.find("III hyper"), std::string::npos);
  EXPECT_EQ(testing_support::Slurp(png).substr(1, 3), "PNG");
}

TEST(CliTest, BadWeightsFileIsExitTwoAndWritesNothing) {
  ScratchDir dir("bad_weights");
  const auto weights = dir.path / "w.yaml";
  std::ofstream(weights) << "weights:\n  end_states: {C: 0.163, FL: 0.408, T: 0, E: 0}\n"
                            "  actions: {NoOp: x, Terminate: 0, LandASAP: 0.02, LandPract: 0.041}\n"
                            "  state_features: {FS: 0, MH: 0, MM: 0.082, BH: 0.041, RM: 0.163}\n";
  const auto out = dir.path / "p.json";
  const auto result = RunCli("policy solve --model cma --weights " + weights.string() + " --out " + out.string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find(weights.string()), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("weights.actions.NoOp"), std::string::npos) << result.err;
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1);
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path), {}), 1);  // only w.yaml
}

TEST(CliTest, PolicyWithAnotherModelsHashIsRefused) {
  ScratchDir dir("hash");
  const std::string policy = (dir.path / "p.json").string();
  ASSERT_EQ(RunCli("policy solve --model cma --out " + policy).exit_code, 0);
  {
    std::ifstream in(policy);
    std::string text((std::istreambuf_iterator<char>(in)), {});
    const auto at = text.find("\"MM\": 0.082");
    ASSERT_NE(at, std::string::npos);
    text.replace(at, 11, "\"MM\": 0.083");
    std::ofstream(policy) << text;
  }
  const auto result = RunCli("policy show " + policy);
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("model_hash"), std::string::npos) << result.err;
}

TEST(CliTest, SensitivityReportsChangesPerStep) {
  const auto result = RunCli("policy sensitivity --weight MM --from 0 --to 0.3 --step 0.1 --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("\"steps\""), std::string::npos);
  EXPECT_EQ(RunCli("policy sensitivity --weight XX --from 0 --to 0.3 --step 0.1").exit_code, 2);
}

}  // namespace
}  // namespace uascma
