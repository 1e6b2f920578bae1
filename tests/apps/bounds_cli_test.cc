// Plausibility bounds of every numeric input (issue 16): each CLI numeric option and each number of a
// campaign or weights YAML file has a case just outside its bound that must stop the command with exit
// code 2, one line on stderr naming the option or field and the bound, nothing on stdout and nothing
// written. A value on the bound itself is accepted (the bounds are closed intervals), and --help states
// each option's bound.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_runner.h"

namespace uascma {
namespace {

using testing_support::ExpectBadInput;
using testing_support::RunCli;
using testing_support::ScratchDir;

struct Case {
  std::string arguments;  // after the binary
  std::string named;      // the option or field the error must name
  std::string bound;      // the bound it must state ("" when the message is not a bound, e.g. a seed)
};

void ExpectRefused(const Case& c) {
  SCOPED_TRACE(c.arguments);
  const auto result = RunCli(c.arguments);
  ExpectBadInput(result, c.named);
  if (!c.bound.empty()) EXPECT_NE(result.err.find(c.bound), std::string::npos) << result.err;
}

// ---- CLI options -------------------------------------------------------------------------------------

TEST(BoundsCliTest, EveryNumericOptionOutsideItsBoundExitsTwoNamingOptionAndBound) {
  ScratchDir scratch("bounds_cli");
  const std::string db = (scratch.path / "never.db").string();
  const std::string campaign = "campaign --db " + db + " ";
  const std::string thrust = "thrust --config tractor ";
  const std::string authority = "authority --failed-motors 0 --total-thrust-n 24 --mass-kg 1.3 ";
  const std::string footprint = "footprint --speed-mps 5 --eod-s 60 ";
  const std::string sweep = "policy sensitivity --weight RM ";
  const std::vector<Case> cases = {
      {thrust + "--power-w 300 --throttle-us 1099", "--throttle-us", "1100 to 1900 us"},
      {thrust + "--power-w 300 --throttle-us 1901", "--throttle-us", "1100 to 1900 us"},
      {thrust + "--throttle-us 1500 --power-w -1", "--power-w", "0 to 1300 W"},
      {thrust + "--throttle-us 1500 --power-w 1301", "--power-w", "0 to 1300 W"},
      {"authority --total-thrust-n 24 --mass-kg 1.3 --failed-motors -1", "--failed-motors", "0 to 1 motors"},
      {"authority --total-thrust-n 24 --mass-kg 1.3 --failed-motors 2", "--failed-motors", "0 to 1 motors"},
      {"authority --failed-motors 0 --mass-kg 1.3 --total-thrust-n 0", "--total-thrust-n", "0.1 to 1000 N"},
      {"authority --failed-motors 0 --mass-kg 1.3 --total-thrust-n 1001", "--total-thrust-n", "0.1 to 1000 N"},
      {"authority --failed-motors 0 --total-thrust-n 24 --mass-kg 0", "--mass-kg", "0.05 to 25 kg"},
      {"authority --failed-motors 0 --total-thrust-n 24 --mass-kg 26", "--mass-kg", "0.05 to 25 kg"},
      {"eod --current-a -1", "--current-a", "0 to 105 A"},
      {"eod --current-a 1e9", "--current-a", "0 to 105 A"},
      {"eod --current-a 30 --temp-degf -41", "--temp-degf", "-40 to 140 °F"},
      {"eod --current-a 30 --temp-degf 141", "--temp-degf", "-40 to 140 °F"},
      {"eod --current-a 30 --cutoff-v 2.4", "--cutoff-v", "2.5 to 4.2 V"},
      {"eod --current-a 30 --cutoff-v 4.3", "--cutoff-v", "2.5 to 4.2 V"},
      {"eod --current-a 30 --horizon-s 0.5", "--horizon-s", "1 to 604800 s"},
      {"eod --current-a 30 --horizon-s 604801", "--horizon-s", "1 to 604800 s"},
      {"eod --current-a 30 --reference-dt-s 0.0001", "--reference-dt-s", "0.001 to 60 s"},
      {"eod --current-a 30 --reference-dt-s 61", "--reference-dt-s", "0.001 to 60 s"},
      {"eod --current-a 30 --initial-cell-voltage 3.2", "--initial-cell-voltage", ""},
      {"eod --current-a 30 --initial-cell-voltage 4.3", "--initial-cell-voltage", ""},
      {"rul --particles 0", "--particles", "1 to 1e+07"},
      {"rul --particles 10000001", "--particles", "1 to 1e+07"},
      {"rul --runs 0", "--runs", "1 to 1e+07"},
      {"rul --runs 10000001", "--runs", "1 to 1e+07"},
      {"rul --time-per-step 0.0009", "--time-per-step", "0.001 to 3600 s"},
      {"rul --time-per-step 3601", "--time-per-step", "0.001 to 3600 s"},
      {"rul --seed -1", "--seed", "2^64-1"},
      {"rul --seed 18446744073709551616", "--seed", "2^64-1"},
      {"footprint --eod-s 60 --speed-mps -0.1", "--speed-mps", "0 to 30 m/s"},
      {"footprint --eod-s 60 --speed-mps 31", "--speed-mps", "0 to 30 m/s"},
      {"footprint --speed-mps 5 --eod-s -1", "--eod-s", "0 to 7200 s"},
      {"footprint --speed-mps 5 --eod-s 7201", "--eod-s", "0 to 7200 s"},
      {footprint + "--mass-kg 0.04", "--mass-kg", "0.05 to 25 kg"},
      {footprint + "--mass-kg 26", "--mass-kg", "0.05 to 25 kg"},
      {footprint + "--thrust-n 0.05", "--thrust-n", "0.1 to 1000 N"},
      {footprint + "--thrust-n 1001", "--thrust-n", "0.1 to 1000 N"},
      {footprint + "--max-tilt-deg 0.5", "--max-tilt-deg", "1 to 89 deg"},
      {footprint + "--max-tilt-deg 90", "--max-tilt-deg", "1 to 89 deg"},
      {footprint + "--drag-slope -0.1", "--drag-slope", "0 to 100 N*s/m"},
      {footprint + "--drag-slope 101", "--drag-slope", "0 to 100 N*s/m"},
      {footprint + "--maclaurin -1", "--maclaurin", "0 to 30"},
      {footprint + "--maclaurin 31", "--maclaurin", "0 to 30"},
      {"map info --seed -1", "--seed", "2^64-1"},
      {"map info city.geojson --height-from-levels --metres-per-level 0.9", "--metres-per-level", "1 to 10 m"},
      {"map info city.geojson --height-from-levels --metres-per-level 11", "--metres-per-level", "1 to 10 m"},
      {"policy solve --model cma --gamma -0.1", "--gamma", "0 to 0.999"},
      {"policy solve --model cma --gamma 1", "--gamma", "0 to 0.999"},
      {sweep + "--to 0.3 --step 0.1 --from -0.1", "--from", "0 to 1"},
      {sweep + "--to 1.1 --step 0.1 --from 0", "--to", "0 to 1"},
      {sweep + "--from 0 --to 0.3 --step 0", "--step", "0.0001 to 1"},
      {sweep + "--from 0 --to 0.3 --step 1.1", "--step", "0.0001 to 1"},
      {sweep + "--from 0 --to 0.3 --step 0.1 --gamma 1", "--gamma", "0 to 0.999"},
      {campaign + "--runs -1", "--runs", "0 to 1e+07 runs"},
      {campaign + "--runs 10000001", "--runs", "0 to 1e+07 runs"},
      {campaign + "--seed -1", "--seed", "2^64-1"},
      {campaign + "--seed 18446744073709551616", "--seed", "2^64-1"},
      {campaign + "--jobs -1", "--jobs", "0 to 1024 threads"},
      {campaign + "--jobs 1025", "--jobs", "0 to 1024 threads"},
      {campaign + "--commit-every 0", "--commit-every", "0.01 to 3600 s"},
      {campaign + "--commit-every 3601", "--commit-every", "0.01 to 3600 s"},
  };
  for (const Case& c : cases) ExpectRefused(c);
  EXPECT_FALSE(std::filesystem::exists(db));
}

TEST(BoundsCliTest, ValuesOnTheBoundsAreAccepted) {
  for (const std::string arguments :
       {"thrust --config tractor --throttle-us 1900 --power-w 1300", "authority --failed-motors 1 --total-thrust-n 1000 --mass-kg 25",
        "eod --current-a 0 --temp-degf -40 --horizon-s 1", "eod --current-a 105 --cutoff-v 2.5",
        "rul --particles 1 --runs 1 --time-per-step 3600 --seed 18446744073709551615",
        "footprint --speed-mps 30 --eod-s 0 --max-tilt-deg 89", "policy solve --model cma --gamma 0.999 --format tsv"}) {
    const auto result = RunCli(arguments);
    EXPECT_EQ(result.exit_code, 0) << arguments << "\n" << result.err;
  }
}

// Issue 16: 10^9 A printed a negative bus voltage. The worst case inside the bounds — I_max through one
// pack of poor health, cold, nearly empty — still gives a positive bus voltage (eqs. 3.4-3.7).
TEST(BoundsCliTest, TheWorstCaseInsideTheBoundsHasAPositiveBusVoltage) {
  const auto result =
      RunCli("eod --current-a 105 --use UseBatt1 --health P --temp-degf -40 --initial-cell-voltage 3.3 --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_GT(nlohmann::json::parse(result.out).at("bus_voltage_v").get<double>(), 0.0) << result.out;
}

TEST(BoundsCliTest, HelpStatesTheBounds) {
  const std::vector<std::pair<std::string, std::string>> helps = {
      {"eod --help", "0 to 105 A"},       {"thrust --help", "0 to 1300 W"},   {"authority --help", "0.05 to 25 kg"},
      {"rul --help", "0.001 to 3600 s"}, {"footprint --help", "1 to 89 deg"}, {"map info --help", "1 to 10 m"},
      {"policy solve --help", "0 to 0.999"}, {"campaign --help", "0 to 1024 threads"}, {"rul --help", "0 to 2^64-1"}};
  for (const auto& [arguments, bound] : helps) {
    const auto result = RunCli(arguments);
    EXPECT_EQ(result.exit_code, 0) << arguments;
    EXPECT_NE(result.out.find(bound), std::string::npos) << arguments << "\n" << result.out;
  }
}

// ---- YAML numbers ------------------------------------------------------------------------------------

// Each campaign YAML number, just outside its bound: `uascma campaign FILE` exits 2 naming the field.
TEST(BoundsCliTest, EveryCampaignYamlNumberOutsideItsBoundExitsTwo) {
  ScratchDir scratch("bounds_campaign");
  const std::string db = (scratch.path / "never.db").string();
  const std::vector<std::pair<std::string, std::string>> cases = {  // YAML, field named
      {"seed: -1", "seed"},
      {"seed: 18446744073709551616", "seed"},
      {"runs: -1", "runs"},
      {"runs: 10000001", "runs"},
      {"runs: 2.5", "runs"},
      {"map: {procedural_seed: -1}", "map.procedural_seed"},
      {"map: {blocks_north: 0}", "map.blocks_north"},
      {"map: {blocks_north: 1e300}", "map.blocks_north"},
      {"map: {blocks_east: 201}", "map.blocks_east"},
      {"map: {buildings: [city.geojson], origin: [91, 0]}", "map.origin"},
      {"map: {buildings: [city.geojson], origin: [0, -181]}", "map.origin"},
      {"map: {buildings: [city.geojson], metres_per_level: 0}", "map.metres_per_level"},
      {"map: {buildings: [city.geojson], metres_per_level: 21}", "map.metres_per_level"},
      {"mission: {endurance_fraction: [0.001, 0.5]}", "mission.endurance_fraction"},
      {"mission: {endurance_fraction: [0.5, 1.1]}", "mission.endurance_fraction"},
      {"mission: {wall_clearance_m: -1}", "mission.wall_clearance_m"},
      {"mission: {wall_clearance_m: 101}", "mission.wall_clearance_m"},
      {"mission: {distance_m: [0.5, 100]}", "mission.distance_m"},
      {"mission: {distance_m: [100, 50001]}", "mission.distance_m"},
      {"mission: {cruise_speed_mps: [0.05, 5]}", "mission.cruise_speed_mps"},
      {"mission: {cruise_speed_mps: [1, 31]}", "mission.cruise_speed_mps"},
      {"mission: {cruise_altitude_m: 0.5}", "mission.cruise_altitude_m"},
      {"mission: {cruise_altitude_m: 1001}", "mission.cruise_altitude_m"},
      {"mission: {drop_hover_s: -1}", "mission.drop_hover_s"},
      {"mission: {drop_hover_s: 3601}", "mission.drop_hover_s"},
      {"safety_margin_s: [-1, 5]", "safety_margin_s"},
      {"safety_margin_s: [5, 601]", "safety_margin_s"},
      {"battery: {initial_cell_voltage_v: [3.2, 4.1]}", "battery.initial_cell_voltage_v"},
      {"battery: {initial_cell_voltage_v: [4.0, 4.3]}", "battery.initial_cell_voltage_v"},
      {"battery: {health_weights: {G: -1}}", "battery.health_weights"},
      {"battery: {health_weights: {M: 1e7}}", "battery.health_weights"},
      {"battery: {degraded_cells: [0, 6]}", "battery.degraded_cells"},
      {"battery: {degraded_cells: [1, 4294967297]}", "battery.degraded_cells"},
      {"battery: {cold_probability: -0.1}", "battery.cold_probability"},
      {"battery: {cold_probability: 1.1}", "battery.cold_probability"},
      {"battery: {cold_temp_degf: -41}", "battery.cold_temp_degf"},
      {"battery: {cold_temp_degf: 50}", "battery.cold_temp_degf"},
      {"battery: {warm_temp_degf: 49}", "battery.warm_temp_degf"},
      {"battery: {warm_temp_degf: 141}", "battery.warm_temp_degf"},
      {"wind: {speed_mps: [-1, 2]}", "wind.speed_mps"},
      {"wind: {speed_mps: [1, 51]}", "wind.speed_mps"},
      {"wind: {direction_rad: [-13, 0]}", "wind.direction_rad"},
      {"wind: {direction_rad: [0, 13]}", "wind.direction_rad"},
      {"fault: {probability: -0.1}", "fault.probability"},
      {"fault: {probability: 1.1}", "fault.probability"},
      {"fault: {onset_fraction: [-0.1, 0.5]}", "fault.onset_fraction"},
      {"fault: {onset_fraction: [0.5, 1.1]}", "fault.onset_fraction"},
      {"fault: {motors: [0]}", "fault.motors[0]"},
      {"fault: {motors: [1, 7]}", "fault.motors[1]"},
      {"fault: {time_per_growth_step_s: 0.0009}", "fault.time_per_growth_step_s"},
      {"fault: {time_per_growth_step_s: 3601}", "fault.time_per_growth_step_s"},
  };
  int index = 0;
  for (const auto& [yaml, field] : cases) {
    const auto file = scratch.path / ("case" + std::to_string(index++) + ".yaml");
    std::ofstream(file) << yaml << "\n";
    SCOPED_TRACE(yaml);
    const auto result = RunCli("campaign " + file.string() + " --db " + db);
    ExpectBadInput(result, field);
    EXPECT_NE(result.err.find(file.string()), std::string::npos) << result.err;
  }
  EXPECT_FALSE(std::filesystem::exists(db));
}

// Each CMA weight and gamma of a weights YAML file, just outside its bound: `policy solve --weights`.
TEST(BoundsCliTest, EveryWeightsYamlNumberOutsideItsBoundExitsTwo) {
  ScratchDir scratch("bounds_weights");
  const std::vector<std::pair<std::string, std::vector<std::string>>> groups = {
      {"end_states", {"C", "FL", "T", "E"}},
      {"actions", {"NoOp", "Terminate", "LandASAP", "LandPract"}},
      {"state_features", {"FS", "MH", "MM", "BH", "RM"}}};
  auto weights_yaml = [&](const std::string& gamma, const std::string& bad_name, const std::string& bad_value) {
    std::string text = "gamma: " + gamma + "\nweights:\n";
    for (const auto& [group, names] : groups) {
      text += "  " + group + ": {";
      for (std::size_t i = 0; i < names.size(); ++i) {
        text += (i ? ", " : "") + names[i] + ": " + (names[i] == bad_name ? bad_value : "0.05");
      }
      text += "}\n";
    }
    return text;
  };
  std::vector<std::pair<std::string, std::string>> cases;  // YAML, field named
  cases.emplace_back(weights_yaml("-0.01", "", ""), "gamma");
  cases.emplace_back(weights_yaml("1", "", ""), "gamma");
  for (const auto& [group, names] : groups) {
    for (const auto& name : names) {
      cases.emplace_back(weights_yaml("0.95", name, "-0.01"), "weights." + group + "." + name);
      cases.emplace_back(weights_yaml("0.95", name, "1.01"), "weights." + group + "." + name);
    }
  }
  const auto good = scratch.path / "good.yaml";
  std::ofstream(good) << weights_yaml("0.95", "", "");
  ASSERT_EQ(RunCli("policy solve --model cma --format tsv --weights " + good.string()).exit_code, 0);
  int index = 0;
  for (const auto& [yaml, field] : cases) {
    const auto file = scratch.path / ("w" + std::to_string(index++) + ".yaml");
    std::ofstream(file) << yaml;
    SCOPED_TRACE(field);
    const auto result = RunCli("policy solve --model cma --weights " + file.string());
    ExpectBadInput(result, field);
    EXPECT_NE(result.err.find(field == "gamma" ? "0 to 0.999" : "0 to 1"), std::string::npos) << result.err;
  }
}

}  // namespace
}  // namespace uascma
