// End-to-end checks of `uascma footprint`: the drag-free closed form through the CLI, text and JSON output, the
// Maclaurin option, --plot, and bad input (exit 2, one line naming the option).
#include "cli_runner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

namespace uascma {
namespace {

using testing_support::ExpectBadInput;
using testing_support::RunCli;
using testing_support::RunResult;
using testing_support::ScratchDir;

constexpr double kMetres = 1e-9;  // m: the CLI prints JSON doubles in full

nlohmann::json RunJson(const std::string& arguments) {
  const RunResult result = RunCli("footprint " + arguments + " --json");
  EXPECT_EQ(result.exit_code, 0) << result.err;
  return result.exit_code == 0 ? nlohmann::json::parse(result.out) : nlohmann::json::object();
}

TEST(FootprintCliTest, DragFreeLimitsThroughTheCli) {
  // d_x = 0: forward v T, backward −v T/3, lateral 2 v T/3 (bounds inactive at 4 m/s over 10 s).
  const auto json = RunJson("--speed-mps 4 --eod-s 10 --drag-slope 0");
  EXPECT_NEAR(json.at("forward_m").get<double>(), 40.0, kMetres);
  EXPECT_NEAR(json.at("backward_m").get<double>(), -40.0 / 3.0, kMetres);
  EXPECT_NEAR(json.at("lateral_m").get<double>(), 80.0 / 3.0, kMetres);
  const auto& shape = json.at("shape");
  EXPECT_EQ(shape.at("type"), "ellipse");
  EXPECT_NEAR(shape.at("center_x_m").get<double>(), (40.0 - 40.0 / 3.0) / 2, kMetres);
  EXPECT_NEAR(shape.at("semi_axis_x_m").get<double>(), (40.0 + 40.0 / 3.0) / 2, kMetres);
  EXPECT_NEAR(shape.at("semi_axis_y_m").get<double>(), 80.0 / 3.0, kMetres);
  EXPECT_EQ(json.at("model"), "exact exponentials");
}

TEST(FootprintCliTest, DefaultsAndBounds) {
  const auto json = RunJson("--speed-mps 9 --eod-s 20");
  EXPECT_NEAR(json.at("mass_kg").get<double>(), 1.3, 1e-12);
  EXPECT_NEAR(json.at("thrust_n").get<double>(), 26.85, 1e-12);
  EXPECT_NEAR(json.at("max_tilt_deg").get<double>(), 30.0, 1e-9);
  EXPECT_GT(json.at("drag_slope").get<double>(), 0.5);  // the default table's slope at 9 m/s
  EXPECT_NEAR(json.at("max_force_n").get<double>(), 1.3 * 9.80665 * std::tan(30.0 / 180.0 * M_PI), 1e-9);
  // Bounded limits inside the unbounded ones.
  const auto& unbounded = json.at("unbounded");
  EXPECT_LT(json.at("forward_m").get<double>(), unbounded.at("forward_m").get<double>());
  EXPECT_GT(json.at("backward_m").get<double>(), unbounded.at("backward_m").get<double>());
  EXPECT_LT(json.at("lateral_m").get<double>(), unbounded.at("lateral_m").get<double>());
  // A smaller tilt limit shrinks the footprint.
  const auto tight = RunJson("--speed-mps 9 --eod-s 20 --max-tilt-deg 10");
  EXPECT_LT(tight.at("forward_m").get<double>(), json.at("forward_m").get<double>());
  EXPECT_GT(tight.at("backward_m").get<double>(), json.at("backward_m").get<double>());
  EXPECT_LT(tight.at("lateral_m").get<double>(), json.at("lateral_m").get<double>());
}

TEST(FootprintCliTest, TextNamesTheLimitsAndTheShape) {
  const RunResult result = RunCli("footprint --speed-mps 4 --eod-s 10 --drag-slope 0");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("forward limit"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("40.00 m"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("-13.33 m"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("26.67 m"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("ellipse"), std::string::npos) << result.out;
}

TEST(FootprintCliTest, MaclaurinOptionMatchesExactForShortDragTimeOnly) {
  const auto exact = RunJson("--speed-mps 9 --eod-s 0.5 --drag-slope 0.55");
  const auto series = RunJson("--speed-mps 9 --eod-s 0.5 --drag-slope 0.55 --maclaurin 5");
  EXPECT_EQ(series.at("model"), "order-5 Maclaurin series");
  EXPECT_NEAR(series.at("lateral_m").get<double>(), exact.at("lateral_m").get<double>(),
              1e-4 * exact.at("lateral_m").get<double>());
  const auto exact_long = RunJson("--speed-mps 9 --eod-s 20 --drag-slope 0.55");
  const auto series_long = RunJson("--speed-mps 9 --eod-s 20 --drag-slope 0.55 --maclaurin 5");
  EXPECT_LT(series_long.at("lateral_m").get<double>(), 0.1 * exact_long.at("lateral_m").get<double>());
}

TEST(FootprintCliTest, PlotWritesAPng) {
  ScratchDir dir("footprint_plot");
  const std::string png = (dir.path / "footprint.png").string();
  const RunResult result = RunCli("footprint --speed-mps 9 --eod-s 50 --plot " + png);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  ASSERT_TRUE(std::filesystem::exists(png));
  EXPECT_GT(std::filesystem::file_size(png), 10000u);
  EXPECT_NE(result.out.find("wrote"), std::string::npos) << result.out;
}

TEST(FootprintCliTest, BadInputIsExitTwoNamingTheOption) {
  ExpectBadInput(RunCli("footprint --speed-mps -1 --eod-s 10"), "--speed-mps");
  ExpectBadInput(RunCli("footprint --speed-mps abc --eod-s 10"), "--speed-mps");
  ExpectBadInput(RunCli("footprint --speed-mps 5 --eod-s nan"), "--eod-s");
  ExpectBadInput(RunCli("footprint --speed-mps 5 --eod-s -3"), "--eod-s");
  ExpectBadInput(RunCli("footprint --speed-mps 5"), "--eod-s");
  ExpectBadInput(RunCli("footprint --speed-mps 5 --eod-s 10 --mass-kg 0"), "--mass-kg");
  ExpectBadInput(RunCli("footprint --speed-mps 5 --eod-s 10 --thrust-n -1"), "--thrust-n");
  ExpectBadInput(RunCli("footprint --speed-mps 5 --eod-s 10 --thrust-n 10"), "--thrust-n");  // below m g
  ExpectBadInput(RunCli("footprint --speed-mps 5 --eod-s 10 --max-tilt-deg 90"), "--max-tilt-deg");
  ExpectBadInput(RunCli("footprint --speed-mps 5 --eod-s 10 --drag-slope -0.2"), "--drag-slope");
  ExpectBadInput(RunCli("footprint --speed-mps 5 --eod-s 10 --maclaurin 31"), "--maclaurin");
  ExpectBadInput(RunCli("footprint --speed-mps 5 --eod-s 10 --maclaurin 5 --drag-slope 0"), "--drag-slope");
}

}  // namespace
}  // namespace uascma
