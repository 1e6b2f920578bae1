// The field tables of the campaign configuration (campaign/config_fields.h) and of scenario files
// (sim/scenario_fields.h). The campaign's against what stored campaigns hold: the
// fingerprints and canonical YAML below were computed by uascma before the table existed (git 9bbf1fd, the
// hand-written parse/validate/YAML/hash of src/campaign/config.cc), so a stored campaign keeps its hash.
#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "uascma/campaign/config.h"
#include "uascma/campaign/config_fields.h"
#include "uascma/campaign/input_bounds_doc.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/sim/scenario.h"
#include "uascma/sim/scenario_fields.h"

namespace uascma::campaign {
namespace {

struct StoredCase {
  const char* name;
  const char* yaml;
  const char* hash;  // CampaignConfigHash before the field table
};

const StoredCase kStored[] = {
    {"default", "", "7e9351e71d283024"},
    {"distance",
     "mission: {distance_m: [300, 900], cruise_altitude_m: 40.5}\n"
     "fault: {time_per_growth_step_s: null, motors: [2, 5]}\n",
     "09bc75e19746a37d"},
    {"imported_all",
     "map:\n"
     "  buildings: [/a/b.geojson, c.osm]\n"
     "  sites: s.csv\n"
     "  origin: [40.77, -73.96]\n"
     "  height_from_levels: true\n"
     "  metres_per_level: 3.5\n"
     "  skip_missing_height: true\n"
     "  height_from_type: true\n"
     "  default_height_m: 12.25\n"
     "  sites_from_map: true\n",
     "a3738d9aebccdac3"},
    {"imported_sfm_false",
     "map:\n"
     "  buildings: [x.geojson]\n"
     "  sites_from_map: false\n",
     "d7d0c1161a8eafc0"},
    {"imported_sites_sfm_false",
     "map:\n"
     "  buildings: [x.geojson]\n"
     "  sites: s.csv\n"
     "  sites_from_map: false\n",
     "436c210e297dfaf6"},
    {"misc",
     "name: t1\n"
     "seed: 18446744073709551615\n"
     "runs: 7\n"
     "policies: [noop]\n"
     "map: {procedural_seed: 0, blocks_north: 3, blocks_east: 200}\n"
     "battery: {health_weights: {G: 0.1, M: 2, P: 0}, degraded_cells: [2, 2], medium_fades: per_cell, "
     "cold_probability: 0.25, cold_temp_degf: -3.5, warm_temp_degf: 100}\n"
     "wind: {speed_mps: [0, 0.1], direction_rad: [-1, 12.5], turbulence: [none, medium-moderate]}\n"
     "options: {eod_load: present, cap_speed_after_isolation: false}\n"
     "safety_margin_s: [0, 0]\n"
     "fault: {probability: 1, onset_fraction: [0.1, 0.3]}\n",
     "cd7b0d21342405ef"},
};

TEST(ConfigFieldsTest, StoredCampaignsKeepTheirFingerprints) {
  for (const StoredCase& stored : kStored) {
    const CampaignConfig config = ParseCampaignConfig(stored.yaml, stored.name);
    EXPECT_EQ(CampaignConfigHash(config), stored.hash) << stored.name;
    // The canonical YAML reads back to the same configuration and writes itself again.
    const std::string yaml = CampaignConfigYaml(config);
    const CampaignConfig again = ParseCampaignConfig(yaml, stored.name);
    EXPECT_EQ(CampaignConfigHash(again), stored.hash) << stored.name;
    EXPECT_EQ(CampaignConfigYaml(again), yaml) << stored.name;
  }
}

// Noisy sensing is a campaign setting that changes the fingerprint only when switched on.
TEST(ConfigFieldsTest, NoisySensingChangesTheFingerprintOnlyWhenOn) {
  const CampaignConfig plain = ParseCampaignConfig("runs: 3\n", "plain");
  const CampaignConfig off = ParseCampaignConfig("runs: 3\noptions: {noisy_sensing: false}\n", "off");
  const CampaignConfig on = ParseCampaignConfig("runs: 3\noptions: {noisy_sensing: true}\n", "on");
  EXPECT_EQ(CampaignConfigHash(off), CampaignConfigHash(plain));
  EXPECT_NE(CampaignConfigHash(on), CampaignConfigHash(plain));
  EXPECT_EQ(CampaignConfigYaml(plain).find("noisy_sensing"), std::string::npos);
  const CampaignConfig again = ParseCampaignConfig(CampaignConfigYaml(on), "again");
  ASSERT_TRUE(again.options.noisy_sensing.has_value());
  EXPECT_TRUE(*again.options.noisy_sensing);
  EXPECT_EQ(CampaignConfigHash(again), CampaignConfigHash(on));
}

TEST(ConfigFieldsTest, PackFaultsChangeTheFingerprintOnlyWhenSet) {
  const CampaignConfig plain = ParseCampaignConfig("runs: 3\n", "plain");
  const CampaignConfig faulty =
      ParseCampaignConfig("runs: 3\npack_faults: {share: 0.2, short_resistance_ohm: [2, 5]}\n", "faulty");
  EXPECT_EQ(CampaignConfigYaml(plain).find("pack_faults"), std::string::npos);
  EXPECT_NE(CampaignConfigHash(faulty), CampaignConfigHash(plain));
  const CampaignConfig again = ParseCampaignConfig(CampaignConfigYaml(faulty), "again");
  ASSERT_TRUE(again.pack_faults.share.has_value());
  EXPECT_EQ(*again.pack_faults.share, 0.2);
  EXPECT_EQ(again.pack_faults.Sampling().short_resistance_ohm[1], 5.0);
  EXPECT_EQ(again.pack_faults.Sampling().connector_resistance_ohm[0], 0.05);  // unset: PackFaultSampling's
  EXPECT_EQ(CampaignConfigHash(again), CampaignConfigHash(faulty));
  EXPECT_THROW(ParseCampaignConfig("pack_faults: {share: 1.5}\n", "bad"), InputError);
}

TEST(ConfigFieldsTest, TheCanonicalYamlIsByteForByteTheStoredOne) {
  const std::string imported_all =
      "name: \"campaign\"\n"
      "seed: 1\n"
      "runs: 465\n"
      "policies: [\"cma\", \"noop\"]\n"
      "map:\n"
      "  blocks_north: 56\n"
      "  blocks_east: 20\n"
      "  buildings: [\"/a/b.geojson\", \"c.osm\"]\n"
      "  sites: \"s.csv\"\n"
      "  origin: [40.77, -73.96]\n"
      "  height_from_levels: true\n"
      "  metres_per_level: 3.5\n"
      "  skip_missing_height: true\n"
      "  height_from_type: true\n"
      "  default_height_m: 12.25\n"
      "  sites_from_map: true\n"
      "mission:\n"
      "  endurance_fraction: [0.5, 0.9]\n"
      "  distance_m: null\n"
      "  wall_clearance_m: 5\n"
      "  cruise_speed_mps: [1, 9]\n"
      "  cruise_altitude_m: 30\n"
      "  drop_hover_s: 30\n"
      "safety_margin_s: [5, 10]\n"
      "battery:\n"
      "  initial_cell_voltage_v: [4.05, 4.12]\n"
      "  health_weights: {G: 1, M: 1, P: 1}\n"
      "  degraded_cells: [1, 6]\n"
      "  medium_fades: one_kind\n"
      "  cold_probability: 0.5\n"
      "  cold_temp_degf: 40\n"
      "  warm_temp_degf: 77\n"
      "wind:\n"
      "  speed_mps: [1, 3]\n"
      "  direction_rad: [0, 3.141592653589793]\n"
      "  turbulence: [low-light, low-moderate, medium-light, medium-moderate]\n"
      "fault:\n"
      "  probability: 0.5\n"
      "  onset_fraction: [0, 1]\n"
      "  motors: [1, 2, 3, 4, 5, 6]\n"
      "  time_per_growth_step_s: 0.7128\n"
      "options:\n"
      "  eod_load: forecast\n"
      "  cap_speed_after_isolation: true\n";
  EXPECT_EQ(CampaignConfigYaml(ParseCampaignConfig(kStored[2].yaml, "imported")), imported_all);
  const std::string defaults =
      "name: \"campaign\"\n"
      "seed: 1\n"
      "runs: 465\n"
      "policies: [\"cma\", \"noop\"]\n"
      "map:\n"
      "  procedural_seed: 3\n"
      "  blocks_north: 56\n"
      "  blocks_east: 20\n"
      "mission:\n"
      "  endurance_fraction: [0.5, 0.9]\n"
      "  distance_m: null\n"
      "  wall_clearance_m: 5\n"
      "  cruise_speed_mps: [1, 9]\n"
      "  cruise_altitude_m: 30\n"
      "  drop_hover_s: 30\n"
      "safety_margin_s: [5, 10]\n"
      "battery:\n"
      "  initial_cell_voltage_v: [4.05, 4.12]\n"
      "  health_weights: {G: 1, M: 1, P: 1}\n"
      "  degraded_cells: [1, 6]\n"
      "  medium_fades: one_kind\n"
      "  cold_probability: 0.5\n"
      "  cold_temp_degf: 40\n"
      "  warm_temp_degf: 77\n"
      "wind:\n"
      "  speed_mps: [1, 3]\n"
      "  direction_rad: [0, 3.141592653589793]\n"
      "  turbulence: [low-light, low-moderate, medium-light, medium-moderate]\n"
      "fault:\n"
      "  probability: 0.5\n"
      "  onset_fraction: [0, 1]\n"
      "  motors: [1, 2, 3, 4, 5, 6]\n"
      "  time_per_growth_step_s: 0.7128\n"
      "options:\n"
      "  eod_load: forecast\n"
      "  cap_speed_after_isolation: true\n";
  EXPECT_EQ(CampaignConfigYaml(CampaignConfig{}), defaults);
}

TEST(ConfigFieldsTest, EveryKeyIsDeclaredOnceWithItsSource) {
  CampaignConfig config;
  std::set<std::string> keys;
  for (const CampaignFieldEntry& entry : CampaignFields(config)) {
    EXPECT_TRUE(keys.insert(std::string(entry.field.key)).second) << entry.field.key;
    EXPECT_FALSE(entry.field.citation.empty()) << entry.field.key;
    // A number's bound contains its default (the defaults are the dissertation's, config.h).
    if (const auto* value = std::get_if<double*>(&entry.value); value && entry.field.bounds) {
      EXPECT_TRUE(entry.field.bounds->Contains(**value)) << entry.field.key;
    }
    if (const auto* range = std::get_if<Range*>(&entry.value)) {
      ASSERT_NE(entry.field.bounds, nullptr) << entry.field.key;
      EXPECT_TRUE(entry.field.bounds->Contains((*range)->low) && entry.field.bounds->Contains((*range)->high))
          << entry.field.key;
    }
  }
  // 39 + options.pack_rate_hz and options.wind_rate_hz + fault.prognosis_time_per_growth_step_s,
  // options.noisy_sensing and options.termination (sim/termination.h) + vehicle and vehicle_hash (sim/vehicle_file.h)
  // + the five pack_faults keys (docs/modelling-choices.md#pack-faults).
  EXPECT_EQ(keys.size(), 51u);
}

// A vehicle file enters the YAML and the fingerprint only when set, by its content hash (not its path); the stored
// YAML reads back without the file (the hash is in it).
TEST(ConfigFieldsTest, TheVehicleEntersTheFingerprintByItsContentHashOnlyWhenSet) {
  const CampaignConfig defaults;
  EXPECT_EQ(CampaignConfigYaml(defaults).find("vehicle"), std::string::npos);
  CampaignConfig a = defaults, b = defaults;
  a.vehicle = b.vehicle = "/nowhere/vehicle.yaml";
  a.vehicle_hash = "0123456789abcdef";
  b.vehicle_hash = "fedcba9876543210";
  EXPECT_NE(CampaignConfigHash(a), CampaignConfigHash(defaults));
  EXPECT_NE(CampaignConfigHash(a), CampaignConfigHash(b));
  CampaignConfig moved = a;
  moved.vehicle = "/elsewhere/vehicle.yaml";
  EXPECT_EQ(CampaignConfigHash(moved), CampaignConfigHash(a));
  const CampaignConfig again = ParseCampaignConfig(CampaignConfigYaml(a), "stored");
  EXPECT_EQ(again.vehicle, a.vehicle);
  EXPECT_EQ(again.vehicle_hash, a.vehicle_hash);
  EXPECT_EQ(CampaignConfigHash(again), CampaignConfigHash(a));
}

// The prognoser's time scale is left out of the YAML and the fingerprint unless set.
TEST(ConfigFieldsTest, ThePrognosisTimeScaleEntersTheFingerprintOnlyWhenSet) {
  const CampaignConfig defaults;
  CampaignConfig shared = defaults;
  shared.fault.prognosis_time_per_growth_step_s = 0.7128;
  EXPECT_EQ(CampaignConfigYaml(defaults).find("prognosis_time_per_growth_step_s"), std::string::npos);
  EXPECT_NE(CampaignConfigYaml(shared).find("  prognosis_time_per_growth_step_s: 0.7128\n"), std::string::npos);
  EXPECT_NE(CampaignConfigHash(shared), CampaignConfigHash(defaults));
  const CampaignConfig parsed = ParseCampaignConfig(CampaignConfigYaml(shared), "shared");
  EXPECT_EQ(parsed.fault.prognosis_time_per_growth_step_s, 0.7128);
  EXPECT_EQ(CampaignConfigHash(parsed), CampaignConfigHash(shared));
}

// Each bound refuses a value just outside it, naming the file and the key (one case per kind of member).
TEST(ConfigFieldsTest, AValueOutsideItsBoundNamesFileKeyAndBound) {
  const struct {
    const char* yaml;
    const char* message;
  } cases[] = {
      {"runs: 1e8\n", "c.yaml: runs: from 0 to 1e+07 runs, got 1e+08"},
      {"map: {blocks_east: 201}\n", "c.yaml: map.blocks_east: from 1 to 200 blocks, got 201"},
      {"mission: {cruise_speed_mps: [1, 31]}\n",
       "c.yaml: mission.cruise_speed_mps: expected [low, high] with low <= high, both from 0.1 to 30 m/s, got [1, 31]"},
      {"mission: {distance_m: [0.5, 9]}\n", "c.yaml: mission.distance_m: expected [low, high]"},
      {"battery: {cold_temp_degf: 50}\n", "c.yaml: battery.cold_temp_degf: expected from -40 to 49.999 °F, got 50"},
      {"battery: {degraded_cells: [2, 1]}\n", "c.yaml: battery.degraded_cells: expected [low, high] with low <= high"},
      {"battery: {degraded_cells: [1.5, 2]}\n", "c.yaml: battery.degraded_cells: whole numbers of cells, got 1.5"},
      {"battery: {health_weights: {G: 0, M: 0, P: 0}}\n", "c.yaml: battery.health_weights: expected G, M, P"},
      {"fault: {motors: [7]}\n", "c.yaml: fault.motors[0]: from 1 to 6, got 7"},
      {"fault: {motors: []}\n", "c.yaml: fault.motors: expected at least one motor"},
      {"fault: {time_per_growth_step_s: 0}\n", "c.yaml: fault.time_per_growth_step_s: expected from 0.001 to 3600 s"},
      {"wind: {turbulence: []}\n", "c.yaml: wind.turbulence: expected at least one category"},
      {"mission: {speed: 3}\n", "c.yaml: mission.speed: no such key here; expected one of: endurance_fraction"},
      {"policies: []\n", "c.yaml: policies: expected at least one policy"},
      {"map: {buildings: [a.geojson], metres_per_level: 0}\n", "c.yaml: map.metres_per_level: expected a storey"},
      {"map: {sites: s.csv}\n", "c.yaml: map.buildings: building files: sites, origin"},
      {"seed: -1\n", "c.yaml: seed: a seed from 0 to 2^64-1"},
  };
  for (const auto& c : cases) {
    try {
      (void)ParseCampaignConfig(c.yaml, "c.yaml");
      ADD_FAILURE() << c.yaml << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what();
    }
  }
}

// Every bounded scenario key refuses a value above its bound, naming the file, the key and the bound (the table
// drives both the reading and Scenario::IsValid's first check).
TEST(ScenarioFieldsTest, EveryBoundedKeyRefusesAValueAboveItsBound) {
  sim::Scenario defaults;
  int checked = 0;
  for (const sim::ScenarioFieldEntry& entry : sim::ScenarioFields(defaults)) {
    const sim::ScenarioField& f = entry.field;
    if (f.bounds == nullptr || std::holds_alternative<std::monostate>(entry.value)) continue;
    const double outside = f.bounds->high + std::max(1.0, std::abs(f.bounds->high));
    std::string value = fmt::format("{}", outside);
    if (std::holds_alternative<Eigen::Vector2d*>(entry.value)) value = fmt::format("[{}, 0]", outside);
    if (std::holds_alternative<Eigen::Vector3d*>(entry.value)) value = fmt::format("[{}, 0.011, 0.021]", outside);
    const std::string section(f.section());
    const std::string leaf(f.leaf());
    std::string yaml = section == "fault" ? "fault: {motor: 3, spall_onset_s: 175}\n" : "";
    if (section == "fault") {
      yaml = leaf == "motor"           ? fmt::format("fault: {{motor: {}, spall_onset_s: 175}}\n", value)
             : leaf == "spall_onset_s" ? fmt::format("fault: {{motor: 3, spall_onset_s: {}}}\n", value)
                                       : fmt::format("fault: {{motor: 3, spall_onset_s: 175, {}: {}}}\n", leaf, value);
    } else {
      yaml = fmt::format("{}: {{{}: {}}}\n", section, leaf, value);
    }
    try {
      (void)sim::ParseScenario(yaml, "s.yaml");
      ADD_FAILURE() << yaml << " was accepted";
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind("s.yaml: " + std::string(f.key), 0), 0u) << message;
      const bool names_bound = message.find("from " + f.bounds->Text()) != std::string::npos ||
                               message.find(std::string(f.expected)) != std::string::npos;
      EXPECT_TRUE(names_bound) << message;
    }
    ++checked;
  }
  EXPECT_EQ(checked, 23);  // 21 + options.pack_rate_hz and options.wind_rate_hz
}

// A scenario's keys read through the table land in the members the simulator uses (degrees held in radians).
TEST(ScenarioFieldsTest, KeysLandInTheirMembers) {
  const sim::ScenarioFile file = sim::ParseScenario(
      "vehicle: {mass_kg: 1.25, inertia_kg_m2: [0.01, 0.012, 0.02], configuration: pusher}\n"
      "wind: {speed_mps: 2.5, direction_deg: 90, turbulence: low-moderate}\n"
      "mission: {home_ne_m: [1, 2], destination_ne_m: [300, 40], cruise_altitude_m: 35, drop_hover_s: 20}\n"
      "limits: {cruise_speed_mps: 6}\n"
      "fault: {motor: 2, spall_onset_s: 100, time_per_growth_step_s: 0.5}\n"
      "options: {max_tilt_deg: 45, eod_load: present, sensor_noise: false}\n",
      "s.yaml");
  const sim::Scenario& s = file.scenario;
  EXPECT_EQ(s.body.mass, 1.25);
  EXPECT_EQ(s.body.inertia_diagonal.y(), 0.012);
  EXPECT_EQ(s.configuration, models::PropellerConfiguration::kPusher);
  EXPECT_NEAR(s.wind.direction_rad, 3.14159265358979323846 / 2.0, 1e-15);  // rad, from 90°
  EXPECT_EQ(s.wind.turbulence, models::TurbulenceCategory::kLowModerate);
  EXPECT_EQ(s.mission.destination_NE, Eigen::Vector2d(300, 40));
  EXPECT_EQ(s.limits.cruise_speed, 6.0);
  EXPECT_TRUE(s.fault.enabled);
  EXPECT_EQ(s.fault.motor, 2);
  EXPECT_EQ(s.fault.time_per_growth_step_s, 0.5);
  EXPECT_FALSE(s.fault.prognosis_time_per_growth_step_s.has_value());
  EXPECT_NEAR(s.options.outcome.max_tilt, 3.14159265358979323846 / 4.0, 1e-15);  // rad, from 45°
  EXPECT_EQ(s.options.eod_load, sim::EodLoad::kPresent);
  EXPECT_FALSE(s.options.sensor_noise);
  try {
    (void)sim::ParseScenario("limits: {cruise_speed: 6}\n", "s.yaml");
    ADD_FAILURE() << "a misspelt key was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("s.yaml: limits.cruise_speed: no such key here; expected one of: "
                                         "cruise_speed_mps, vertical_speed_mps"),
              std::string::npos)
        << e.what();
  }
}

// docs/input-bounds.md holds the table the field table writes today.
TEST(ConfigFieldsTest, TheCommittedBoundsDocumentIsCurrent) {
  const std::string path = std::string(UASCMA_SOURCE_DIR) + "/docs/input-bounds.md";
  const std::string committed = ReadFile(path);
  EXPECT_EQ(WithGeneratedBounds(committed, path), committed)
      << "docs/input-bounds.md is not current: run `uascma docs input-bounds --file docs/input-bounds.md --write`";
  EXPECT_NE(committed.find("| `mission.cruise_speed_mps` | 0.1 to 30 m/s | `[1, 9]` | Table 4.4 |"), std::string::npos);
}

}  // namespace
}  // namespace uascma::campaign
