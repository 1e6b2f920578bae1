// uascma map — the city map the planners fly over (dissertation §5.1, §5.4): import real OpenStreetMap data
// (GeoJSON, .osm, .osm.pbf, landing-site CSV) or build the procedural default, and report what it holds.
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "bounded_option.h"
#include "commands.h"
#include "output.h"
#include "plotting.h"
#include "uascma/campaign/config.h"
#include "uascma/campaign/sampler.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/planning/city_map.h"
#include "uascma/planning/map_import.h"
#include "uascma/planning/map_projection.h"
#include "uascma/planning/procedural_city.h"

namespace uascma::cli {
namespace {

// Storey height for --height-from-levels: 1 to 10 m (our bound; a typical floor is ~3 m, map_import.h).
constexpr Bounds kMetresPerLevelBounds{1.0, 10.0, "m"};

using namespace uascma::planning;

// "LAT,LON" in degrees.
GeoPoint ParseOrigin(const std::string& text) {
  const auto comma = text.find(',');
  const std::string expected = fmt::format("LAT,LON in degrees (e.g. 40.7387,-73.9894), got '{}'", text);
  if (comma == std::string::npos) throw InputError("--origin", "value", expected);
  double lat = 0.0, lon = 0.0;
  try {
    std::size_t used_lat = 0, used_lon = 0;
    const std::string lat_text = text.substr(0, comma), lon_text = text.substr(comma + 1);
    lat = std::stod(lat_text, &used_lat);
    lon = std::stod(lon_text, &used_lon);
    if (used_lat != lat_text.size() || used_lon != lon_text.size()) throw InputError("--origin", "value", expected);
  } catch (const std::logic_error&) {  // std::stod's invalid_argument and out_of_range
    throw InputError("--origin", "value", expected);
  }
  if (!(lat >= -90.0 && lat <= 90.0 && lon >= -180.0 && lon <= 180.0)) {
    throw InputError("--origin", "value",
                     fmt::format("latitude in [-90, 90] and longitude in [-180, 180], got '{}'", text));
  }
  return {lat, lon};
}

// The summary of the procedural city, in the importers' terms.
ImportSummary SummariseProcedural(const CityMap& map, std::uint64_t seed) {
  ImportSummary summary;
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
  return summary;
}

nlohmann::json HeightSourcesJson(const ImportSummary& s) {
  nlohmann::json out = nlohmann::json::object();
  for (int h = 0; h < kNumHeightSources; ++h) out[HeightSourceName(static_cast<HeightSource>(h))] = s.height_sources[h];
  return out;
}

nlohmann::json SummaryJson(const ImportSummary& s, bool procedural, std::uint64_t seed) {
  nlohmann::json skipped = nlohmann::json::object();
  for (int r = 0; r < kNumSkipReasons; ++r) skipped[SkipReasonName(static_cast<SkipReason>(r))] = s.skipped[r];
  skipped["total"] = s.skipped_total();
  nlohmann::json skipped_features = nlohmann::json::array();
  for (const auto& f : s.skipped_features) {
    skipped_features.push_back(
        {{"source", f.source}, {"feature", f.feature}, {"reason", SkipReasonName(f.reason)}, {"detail", f.detail}});
  }
  nlohmann::json out = {
      {"source", procedural ? "procedural" : "files"},
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
  if (procedural) {
    out["seed"] = seed;
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

std::string SummaryText(const ImportSummary& s, bool procedural, std::uint64_t seed, bool list_skipped) {
  if (!procedural) {
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
      seed, defaults.blocks_north, defaults.blocks_east, defaults.block_north, defaults.block_east);
  text += fmt::format("buildings: {}\nlanding sites: {} ({} on rooftops, {} on the ground)\n", s.buildings, s.sites,
                      s.rooftop_sites, s.sites - s.rooftop_sites);
  text += fmt::format("extent: x {:.1f} .. {:.1f} m (north), y {:.1f} .. {:.1f} m (east)\n", s.bounds.min().x(),
                      s.bounds.max().x(), s.bounds.min().y(), s.bounds.max().y());
  text += fmt::format("tallest building: {}, {:.1f} m\n", s.tallest_building, s.tallest_height);
  return text;
}

// The data python/plots/city_map.py draws: outlines with heights, sites with risks, in metres.
nlohmann::json PlotData(const CityMap& map, const std::string& title) {
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

void AddInfo(CLI::App* map_command) {
  struct Options {
    std::vector<std::string> files;
    std::string sites;
    std::string origin;
    std::uint64_t seed = ProceduralCityParams{}.seed;
    bool json = false;
    bool skip_missing_height = false;
    bool height_from_levels = false;
    bool height_from_type = false;
    std::optional<double> default_height;
    bool sites_from_map = false;
    double metres_per_level = MapImportOptions{}.metres_per_level;
    bool list_skipped = false;
    std::string plot;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = map_command->add_subcommand(
      "info",
      "Import a city map and print its summary: buildings, skipped features by reason, landing sites,\n"
      "extent and tallest building. FILE: .geojson/.json (Overpass export), .osm or .osm.pbf; with no FILE\n"
      "(and no --sites) the built-in procedural city of --seed. Data projected to a local transverse\n"
      "Mercator frame (x north, y east) centred on --origin or the centre of the data");
  command->add_option("files", options->files, "Building files (.geojson, .json, .osm, .osm.pbf)");
  command->add_option(
      "--sites", options->sites,
      "Landing-site CSV: osm_id, lat|gps.lat, lon|gps.lon, alt|gps.alt, risk|landing_site_risk, radius");
  command->add_option("--origin", options->origin, "Origin of the local frame, LAT,LON in degrees");
  AddSeedOption(command, "--seed", options->seed, "Seed of the procedural city (no FILE) (default 1)");
  command->add_flag("--skip-missing-height", options->skip_missing_height,
                    "Skip (and count) buildings without a height instead of stopping with an error");
  command->add_flag("--height-from-levels", options->height_from_levels,
                    "Take a missing height from building:levels x --metres-per-level");
  AddBoundedOption(command, "--metres-per-level", options->metres_per_level,
                   "Storey height for --height-from-levels (default 3 m)", kMetresPerLevelBounds);
  command->add_flag("--height-from-type", options->height_from_type,
                    "Then take a missing height from the building=* value: typical storeys x the CTBUH storey\n"
                    "height (house 6.2 m, apartments 15.5 m, yes 10.5 m; the table in map_import.h)");
  command->add_option(
      "--default-height", options->default_height,
      "Then give every building still without a height this one (m, " + kDefaultHeightBounds.Text() + ")");
  command->add_flag("--sites-from-map", options->sites_from_map,
                    "Derive landing sites from the map: flat-roof centroids and open areas (parks, pitches,\n"
                    "surface parking) of the same files (dissertation §5.1)");
  command->add_flag("--list-skipped", options->list_skipped, "List every skipped feature (text output)");
  command->add_flag("--json", options->json, "Print the summary as JSON");
  command->add_option("--plot", options->plot,
                      "Also draw the map to this PNG: footprints shaded by height, sites coloured by risk");
  command->callback([options, command] {
    const bool procedural = options->files.empty() && options->sites.empty();
    if (!procedural && command->count("--seed") > 0) {
      throw InputError("--seed", "value", "only with the procedural city (no FILE and no --sites)");
    }
    if (procedural && !options->origin.empty()) {
      throw InputError("--origin", "value", "map files to project (the procedural city has no geographic origin)");
    }
    CityMap map;
    ImportSummary summary;
    if (procedural) {
      ProceduralCityParams params;
      params.seed = options->seed;
      map = MakeProceduralCity(params);
      summary = SummariseProcedural(map, options->seed);
    } else {
      MapImportOptions import;
      import.skip_missing_height = options->skip_missing_height;
      import.height_from_levels = options->height_from_levels;
      import.metres_per_level = options->metres_per_level;
      import.height_from_type = options->height_from_type;
      import.default_height = options->default_height;
      import.sites_from_map = options->sites_from_map;
      RequireWithin(options->metres_per_level, kMetresPerLevelBounds, "--metres-per-level", "value");
      if (options->default_height) {
        RequireWithin(*options->default_height, kDefaultHeightBounds, "--default-height", "value");
      }
      if (!options->origin.empty()) import.origin = ParseOrigin(options->origin);
      const std::vector<std::filesystem::path> files(options->files.begin(), options->files.end());
      ImportedMap imported;
      try {
        imported = ImportCityMap(files, options->sites, import);
      } catch (const MapImportError& error) {
        // The one-line error (exit 2) counts what was read and skipped; --json adds the whole summary, by reason.
        if (options->json) {
          nlohmann::json out = SummaryJson(error.summary(), false, options->seed);
          out["error"] = error.what();
          PrintJson(out);
        }
        throw;
      }
      map = std::move(imported.map);
      summary = std::move(imported.summary);
    }
    if (!options->plot.empty()) {
      std::string sources;
      for (const auto& source : summary.sources) {
        sources += (sources.empty() ? "" : ", ") + std::filesystem::path(source).filename().string();
      }
      const std::string title =
          fmt::format("{} — {} buildings, {} landing sites", sources, summary.buildings, summary.sites);
      PlotJson("city_map.py", PlotData(map, title), options->plot);
    }
    if (options->json) {
      nlohmann::json out = SummaryJson(summary, procedural, options->seed);
      if (!options->plot.empty()) out["plot"] = options->plot;
      PrintJson(out);
      return;
    }
    std::string text = SummaryText(summary, procedural, options->seed, options->list_skipped);
    if (!options->plot.empty()) text += fmt::format("wrote {}\n", options->plot);
    std::fputs(text.c_str(), stdout);
  });
}

// Runs checked by `map coverage` at most: each is one sampled scenario (no flight), a few milliseconds.
constexpr Bounds kCoverageRunsBounds{1.0, 100'000.0, "runs"};

void AddCoverage(CLI::App* map_command) {
  struct Options {
    std::string file;
    std::int64_t runs = 100;
    std::optional<std::uint64_t> seed;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = map_command->add_subcommand(
      "coverage",
      "Do a campaign's landing sites cover its routes? Samples the first --runs scenarios of CAMPAIGN.yaml (no\n"
      "flight), places LandPract's checkpoints on each nominal plan and counts those with no landing site within\n"
      "the planners' reach (500 m). Exit 0 either way; the numbers say whether the sites file fits the map");
  command->add_option("campaign", options->file, "Campaign YAML file")->required();
  AddBoundedOption(command, "--runs", options->runs, "Scenarios to sample (default 100)", kCoverageRunsBounds);
  AddSeedOption(command, "--seed", options->seed, "Campaign seed (default: the file's seed)");
  command->add_flag("--json", options->json, "Print the numbers as JSON");
  command->callback([options] {
    const campaign::CampaignConfig config = campaign::LoadCampaignConfig(options->file);
    const campaign::SiteCoverage c =
        campaign::CalcSiteCoverage(config, options->seed.value_or(config.seed), options->runs);
    if (options->json) {
      PrintJson({{"runs", c.runs},
                 {"checkpoints", c.checkpoints},
                 {"checkpoints_without_site", c.checkpoints_without_site},
                 {"runs_with_uncovered_checkpoint", c.runs_with_uncovered_checkpoint},
                 {"reach_m", c.reach},
                 {"largest_gap_m", c.largest_gap},
                 {"sites", c.sites},
                 {"covered", c.covered()}});
      return;
    }
    std::fputs(c.BriefReport().c_str(), stdout);
  });
}

}  // namespace

void AddMapCommand(CLI::App& app) {
  CLI::App* map_command = app.add_subcommand(
      "map", "City maps (§5.1, §5.4): import OpenStreetMap buildings and landing sites, or the procedural city");
  map_command->require_subcommand(1);
  AddInfo(map_command);
  AddCoverage(map_command);
}

}  // namespace uascma::cli
