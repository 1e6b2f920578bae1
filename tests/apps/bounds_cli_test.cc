// Plausibility bounds of every numeric input: each CLI numeric option and each number of a
// campaign or weights YAML file has a case just outside its bound that must stop the command with exit
// code 2, one line on stderr naming the option or field and the bound, nothing on stdout and nothing
// written. A value on the bound itself is accepted (the bounds are closed intervals), and --help states
// each option's bound.
#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "uascma/common/error.h"
#include "uascma/sim/scenario.h"

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
  if (!c.bound.empty()) {
    EXPECT_NE(result.err.find(c.bound), std::string::npos) << result.err;
  }
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
      {"map info city.geojson --origin 91,0", "--origin", "latitude in [-90, 90]"},
      {"map info city.geojson --origin 40,-181", "--origin", "longitude in [-180, 180]"},
      {"simulate examples/nominal.yaml --seed -1", "--seed", "2^64-1"},
      {"simulate examples/nominal.yaml --seed 18446744073709551616", "--seed", "2^64-1"},
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
       {"thrust --config tractor --throttle-us 1900 --power-w 1300",
        "authority --failed-motors 1 --total-thrust-n 1000 --mass-kg 25",
        "eod --current-a 0 --temp-degf -40 --horizon-s 1", "eod --current-a 105 --cutoff-v 2.5",
        "rul --particles 1 --runs 1 --time-per-step 3600 --seed 18446744073709551615",
        "footprint --speed-mps 30 --eod-s 0 --max-tilt-deg 89",
        "policy solve --model cma --gamma 0.999 --format tsv"}) {
    const auto result = RunCli(arguments);
    EXPECT_EQ(result.exit_code, 0) << arguments << "\n" << result.err;
  }
}

// Once, 10^9 A printed a negative bus voltage. The worst case inside the bounds — I_max through one
// pack of poor health, cold, nearly empty — still gives a positive bus voltage (eqs. 3.4-3.7).
TEST(BoundsCliTest, TheWorstCaseInsideTheBoundsHasAPositiveBusVoltage) {
  const auto result =
      RunCli("eod --current-a 105 --use UseBatt1 --health P --temp-degf -40 --initial-cell-voltage 3.3 --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_GT(nlohmann::json::parse(result.out).at("bus_voltage_v").get<double>(), 0.0) << result.out;
}

TEST(BoundsCliTest, HelpStatesTheBounds) {
  const std::vector<std::pair<std::string, std::string>> helps = {
      {"eod --help", "0 to 105 A"},          {"thrust --help", "0 to 1300 W"},
      {"authority --help", "0.05 to 25 kg"}, {"rul --help", "0.001 to 3600 s"},
      {"footprint --help", "1 to 89 deg"},   {"map info --help", "1 to 10 m"},
      {"policy solve --help", "0 to 0.999"}, {"campaign --help", "0 to 1024 threads"},
      {"rul --help", "0 to 2^64-1"}};
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
  const std::vector<std::pair<std::string, std::string>> cases = {
      // YAML, field named
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
      {"map: {buildings: [city.geojson], default_height_m: 0.5}", "map.default_height_m"},
      {"map: {buildings: [city.geojson], default_height_m: 501}", "map.default_height_m"},
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
      {"battery: {health_weights: {P: -0.1}}", "battery.health_weights"},
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

// ---- Scenario YAML numbers (sim/scenario_bounds.h) ---------------------------------------------------

struct YamlCase {
  std::string yaml;   // the whole scenario file
  std::string field;  // the key the error must name
  std::string bound;  // the bound it must state ("" when the message is not a bound)
};

// Every number of a scenario file, just outside its bound on each side: `uascma simulate FILE --out DIR` exits 2
// naming the file, the key and the bound, prints nothing on stdout and creates no DIR.
TEST(BoundsCliTest, EveryScenarioYamlNumberOutsideItsBoundExitsTwo) {
  ScratchDir scratch("bounds_scenario");
  const std::string out = (scratch.path / "never").string();
  const std::string inertia = "0.011, 0.011, 0.021";
  const std::vector<YamlCase> cases = {
      {"seed: -1", "seed", "2^64-1"},
      {"seed: 18446744073709551616", "seed", "2^64-1"},
      {"map: {procedural: {seed: -1}}", "map.procedural.seed", "2^64-1"},
      {"map: {procedural: {blocks_north: 0}}", "map.procedural.blocks_north", "1 to 200 blocks"},
      {"map: {procedural: {blocks_east: 201}}", "map.procedural.blocks_east", "1 to 200 blocks"},
      {"map: {procedural: {rooftop_site_probability: -0.1}}", "map.procedural.rooftop_site_probability", "0 to 1"},
      {"map: {procedural: {rooftop_site_probability: 1.1}}", "map.procedural.rooftop_site_probability", "0 to 1"},
      {"map: {buildings: [city.geojson], metres_per_level: 0.9}", "map.metres_per_level", "1 to 20 m"},
      {"map: {buildings: [city.geojson], metres_per_level: 21}", "map.metres_per_level", "1 to 20 m"},
      {"map: {buildings: [city.geojson], default_height_m: 0.5}", "map.default_height_m", "1 to 500 m"},
      {"map: {buildings: [city.geojson], default_height_m: 501}", "map.default_height_m", "1 to 500 m"},
      {"map: {buildings: [city.geojson], origin: [91, 0]}", "map.origin[0]", "-90 to 90 deg"},
      {"map: {buildings: [city.geojson], origin: [0, -181]}", "map.origin[1]", "-180 to 180 deg"},
      {"vehicle: {mass_kg: 0.04}", "vehicle.mass_kg", "0.05 to 25 kg"},
      {"vehicle: {mass_kg: 26}", "vehicle.mass_kg", "0.05 to 25 kg"},
      {"vehicle: {inertia_kg_m2: [0.000009, 0.011, 0.021]}", "vehicle.inertia_kg_m2[0]", "1e-05 to 10 kg m^2"},
      {"vehicle: {inertia_kg_m2: [11, 0.011, 0.021]}", "vehicle.inertia_kg_m2[0]", "1e-05 to 10 kg m^2"},
      {"vehicle: {inertia_kg_m2: [0.011, 0, 0.021]}", "vehicle.inertia_kg_m2[1]", "1e-05 to 10 kg m^2"},
      {"vehicle: {inertia_kg_m2: [0.011, 11, 0.021]}", "vehicle.inertia_kg_m2[1]", "1e-05 to 10 kg m^2"},
      {"vehicle: {inertia_kg_m2: [0.011, 0.011, -1]}", "vehicle.inertia_kg_m2[2]", "1e-05 to 10 kg m^2"},
      {"vehicle: {inertia_kg_m2: [0.011, 0.011, 11]}", "vehicle.inertia_kg_m2[2]", "1e-05 to 10 kg m^2"},
      {"battery: {initial_cell_voltage_v: 3.2}", "initial_cell_voltage_v", ""},
      {"battery: {initial_cell_voltage_v: 4.3}", "initial_cell_voltage_v", ""},
      {"battery: {initial_cell_voltage_v: [[4.1, 4.1, 4.1], [4.1, 4.1, 4.3]]}", "initial_cell_voltage_v", ""},
      {"battery: {ambient_temp_degf: -41}", "battery.ambient_temp_degf", "-40 to 140 °F"},
      {"battery: {ambient_temp_degf: 141}", "battery.ambient_temp_degf", "-40 to 140 °F"},
      {"wind: {speed_mps: -0.1}", "wind.speed_mps", "0 to 50 m/s"},
      {"wind: {speed_mps: 51}", "wind.speed_mps", "0 to 50 m/s"},
      {"wind: {direction_deg: -721}", "wind.direction_deg", "-720 to 720 deg"},
      {"wind: {direction_deg: 721}", "wind.direction_deg", "-720 to 720 deg"},
      {"mission: {home_ne_m: [-50001, 0]}", "mission.home_ne_m[0]", "-50000 to 50000 m"},
      {"mission: {home_ne_m: [0, 50001]}", "mission.home_ne_m[1]", "-50000 to 50000 m"},
      {"mission: {destination_ne_m: [50001, 0]}", "mission.destination_ne_m[0]", "-50000 to 50000 m"},
      {"mission: {destination_ne_m: [0, -50001]}", "mission.destination_ne_m[1]", "-50000 to 50000 m"},
      {"mission: {cruise_altitude_m: 0.5}", "mission.cruise_altitude_m", "1 to 1000 m"},
      {"mission: {cruise_altitude_m: 1001}", "mission.cruise_altitude_m", "1 to 1000 m"},
      {"mission: {drop_hover_s: -1}", "mission.drop_hover_s", "0 to 3600 s"},
      {"mission: {drop_hover_s: 3601}", "mission.drop_hover_s", "0 to 3600 s"},
      {"mission: {origin: [91, 0]}", "origin", ""},
      {"mission: {origin: [0, 181]}", "origin", ""},
      {"limits: {cruise_speed_mps: 0.05}", "limits.cruise_speed_mps", "0.1 to 30 m/s"},
      {"limits: {cruise_speed_mps: 31}", "limits.cruise_speed_mps", "0.1 to 30 m/s"},
      {"limits: {vertical_speed_mps: 0.05}", "limits.vertical_speed_mps", "0.1 to 10 m/s"},
      {"limits: {vertical_speed_mps: 11}", "limits.vertical_speed_mps", "0.1 to 10 m/s"},
      {"limits: {horizontal_accel_mps2: 0.05}", "limits.horizontal_accel_mps2", "0.1 to 10 m/s^2"},
      {"limits: {horizontal_accel_mps2: 11}", "limits.horizontal_accel_mps2", "0.1 to 10 m/s^2"},
      {"limits: {vertical_accel_mps2: 0.05}", "limits.vertical_accel_mps2", "0.1 to 5 m/s^2"},
      {"limits: {vertical_accel_mps2: 6}", "limits.vertical_accel_mps2", "0.1 to 5 m/s^2"},
      {"fault: {motor: 0, spall_onset_s: 100}", "fault.motor", "1..6"},
      {"fault: {motor: 7, spall_onset_s: 100}", "fault.motor", "1..6"},
      {"fault: {motor: 3, spall_onset_s: -1}", "fault.spall_onset_s", "0 to 7200 s"},
      {"fault: {motor: 3, spall_onset_s: 7201}", "fault.spall_onset_s", "0 to 7200 s"},
      {"fault: {motor: 3, spall_onset_s: 100, time_per_growth_step_s: 0.0009}", "fault.time_per_growth_step_s",
       "0.001 to 3600 s"},
      {"fault: {motor: 3, spall_onset_s: 100, time_per_growth_step_s: 3601}", "fault.time_per_growth_step_s",
       "0.001 to 3600 s"},
      {"fault: {motor: 3, spall_onset_s: 100, prognosis_time_per_growth_step_s: 0.0009}",
       "fault.prognosis_time_per_growth_step_s", "0.001 to 3600 s"},
      {"fault: {motor: 3, spall_onset_s: 100, prognosis_time_per_growth_step_s: 3601}",
       "fault.prognosis_time_per_growth_step_s", "0.001 to 3600 s"},
      {"options: {telemetry_rate_hz: 0.05}", "options.telemetry_rate_hz", "0.1 to 200 Hz"},
      {"options: {telemetry_rate_hz: 201}", "options.telemetry_rate_hz", "0.1 to 200 Hz"},
      {"options: {safety_margin_s: -1}", "options.safety_margin_s", "0 to 600 s"},
      {"options: {safety_margin_s: 601}", "options.safety_margin_s", "0 to 600 s"},
      {"options: {max_tilt_deg: 0.5}", "options.max_tilt_deg", "1 to 89 deg"},
      {"options: {max_tilt_deg: 90}", "options.max_tilt_deg", "1 to 89 deg"},
      {"options: {max_cross_track_error_m: 0.05}", "options.max_cross_track_error_m", "0.1 to 1000 m"},
      {"options: {max_cross_track_error_m: 1001}", "options.max_cross_track_error_m", "0.1 to 1000 m"},
  };
  int index = 0;
  for (const YamlCase& c : cases) {
    const auto file = scratch.path / ("s" + std::to_string(index++) + ".yaml");
    std::ofstream(file) << c.yaml << "\n";
    SCOPED_TRACE(c.yaml);
    const auto result = RunCli("simulate " + file.string() + " --out " + out);
    ExpectBadInput(result, c.field);
    EXPECT_NE(result.err.find(file.string()), std::string::npos) << result.err;
    if (!c.bound.empty()) {
      EXPECT_NE(result.err.find(c.bound), std::string::npos) << result.err;
    }
  }
  EXPECT_FALSE(std::filesystem::exists(out));
}

// The bounds are closed: a scenario with every bounded number on its low bound, and one with each on its high
// bound, both load (sim::ParseScenario; no flight).
TEST(BoundsCliTest, ScenarioValuesOnTheBoundsAreAccepted) {
  const std::string low =
      "vehicle: {mass_kg: 0.05, inertia_kg_m2: [0.00001, 0.00001, 0.00001]}\n"
      "battery: {ambient_temp_degf: -40}\n"
      "wind: {speed_mps: 0, direction_deg: -720}\n"
      "mission: {home_ne_m: [-50000, -50000], destination_ne_m: [-50000, 0], cruise_altitude_m: 1, drop_hover_s: 0}\n"
      "limits: {cruise_speed_mps: 0.1, vertical_speed_mps: 0.1, horizontal_accel_mps2: 0.1, vertical_accel_mps2: 0.1}\n"
      "fault: {motor: 1, spall_onset_s: 0, time_per_growth_step_s: 0.001, prognosis_time_per_growth_step_s: 0.001}\n"
      "options: {telemetry_rate_hz: 0.1, safety_margin_s: 0, max_tilt_deg: 1, max_cross_track_error_m: 0.1}\n"
      "map: {procedural: {blocks_north: 1, blocks_east: 1, rooftop_site_probability: 0}}\n";
  // vehicle.mass_kg's own bound, 25 kg, is refused by the cross-check against the rotors' thrust (below):
  // the high case takes the heaviest vehicle the six rotors hold, 26.85 N / g = 2.738 kg.
  const std::string high =
      "vehicle: {mass_kg: 2.73, inertia_kg_m2: [10, 10, 10]}\n"
      "battery: {ambient_temp_degf: 140}\n"
      "wind: {speed_mps: 50, direction_deg: 720}\n"
      "mission: {home_ne_m: [50000, 50000], destination_ne_m: [0, 50000], cruise_altitude_m: 1000, "
      "drop_hover_s: 3600}\n"
      "limits: {cruise_speed_mps: 30, vertical_speed_mps: 10, horizontal_accel_mps2: 10, vertical_accel_mps2: 5}\n"
      "fault: {motor: 6, spall_onset_s: 7200, time_per_growth_step_s: 3600, prognosis_time_per_growth_step_s: 3600}\n"
      "options: {telemetry_rate_hz: 200, safety_margin_s: 600, max_tilt_deg: 89, max_cross_track_error_m: 1000}\n";
  for (const std::string& yaml : {low, high}) {
    SCOPED_TRACE(yaml);
    EXPECT_NO_THROW((void)sim::ParseScenario(yaml, "bounds.yaml"));
  }
}

// Numbers each inside their bound can make a vehicle that cannot fly (25 kg reported a cell at -2.55 V and
// negative energy). Mass against the rotors' thrust (Table 2.2) is refused naming the combination; the rotors' limit
// itself is the closed form m g <= 26.85 N.
TEST(BoundsCliTest, AVehicleHeavierThanItsRotorsCanHoldIsRefused) {
  for (const char* mass : {"25", "2.74"}) {
    try {
      (void)sim::ParseScenario(std::string("vehicle: {mass_kg: ") + mass + "}\n", "heavy.yaml");
      ADD_FAILURE() << mass << " kg loaded";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("heavy.yaml: vehicle.mass_kg ") + mass + " kg"),
                std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("the six rotors give at most 26.85 N (Table 2.2), so at most 2.738 kg"),
                std::string::npos)
          << e.what();
    }
  }
  EXPECT_NO_THROW((void)sim::ParseScenario(
      "vehicle: {mass_kg: 2.737}\nbattery: {packs: [P, P], ambient_temp_degf: -40}\n", "heavy.yaml"));
}

// Every example scenario still loads: the bounds leave the shipped files' values alone.
TEST(BoundsCliTest, ExampleScenariosAreInsideTheBounds) {
  int loaded = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(UASCMA_SOURCE_DIR) / "examples")) {
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() != ".yaml" || name.rfind("campaign", 0) == 0 || name == "cma-weights.yaml") continue;
    SCOPED_TRACE(name);
    const std::string text = testing_support::Slurp(entry.path());
    EXPECT_NO_THROW((void)sim::LoadScenarioFile(entry.path()));
    ++loaded;
  }
  EXPECT_GE(loaded, 6);  // nominal, poor-battery-long, jam-motor-3, scenario-1, scenario-2, mission-upper-east-side
}

// ---- Battery command options and mission-file numbers ------------------------------------------------

TEST(BoundsCliTest, BatteryOptionsOutsideTheirBoundsExitTwo) {
  ScratchDir scratch("bounds_battery");
  const std::string out = (scratch.path / "never.json").string();
  const std::string model = (scratch.path / "model.json").string();  // a real model, so that --weights is read
  ASSERT_EQ(RunCli("battery learn --runs 3 --out " + model).exit_code, 0);
  const std::string learn = "battery learn --out " + out + " ";
  const std::string study = "battery case-study ";
  const std::vector<Case> cases = {
      {learn + "--runs 0", "--runs", "1 to 1e+07 flights"},
      {learn + "--runs 10000001", "--runs", "1 to 1e+07 flights"},
      {learn + "--seed -1", "--seed", "2^64-1"},
      {learn + "--seed 18446744073709551616", "--seed", "2^64-1"},
      {learn + "--jobs 0", "--jobs", "1 to 256 threads"},
      {learn + "--jobs 257", "--jobs", "1 to 256 threads"},
      {study + "0", "N", "1 to 4"},
      {study + "5", "N", "1 to 4"},
      {study + "2 --runs 0", "--runs", "1 to 1e+07 flights"},
      {study + "2 --runs 10000001", "--runs", "1 to 1e+07 flights"},
      {study + "2 --jobs 0", "--jobs", "1 to 256 threads"},
      {study + "2 --jobs 257", "--jobs", "1 to 256 threads"},
      {"battery solve " + model + " --out " + out + " --weights -0.1,0.6,0.5", "--weights", "w1, w2, w3"},
      {"battery solve " + model + " --out " + out + " --weights 0.5,0.6,0.1", "--weights", "w1 + w2 + w3 = 1"},
  };
  for (const Case& c : cases) ExpectRefused(c);
  EXPECT_FALSE(std::filesystem::exists(out));
  for (const auto& [arguments, bound] :
       std::vector<std::pair<std::string, std::string>>{{"battery learn --help", "1 to 1e+07 flights"},
                                                        {"battery learn --help", "0 to 2^64-1"},
                                                        {"battery case-study --help", "1 to 256 threads"}}) {
    const auto result = RunCli(arguments);
    EXPECT_NE(result.out.find(bound), std::string::npos) << arguments << "\n" << result.out;
  }
}

// A mission file's heights, hovers and speeds (planning/mission_file.h): one bad number in an otherwise good
// .waypoints or .plan file stops `simulate --mission` with exit code 2 naming the item and the bound.
TEST(BoundsCliTest, MissionFileNumbersOutsideTheirBoundsExitTwo) {
  ScratchDir scratch("bounds_mission");
  const auto scenario = std::filesystem::path(UASCMA_SOURCE_DIR) / "examples" / "nominal.yaml";
  const std::string out = (scratch.path / "never").string();
  auto waypoints = [](const std::string& item) {
    return "QGC WPL 110\n0\t1\t0\t16\t0\t0\t0\t0\t40.775\t-73.955\t12\t1\n1\t0\t3\t22\t0\t0\t0\t0\t0\t0\t25\t1\n" +
           item + "\n3\t0\t3\t21\t0\t0\t0\t0\t40.776\t-73.955\t0\t1\n";
  };
  const std::string plan_head =
      R"({"fileType": "Plan", "version": 1, "mission": {"version": 2, "plannedHomePosition": [40.77, -73.96, 10], )";
  const std::string plan_items =
      R"("items": [{"type": "SimpleItem", "command": 22, "frame": 3, "params": [0, 0, 0, null, 40.77, -73.96, 30]},
          {"type": "SimpleItem", "command": 21, "frame": 3, "params": [0, 0, 0, null, 40.771, -73.96, 0]}]}})";
  const std::vector<std::tuple<std::string, std::string, std::string, std::string>> cases = {
      // name, text, field, bound
      {"high.waypoints", waypoints("2\t0\t3\t16\t0\t0\t0\t0\t40.776\t-73.955\t1001\t1"), "line 4 (item 2) altitude",
       "0 to 1000 m above home"},
      {"hold.waypoints", waypoints("2\t0\t3\t16\t3601\t0\t0\t0\t40.776\t-73.955\t30\t1"), "line 4 (item 2) param1",
       "0 to 3600 s"},
      {"delay.waypoints", waypoints("2\t0\t3\t93\t3601\t-1\t-1\t-1\t0\t0\t0\t1"), "line 4 (item 2) param1",
       "0 to 3600 s"},
      {"speed.waypoints", waypoints("2\t0\t2\t178\t1\t31\t-1\t0\t0\t0\t0\t1"), "line 4 (item 2) param2",
       "0.1 to 30 m/s"},
      {"hover.plan", plan_head + R"("hoverSpeed": 31, )" + plan_items, "mission.hoverSpeed", "0.1 to 30 m/s"},
  };
  for (const auto& [name, text, field, bound] : cases) {
    const auto file = scratch.path / name;
    std::ofstream(file) << text;
    SCOPED_TRACE(name);
    const auto result = RunCli("simulate " + scenario.string() + " --mission " + file.string() + " --out " + out);
    ExpectBadInput(result, field);
    EXPECT_NE(result.err.find(bound), std::string::npos) << result.err;
    EXPECT_NE(result.err.find(file.string()), std::string::npos) << result.err;
  }
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace uascma
