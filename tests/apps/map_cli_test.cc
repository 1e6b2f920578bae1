// End-to-end checks of `uascma map info`: the procedural default and its seed, the real OSM files of
// data/osm, the plot, and one-line exit-2 errors naming the file, the feature
// and what was expected.
#include "cli_runner.h"
#include "../support/data_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

namespace uascma {
namespace {

using testing_support::RunCli;
using testing_support::ScratchDir;

using ::uascma::testing_support::OsmDataDir;

nlohmann::json RunJson(const std::string& arguments) {
  const auto result = RunCli(arguments);
  EXPECT_EQ(result.exit_code, 0) << result.err;
  return nlohmann::json::parse(result.out);
}

void ExpectOneLineErrorNaming(const std::string& arguments, std::initializer_list<std::string> parts) {
  const auto result = RunCli(arguments);
  EXPECT_EQ(result.exit_code, 2) << arguments << "\n" << result.err;
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
  for (const auto& part : parts) EXPECT_NE(result.err.find(part), std::string::npos) << part << " in: " << result.err;
  EXPECT_TRUE(result.out.empty()) << result.out;
}

TEST(MapCliTest, ProceduralCityByDefaultReplaysFromItsSeed) {
  const auto first = RunCli("map info --json --seed 7");
  const auto again = RunCli("map info --json --seed 7");
  const auto other = RunCli("map info --json --seed 8");
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_EQ(first.out, again.out);
  EXPECT_NE(first.out, other.out);
  const nlohmann::json out = nlohmann::json::parse(first.out);
  for (const char* field : {"source", "sources", "features", "buildings", "skipped", "sites", "rooftop_sites",
                            "ground_sites", "bounds_m", "tallest_building", "seed"}) {
    EXPECT_TRUE(out.contains(field)) << field;
  }
  EXPECT_EQ(out.at("source"), "procedural");
  EXPECT_GT(out.at("buildings").get<int>(), 300);
  EXPECT_GT(out.at("ground_sites").get<int>(), 0);
  EXPECT_EQ(out.at("rooftop_sites").get<int>() + out.at("ground_sites").get<int>(), out.at("sites").get<int>());
  const auto text = RunCli("map info");
  EXPECT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("procedural city, seed 1"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("tallest building"), std::string::npos) << text.out;
  EXPECT_EQ(RunCli("map --help").exit_code, 0);
  EXPECT_EQ(RunCli("map info --help").exit_code, 0);
}

TEST(MapCliTest, RealFilesReportTheirCounts) {
  const std::string dir = OsmDataDir().string();
  const nlohmann::json broadway = RunJson("map info --json " + dir + "/broadway-14th-buildings.geojson");
  EXPECT_EQ(broadway.at("buildings").get<int>(), 67);
  EXPECT_EQ(broadway.at("skipped").at("total").get<int>(), 0);
  EXPECT_TRUE(broadway.at("origin").at("from_data").get<bool>());
  const nlohmann::json ues =
      RunJson("map info --json --skip-missing-height " + dir + "/upper-east-side-buildings.geojson --sites " + dir +
              "/midtown-landing-sites.csv --origin 40.7616,-73.9708");
  EXPECT_EQ(ues.at("features").get<int>(), 1286);
  EXPECT_EQ(ues.at("buildings").get<int>(), 1228);
  EXPECT_EQ(ues.at("skipped").at("not_polygon").get<int>(), 47);
  EXPECT_EQ(ues.at("skipped").at("missing_height").get<int>(), 11);
  EXPECT_EQ(ues.at("sites").get<int>(), 1828);
  EXPECT_FALSE(ues.at("origin").at("from_data").get<bool>());
  EXPECT_NEAR(ues.at("tallest_building").at("height_m").get<double>(), 160.0, 1e-9);
  EXPECT_EQ(ues.at("skipped_features").size(), 58u);
  const auto listed =
      RunCli("map info --skip-missing-height --list-skipped " + dir + "/upper-east-side-buildings.geojson");
  EXPECT_EQ(listed.exit_code, 0) << listed.err;
  EXPECT_NE(listed.out.find("(node/2296577459) not_polygon (geometry Point)"), std::string::npos) << listed.out;
}

TEST(MapCliTest, PlotDrawsAPng) {
  ScratchDir scratch("map_plot");
  const auto png = scratch.path / "city.png";
  const auto result = RunCli("map info --seed 3 --plot " + png.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  ASSERT_TRUE(std::filesystem::exists(png));
  std::ifstream in(png, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
  EXPECT_GT(std::filesystem::file_size(png), 10'000u);
}

TEST(MapCliTest, BadInputIsExitTwoOnOneLineNamingTheFileAndTheFeature) {
  ScratchDir scratch("map_bad");
  const auto write = [&](const std::string& name, const std::string& content) {
    std::ofstream(scratch.path / name) << content;
    return (scratch.path / name).string();
  };
  const std::string short_ring = write("short.geojson", R"({"type": "FeatureCollection", "features": [
      {"type": "Feature", "properties": {"@id": "way/77", "building": "yes", "height": "9"},
       "geometry": {"type": "Polygon", "coordinates": [[[-73.99, 40.738], [-73.989, 40.738], [-73.99, 40.738]]]}}]})");
  ExpectOneLineErrorNaming("map info " + short_ring, {"short.geojson", "features[0] (way/77)", "at least 4 positions"});
  ExpectOneLineErrorNaming("map info " + write("bad.geojson", "{not json"), {"bad.geojson", "JSON"});
  ExpectOneLineErrorNaming("map info " + write("city.shp", "x"), {"city.shp", ".geojson"});
  ExpectOneLineErrorNaming("map info " + (scratch.path / "absent.geojson").string(), {"absent.geojson"});
  ExpectOneLineErrorNaming("map info --sites " + write("s.csv", "osm_id,lat,lon,alt,risk,radius\n5,40.7,-73.9,3,2,4\n"),
                           {"s.csv", "line 2 (site 5)", "risk in [0, 1]"});
  ExpectOneLineErrorNaming("map info --sites " +
                               write("ok.csv", "osm_id,lat,lon,alt,risk,radius\n5,40.7,-73.9,3,0.2,4\n") +
                               " --origin 40.7",
                           {"--origin", "LAT,LON"});
  ExpectOneLineErrorNaming("map info --origin 40.7,-73.9", {"--origin"});  // the procedural city has no origin
  ExpectOneLineErrorNaming("map info --seed -1", {"seed"});
  ExpectOneLineErrorNaming("map info " + (OsmDataDir() / "upper-east-side-buildings.geojson").string(),
                           {"upper-east-side-buildings.geojson", "features[763] (way/266916493)", "'height'"});
}

}  // namespace
}  // namespace uascma
