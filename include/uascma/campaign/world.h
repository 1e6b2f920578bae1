#pragma once
// The world a campaign's flights fly in, built once per campaign and passed to every run (a model apart from its state:
// model apart from state): the city (the built-in procedural city of the configuration's seed, or the imported
// one), its geodetic origin, and the buildings' hulls inflated for the emergency planners. Immutable and shared
// by every thread; a run's scenario (campaign/sampler.h) holds the same map and hulls, so no flight re-imports,
// re-builds or re-inflates them.
//
// The LandPract database (planning/land_pract.h, §5.3.2.2) is not part of it: it is built for a nominal plan, and
// each run draws its own (sim/emergency_planner.cc builds it when the flight model is made).
#include <memory>
#include <optional>

#include "uascma/campaign/config.h"
#include "uascma/planning/city_map.h"
#include "uascma/planning/landing_detour.h"
#include "uascma/planning/map_projection.h"
#include "uascma/sim/vehicle_file.h"

namespace uascma::campaign {

struct CampaignWorld {
  // The campaign's city: procedural (seed 0: open ground, no buildings and no sites) or imported (an imported map
  // without a sites file supplies its own sites: planning::MapImportOptions::sites_from_map, §5.1).
  std::shared_ptr<const planning::CityMap> map;
  std::optional<planning::GeoPoint> origin;  // an imported map's geodetic origin (its plans export for QGroundControl)
  // Where an imported map's landing sites come from: the sites file, and the map itself (sites_from_map: flat roofs,
  // open areas; planning/map_import.h).
  bool sites_from_map = false;
  int rooftop_sites_from_map = 0;
  int open_area_sites_from_map = 0;
  // Every building's hull grown by the emergency planners' lateral margin (planning::LandingPathParams,
  // LandingPathPlanner::InflateBuildings); null when the map has no landing sites (no emergency planner is made).
  std::shared_ptr<const planning::ObstacleSet> obstacles;
  // The campaign's vehicle file (CampaignConfig::vehicle), read once; null: the dissertation's vehicle.
  std::shared_ptr<const sim::Vehicle> vehicle;
};

// Builds the world of `sampling` (reads the map files of an imported city: InputError naming the file).
CampaignWorld BuildCampaignWorld(const MapSampling& sampling);
// The map's world and the configuration's vehicle: InputError naming the file when its content hash is not the
// configuration's (the file, or a file it names, changed since the campaign was stored).
CampaignWorld BuildCampaignWorld(const CampaignConfig& config);

}  // namespace uascma::campaign
