#pragma once
// The GeoJSON building reader (map_geojson.cc): an RFC 7946 FeatureCollection as Overpass exports it, whose Polygon
// and MultiPolygon features tagged building=* become buildings by the rules of map_import.h (what is a building,
// its height and its fall-backs, the open areas of `sites_from_map`, malformed input).
#include <filesystem>
#include <string>
#include <string_view>

#include "uascma/planning/map_import.h"

namespace uascma::planning {

// The readers append to `data` (buildings and open areas, and the summary) and throw InputError on malformed input.
void ParseGeoJsonBuildings(std::string_view text, const std::string& source, const MapImportOptions& options,
                           GeoMapData* data);
void ReadGeoJsonBuildings(const std::filesystem::path& path, const MapImportOptions& options, GeoMapData* data);

}  // namespace uascma::planning
