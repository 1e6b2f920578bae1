#pragma once
// Helpers shared by the map readers (map_geojson.cc, map_osm.cc, map_sites_csv.cc); not a public interface.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "uascma/planning/map_import.h"
#include "uascma/planning/map_projection.h"

namespace uascma::planning::detail {

// A `building` tag value that makes a feature a building: present and not "no".
bool IsBuildingValue(const std::optional<std::string>& value);

// The tags of a building feature that its height and roof come from.
struct BuildingTags {
  std::optional<std::string> building;    // the building=* value
  std::optional<std::string> height;      // m
  std::optional<std::string> levels;      // building:levels
  std::optional<std::string> roof_shape;  // roof:shape
};

// The height (m) of a building feature by the fall-backs of the options (map_import.h), counted by source in
// `summary`; nullopt when it has none: then it is recorded as skipped (kMissingHeight), and
// RequireHeightsResolved decides at the end of the file whether that is an error. Throws InputError naming source
// and feature when a height or level tag is not a positive number.
std::optional<double> ResolveHeight(const BuildingTags& tags, const std::string& source, const std::string& feature,
                                    const MapImportOptions& options, ImportSummary* summary);
// Called by a reader after its file: unless skip_missing_height, throws InputError naming the first building of
// this file without a height, with how many lacked one and the options that would resolve them. `missing_before`:
// summary->skipped_count(kMissingHeight) before the file.
void RequireHeightsResolved(int missing_before, const std::string& source, const MapImportOptions& options,
                            const ImportSummary& summary);

// "leisure=park", "amenity=parking", …: the kind of open area the tags make (map_import.h), nullopt for none.
// `tag` looks a key up.
template <typename TagLookup>
std::optional<std::string> OpenAreaKind(TagLookup&& tag);

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

template <typename TagLookup>
std::optional<std::string> OpenAreaKind(TagLookup&& tag) {
  static constexpr const char* kLeisure[] = {"park",    "pitch", "playground", "garden", "common", "recreation_ground",
                                             "dog_park"};
  static constexpr const char* kLanduse[] = {"grass", "recreation_ground", "meadow", "village_green"};
  if (const std::optional<std::string> leisure = tag("leisure")) {
    for (const char* value : kLeisure) {
      if (*leisure == value) return "leisure=" + *leisure;
    }
  }
  if (const std::optional<std::string> amenity = tag("amenity"); amenity && *amenity == "parking") {
    const std::optional<std::string> parking = tag("parking");
    if (!parking || (*parking != "underground" && *parking != "multi-storey")) return std::string("amenity=parking");
  }
  if (const std::optional<std::string> landuse = tag("landuse")) {
    for (const char* value : kLanduse) {
      if (*landuse == value) return "landuse=" + *landuse;
    }
  }
  return std::nullopt;
}

}  // namespace uascma::planning::detail
