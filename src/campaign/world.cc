#include "uascma/campaign/world.h"

#include <filesystem>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/planning/landing_path.h"
#include "uascma/planning/map_import.h"
#include "uascma/planning/map_projection.h"
#include "uascma/planning/procedural_city.h"

namespace uascma::campaign {
namespace {

// The imported city of `sampling` (config.h, MapSampling::imported) and its geodetic origin.
void ImportCity(const MapSampling& sampling, CampaignWorld& world) {
  planning::MapImportOptions options;
  options.height_from_levels = sampling.height_from_levels;
  options.metres_per_level = sampling.metres_per_level;
  options.skip_missing_height = sampling.skip_missing_height;
  options.height_from_type = sampling.height_from_type;
  options.default_height = sampling.default_height_m;
  // Without a landing-site file (or with sites_from_map: true) the map supplies its own sites: flat roofs and open
  // areas (map_import.h; §5.1; config.h).
  options.sites_from_map = sampling.DerivesSites();
  if (sampling.origin_deg) options.origin = planning::GeoPoint{(*sampling.origin_deg)[0], (*sampling.origin_deg)[1]};
  const std::vector<std::filesystem::path> files(sampling.buildings.begin(), sampling.buildings.end());
  planning::ImportedMap imported = planning::ImportCityMap(files, sampling.sites, options);
  world.origin = imported.summary.origin;
  world.sites_from_map = options.sites_from_map;
  world.rooftop_sites_from_map = imported.summary.derived_rooftop_sites;
  world.open_area_sites_from_map = imported.summary.derived_open_sites;
  world.map = std::make_shared<const planning::CityMap>(std::move(imported.map));
}

}  // namespace

CampaignWorld BuildCampaignWorld(const MapSampling& sampling) {
  CampaignWorld world;
  if (sampling.imported()) {
    ImportCity(sampling, world);
  } else if (sampling.procedural_seed == 0) {
    world.map = std::make_shared<const planning::CityMap>();
  } else {
    planning::ProceduralCityParams params;
    params.seed = sampling.procedural_seed;
    params.blocks_north = sampling.blocks_north;
    params.blocks_east = sampling.blocks_east;
    world.map = std::make_shared<const planning::CityMap>(planning::MakeProceduralCity(params));
  }
  // The hulls at the margin the simulator's emergency planners use (sim/emergency_planner.cc: default params).
  if (!world.map->sites().empty()) {
    world.obstacles =
        planning::LandingPathPlanner::InflateBuildings(*world.map, planning::LandingPathParams{}.lateral_margin);
  }
  return world;
}

CampaignWorld BuildCampaignWorld(const CampaignConfig& config) {
  CampaignWorld world = BuildCampaignWorld(config.map);
  if (!config.vehicle.empty()) {
    world.vehicle = sim::LoadVehicleFile(config.vehicle);
    if (!config.vehicle_hash.empty() && world.vehicle->content_hash != config.vehicle_hash) {
      throw InputError(config.vehicle, "vehicle_hash",
                       fmt::format("the campaign's {} (the file or a file it names changed since), got {}",
                                   config.vehicle_hash, world.vehicle->content_hash));
    }
  }
  return world;
}

}  // namespace uascma::campaign
