// What `uascma map info` reports (planning/map_summary.h): the procedural city's summary against the map counted here,
// the JSON and the text against the summary, and the plot data against the map.
#include "uascma/planning/map_summary.h"

#include <cstddef>
#include <string>

#include <gtest/gtest.h>

#include "uascma/planning/procedural_city.h"

namespace uascma::planning {
namespace {

constexpr std::uint64_t kSeed = 7;  // any seed: the checks hold for every procedural city

TEST(MapSummaryTest, TheProceduralCitysSummaryCountsItsMap) {
  const ImportedMap city = MakeProceduralCityMap(kSeed);
  ProceduralCityParams params;
  params.seed = kSeed;
  const CityMap same = MakeProceduralCity(params);
  ASSERT_EQ(city.map.buildings().size(), same.buildings().size());  // the same city as MakeProceduralCity's
  const ImportSummary& summary = city.summary;
  EXPECT_EQ(summary.buildings, static_cast<int>(city.map.buildings().size()));
  EXPECT_EQ(summary.features, summary.buildings);
  EXPECT_EQ(summary.sites, static_cast<int>(city.map.sites().size()));
  int rooftop = 0;
  for (const LandingSite& site : city.map.sites()) rooftop += site.on_rooftop() ? 1 : 0;
  EXPECT_EQ(summary.rooftop_sites, rooftop);
  double tallest = 0.0;
  for (const Building& building : city.map.buildings()) tallest = std::max(tallest, building.height);
  EXPECT_EQ(summary.tallest_height, tallest);  // the same number, taken from the same building
  EXPECT_EQ(summary.skipped_total(), 0);
}

TEST(MapSummaryTest, JsonAndTextSayWhatTheSummaryHolds) {
  const ImportedMap city = MakeProceduralCityMap(kSeed);
  const ImportSummary& s = city.summary;
  const nlohmann::json procedural = ImportSummaryJson(s, kSeed);
  EXPECT_EQ(procedural.at("source"), "procedural");
  EXPECT_EQ(procedural.at("seed"), kSeed);
  EXPECT_TRUE(procedural.at("origin").is_null());
  EXPECT_EQ(procedural.at("ground_sites").get<int>() + procedural.at("rooftop_sites").get<int>(), s.sites);
  EXPECT_EQ(procedural.at("tallest_building").at("id"), s.tallest_building);
  const nlohmann::json files = ImportSummaryJson(s, std::nullopt);
  EXPECT_EQ(files.at("source"), "files");
  EXPECT_EQ(files.count("seed"), 0u);
  EXPECT_EQ(files.at("origin").at("from_data"), s.origin_from_data);

  const std::string text = ImportSummaryText(s, kSeed, false);
  EXPECT_EQ(text.rfind("procedural city, seed 7 (", 0), 0u) << text;
  EXPECT_NE(text.find("buildings: " + std::to_string(s.buildings) + "\n"), std::string::npos) << text;
  EXPECT_EQ(ImportSummaryText(s, std::nullopt, false), s.BriefReport());
}

TEST(MapSummaryTest, PlotDataHoldsEveryBuildingAndSite) {
  const ImportedMap city = MakeProceduralCityMap(kSeed);
  const std::string title = CityMapPlotTitle(city.summary);
  EXPECT_EQ(title, "procedural city (seed 7) — " + std::to_string(city.summary.buildings) + " buildings, " +
                       std::to_string(city.summary.sites) + " landing sites");
  const nlohmann::json plot = CityMapPlotJson(city.map, title);
  ASSERT_EQ(plot.at("buildings").size(), city.map.buildings().size());
  ASSERT_EQ(plot.at("sites").size(), city.map.sites().size());
  for (std::size_t k = 0; k < city.map.buildings().size(); ++k) {
    EXPECT_EQ(plot["buildings"][k].at("rings").size(), city.map.buildings()[k].rings.size());
  }
}

}  // namespace
}  // namespace uascma::planning
