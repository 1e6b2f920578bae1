#pragma once
// The OpenStreetMap building reader (map_osm.cc): .osm XML, .osm.pbf and the other formats libosmium reads, whose
// closed ways and type=multipolygon relations tagged building=* become buildings by the rules of map_import.h.
#include <filesystem>

#include "uascma/planning/map_import.h"

namespace uascma::planning {

// Reads ways and multipolygon relations tagged building=* (libosmium's area assembler builds the polygons), and
// appends them (and the open areas, and the summary) to `data`; InputError on malformed input.
void ReadOsmBuildings(const std::filesystem::path& path, const MapImportOptions& options, GeoMapData* data);

}  // namespace uascma::planning
