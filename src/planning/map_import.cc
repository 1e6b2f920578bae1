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
#include "uascma/planning/map_geojson.h"
#include "uascma/planning/map_geometry.h"
#include "uascma/planning/map_osm.h"
#include "uascma/planning/map_sites_csv.h"

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
  if (count <= kMaxRecordedSkipsPerReason)
    summary->skipped_features.push_back({source, feature, reason, std::move(detail)});
}

namespace {

double ParseHeightTag(const std::string& height, const std::string& source, const std::string& feature) {
  // "44.6", "44.6 m" or "44.6m": metres (OSM's default unit for height).
  std::string_view text = Trim(height);
  if (!text.empty() && text.back() == 'm') text.remove_suffix(1);
  const auto value = ParseNumber(text);
  if (!value || *value <= 0.0) {
    throw InputError(source, feature,
                     fmt::format("a 'height' in metres > 0 (e.g. '12.5' or '12.5 m'), got '{}'", height));
  }
  return *value;
}

std::string FallbackOptionsText() {
  return "--height-from-levels, --height-from-type, --default-height H or --skip-missing-height (campaign and "
         "scenario map keys: height_from_levels, skip_missing_height)";
}

}  // namespace

std::optional<double> ResolveHeight(const BuildingTags& tags, const std::string& source, const std::string& feature,
                                    const MapImportOptions& options, ImportSummary* summary) {
  auto count = [&](HeightSource source_kind, double value) {
    ++summary->height_sources[static_cast<int>(source_kind)];
    return std::optional<double>(value);
  };
  if (tags.height) return count(HeightSource::kTag, ParseHeightTag(*tags.height, source, feature));
  if (options.height_from_levels && tags.levels) {
    const auto levels = ParseNumber(*tags.levels);
    if (!levels || *levels <= 0.0) {
      throw InputError(source, feature, fmt::format("a 'building:levels' count > 0, got '{}'", *tags.levels));
    }
    ++summary->heights_from_levels;
    return count(HeightSource::kLevels, *levels * options.metres_per_level);
  }
  if (options.height_from_type) {
    return count(HeightSource::kBuildingType, BuildingTypeHeight(tags.building.value_or("yes")));
  }
  if (options.default_height) return count(HeightSource::kDefault, *options.default_height);
  RecordSkip(summary, source, feature, SkipReason::kMissingHeight,
             options.height_from_levels ? "no height or building:levels tag" : "no height tag");
  return std::nullopt;
}

void RequireHeightsResolved(int missing_before, const std::string& source, const MapImportOptions& options,
                            const ImportSummary& summary) {
  const int missing = summary.skipped_count(SkipReason::kMissingHeight) - missing_before;
  if (options.skip_missing_height || missing == 0) return;
  // The first building of this file without a height (recorded: the first kMaxRecordedSkipsPerReason are kept).
  std::string first = "buildings";
  int seen = 0;
  for (const SkippedFeature& f : summary.skipped_features) {
    if (f.reason != SkipReason::kMissingHeight) continue;
    if (++seen > missing_before && f.source == source) {
      first = f.feature;
      break;
    }
  }
  const int read = summary.buildings + missing;
  throw InputError(
      source, first,
      fmt::format("{} (or a fall-back: {}); {} of the {} buildings read here have no height{}",
                  options.height_from_levels ? "a 'height' or 'building:levels' tag" : "a 'height' tag in metres",
                  FallbackOptionsText(), missing, read, summary.buildings > 0 ? "" : " (none has one)"));
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
    if (error)
      *error = fmt::format("max_distance_from_origin: expected a positive number, got {}", max_distance_from_origin);
    return false;
  }
  if (default_height && !kDefaultHeightBounds.Contains(*default_height)) {
    if (error) *error = "default_height: expected " + OutsideBoundsMessage(kDefaultHeightBounds, *default_height);
    return false;
  }
  return map.IsValid(error);
}

std::string SkipReasonName(SkipReason reason) {
  switch (reason) {
    case SkipReason::kNotPolygon:
      return "not_polygon";
    case SkipReason::kNotBuilding:
      return "not_building";
    case SkipReason::kMissingHeight:
      return "missing_height";
    case SkipReason::kIncompleteRelation:
      return "incomplete_relation";
  }
  return "unknown";
}

std::string HeightSourceName(HeightSource source) {
  switch (source) {
    case HeightSource::kTag:
      return "height_tag";
    case HeightSource::kLevels:
      return "building_levels";
    case HeightSource::kBuildingType:
      return "building_type";
    case HeightSource::kDefault:
      return "default_height";
  }
  return "unknown";
}

double BuildingTypeHeight(std::string_view building_value, int* storeys, double* storey_height) {
  // Floor-to-floor heights of the CTBUH Height Calculator (map_import.h): residential/hotel 3.1 m, office 3.9 m,
  // function unknown or mixed use 3.5 m. The storey counts are ours (map_import.h).
  constexpr double kResidential = 3.1, kOffice = 3.9, kMixed = 3.5;
  struct Row {
    std::string_view value;
    int storeys;
    double storey_height;
  };
  static constexpr Row kTable[] = {
      {"house", 2, kResidential},
      {"detached", 2, kResidential},
      {"semidetached_house", 2, kResidential},
      {"terrace", 2, kResidential},
      {"farm", 2, kResidential},
      {"bungalow", 1, kResidential},
      {"cabin", 1, kResidential},
      {"hut", 1, kResidential},
      {"static_caravan", 1, kResidential},
      {"houseboat", 1, kResidential},
      {"residential", 3, kResidential},
      {"dormitory", 4, kResidential},
      {"apartments", 5, kResidential},
      {"hotel", 6, kResidential},
      {"retail", 1, kOffice},
      {"supermarket", 1, kOffice},
      {"kiosk", 1, kOffice},
      {"kindergarten", 1, kOffice},
      {"industrial", 2, kOffice},
      {"warehouse", 2, kOffice},
      {"manufacture", 2, kOffice},
      {"fire_station", 2, kOffice},
      {"train_station", 2, kOffice},
      {"transportation", 2, kOffice},
      {"chapel", 2, kOffice},
      {"commercial", 3, kOffice},
      {"civic", 3, kOffice},
      {"public", 3, kOffice},
      {"school", 3, kOffice},
      {"sports_hall", 3, kOffice},
      {"mosque", 3, kOffice},
      {"synagogue", 3, kOffice},
      {"temple", 3, kOffice},
      {"religious", 3, kOffice},
      {"government", 4, kOffice},
      {"university", 4, kOffice},
      {"college", 4, kOffice},
      {"stadium", 4, kOffice},
      {"church", 4, kOffice},
      {"office", 5, kOffice},
      {"hospital", 5, kOffice},
      {"cathedral", 8, kOffice},
      {"garage", 1, kResidential},
      {"garages", 1, kResidential},
      {"shed", 1, kResidential},
      {"carport", 1, kResidential},
      {"roof", 1, kResidential},
      {"greenhouse", 1, kResidential},
      {"farm_auxiliary", 1, kResidential},
      {"stable", 1, kResidential},
      {"cowshed", 1, kResidential},
      {"service", 1, kResidential},
      {"toilets", 1, kResidential},
      {"container", 1, kResidential},
      {"bunker", 1, kResidential},
      {"ruins", 1, kResidential},
      {"barn", 2, kResidential},
  };
  Row row{building_value, 3, kMixed};  // "yes" and every other value
  for (const Row& r : kTable) {
    if (r.value == building_value) row = r;
  }
  if (storeys) *storeys = row.storeys;
  if (storey_height) *storey_height = row.storey_height;
  return row.storeys * row.storey_height;
}

double DerivedSiteRisk(double radius) {
  // procedural_city.h's least-squares fit of the Midtown landing-site CSV, without its noise term.
  return std::clamp(0.698 - 0.192 * std::log(radius), 0.0, 1.0);
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
  if (buildings > 0) {
    report += fmt::format(
        " (heights: {} from the height tag, {} from building:levels, {} from the building type, "
        "{} default)",
        height_count(HeightSource::kTag), height_count(HeightSource::kLevels),
        height_count(HeightSource::kBuildingType), height_count(HeightSource::kDefault));
  }
  report += fmt::format(
      "; {} skipped ({} not a polygon, {} not a building, {} missing height, {} incomplete "
      "relation)\n",
      skipped_total(), skipped_count(SkipReason::kNotPolygon), skipped_count(SkipReason::kNotBuilding),
      skipped_count(SkipReason::kMissingHeight), skipped_count(SkipReason::kIncompleteRelation));
  report += fmt::format("landing sites: {} ({} on the roof of an imported building", sites, rooftop_sites);
  if (derived_rooftop_sites + derived_open_sites > 0) {
    report += fmt::format("; derived from the map: {} flat roofs, {} in {} open areas", derived_rooftop_sites,
                          derived_open_sites, open_areas);
  }
  report += ")\n";
  if (!bounds.isEmpty()) {  // set with the projection (ProjectToCityMap)
    report += fmt::format("origin: lat {:.7f} lon {:.7f} ({})\n", origin.lat_deg, origin.lon_deg,
                          origin_from_data ? "centre of the data" : "given");
  }
  if (!bounds.isEmpty()) {
    report += fmt::format(
        "extent: x {:.1f} .. {:.1f} m (north), y {:.1f} .. {:.1f} m (east); lat {:.6f} .. {:.6f}, "
        "lon {:.6f} .. {:.6f}\n",
        bounds.min().x(), bounds.max().x(), bounds.min().y(), bounds.max().y(), south_west.lat_deg, north_east.lat_deg,
        south_west.lon_deg, north_east.lon_deg);
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

namespace {

// The centroid of a ring (the shoelace formula's area-weighted mean of its triangles); its vertex mean when the
// ring has no area.
Eigen::Vector2d RingCentroid(const Ring& ring) {
  double twice_area = 0.0;
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const Eigen::Vector2d& a = ring[i];
    const Eigen::Vector2d& b = ring[(i + 1) % ring.size()];
    const double cross = a.x() * b.y() - b.x() * a.y();
    twice_area += cross;
    sum += cross * (a + b);
  }
  if (std::abs(twice_area) < 1e-9) {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& p : ring) mean += p;
    return mean / static_cast<double>(ring.size());
  }
  return sum / (3.0 * twice_area);
}

double DistanceToEdges(std::span<const Edge2> edges, const Eigen::Vector2d& p_NE) {
  double distance = std::numeric_limits<double>::infinity();
  for (const Edge2& e : edges) distance = std::min(distance, PointSegmentDistance(p_NE, e.a_NE, e.b_NE));
  return distance;
}

// m: the distance from p_NE to the nearest building wall within `reach` (reach when none is nearer).
double DistanceToBuildings(const CityMap& map, const Eigen::Vector2d& p_NE, double reach) {
  const Eigen::AlignedBox2d box(p_NE - Eigen::Vector2d::Constant(reach), p_NE + Eigen::Vector2d::Constant(reach));
  double distance = reach;
  for (int k : map.BuildingsInBox(box)) distance = std::min(distance, DistanceToEdges(map.edges(k), p_NE));
  return distance;
}

// The landing sites the map itself supplies (map_import.h, "Landing sites from the map"): flat-roof centroids and
// grids over open areas. `flat_roof[k]` for buildings()[k]; `areas` projected.
std::vector<LandingSite> DeriveSites(const CityMap& map, const std::vector<bool>& flat_roof,
                                     const std::vector<std::pair<std::string, std::vector<Ring>>>& areas,
                                     const CityMapOptions& map_options, ImportSummary* summary) {
  std::vector<LandingSite> sites;
  for (int k = 0; k < static_cast<int>(map.buildings().size()); ++k) {
    const Building& building = map.building(k);
    if (!flat_roof[k] || building.rings.empty()) continue;
    const Eigen::Vector2d centroid = RingCentroid(building.rings.front());
    // On this roof: inside the outline and not under a taller overlapping building.
    if (!OutlineContains(map.edges(k), centroid)) continue;
    if (std::abs(map.SurfaceAltitudeAt(centroid) - building.height) > map_options.roof_match_tolerance) continue;
    const double radius = DistanceToEdges(map.edges(k), centroid);
    if (!(radius >= kMinDerivedSiteRadius)) continue;
    LandingSite site;
    site.id = "roof of " + building.id;
    site.p_W = Eigen::Vector3d(centroid.x(), centroid.y(), -building.height);
    site.radius = radius;
    site.risk = DerivedSiteRisk(radius);
    sites.push_back(std::move(site));
    ++summary->derived_rooftop_sites;
  }
  for (const auto& [id, rings] : areas) {
    const std::vector<Edge2> edges = EdgesOfRings(rings);
    Eigen::AlignedBox2d box;
    for (const Ring& ring : rings) {
      for (const auto& p : ring) box.extend(p);
    }
    // A grid of kOpenAreaSiteSpacing centred on the area's box (its centre always a candidate).
    const Eigen::Vector2d centre = box.center();
    const Eigen::Vector2d half = 0.5 * box.sizes();
    const int nx = static_cast<int>(std::floor(half.x() / kOpenAreaSiteSpacing));
    const int ny = static_cast<int>(std::floor(half.y() / kOpenAreaSiteSpacing));
    int index = 0;
    for (int i = -nx; i <= nx; ++i) {
      for (int j = -ny; j <= ny; ++j) {
        const Eigen::Vector2d p = centre + kOpenAreaSiteSpacing * Eigen::Vector2d(i, j);
        if (!OutlineContains(edges, p) || map.SurfaceAltitudeAt(p) > 0.0) continue;
        const double to_edge = std::min(DistanceToEdges(edges, p), kMaxOpenSiteRadius);
        const double radius = std::min(to_edge, DistanceToBuildings(map, p, kMaxOpenSiteRadius));
        if (!(radius >= kMinDerivedSiteRadius)) continue;
        LandingSite site;
        site.id = fmt::format("{} {}", id, index++);
        site.p_W = Eigen::Vector3d(p.x(), p.y(), 0.0);
        site.radius = radius;
        site.risk = DerivedSiteRisk(radius);
        sites.push_back(std::move(site));
        ++summary->derived_open_sites;
      }
    }
  }
  return sites;
}

// "a.osm + b.geojson": the sources an import read, for messages ("map" when none is named).
std::string SourcesName(const ImportSummary& summary) {
  std::string sources;
  for (const auto& s : summary.sources) sources += (sources.empty() ? "" : " + ") + s;
  if (sources.empty()) sources = "map";
  return sources;
}

void RequireFeatures(const GeoMapData& data, const ImportSummary& summary, const std::string& sources) {
  if (data.buildings.empty() && data.sites.empty()) {
    throw InputError(
        sources, "features",
        fmt::format("at least one building or landing site to import; read {} features, imported {} "
                    "buildings, skipped {} ({} not a polygon, {} not a building, {} missing height, {} "
                    "incomplete relation)",
                    summary.features, summary.buildings, summary.skipped_total(),
                    summary.skipped_count(SkipReason::kNotPolygon), summary.skipped_count(SkipReason::kNotBuilding),
                    summary.skipped_count(SkipReason::kMissingHeight),
                    summary.skipped_count(SkipReason::kIncompleteRelation)));
  }
}

// The data's latitude/longitude bounds (the open areas' too when sites are derived from them).
struct GeoBounds {
  GeoPoint south_west{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  GeoPoint north_east{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  void Extend(const GeoPoint& p) {
    south_west.lat_deg = std::min(south_west.lat_deg, p.lat_deg);
    south_west.lon_deg = std::min(south_west.lon_deg, p.lon_deg);
    north_east.lat_deg = std::max(north_east.lat_deg, p.lat_deg);
    north_east.lon_deg = std::max(north_east.lon_deg, p.lon_deg);
  }
};

GeoBounds DataBounds(const GeoMapData& data, bool with_open_areas) {
  GeoBounds bounds;
  for (const auto& b : data.buildings) {
    for (const auto& ring : b.rings) {
      for (const auto& p : ring) bounds.Extend(p);
    }
  }
  for (const auto& s : data.sites) bounds.Extend(s.position);
  if (with_open_areas) {
    for (const auto& a : data.open_areas) {
      for (const auto& ring : a.rings) {
        for (const auto& p : ring) bounds.Extend(p);
      }
    }
  }
  return bounds;
}

// Latitude/longitude to the local frame, refusing a point farther than max_distance_from_origin.
struct PointProjector {
  const LocalProjection& projection;
  const GeoPoint& origin;
  double max_distance_from_origin;
  const std::string& sources;

  Eigen::Vector2d operator()(const GeoPoint& p, const std::string& what) const {
    const Eigen::Vector2d p_NE = projection.ToLocal(p);
    if (!(p_NE.norm() <= max_distance_from_origin)) {
      throw InputError(
          sources, what,
          fmt::format("a point within {:.0f} km of the map origin (lat {:.6f}, lon {:.6f}; a local flat "
                      "frame), got one {:.0f} km away",
                      max_distance_from_origin / 1000.0, origin.lat_deg, origin.lon_deg, p_NE.norm() / 1000.0));
    }
    return p_NE;
  }
};

std::vector<Building> ProjectBuildings(const GeoMapData& data, const PointProjector& project) {
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
  return buildings;
}

std::vector<LandingSite> ProjectSites(const GeoMapData& data, const PointProjector& project) {
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
  return sites;
}

// The sites derived from the map (flat roofs, open areas: DeriveSites) for the projected buildings.
std::vector<LandingSite> DeriveProjectedSites(const GeoMapData& data, const std::vector<Building>& buildings,
                                              const PointProjector& project, const MapImportOptions& options,
                                              ImportSummary* summary) {
  std::vector<bool> flat_roof;
  for (const auto& geo : data.buildings) flat_roof.push_back(geo.flat_roof);
  std::vector<std::pair<std::string, std::vector<Ring>>> areas;
  for (const auto& geo : data.open_areas) {
    std::vector<Ring> rings;
    for (const auto& geo_ring : geo.rings) {
      Ring ring;
      for (const auto& p : geo_ring) ring.push_back(project(p, "open area " + geo.id));
      rings.push_back(std::move(ring));
    }
    areas.emplace_back(geo.kind + " " + geo.id, std::move(rings));
  }
  const CityMap buildings_only(buildings, {}, options.map);
  return DeriveSites(buildings_only, flat_roof, areas, options.map, summary);
}

void SummariseMap(const CityMap& map, ImportSummary* summary) {
  summary->bounds = map.bounds();
  summary->buildings = static_cast<int>(map.buildings().size());
  summary->sites = static_cast<int>(map.sites().size());
  summary->rooftop_sites = static_cast<int>(
      std::count_if(map.sites().begin(), map.sites().end(), [](const LandingSite& s) { return s.on_rooftop(); }));
  if (map.tallest_building() != kNoBuilding) {
    summary->tallest_building = map.building(map.tallest_building()).id;
    summary->tallest_height = map.max_building_height();
  }
}

}  // namespace

CityMap ProjectToCityMap(const GeoMapData& data, const MapImportOptions& options, ImportSummary* summary) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("map import options", "MapImportOptions", error);
  const std::string sources = SourcesName(*summary);
  RequireFeatures(data, *summary, sources);

  // The data's bounds; their centre is the default origin.
  const GeoBounds bounds = DataBounds(data, options.sites_from_map);
  const GeoPoint origin =
      options.origin.value_or(GeoPoint{0.5 * (bounds.south_west.lat_deg + bounds.north_east.lat_deg),
                                       0.5 * (bounds.south_west.lon_deg + bounds.north_east.lon_deg)});
  const LocalProjection projection(origin);
  const PointProjector project{projection, origin, options.max_distance_from_origin, sources};
  std::vector<Building> buildings = ProjectBuildings(data, project);
  std::vector<LandingSite> sites = ProjectSites(data, project);

  CityMap map;
  try {
    if (options.sites_from_map) {
      std::vector<LandingSite> derived = DeriveProjectedSites(data, buildings, project, options, summary);
      sites.insert(sites.end(), std::make_move_iterator(derived.begin()), std::make_move_iterator(derived.end()));
    }
    map = CityMap(std::move(buildings), std::move(sites), options.map);
  } catch (const InputError& e) {
    throw InputError(sources + ": " + e.what());  // the map's message names the building or site
  }

  summary->origin = origin;
  summary->origin_from_data = !options.origin.has_value();
  summary->south_west = bounds.south_west;
  summary->north_east = bounds.north_east;
  SummariseMap(map, summary);
  return map;
}

ImportedMap ImportCityMap(std::span<const std::filesystem::path> building_files, const std::filesystem::path& sites_csv,
                          const MapImportOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("map import options", "MapImportOptions", error);
  GeoMapData data;
  ImportedMap imported;
  try {
    for (const auto& path : building_files) ReadBuildings(path, options, &data);
    if (!sites_csv.empty()) ReadLandingSitesCsv(sites_csv, options, &data);
    imported.summary = data.summary;
    imported.map = ProjectToCityMap(data, options, &imported.summary);
  } catch (const MapImportError&) {
    throw;
  } catch (const InputError& e) {
    throw MapImportError(e.what(), data.summary);
  }
  return imported;
}

}  // namespace uascma::planning
