#pragma once
// The landing-site reader (map_sites_csv.cc) of the map importer (map_import.h).
//
// Landing-site CSV (RFC 4180, common/csv.h: quoted fields may hold commas, doubled quotes and line breaks):
// a header row, then one site per row. Columns are found by name (any order, extra columns
// ignored; names are trimmed and compared case-insensitively), each with accepted aliases:
//   id      osm_id | id | site_id
//   lat     lat | gps.lat | latitude          (degrees, WGS84)
//   lon     lon | gps.lon | lng | longitude   (degrees, WGS84)
//   alt     alt | gps.alt | altitude          (m above ground: the roof height for a rooftop site, 0 on the ground)
//   risk    risk | landing_site_risk          (0 … 1)
//   radius  radius                            (m, the clear touchdown radius)
// so both `osm_id, lat, lon, alt, risk, radius` and the midtown file's `osm_id, gps.lat, gps.lon, gps.alt,
// landing_site_risk, radius` are read.
#include <filesystem>
#include <string>
#include <string_view>

#include "uascma/planning/map_import.h"

namespace uascma::planning {

// The readers append the sites (and the summary) to `data` and throw InputError on a row that does not parse.
void ParseLandingSitesCsv(std::string_view text, const std::string& source, const MapImportOptions& options,
                          GeoMapData* data);
void ReadLandingSitesCsv(const std::filesystem::path& path, const MapImportOptions& options, GeoMapData* data);

}  // namespace uascma::planning
