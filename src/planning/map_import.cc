// The shared part of the map importers: tag and coordinate checks, the projection of the collected records into
// a CityMap, and the import summary.
#include "uascma/planning/map_import.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "map_import_detail.h"
#include "uascma/common/error.h"

namespace uascma::planning {
namespace detail {

std::string_view Trim(std::string_view text) {
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.front()))) text.remove_prefix(1);
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.remove_suffix(1);
  return text;
}

std::optional<double> ParseNumber(std::string_view text) {
  text = Trim(text);
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) {
    return std::nullopt;
  }
  return value;
}

bool IsBuildingValue(const std::optional<std::string>& value) { return value && *value != "no"; }

void RecordSkip(ImportSummary* summary, const std::string& source, const std::string& feature, SkipReason reason,
                std::string detail) {
  const int count = ++summary->skipped[static_cast<int>(reason)];
  if (count <= kMaxRecordedSkipsPerReason) summary->skipped_features.push_back({source, feature, reason, std::move(detail)});
}

std::optional<double> ResolveHeight(const std::optional<std::string>& height, const std::optional<std::string>& levels,
                                    const std::string& source, const std::string& feature,
                                    const MapImportOptions& options, ImportSummary* summary) {
  if (height) {
    // "44.6", "44.6 m" or "44.6m": metres (OSM's default unit for height).
    std::string_view text = Trim(*height);
    if (!text.empty() && text.back() == 'm') text.remove_suffix(1);
    const auto value = ParseNumber(text);
    if (!value || *value <= 0.0) {
      throw InputError(source, feature, fmt::format("a 'height' in metres > 0 (e.g. '12.5' or '12.5 m'), got '{}'",
                                                    *height));
    }
    return *value;
  }
  if (options.height_from_levels && levels) {
    const auto count = ParseNumber(*levels);
    if (!count || *count <= 0.0) {
      throw InputError(source, feature, fmt::format("a 'building:levels' count > 0, got '{}'", *levels));
    }
    ++summary->heights_from_levels;
    return *count * options.metres_per_level;
  }
  if (options.skip_missing_height) {
    RecordSkip(summary, source, feature, SkipReason::kMissingHeight,
               options.height_from_levels ? "no height or building:levels tag" : "no height tag");
    return std::nullopt;
  }
  throw InputError(source, feature,
                   options.height_from_levels
                       ? "a 'height' or 'building:levels' tag (or allow skipping: --skip-missing-height)"
                       : "a 'height' tag in metres (or allow a fallback: --height-from-levels, "
                         "--skip-missing-height)");
}

void CheckGeoPoint(const GeoPoint& point, const std::string& source, const std::string& feature) {
  if (!(point.lat_deg >= -90.0 && point.lat_deg <= 90.0 && point.lon_deg >= -180.0 && point.lon_deg <= 180.0)) {
    throw InputError(source, feature,
                     fmt::format("latitude in [-90, 90] and longitude in [-180, 180] degrees, got lat {} lon {}",
                                 point.lat_deg, point.lon_deg));
  }
}

std::vector<GeoPoint> CleanRing(const std::vector<GeoPoint>& ring, const std::string& source,
                                const std::string& feature, const std::string& ring_name) {
  auto same = [](const GeoPoint& a, const GeoPoint& b) { return a.lat_deg == b.lat_deg && a.lon_deg == b.lon_deg; };
  std::vector<GeoPoint> clean;
  clean.reserve(ring.size());
  for (const GeoPoint& p : ring) {
    if (clean.empty() || !same(clean.back(), p)) clean.push_back(p);
  }
  while (clean.size() > 1 && same(clean.front(), clean.back())) clean.pop_back();
  if (clean.size() < 3) {
    throw InputError(source, feature,
                     fmt::format("{} with at least 3 distinct corners, got {}", ring_name, clean.size()));
  }
  return clean;
}

}  // namespace detail

bool MapImportOptions::IsValid(std::string* error) const {
  if (!(std::isfinite(metres_per_level) && metres_per_level > 0.0)) {
    if (error) *error = fmt::format("metres_per_level: expected a positive number, got {}", metres_per_level);
    return false;
  }
  if (!(max_distance_from_origin > 0.0)) {
    if (error) *error = fmt::format("max_distance_from_origin: expected a positive number, got {}",
                                    max_distance_from_origin);
    return false;
  }
  return map.IsValid(error);
}

std::string SkipReasonName(SkipReason reason) {
  switch (reason) {
    case SkipReason::kNotPolygon: return "not_polygon";
    case SkipReason::kNotBuilding: return "not_building";
    case SkipReason::kMissingHeight: return "missing_height";
    case SkipReason::kIncompleteRelation: return "incomplete_relation";
  }
  return "unknown";
}

int ImportSummary::skipped_total() const {
  int total = 0;
  for (int count : skipped) total += count;
  return total;
}

std::string ImportSummary::BriefReport() const {
  std::string sources_text;
  for (const auto& s : sources) sources_text += (sources_text.empty() ? "" : ", ") + s;
  std::string report = fmt::format("sources: {}\n", sources_text.empty() ? "(none)" : sources_text);
  report += fmt::format("features: {} read; {} buildings imported", features, buildings);
  if (heights_from_levels > 0) report += fmt::format(" ({} heights from building:levels)", heights_from_levels);
  report += fmt::format("; {} skipped ({} not a polygon, {} not a building, {} missing height, {} incomplete "
                        "relation)\n",
                        skipped_total(), skipped_count(SkipReason::kNotPolygon),
                        skipped_count(SkipReason::kNotBuilding), skipped_count(SkipReason::kMissingHeight),
                        skipped_count(SkipReason::kIncompleteRelation));
  report += fmt::format("landing sites: {} ({} on the roof of an imported building)\n", sites, rooftop_sites);
  report += fmt::format("origin: lat {:.7f} lon {:.7f} ({})\n", origin.lat_deg, origin.lon_deg,
                        origin_from_data ? "centre of the data" : "given");
  if (!bounds.isEmpty()) {
    report += fmt::format("extent: x {:.1f} .. {:.1f} m (north), y {:.1f} .. {:.1f} m (east); lat {:.6f} .. {:.6f}, "
                          "lon {:.6f} .. {:.6f}\n",
                          bounds.min().x(), bounds.max().x(), bounds.min().y(), bounds.max().y(), south_west.lat_deg,
                          north_east.lat_deg, south_west.lon_deg, north_east.lon_deg);
  }
  if (!tallest_building.empty()) {
    report += fmt::format("tallest building: {}, {:.1f} m\n", tallest_building, tallest_height);
  }
  return report;
}

MapFileFormat DetectMapFormat(const std::filesystem::path& path) {
  std::string name = path.filename().string();
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
  auto ends_with = [&](std::string_view suffix) { return name.ends_with(suffix); };
  if (ends_with(".geojson") || ends_with(".json")) return MapFileFormat::kGeoJson;
  if (ends_with(".osm") || ends_with(".osm.pbf") || ends_with(".pbf") || ends_with(".osm.gz") ||
      ends_with(".osm.bz2")) {
    return MapFileFormat::kOsm;
  }
  throw InputError(path.string(), "format",
                   "a map file ending in .geojson, .json, .osm, .osm.pbf, .pbf, .osm.gz or .osm.bz2");
}

void ReadBuildings(const std::filesystem::path& path, const MapImportOptions& options, GeoMapData* data) {
  if (DetectMapFormat(path) == MapFileFormat::kGeoJson) {
    ReadGeoJsonBuildings(path, options, data);
  } else {
    ReadOsmBuildings(path, options, data);
  }
}

CityMap ProjectToCityMap(const GeoMapData& data, const MapImportOptions& options, ImportSummary* summary) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("map import options", "MapImportOptions", error);
  std::string sources;
  for (const auto& s : summary->sources) sources += (sources.empty() ? "" : " + ") + s;
  if (sources.empty()) sources = "map";
  if (data.buildings.empty() && data.sites.empty()) {
    throw InputError(sources, "features", "at least one building or landing site to import");
  }

  // The data's latitude/longitude bounds; their centre is the default origin.
  GeoPoint south_west{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  GeoPoint north_east{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  auto extend = [&](const GeoPoint& p) {
    south_west.lat_deg = std::min(south_west.lat_deg, p.lat_deg);
    south_west.lon_deg = std::min(south_west.lon_deg, p.lon_deg);
    north_east.lat_deg = std::max(north_east.lat_deg, p.lat_deg);
    north_east.lon_deg = std::max(north_east.lon_deg, p.lon_deg);
  };
  for (const auto& b : data.buildings) {
    for (const auto& ring : b.rings) {
      for (const auto& p : ring) extend(p);
    }
  }
  for (const auto& s : data.sites) extend(s.position);
  const GeoPoint origin = options.origin.value_or(GeoPoint{0.5 * (south_west.lat_deg + north_east.lat_deg),
                                                           0.5 * (south_west.lon_deg + north_east.lon_deg)});
  const LocalProjection projection(origin);

  auto project = [&](const GeoPoint& p, const std::string& what) {
    const Eigen::Vector2d p_NE = projection.ToLocal(p);
    if (!(p_NE.norm() <= options.max_distance_from_origin)) {
      throw InputError(sources, what,
                       fmt::format("a point within {:.0f} km of the map origin (lat {:.6f}, lon {:.6f}; a local flat "
                                   "frame), got one {:.0f} km away",
                                   options.max_distance_from_origin / 1000.0, origin.lat_deg, origin.lon_deg,
                                   p_NE.norm() / 1000.0));
    }
    return p_NE;
  };
  std::vector<Building> buildings;
  buildings.reserve(data.buildings.size());
  for (const auto& geo : data.buildings) {
    Building b;
    b.id = geo.id;
    b.height = geo.height;
    for (const auto& geo_ring : geo.rings) {
      Ring ring;
      ring.reserve(geo_ring.size());
      for (const auto& p : geo_ring) ring.push_back(project(p, "building " + geo.id));
      b.rings.push_back(std::move(ring));
    }
    buildings.push_back(std::move(b));
  }
  std::vector<LandingSite> sites;
  sites.reserve(data.sites.size());
  for (const auto& geo : data.sites) {
    LandingSite s;
    s.id = geo.id;
    const Eigen::Vector2d p_NE = project(geo.position, "landing site " + geo.id);
    s.p_W = Eigen::Vector3d(p_NE.x(), p_NE.y(), -geo.altitude);
    s.risk = geo.risk;
    s.radius = geo.radius;
    sites.push_back(std::move(s));
  }

  CityMap map;
  try {
    map = CityMap(std::move(buildings), std::move(sites), options.map);
  } catch (const InputError& e) {
    throw InputError(sources + ": " + e.what());  // the map's message names the building or site
  }

  summary->origin = origin;
  summary->origin_from_data = !options.origin.has_value();
  summary->south_west = south_west;
  summary->north_east = north_east;
  summary->bounds = map.bounds();
  summary->buildings = static_cast<int>(map.buildings().size());
  summary->sites = static_cast<int>(map.sites().size());
  summary->rooftop_sites = static_cast<int>(
      std::count_if(map.sites().begin(), map.sites().end(), [](const LandingSite& s) { return s.on_rooftop(); }));
  if (map.tallest_building() != kNoBuilding) {
    summary->tallest_building = map.building(map.tallest_building()).id;
    summary->tallest_height = map.max_building_height();
  }
  return map;
}

ImportedMap ImportCityMap(std::span<const std::filesystem::path> building_files,
                          const std::filesystem::path& sites_csv, const MapImportOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("map import options", "MapImportOptions", error);
  GeoMapData data;
  for (const auto& path : building_files) ReadBuildings(path, options, &data);
  if (!sites_csv.empty()) ReadLandingSitesCsv(sites_csv, options, &data);
  ImportedMap imported;
  imported.summary = data.summary;
  imported.map = ProjectToCityMap(data, options, &imported.summary);
  return imported;
}

}  // namespace uascma::planning
