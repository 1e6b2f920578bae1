// What `uascma map info` reports of a city map (map_summary.h).
#include "uascma/planning/map_summary.h"

#include <algorithm>
#include <filesystem>

#include <fmt/format.h>

#include "uascma/planning/procedural_city.h"

namespace uascma::planning {
namespace {

nlohmann::json HeightSourcesJson(const ImportSummary& s) {
  nlohmann::json out = nlohmann::json::object();
  for (int h = 0; h < kNumHeightSources; ++h) out[HeightSourceName(static_cast<HeightSource>(h))] = s.height_sources[h];
  return out;
}

}  // namespace

ImportedMap MakeProceduralCityMap(std::uint64_t seed) {
  ProceduralCityParams params;
  params.seed = seed;
  ImportedMap out;
  out.map = MakeProceduralCity(params);
  const CityMap& map = out.map;
  ImportSummary& summary = out.summary;
  summary.sources = {fmt::format("procedural city (seed {})", seed)};
  summary.features = static_cast<int>(map.buildings().size());
  summary.buildings = static_cast<int>(map.buildings().size());
  summary.sites = static_cast<int>(map.sites().size());
  summary.rooftop_sites = static_cast<int>(
      std::count_if(map.sites().begin(), map.sites().end(), [](const LandingSite& s) { return s.on_rooftop(); }));
  summary.bounds = map.bounds();
  if (map.tallest_building() != kNoBuilding) {
    summary.tallest_building = map.building(map.tallest_building()).id;
    summary.tallest_height = map.max_building_height();
  }
  return out;
}

nlohmann::json ImportSummaryJson(const ImportSummary& s, std::optional<std::uint64_t> procedural_seed) {
  nlohmann::json skipped = nlohmann::json::object();
  for (int r = 0; r < kNumSkipReasons; ++r) skipped[SkipReasonName(static_cast<SkipReason>(r))] = s.skipped[r];
  skipped["total"] = s.skipped_total();
  nlohmann::json skipped_features = nlohmann::json::array();
  for (const auto& f : s.skipped_features) {
    skipped_features.push_back(
        {{"source", f.source}, {"feature", f.feature}, {"reason", SkipReasonName(f.reason)}, {"detail", f.detail}});
  }
  nlohmann::json out = {
      {"source", procedural_seed ? "procedural" : "files"},
      {"sources", s.sources},
      {"features", s.features},
      {"buildings", s.buildings},
      {"heights_from_levels", s.heights_from_levels},
      {"height_sources", HeightSourcesJson(s)},
      {"open_areas", s.open_areas},
      {"derived_rooftop_sites", s.derived_rooftop_sites},
      {"derived_open_sites", s.derived_open_sites},
      {"skipped", skipped},
      {"skipped_features", skipped_features},
      {"sites", s.sites},
      {"rooftop_sites", s.rooftop_sites},
      {"ground_sites", s.sites - s.rooftop_sites},
  };
  if (procedural_seed) {
    out["seed"] = *procedural_seed;
    out["origin"] = nullptr;
    out["bounds_deg"] = nullptr;
  } else {
    out["origin"] = {{"lat_deg", s.origin.lat_deg}, {"lon_deg", s.origin.lon_deg}, {"from_data", s.origin_from_data}};
    out["bounds_deg"] = {{"lat_min", s.south_west.lat_deg},
                         {"lat_max", s.north_east.lat_deg},
                         {"lon_min", s.south_west.lon_deg},
                         {"lon_max", s.north_east.lon_deg}};
  }
  if (s.bounds.isEmpty()) {
    out["bounds_m"] = nullptr;
  } else {
    out["bounds_m"] = {{"x_min", s.bounds.min().x()},
                       {"x_max", s.bounds.max().x()},
                       {"y_min", s.bounds.min().y()},
                       {"y_max", s.bounds.max().y()}};
  }
  out["tallest_building"] = s.tallest_building.empty()
                                ? nlohmann::json(nullptr)
                                : nlohmann::json{{"id", s.tallest_building}, {"height_m", s.tallest_height}};
  return out;
}

std::string ImportSummaryText(const ImportSummary& s, std::optional<std::uint64_t> procedural_seed, bool list_skipped) {
  if (!procedural_seed) {
    std::string text = s.BriefReport();
    if (list_skipped) {
      for (const auto& f : s.skipped_features) {
        text += fmt::format("  skipped {}: {} {} ({})\n", f.source, f.feature, SkipReasonName(f.reason), f.detail);
      }
    }
    return text;
  }
  const ProceduralCityParams defaults;
  std::string text = fmt::format(
      "procedural city, seed {} ({} x {} blocks of {:.0f} m x {:.0f} m; include/uascma/planning/procedural_city.h)\n",
      *procedural_seed, defaults.blocks_north, defaults.blocks_east, defaults.block_north, defaults.block_east);
  text += fmt::format("buildings: {}\nlanding sites: {} ({} on rooftops, {} on the ground)\n", s.buildings, s.sites,
                      s.rooftop_sites, s.sites - s.rooftop_sites);
  text += fmt::format("extent: x {:.1f} .. {:.1f} m (north), y {:.1f} .. {:.1f} m (east)\n", s.bounds.min().x(),
                      s.bounds.max().x(), s.bounds.min().y(), s.bounds.max().y());
  text += fmt::format("tallest building: {}, {:.1f} m\n", s.tallest_building, s.tallest_height);
  return text;
}

std::string CityMapPlotTitle(const ImportSummary& summary) {
  std::string sources;
  for (const auto& source : summary.sources) {
    sources += (sources.empty() ? "" : ", ") + std::filesystem::path(source).filename().string();
  }
  return fmt::format("{} — {} buildings, {} landing sites", sources, summary.buildings, summary.sites);
}

nlohmann::json CityMapPlotJson(const CityMap& map, const std::string& title) {
  nlohmann::json buildings = nlohmann::json::array();
  for (const Building& b : map.buildings()) {
    nlohmann::json rings = nlohmann::json::array();
    for (const Ring& ring : b.rings) {
      nlohmann::json points = nlohmann::json::array();
      for (const auto& p : ring) points.push_back({p.x(), p.y()});
      rings.push_back(points);
    }
    buildings.push_back({{"rings", rings}, {"height", b.height}});
  }
  nlohmann::json sites = nlohmann::json::array();
  for (const LandingSite& s : map.sites()) {
    sites.push_back(
        {{"x", s.p_W.x()}, {"y", s.p_W.y()}, {"risk", s.risk}, {"radius", s.radius}, {"rooftop", s.on_rooftop()}});
  }
  return {{"title", title}, {"buildings", buildings}, {"sites", sites}};
}

}  // namespace uascma::planning
