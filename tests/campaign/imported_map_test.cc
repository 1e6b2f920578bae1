// Campaigns over an imported city (campaign/config.h, MapSampling): the YAML keys, their canonical form and
// fingerprint, and missions sampled over the real OpenStreetMap data of data/osm.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <string>

#include <fmt/format.h>

#include "../support/data_paths.h"
#include "uascma/campaign/config.h"
#include "uascma/campaign/sampler.h"
#include "uascma/common/error.h"
#include "uascma/planning/flight_plan.h"
#include "uascma/planning/land_pract.h"
#include "uascma/planning/map_import.h"
#include "uascma/sim/scenario.h"

namespace uascma::campaign {
namespace {

using ::uascma::testing_support::OsmDataDir;

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
  EXPECT_EQ(std::filesystem::path(config.map.buildings[0]),
            (dir / "upper-east-side-buildings.geojson").lexically_normal());
  EXPECT_EQ(std::filesystem::path(config.map.sites), (dir / "midtown-landing-sites.csv").lexically_normal());
}

TEST(ImportedMapSamplerTest, MissionsAreSampledOverTheRealCityOnOpenGround) {
  CampaignConfig config = ParseCampaignConfig(kImportedYaml, "c.yaml");
  config.map.buildings = {(OsmDataDir() / "upper-east-side-buildings.geojson").string()};
  config.map.sites = (OsmDataDir() / "midtown-landing-sites.csv").string();
  const CampaignWorld world = BuildCampaignWorld(config.map);  // read once, shared by every run
  const auto map = world.map;
  // 1,239 buildings, 9 skipped without height or levels (map_import.h); 1,828 sites.
  EXPECT_EQ(map->buildings().size(), 1230u);
  EXPECT_EQ(map->sites().size(), 1828u);
  ASSERT_NE(world.obstacles, nullptr);  // the emergency planners' hulls, one per building
  EXPECT_EQ(world.obstacles->size(), static_cast<int>(map->buildings().size()));
  const Eigen::AlignedBox2d extent = BuildingsExtent(*map);
  EXPECT_FALSE(extent.contains(map->bounds()));  // the sites file reaches beyond the buildings
  EXPECT_TRUE(RouteArea(*map, config.map).isApprox(extent));
  for (std::int64_t index = 0; index < 40; ++index) {
    const SampledRun run = SampleRun(config, world, 7, index);
    const auto& mission = run.scenario.mission;
    EXPECT_EQ(run.scenario.map.get(), map.get());
    EXPECT_EQ(run.scenario.map_obstacles.get(), world.obstacles.get());
    // Homes, destinations (hover points) over the city, not beside it: inside the buildings' extent (the Midtown
    // sites lie 2 km away and do not widen it), on open ground with the wall clearance of
    // docs/modelling-choices.md#battery-health-draw.
    for (const Eigen::Vector2d& p : {mission.home_NE, mission.destination_NE}) {
      EXPECT_TRUE(extent.contains(p)) << "index " << index << " (" << p.transpose() << ")";
      EXPECT_FALSE(map->IsInsideBuilding(Eigen::Vector3d(p.x(), p.y(), -0.1))) << "index " << index;
      const std::array<Eigen::Vector2d, 1> point = {p};
      EXPECT_EQ(map->TallestBuildingUnder(point, config.mission.wall_clearance_m).building, planning::kNoBuilding)
          << "index " << index;
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

TEST(ImportedMapSamplerTest, SitesThatMissTheRoutesAreReportedAndTheMapSuppliesItsOwn) {
  CampaignConfig config = ParseCampaignConfig(kImportedYaml, "c.yaml");
  config.map.buildings = {(OsmDataDir() / "upper-east-side-buildings.geojson").string()};
  // The Midtown sites lie ~2 km south of the Upper East Side: LandPract's 500 m reach misses every checkpoint.
  config.map.sites = (OsmDataDir() / "midtown-landing-sites.csv").string();
  constexpr std::int64_t kRuns = 20;
  const SiteCoverage midtown = CalcSiteCoverage(config, 7, kRuns);
  EXPECT_EQ(midtown.runs, kRuns);
  EXPECT_EQ(midtown.checkpoints, kRuns * planning::LandPractParams{}.checkpoint_count);
  EXPECT_EQ(midtown.checkpoints_without_site, midtown.checkpoints);
  EXPECT_GT(midtown.largest_gap, 1000.0);
  EXPECT_FALSE(midtown.covered());
  EXPECT_NE(midtown.BriefReport().find("100 of 100 checkpoints"), std::string::npos) << midtown.BriefReport();

  // Without a sites file the map supplies its flat roofs (map_import.h): every checkpoint has a site in reach.
  config.map.sites.clear();
  const auto map = BuildCampaignWorld(config.map).map;
  EXPECT_EQ(map->buildings().size(), 1230u);
  EXPECT_GT(map->sites().size(), 1000u);
  for (const planning::LandingSite& site : map->sites()) EXPECT_TRUE(site.on_rooftop()) << site.id;
  const SiteCoverage own = CalcSiteCoverage(config, 7, kRuns);
  EXPECT_TRUE(own.sites_from_map);
  EXPECT_EQ(own.rooftop_sites_from_map + own.open_area_sites_from_map, own.sites);  // no sites file
  EXPECT_EQ(own.checkpoints_without_site, 0);
  EXPECT_TRUE(own.covered());
  EXPECT_LT(own.largest_gap, own.reach);
}

// The report says where the sites come from, and its hint fits them: the map's own sites name the kinds of land
// they come from and how to widen them (not "give a sites file, or none": none is what the map already has).
TEST(ImportedMapSamplerTest, CoverageReportNamesTheMapsOwnSitesAndHowToWidenThem) {
  SiteCoverage coverage;
  coverage.runs = 25;
  coverage.checkpoints = 250;
  coverage.checkpoints_without_site = 169;
  coverage.runs_with_uncovered_checkpoint = 25;
  coverage.reach = 500.0;
  coverage.largest_gap = 2100.0;
  coverage.sites = 40;
  coverage.sites_from_map = true;
  coverage.rooftop_sites_from_map = 30;
  coverage.open_area_sites_from_map = 10;
  const std::string own = coverage.BriefReport();
  EXPECT_NE(own.find("169 of 250 checkpoints"), std::string::npos) << own;
  EXPECT_NE(own.find("30 are the map's flat roofs and 10 lie in its open areas; 0 come from the sites file"),
            std::string::npos)
      << own;
  EXPECT_NE(own.find("leisure=park"), std::string::npos) << own;
  EXPECT_EQ(own.find("or none"), std::string::npos) << own;
  coverage.sites_from_map = false;
  const std::string file = coverage.BriefReport();
  EXPECT_NE(file.find("give a sites file of the same district, or none"), std::string::npos) << file;
  EXPECT_EQ(file.find("flat roofs and 10"), std::string::npos) << file;
  coverage.checkpoints_without_site = 0;
  EXPECT_EQ(coverage.BriefReport().find("do not cover"), std::string::npos);
}

// ---- A region, not a district: two towns and the open land between them ----------------------------------

// Two towns of 3 x 3 houses (20 m squares, 60 m apart, 10 m tall) whose centres lie 4 km apart on an east-west line
// at 46° N, written as GeoJSON; the buildings' extent is then ~4.1 km by ~0.14 km, ~97 % of it open land.
std::filesystem::path WriteTwoTownsGeojson(const std::filesystem::path& dir) {
  constexpr double kLat0Deg = 46.0;
  constexpr double kLon0Deg = 8.0;
  constexpr double kMetresPerDegLat = 111'132.0;                   // near 46° N (WGS 84), to ~0.1 %
  const double metres_per_deg_lon = 111'320.0 * std::cos(kLat0Deg * kPi / 180.0);
  std::string features;
  for (const double town_east_m : {0.0, 4000.0}) {
    for (int row = 0; row < 3; ++row) {
      for (int column = 0; column < 3; ++column) {
        const double north = 60.0 * row;
        const double east = town_east_m + 60.0 * column;
        auto corner = [&](double dn, double de) {
          return fmt::format("[{:.7f},{:.7f}]", kLon0Deg + (east + de) / metres_per_deg_lon,
                             kLat0Deg + (north + dn) / kMetresPerDegLat);
        };
        if (!features.empty()) features += ",";
        features += fmt::format(
            R"({{"type":"Feature","properties":{{"building":"house","height":"10"}},)"
            R"("geometry":{{"type":"Polygon","coordinates":[[{},{},{},{},{}]]}}}})",
            corner(0, 0), corner(0, 20), corner(20, 20), corner(20, 0), corner(0, 0));
      }
    }
  }
  const std::filesystem::path file = dir / "two-towns.geojson";
  std::ofstream(file) << R"({"type":"FeatureCollection","features":[)" << features << "]}";
  return file;
}

TEST(ImportedMapSamplerTest, RoutesOverARegionStartAndEndWhereItIsBuiltUp) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "uascma_two_towns_test";
  std::filesystem::create_directories(dir);
  const std::filesystem::path geojson = WriteTwoTownsGeojson(dir);
  const CampaignConfig config = ParseCampaignConfig(
      "map:\n  buildings: [" + geojson.string() + "]\nmission: {distance_m: [300, 900]}\n", "c.yaml");
  const CampaignWorld world = BuildCampaignWorld(config.map);
  std::filesystem::remove_all(dir);
  const auto map = world.map;
  ASSERT_EQ(map->buildings().size(), 18u);
  const Eigen::AlignedBox2d extent = BuildingsExtent(*map);
  ASSERT_GT(extent.sizes().maxCoeff(), 4000.0);
  // IsBuiltUp against its definition computed another way: the distance to the nearest building's box (a
  // rectangle's box is its outline) or site, within LandPract's reach.
  const double reach = planning::LandPractParams{}.site_search_radius;  // m
  auto nearest_building_or_site = [&](const Eigen::Vector2d& p) {
    double nearest = std::numeric_limits<double>::infinity();
    for (int k = 0; k < static_cast<int>(map->buildings().size()); ++k)
      nearest = std::min(nearest, map->building_box(k).exteriorDistance(p));
    for (const planning::LandingSite& site : map->sites())
      nearest = std::min(nearest, (site.p_W.head<2>() - p).norm());
    return nearest;
  };
  constexpr double kEdgeToleranceM = 1.0;  // points this near LandPract's reach are not judged
  int open_land_points = 0;
  for (double east = extent.min().y(); east <= extent.max().y(); east += 50.0) {
    const Eigen::Vector2d p(extent.center().x(), east);
    const double nearest = nearest_building_or_site(p);
    if (std::abs(nearest - reach) < kEdgeToleranceM) continue;
    EXPECT_EQ(IsBuiltUp(*map, p), nearest < reach) << "east " << east << " m, nearest " << nearest << " m";
    open_land_points += nearest < reach ? 0 : 1;
  }
  EXPECT_GT(open_land_points, 40);  // most of the line between the towns is open land
  // Every home and destination where the map is built up: in or beside one of the two towns. Drawn uniformly
  // over the extent, ~75 % of the homes would fall on the open land between them (3 km of its 4.1 km).
  for (std::int64_t index = 0; index < 40; ++index) {
    const SampledRun run = SampleRun(config, world, 11, index);
    for (const Eigen::Vector2d& p : {run.scenario.mission.home_NE, run.scenario.mission.destination_NE}) {
      EXPECT_LE(nearest_building_or_site(p), reach + kEdgeToleranceM) << "index " << index << " " << p.transpose();
    }
  }
}

// ---- Buildings without heights: the import keys of `map info` in campaign and scenario files --------------

// Six buildings, five without a height tag (one with building:levels, one with 14.5 m), a park and a surface car
// park (tests/data/maps/no-heights.osm; map_import_test.cc counts them).
std::string NoHeightsOsm() {
  return (std::filesystem::path(UASCMA_SOURCE_DIR) / "tests" / "data" / "maps" / "no-heights.osm").string();
}
constexpr double kHeightToleranceM = 1e-9;  // heights are copied, not computed in another way
constexpr int kNoHeightsDerivedSites = 15;  // 5 flat roofs + 10 open-area sites (map_import_test.cc)

std::string NoHeightsCampaign(const std::string& keys) {
  return "map:\n  buildings: [" + NoHeightsOsm() + "]\n" + keys;
}

std::map<std::string, double> HeightsById(const planning::CityMap& map) {
  std::map<std::string, double> heights;
  for (const planning::Building& b : map.buildings()) heights[b.id] = b.height;
  return heights;
}

// The canonical YAML gives back the same map section, the same text and the same fingerprint.
void ExpectRoundTrip(const CampaignConfig& config) {
  const CampaignConfig again = ParseCampaignConfig(CampaignConfigYaml(config), "canonical");
  EXPECT_EQ(again.map, config.map);
  EXPECT_EQ(CampaignConfigYaml(again), CampaignConfigYaml(config));
  EXPECT_EQ(CampaignConfigHash(again), CampaignConfigHash(config));
}

TEST(ImportedMapHeightsTest, CampaignKeysImportBuildingsWithoutHeights) {
  // Without a fall-back the import stops, as `map info` does without its flags.
  const CampaignConfig bare = ParseCampaignConfig(NoHeightsCampaign(""), "c.yaml");
  EXPECT_THROW((void)BuildCampaignWorld(bare.map).map, InputError);

  // height_from_type: the building=* table (map_import.h); no sites file, so the map supplies its own sites.
  const CampaignConfig by_type = ParseCampaignConfig(NoHeightsCampaign("  height_from_type: true\n"), "c.yaml");
  EXPECT_TRUE(by_type.map.height_from_type);
  EXPECT_TRUE(by_type.map.DerivesSites());
  ExpectRoundTrip(by_type);
  const auto typed = BuildCampaignWorld(by_type.map).map;
  EXPECT_EQ(typed->buildings().size(), 6u);
  EXPECT_EQ(static_cast<int>(typed->sites().size()), kNoHeightsDerivedSites);
  std::map<std::string, double> heights = HeightsById(*typed);
  EXPECT_NEAR(heights.at("way/101"), planning::BuildingTypeHeight("house"), kHeightToleranceM);
  EXPECT_NEAR(heights.at("way/102"), planning::BuildingTypeHeight("apartments"), kHeightToleranceM);
  EXPECT_NEAR(heights.at("way/104"), planning::BuildingTypeHeight("yes"), kHeightToleranceM);  // levels not asked
  EXPECT_NEAR(heights.at("way/106"), 14.5, kHeightToleranceM);                                 // the height tag first

  // default_height_m: every building still without a height gets it; levels first when asked.
  const CampaignConfig by_default =
      ParseCampaignConfig(NoHeightsCampaign("  height_from_levels: true\n  default_height_m: 8\n"), "c.yaml");
  ASSERT_TRUE(by_default.map.default_height_m.has_value());
  ExpectRoundTrip(by_default);
  heights = HeightsById(*BuildCampaignWorld(by_default.map).map);
  ASSERT_EQ(heights.size(), 6u);
  for (const char* id : {"way/101", "way/102", "way/103", "way/105"}) {
    EXPECT_NEAR(heights.at(id), 8.0, kHeightToleranceM) << id;
  }
  EXPECT_NEAR(heights.at("way/104"), 4 * by_default.map.metres_per_level, kHeightToleranceM);
  EXPECT_NEAR(heights.at("way/106"), 14.5, kHeightToleranceM);
}

TEST(ImportedMapHeightsTest, CampaignSitesFromMapAddsToOrReplacesTheSitesFile) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "uascma_imported_map_sites_test";
  std::filesystem::create_directories(dir);
  const std::filesystem::path sites = dir / "one-site.csv";
  // One ground site inside the park of no-heights.osm.
  std::ofstream(sites) << "osm_id,lat,lon,alt,risk,radius\n900,47.1410,9.5205,0,0.2,5\n";
  const std::string type = "  height_from_type: true\n";
  auto sites_of = [](const CampaignConfig& config) { return BuildCampaignWorld(config.map).map->sites().size(); };

  // With a sites file and no key: the file's sites only (as before the key existed).
  const CampaignConfig file_only =
      ParseCampaignConfig(NoHeightsCampaign(type + "  sites: " + sites.string() + "\n"), "c");
  EXPECT_FALSE(file_only.map.DerivesSites());
  EXPECT_EQ(sites_of(file_only), 1u);
  // sites_from_map: true adds the map's own beside the file's.
  const CampaignConfig both =
      ParseCampaignConfig(NoHeightsCampaign(type + "  sites: " + sites.string() + "\n  sites_from_map: true\n"), "c");
  EXPECT_TRUE(both.map.DerivesSites());
  ExpectRoundTrip(both);
  EXPECT_EQ(static_cast<int>(sites_of(both)), 1 + kNoHeightsDerivedSites);
  // sites_from_map: false without a file: no sites at all (the emergency actions then have nowhere to go).
  const CampaignConfig none = ParseCampaignConfig(NoHeightsCampaign(type + "  sites_from_map: false\n"), "c");
  EXPECT_FALSE(none.map.DerivesSites());
  ExpectRoundTrip(none);
  EXPECT_EQ(sites_of(none), 0u);
  std::filesystem::remove_all(dir);
}

TEST(ImportedMapHeightsTest, NewKeysLeaveOlderFingerprintsAloneAndChangeTheirOwn) {
  // The fingerprints kImportedYaml had before the three keys existed (printed by CampaignConfigHash as it was
  // before them, built from the same tree): with and without its sites file.
  CampaignConfig config = ParseCampaignConfig(kImportedYaml, "c.yaml");
  EXPECT_EQ(CampaignConfigHash(config), "c6309fb213bca430");
  CampaignConfig no_file = config;
  no_file.map.sites.clear();
  EXPECT_EQ(CampaignConfigHash(no_file), "d6386a4b961d6600");
  // The explicit form of what the import does anyway is the same campaign.
  CampaignConfig same = no_file;
  same.map.sites_from_map = true;
  EXPECT_EQ(CampaignConfigHash(same), CampaignConfigHash(no_file));
  same = config;
  same.map.sites_from_map = false;
  EXPECT_EQ(CampaignConfigHash(same), CampaignConfigHash(config));
  // Each key that changes the import changes the fingerprint.
  CampaignConfig other = config;
  other.map.sites_from_map = true;
  EXPECT_NE(CampaignConfigHash(other), CampaignConfigHash(config));
  other = no_file;
  other.map.sites_from_map = false;
  EXPECT_NE(CampaignConfigHash(other), CampaignConfigHash(no_file));
  other = config;
  other.map.height_from_type = true;
  EXPECT_NE(CampaignConfigHash(other), CampaignConfigHash(config));
  other = config;
  other.map.default_height_m = 8.0;
  const std::string eight = CampaignConfigHash(other);
  EXPECT_NE(eight, CampaignConfigHash(config));
  other.map.default_height_m = 9.0;
  EXPECT_NE(CampaignConfigHash(other), eight);
}

TEST(ImportedMapHeightsTest, BadCampaignKeysAreNamed) {
  auto error_of = [](const std::string& yaml) -> std::string {
    try {
      ParseCampaignConfig(yaml, "c.yaml");
    } catch (const InputError& error) {
      return error.what();
    }
    return "";
  };
  // 1 to 500 m (planning::kDefaultHeightBounds, as --default-height).
  EXPECT_NE(error_of(NoHeightsCampaign("  default_height_m: 0.5\n")).find("map.default_height_m"), std::string::npos);
  EXPECT_NE(error_of(NoHeightsCampaign("  default_height_m: 501\n")).find("1 to 500 m"), std::string::npos);
  EXPECT_EQ(error_of(NoHeightsCampaign("  default_height_m: 500\n")), "");
  EXPECT_NE(error_of(NoHeightsCampaign("  sites_from_map: 2\n")).find("map.sites_from_map"), std::string::npos);
  // Import keys without building files belong to no map.
  for (const char* key : {"height_from_type: true", "default_height_m: 8", "sites_from_map: true"}) {
    EXPECT_NE(error_of(std::string("map: {") + key + "}\n").find("map.buildings"), std::string::npos) << key;
  }
}

TEST(ImportedMapHeightsTest, ScenarioKeysImportBuildingsWithoutHeights) {
  auto scenario = [](const std::string& keys) {
    return sim::ParseScenario("map: {buildings: [" + NoHeightsOsm() + "]" + keys + "}\n", "s.yaml").scenario;
  };
  EXPECT_THROW((void)scenario(""), InputError);
  const sim::Scenario typed = scenario(", height_from_type: true");
  ASSERT_TRUE(typed.map);
  EXPECT_EQ(typed.map->buildings().size(), 6u);
  EXPECT_TRUE(typed.map->sites().empty());  // a scenario's map supplies sites only when asked
  EXPECT_NEAR(HeightsById(*typed.map).at("way/101"), planning::BuildingTypeHeight("house"), kHeightToleranceM);

  const sim::Scenario by_default = scenario(", default_height_m: 8, sites_from_map: true");
  const std::map<std::string, double> heights = HeightsById(*by_default.map);
  ASSERT_EQ(heights.size(), 6u);
  EXPECT_NEAR(heights.at("way/104"), 8.0, kHeightToleranceM);
  EXPECT_NEAR(heights.at("way/106"), 14.5, kHeightToleranceM);
  EXPECT_EQ(static_cast<int>(by_default.map->sites().size()), kNoHeightsDerivedSites);

  auto error_of = [](const std::string& yaml) -> std::string {
    try {
      (void)sim::ParseScenario(yaml, "s.yaml");
    } catch (const InputError& error) {
      return error.what();
    }
    return "";
  };
  EXPECT_NE(error_of("map: {buildings: [" + NoHeightsOsm() + "], default_height_m: 501}\n")
                .find("s.yaml: map.default_height_m"),
            std::string::npos);
  EXPECT_NE(error_of("map: {procedural: {seed: 3}, height_from_type: true}\n").find("map.height_from_type"),
            std::string::npos);
}

}  // namespace
}  // namespace uascma::campaign
