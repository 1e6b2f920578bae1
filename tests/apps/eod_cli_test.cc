// End-to-end checks of `uascma eod`: JSON contract, agreement with the library, health and temperature
// ordering, one-line errors with exit code 2.
#include <algorithm>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "uascma/models/battery.h"
#include "uascma/prognostics/eod.h"
#include "uascma/prognostics/eod_distribution.h"

namespace uascma {
namespace {

using testing_support::LineCount;
using testing_support::RunCli;
using testing_support::ScratchDir;

// Seconds: the CLI prints the library's double through JSON (17 significant digits).
constexpr double kPrintedTolerance = 1e-9;

nlohmann::json RunJson(const std::string& arguments) {
  const auto result = RunCli(arguments + " --json");
  EXPECT_EQ(result.exit_code, 0) << arguments << ": " << result.err;
  return nlohmann::json::parse(result.out);
}

TEST(EodCliTest, JsonMatchesTheLibraryForTheDefaultBattery) {
  const nlohmann::json out = RunJson("eod --current-a 30");
  ASSERT_TRUE(out.at("eod_s").is_number());
  EXPECT_EQ(out.at("status"), "reached");
  ASSERT_TRUE(out.at("limiting_cell").is_object());
  const int pack = out.at("limiting_cell").at("pack");
  const int cell = out.at("limiting_cell").at("cell");
  const models::BatteryPack battery;
  const prognostics::EodResult expected = prognostics::CalcPackEod(battery, battery.MakeRestingState(4.1), 30.0);
  EXPECT_NEAR(out.at("eod_s").get<double>(), expected.eod_s, kPrintedTolerance);
  EXPECT_EQ(pack, expected.limiting_branch + 1);
  EXPECT_EQ(cell, expected.limiting_cell + 1);
  EXPECT_EQ(out.at("health"), "G");
  EXPECT_DOUBLE_EQ(out.at("temp_degf").get<double>(), 77.0);
  EXPECT_DOUBLE_EQ(out.at("initial_cell_voltage_v").get<double>(), 4.1);
  const auto branch = out.at("branch_current_a");
  EXPECT_NEAR(branch.at(0).get<double>() + branch.at(1).get<double>(), 30.0, 1e-9);
}

TEST(EodCliTest, TextOutputNamesTheLimitingCell) {
  const auto result = RunCli("eod --current-a 30 --initial-cell-voltage 4.05");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("EOD "), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("pack "), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("reaches 3.3 V first"), std::string::npos) << result.out;
}

TEST(EodCliTest, HealthTemperatureAndVoltageOrderTheEod) {
  const double good_s = RunJson("eod --current-a 40").at("eod_s");
  const double medium_s = RunJson("eod --current-a 40 --health M").at("eod_s");
  const double poor_s = RunJson("eod --current-a 40 --health P").at("eod_s");
  const double cold_s = RunJson("eod --current-a 40 --temp-degf 40").at("eod_s");
  const double fuller_s = RunJson("eod --current-a 40 --initial-cell-voltage 4.12").at("eod_s");
  EXPECT_LT(medium_s, good_s);
  EXPECT_LT(poor_s, medium_s);
  EXPECT_LT(cold_s, good_s);
  EXPECT_GT(fuller_s, good_s);
  // One pack alone carries twice the current per cell: it runs out sooner than both together.
  const double one_pack_s = RunJson("eod --current-a 40 --use UseBatt2").at("eod_s");
  EXPECT_LT(one_pack_s, good_s);
  EXPECT_EQ(RunJson("eod --current-a 40 --use UseBatt2").at("limiting_cell").at("pack"), 2);
}

TEST(EodCliTest, ReferenceComparisonAndSpecialStatusesKeepEodANumber) {
  const nlohmann::json checked = RunJson("eod --current-a 60 --reference-dt-s 0.01");
  EXPECT_LT(std::abs(checked.at("reference").at("relative_difference").get<double>()), 0.005);
  const nlohmann::json idle = RunJson("eod --current-a 0");
  EXPECT_EQ(idle.at("status"), "not_reached_within_horizon");
  EXPECT_TRUE(idle.at("eod_s").is_number());
  EXPECT_TRUE(idle.at("limiting_cell").is_null());
  const nlohmann::json empty = RunJson("eod --current-a 100 --initial-cell-voltage 3.4");
  EXPECT_EQ(empty.at("status"), "already_below_cutoff");
  EXPECT_DOUBLE_EQ(empty.at("eod_s").get<double>(), 0.0);
}

TEST(EodCliTest, OcvTableFromCsv) {
  ScratchDir dir("eod_cli_ocv");
  const auto path = dir.path / "ocv.csv";
  std::ofstream(path) << "soc_percent,ocv_v\n0,3.27\n5,3.61\n10,3.69\n50,3.84\n100,4.20\n";
  const nlohmann::json out = RunJson("eod --current-a 30 --ocv-csv " + path.string());
  EXPECT_EQ(out.at("status"), "reached");
  std::ofstream(path) << "soc_percent,ocv_v\n0,3.27\n5,oops\n";
  const auto bad = RunCli("eod --current-a 30 --ocv-csv " + path.string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("line 3"), std::string::npos) << bad.err;
}

TEST(EodCliTest, BadInputIsExitTwoWithOneLineNamingTheOption) {
  struct Case {
    std::string arguments;
    std::string option;
  };
  for (const Case& c : {Case{"eod --current-a -5", "--current-a"}, Case{"eod --current-a 10 --health X", "--health"},
                        Case{"eod --current-a 10 --initial-cell-voltage 4.5", "--initial-cell-voltage"},
                        Case{"eod --current-a 10 --initial-cell-voltage 3.0", "--initial-cell-voltage"},
                        Case{"eod --current-a 10 --use UseAll", "--use"}, Case{"eod", "--current-a"},
                        Case{"eod --current-a abc", "--current-a"}}) {
    const auto result = RunCli(c.arguments);
    EXPECT_EQ(result.exit_code, 2) << c.arguments;
    EXPECT_EQ(LineCount(result.err), 1) << c.arguments << ": " << result.err;
    EXPECT_NE(result.err.find(c.option), std::string::npos) << c.arguments << ": " << result.err;
    EXPECT_TRUE(result.out.empty()) << c.arguments;
  }
}

TEST(EodCliTest, QuantilesAreTheLibrarysDistribution) {
  const nlohmann::json out = RunJson(
      "eod --current-a 30 --quantiles --load-log-mean 0.02 --load-log-sigma 0.08 --soc-sigma 0.02 "
      "--cold-probability 0.3 --probability-before-s 550");
  const models::BatteryPack battery;
  prognostics::EodUncertainty uncertainty;
  uncertainty.load_log_mean = 0.02;
  uncertainty.load_log_sigma = 0.08;
  uncertainty.soc_sigma = 0.02;
  uncertainty.cold_probability = 0.3;
  const prognostics::EodDistribution expected =
      prognostics::CalcPackEodDistribution(battery, battery.MakeRestingState(4.1), 30.0, uncertainty);
  const nlohmann::json& distribution = out.at("distribution");
  const auto& levels = distribution.at("levels");
  const auto& quantiles = distribution.at("quantiles_s");
  ASSERT_EQ(levels.size(), quantiles.size());
  for (std::size_t i = 0; i < levels.size(); ++i) {
    EXPECT_NEAR(quantiles[i].get<double>(), expected.Quantile(levels[i].get<double>()), kPrintedTolerance);
    if (i > 0) {
      EXPECT_GT(quantiles[i].get<double>(), quantiles[i - 1].get<double>());
    }
  }
  EXPECT_NEAR(distribution.at("probability_before").at("probability").get<double>(), expected.ProbabilityBefore(550.0),
              kPrintedTolerance);
  const auto text = RunCli("eod --current-a 30 --quantiles --soc-sigma 0.02");
  EXPECT_EQ(text.exit_code, 0);
  EXPECT_NE(text.out.find("p95"), std::string::npos) << text.out;
  // The cold class of an uncertain class is the warm pack's R0 x 1.5: a cold --temp-degf is refused.
  const auto cold = RunCli("eod --current-a 30 --quantiles --temp-degf 40 --cold-probability 0.3");
  EXPECT_EQ(cold.exit_code, 2);
  EXPECT_NE(cold.err.find("--cold-probability"), std::string::npos) << cold.err;
  const auto negative = RunCli("eod --current-a 30 --quantiles --soc-sigma -0.1");
  EXPECT_EQ(negative.exit_code, 2);
  EXPECT_NE(negative.err.find("--soc-sigma"), std::string::npos) << negative.err;
}

TEST(EodCliTest, HelpExitsZero) {
  const auto result = RunCli("eod --help");
  EXPECT_EQ(result.exit_code, 0);
  EXPECT_NE(result.out.find("--current-a"), std::string::npos);
}

}  // namespace
}  // namespace uascma
