#pragma once
// Helpers shared by the map readers (map_geojson.cc, map_osm.cc, map_sites_csv.cc); not a public interface.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "uascma/planning/map_import.h"

namespace uascma::planning::detail {

// A `building` tag value that makes a feature a building: present and not "no".
bool IsBuildingValue(const std::optional<std::string>& value);

// The height (m) of a building feature from its `height` and `building:levels` tags, as the options say; nullopt
// when the feature is to be skipped (recorded in `summary`). Throws InputError naming source and feature when the
// height is missing (and no fallback is enabled) or is not a positive number of metres.
std::optional<double> ResolveHeight(const std::optional<std::string>& height, const std::optional<std::string>& levels,
                                    const std::string& source, const std::string& feature,
                                    const MapImportOptions& options, ImportSummary* summary);

void RecordSkip(ImportSummary* summary, const std::string& source, const std::string& feature, SkipReason reason,
                std::string detail);

// Throws InputError unless the point is a finite latitude in [−90, 90] and longitude in [−180, 180].
void CheckGeoPoint(const GeoPoint& point, const std::string& source, const std::string& feature);

// Drops a repeated closing vertex and consecutive duplicates; throws InputError naming the feature when fewer than
// 3 distinct corners remain.
std::vector<GeoPoint> CleanRing(const std::vector<GeoPoint>& ring, const std::string& source,
                                const std::string& feature, const std::string& ring_name);

// A number from a tag or CSV field: the whole of `text` (trimmed) must parse.
std::optional<double> ParseNumber(std::string_view text);

std::string_view Trim(std::string_view text);

}  // namespace uascma::planning::detail
