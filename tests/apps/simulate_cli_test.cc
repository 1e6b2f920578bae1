// `uascma simulate` and `uascma plot` end to end: outcomes, JSON fields, files, bad input.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_runner.h"

namespace uascma {
namespace {

using testing_support::RunCli;
using testing_support::ScratchDir;

std::string Example(const std::string& name) { return std::string(UASCMA_SOURCE_DIR) + "/examples/" + name; }

TEST(SimulateCliTest, NominalExampleCompletesAndReportsItsSpeed) {
  const auto result = RunCli("simulate " + Example("nominal.yaml") + " --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const nlohmann::json summary = nlohmann::json::parse(result.out);
  EXPECT_EQ(summary.at("outcome"), "completed");
  EXPECT_GT(summary.at("sim_time_s").get<double>(), 100.0);
  EXPECT_GT(summary.at("wall_time_s").get<double>(), 0.0);
  EXPECT_GT(summary.at("realtime_factor").get<double>(), 100.0);
}

TEST(SimulateCliTest, OutWritesTheFlightRecordAndPlotDrawsIt) {
  ScratchDir dir("simulate_out");
  const std::string out = (dir.path / "flight").string();
  const auto result = RunCli("simulate " + Example("jam-motor-3.yaml") + " --out " + out);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  for (const char* file : {"telemetry.csv", "plan.csv", "summary.json"}) {
    EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(out) / file)) << file;
  }
  const nlohmann::json summary = nlohmann::json::parse(testing_support::Slurp(std::filesystem::path(out) / "summary.json"));
  EXPECT_EQ(summary.at("isolated_rotor"), 3);
  EXPECT_LT(summary.at("detection_latency_s").get<double>(), 0.2);
  const auto plot = RunCli("plot " + out);
  ASSERT_EQ(plot.exit_code, 0) << plot.err;
  for (const char* png : {"path.png", "forces.png", "rotors.png", "battery.png", "eod.png", "decisions.png"}) {
    EXPECT_EQ(testing_support::Slurp(std::filesystem::path(out) / png).substr(1, 3), "PNG") << png;
  }
}

TEST(SimulateCliTest, PolicyAndSeedOverrideTheScenario) {
  const auto a = RunCli("simulate " + Example("nominal.yaml") + " --policy cma --seed 9 --json");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const nlohmann::json summary = nlohmann::json::parse(a.out);
  EXPECT_EQ(summary.at("policy"), "cma");
  EXPECT_EQ(summary.at("seed"), 9);
}

TEST(SimulateCliTest, BadScenarioIsExitTwoNamingFileAndKeyAndWritesNothing) {
  ScratchDir dir("simulate_bad");
  const auto scenario = dir.path / "bad.yaml";
  std::ofstream(scenario) << "name: bad\nwind: {speed_mps: fast}\n";
  const auto out = dir.path / "flight";
  const auto result = RunCli("simulate " + scenario.string() + " --out " + out.string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find(scenario.string()), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("wind.speed_mps"), std::string::npos) << result.err;
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1);
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_EQ(RunCli("simulate " + (dir.path / "missing.yaml").string()).exit_code, 2);
  EXPECT_EQ(RunCli("simulate " + Example("nominal.yaml") + " --policy hover").exit_code, 2);
  EXPECT_EQ(RunCli("plot " + dir.path.string()).exit_code, 2);
}

TEST(SimulateCliTest, ReplayFliesOneCampaignRunAgainBitForBit) {
  ScratchDir dir("simulate_replay");
  const std::string db = (dir.path / "c.db").string();
  ScratchDir config_dir("simulate_replay_config");
  const auto config = config_dir.path / "short.yaml";
  std::ofstream(config) << "mission: {distance_m: [200, 300], cruise_speed_mps: [6, 8]}\n";
  ASSERT_EQ(RunCli("campaign " + config.string() + " --runs 3 --policies cma,noop --seed 4 --db " + db + " --json").exit_code, 0);
  const auto first = RunCli("simulate --replay " + db + " 2:noop --json");
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const auto again = RunCli("simulate --replay " + db + " 2:noop --json");
  const nlohmann::json a = nlohmann::json::parse(first.out), b = nlohmann::json::parse(again.out);
  EXPECT_EQ(a.at("policy"), "noop");
  EXPECT_EQ(a.at("sim_time_s"), b.at("sim_time_s"));  // bit-identical flight
  EXPECT_EQ(a.at("outcome"), b.at("outcome"));
  EXPECT_EQ(RunCli("simulate --replay " + db + " 99:cma").exit_code, 2);
  EXPECT_EQ(RunCli("simulate --replay " + (dir.path / "none.db").string() + " 1").exit_code, 2);
}

}  // namespace
}  // namespace uascma
