// Campaigns over an imported city (campaign/config.h, MapSampling): the YAML keys, their canonical form and
// fingerprint, and missions sampled over the real OpenStreetMap data of shared/data/osm (skipped without it).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "uascma/campaign/config.h"
#include "uascma/campaign/sampler.h"
#include "uascma/common/error.h"
#include "uascma/planning/flight_plan.h"

namespace uascma::campaign {
namespace {

std::filesystem::path OsmDataDir() {
  return std::filesystem::path(UASCMA_SOURCE_DIR) / ".." / "shared" / "data" / "osm";
}

const char* kImportedYaml =
    "map:\n"
    "  buildings: [upper-east-side-buildings.geojson]\n"
    "  sites: midtown-landing-sites.csv\n"
    "  origin: [40.77, -73.96]\n"
    "  height_from_levels: true\n"
    "  metres_per_level: 3.2\n"
    "  skip_missing_height: true\n"
    "mission: {distance_m: [300, 900]}\n";

TEST(ImportedMapConfigTest, KeysParseAndRoundTripThroughTheCanonicalYaml) {
  const CampaignConfig config = ParseCampaignConfig(kImportedYaml, "c.yaml");
  ASSERT_TRUE(config.map.imported());
  EXPECT_EQ(config.map.buildings.size(), 1u);
  EXPECT_EQ(config.map.sites, "midtown-landing-sites.csv");
  ASSERT_TRUE(config.map.origin_deg.has_value());
  EXPECT_NEAR((*config.map.origin_deg)[0], 40.77, 1e-12);
  EXPECT_TRUE(config.map.height_from_levels);
  EXPECT_TRUE(config.map.skip_missing_height);
  EXPECT_NEAR(config.map.metres_per_level, 3.2, 1e-12);
  const CampaignConfig again = ParseCampaignConfig(CampaignConfigYaml(config), "canonical");
  EXPECT_EQ(again.map.buildings, config.map.buildings);
  EXPECT_EQ(again.map.sites, config.map.sites);
  EXPECT_EQ(again.map.origin_deg, config.map.origin_deg);
  EXPECT_EQ(again.map.height_from_levels, config.map.height_from_levels);
  EXPECT_EQ(again.map.skip_missing_height, config.map.skip_missing_height);
  EXPECT_EQ(CampaignConfigHash(again), CampaignConfigHash(config));
  // Each import setting is part of the campaign's identity; a procedural campaign's fingerprint is unchanged by
  // the new keys' existence (its map has none).
  CampaignConfig other = config;
  other.map.skip_missing_height = false;
  EXPECT_NE(CampaignConfigHash(other), CampaignConfigHash(config));
  other = config;
  other.map.sites.clear();
  EXPECT_NE(CampaignConfigHash(other), CampaignConfigHash(config));
  EXPECT_NE(CampaignConfigHash(CampaignConfig{}), CampaignConfigHash(config));
}

TEST(ImportedMapConfigTest, ConflictsAndBadValuesAreNamed) {
  auto error_of = [](const std::string& yaml) -> std::string {
    try {
      ParseCampaignConfig(yaml, "c.yaml");
    } catch (const InputError& error) {
      return error.what();
    }
    return "";
  };
  EXPECT_NE(error_of("map: {procedural_seed: 3, buildings: [a.geojson]}\n").find("either procedural_seed"),
            std::string::npos);
  EXPECT_NE(error_of("map: {sites: s.csv}\n").find("map.buildings"), std::string::npos);
  EXPECT_NE(error_of("map: {buildings: [a.geojson], origin: [95, 0]}\n").find("map.origin"), std::string::npos);
  EXPECT_NE(error_of("map: {buildings: [a.geojson], metres_per_level: 0}\n").find("map.metres_per_level"),
            std::string::npos);
  EXPECT_NE(error_of("map: {buildings: [a.geojson], height_from_level: true}\n").find("height_from_level"),
            std::string::npos);
}

TEST(ImportedMapConfigTest, LoadResolvesMapFilesNextToTheCampaignFile) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "uascma_imported_map_test";
  std::filesystem::create_directories(dir);
  const std::filesystem::path file = dir / "campaign.yaml";
  std::ofstream(file) << kImportedYaml;
  const CampaignConfig config = LoadCampaignConfig(file);
  std::filesystem::remove_all(dir);
  EXPECT_EQ(std::filesystem::path(config.map.buildings[0]), (dir / "upper-east-side-buildings.geojson").lexically_normal());
  EXPECT_EQ(std::filesystem::path(config.map.sites), (dir / "midtown-landing-sites.csv").lexically_normal());
}

TEST(ImportedMapSamplerTest, MissionsAreSampledOverTheRealCityOnOpenGround) {
  if (!std::filesystem::exists(OsmDataDir() / "upper-east-side-buildings.geojson")) {
    GTEST_SKIP() << "shared/data/osm not present";
  }
  CampaignConfig config = ParseCampaignConfig(kImportedYaml, "c.yaml");
  config.map.buildings = {(OsmDataDir() / "upper-east-side-buildings.geojson").string()};
  config.map.sites = (OsmDataDir() / "midtown-landing-sites.csv").string();
  const auto map = CampaignMap(config.map);
  // 1,239 buildings, 9 skipped without height or levels (map_import.h); 1,828 sites.
  EXPECT_EQ(map->buildings().size(), 1230u);
  EXPECT_EQ(map->sites().size(), 1828u);
  EXPECT_EQ(CampaignMap(config.map).get(), map.get());  // read once
  for (std::int64_t index = 0; index < 40; ++index) {
    const SampledRun run = SampleRun(config, 7, index);
    const auto& mission = run.scenario.mission;
    EXPECT_EQ(run.scenario.map.get(), map.get());
    for (const Eigen::Vector2d& p : {mission.home_NE, mission.destination_NE}) {
      EXPECT_TRUE(map->bounds().contains(p));
      EXPECT_FALSE(map->IsInsideBuilding(Eigen::Vector3d(p.x(), p.y(), -0.1))) << "index " << index;
    }
    // Never below the open-ground altitude over the imported map (its holes are not open ground).
    EXPECT_GE(mission.cruise_altitude, config.mission.cruise_altitude_m);
    EXPECT_GE(run.distance_m, 300.0);
    EXPECT_LT(run.distance_m, 900.0);
    // The whole nominal plan is clear of the buildings.
    const planning::FlightPlan plan = planning::MakeDeliveryPlan(mission, run.scenario.limits);
    for (double t = 0.0; t <= plan.duration(); t += 0.5) {
      ASSERT_FALSE(map->IsInsideBuilding(plan.At(t).p_W)) << "index " << index << " t " << t;
    }
  }
}

}  // namespace
}  // namespace uascma::campaign
