// uascma map — the city map the planners fly over (dissertation §5.1, §5.4): import real OpenStreetMap data
// (GeoJSON, .osm, .osm.pbf, landing-site CSV) or build the procedural default, and report what it holds.
#include <unistd.h>

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
#include "uascma/planning/map_summary.h"
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
    ImportedMap loaded;
    if (procedural) {
      loaded = MakeProceduralCityMap(options->seed);
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
      try {
        loaded = ImportCityMap(files, options->sites, import);
      } catch (const MapImportError& error) {
        // The one-line error (exit 2) counts what was read and skipped; --json adds the whole summary, by reason.
        if (options->json) {
          nlohmann::json out = ImportSummaryJson(error.summary(), std::nullopt);
          out["error"] = error.what();
          PrintJson(out);
        }
        throw;
      }
    }
    const std::optional<std::uint64_t> procedural_seed =
        procedural ? std::optional<std::uint64_t>(options->seed) : std::nullopt;
    if (!options->plot.empty()) {
      PlotJson("city_map.py", CityMapPlotJson(loaded.map, CityMapPlotTitle(loaded.summary)), options->plot);
    }
    if (options->json) {
      nlohmann::json out = ImportSummaryJson(loaded.summary, procedural_seed);
      if (!options->plot.empty()) out["plot"] = options->plot;
      PrintJson(out);
      return;
    }
    std::string text = ImportSummaryText(loaded.summary, procedural_seed, options->list_skipped);
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
