#pragma once
// Importers that turn real map data into a CityMap (include/uascma/planning/city_map.h): building outlines
// and heights from OpenStreetMap (GeoJSON as exported by Overpass, or .osm / .osm.pbf files read with
// libosmium) and landing sites from CSV (scripts/install-deps.sh, "map import"). Data © OpenStreetMap
// contributors (ODbL).
//
// Two steps, so that files of different kinds share one local frame:
//  1. the readers (map_geojson.h, map_osm.h; the landing sites of map_sites_csv.h) collect geodetic records
//     (WGS84 latitude/longitude in degrees, GeoPoint — the only place degrees appear) into a GeoMapData, counting
//     what they skip in its ImportSummary;
//  2. ProjectToCityMap projects everything to the local frame W with PROJ (map_projection.h: the frame and its
//     accuracy, the reason for MapImportOptions::max_distance_from_origin) and builds the CityMap.
// ImportCityMap does both for a list of files.
//
// What is a building. A feature is imported when its geometry is a polygon (GeoJSON Polygon/MultiPolygon; an
// OSM closed way or a type=multipolygon relation) and it carries a `building` tag other than "no". Its height
// comes from the `height` tag in metres ("44.6", "44.6 m" or a JSON number). Everything else is skipped and
// counted by reason in the ImportSummary: not a polygon (points, lines, open ways), not a building, a missing
// height (only when allowed, below), a multipolygon relation whose members are not all in the file.
//
// A missing height (no `height` tag) is resolved by the fall-backs the options allow, in this order, and the source
// of every imported building's height is counted (ImportSummary::height_sources):
//  1. `height_from_levels`: `building:levels` × `metres_per_level` (3 m per storey by default; the CTBUH height
//     calculator's storey heights are 3.1 m residential, 3.9 m office, 3.5 m mixed or unknown, see below);
//  2. `height_from_type`: the typical height of the `building=*` value (BuildingTypeHeight, the table below);
//  3. `default_height`: one height (m) for every building still without one;
//  4. `skip_missing_height`: the building is skipped and counted.
// With none of them, a building without a height is an error — raised after the whole file has been read, so that
// the message counts how many buildings lack a height and names the first (most of OpenStreetMap carries no
// heights: a country extract may hold thousands of buildings and not one `height`).
//
// The building-type table (BuildingTypeHeight). A height = typical storeys × typical floor-to-floor height. The
// floor-to-floor heights are the Council on Tall Buildings and Urban Habitat's "Height Calculator" assumptions
// (CTBUH: office 3.9 m, residential/hotel 3.1 m, function unknown or mixed-use 3.5 m). The storey counts are ours
// (typical of the type as OpenStreetMap's Key:building wiki page describes the values; not in the dissertation):
//   residential 3.1 m: house, detached, semidetached_house, terrace, farm 2; bungalow, cabin, hut,
//     static_caravan, houseboat 1; residential 3; dormitory 4; apartments 5; hotel 6
//   office 3.9 m: retail, supermarket, kiosk, kindergarten 1; industrial, warehouse, manufacture, fire_station,
//     train_station, transportation, chapel 2; commercial, civic, public, school, sports_hall, mosque,
//     synagogue, temple, religious 3; government, university, college, stadium, church 4; office, hospital 5;
//     cathedral 8
//   ancillary 3.1 m: garage, garages, shed, carport, roof, greenhouse, farm_auxiliary, stable, cowshed, service,
//     toilets, container, bunker, ruins 1; barn 2
//   any other value (most often "yes"): 3 storeys × 3.5 m = 10.5 m
//
// Landing sites from the map (`sites_from_map`; dissertation §5.1: "landing sites are represented as coordinates of
// the centroid of the buildings", "building rooftop, playground, parking lots"): for each imported building with a
// flat roof (`roof:shape` absent or "flat"), a rooftop site at the centroid of its outline when the centroid lies on
// that roof (not under a taller overlapping building) and the largest circle about it inside the outline has a
// radius ≥ kMinDerivedSiteRadius; and for each open area of the same files — a polygon tagged leisure = park,
// pitch, playground, garden, common, recreation_ground or dog_park; amenity = parking (not underground or
// multi-storey); landuse = grass, recreation_ground, meadow or village_green — ground sites on a grid of
// kOpenAreaSiteSpacing inside it, each with at least kMinDerivedSiteRadius clear of the area's edge and of every
// building wall, its radius that clearance capped at kMaxOpenSiteRadius. A derived site's risk is the procedural
// city's fit to the Midtown landing-site data (procedural_city.h): risk = 0.698 − 0.192 ln(radius / 1 m), clamped
// to [0, 1] (no noise). The summary counts both kinds (derived_rooftop_sites, derived_open_sites).
// Malformed input — bad JSON or XML, a ring with fewer than 4 positions (3 corners and the closing one) or
// fewer than 3 distinct corners, an unclosed GeoJSON ring, a height that is not a positive number of metres,
// coordinates out of range, a landing-site row that does not parse — throws InputError naming the file, the
// feature (its OSM id and its index) and what was expected.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "uascma/common/bounds.h"
#include "uascma/common/error.h"
#include "uascma/planning/city_map.h"
#include "uascma/planning/map_projection.h"

namespace uascma::planning {

struct MapImportOptions {
  bool height_from_levels = false;       // a building without `height`: building:levels × metres_per_level
  double metres_per_level = 3.0;         // m per storey (estimate; see the header comment)
  bool height_from_type = false;         // then the typical height of its building=* value (BuildingTypeHeight)
  std::optional<double> default_height;  // m: then this height for every building still without one
  bool skip_missing_height = false;      // a building still without a height is skipped and counted, not an error
  // Derive landing sites from the map itself: flat rooftops and open areas (header comment).
  bool sites_from_map = false;
  std::optional<GeoPoint> origin;  // the local frame's origin; default: the centre of the data
  // Refuse data farther than this (m) from the origin: the local frame is a flat projection (map_projection.h).
  double max_distance_from_origin = 50'000.0;
  CityMapOptions map;
  bool IsValid(std::string* error) const;
};

enum class SkipReason { kNotPolygon = 0, kNotBuilding, kMissingHeight, kIncompleteRelation };
inline constexpr int kNumSkipReasons = 4;
// "not_polygon", "not_building", "missing_height", "incomplete_relation".
std::string SkipReasonName(SkipReason reason);

// Where an imported building's height came from (header comment).
enum class HeightSource { kTag = 0, kLevels, kBuildingType, kDefault };
inline constexpr int kNumHeightSources = 4;
// "height_tag", "building_levels", "building_type", "default_height".
std::string HeightSourceName(HeightSource source);

// MapImportOptions::default_height: 1 m (a shed) to 500 m (above the tallest building of the Manhattan data, 1 WTC's
// roof at 417 m); our plausibility bound.
inline constexpr Bounds kDefaultHeightBounds{1.0, 500.0, "m"};

// The height (m) the building-type table gives a `building=*` value (header comment; "yes" and unknown values:
// 10.5 m). `storeys` and `storey_height` (m), if not null, receive the two factors.
double BuildingTypeHeight(std::string_view building_value, int* storeys = nullptr, double* storey_height = nullptr);

// Derived landing sites (header comment). m: the smallest clear radius of a derived site, the procedural city's
// site_radius_min (procedural_city.h); the spacing of open-area sites and their radius cap, the procedural city's
// park_site_spacing and park_site_radius.
inline constexpr double kMinDerivedSiteRadius = 2.0;
inline constexpr double kOpenAreaSiteSpacing = 40.0;
inline constexpr double kMaxOpenSiteRadius = 12.0;
// The landing risk of a derived site of clear radius `radius` (m): 0.698 − 0.192 ln(radius), clamped to [0, 1].
double DerivedSiteRisk(double radius);

// Skipped features are all counted, but only this many of each reason are listed (a city extract has
// hundreds of thousands of tagged nodes).
inline constexpr int kMaxRecordedSkipsPerReason = 1000;

struct SkippedFeature {
  std::string source;   // the file
  std::string feature;  // "features[12] (node/2296577459)", "way/123"
  SkipReason reason = SkipReason::kNotPolygon;
  std::string detail;  // e.g. "geometry Point", "no building tag"
};

struct ImportSummary {
  std::vector<std::string> sources;                     // the files read, in order
  int features = 0;                                     // map features seen (GeoJSON features; OSM objects with tags)
  int buildings = 0;                                    // imported
  int heights_from_levels = 0;                          // of which the height came from building:levels
  std::array<int, kNumHeightSources> height_sources{};  // imported buildings by the source of their height
  int open_areas = 0;                            // open areas read (parks, pitches, surface parking; header comment)
  std::array<int, kNumSkipReasons> skipped{};    // by SkipReason
  std::vector<SkippedFeature> skipped_features;  // the first kMaxRecordedSkipsPerReason of each reason
  int sites = 0;                                 // landing sites imported
  int rooftop_sites = 0;          // of which on the roof of an imported building (set by ProjectToCityMap)
  int derived_rooftop_sites = 0;  // of the sites, derived from flat roofs (sites_from_map)
  int derived_open_sites = 0;     // of the sites, derived from open areas (sites_from_map)
  // Set by ProjectToCityMap:
  GeoPoint origin;                  // the local frame's origin
  bool origin_from_data = true;     // false when it was given
  GeoPoint south_west, north_east;  // latitude/longitude bounds of the data
  Eigen::AlignedBox2d bounds;       // m, the map's horizontal extent in the local frame
  std::string tallest_building;     // id, empty without buildings
  double tallest_height = 0.0;      // m

  int skipped_total() const;
  int skipped_count(SkipReason reason) const { return skipped[static_cast<int>(reason)]; }
  int height_count(HeightSource source) const { return height_sources[static_cast<int>(source)]; }
  // One paragraph for people: counts, skipped by reason, sites, extent, tallest building.
  std::string BriefReport() const;
};

// Geodetic records collected by the readers.
struct GeoBuilding {
  std::string id;                            // "way/248773492", "relation/…"
  std::vector<std::vector<GeoPoint>> rings;  // even-odd interior (map_geometry.h), closing vertex dropped
  double height = 0.0;                       // m
  bool flat_roof = true;                     // roof:shape absent or "flat" (a rooftop landing site may be derived)
};

// An open area of the map files (header comment): a candidate for ground landing sites.
struct GeoOpenArea {
  std::string id;
  std::string kind;                          // "leisure=park", "amenity=parking", …
  std::vector<std::vector<GeoPoint>> rings;  // even-odd interior
};

struct GeoLandingSite {
  std::string id;
  GeoPoint position;
  double altitude = 0.0;  // m above ground
  double risk = 0.0;      // 0 … 1
  double radius = 0.0;    // m
};

struct GeoMapData {
  std::vector<GeoBuilding> buildings;
  std::vector<GeoLandingSite> sites;
  std::vector<GeoOpenArea> open_areas;
  ImportSummary summary;
};

enum class MapFileFormat { kGeoJson, kOsm };
// By extension: .geojson/.json → GeoJSON; .osm, .osm.pbf, .pbf, .osm.gz, .osm.bz2 → OSM. InputError otherwise.
MapFileFormat DetectMapFormat(const std::filesystem::path& path);

// Reads building files: GeoJSON (map_geojson.h) or OSM (map_osm.h) by DetectMapFormat; appends to `data` and
// throws InputError on malformed input.
void ReadBuildings(const std::filesystem::path& path, const MapImportOptions& options, GeoMapData* data);

// Projects the records to the local frame (origin: options.origin or the centre of the data) and builds the
// CityMap; fills the projection and extent fields of `summary` (which may be &data.summary's copy).
CityMap ProjectToCityMap(const GeoMapData& data, const MapImportOptions& options, ImportSummary* summary);

struct ImportedMap {
  CityMap map;
  ImportSummary summary;
};
// An import that failed: the one-line message of the InputError, and what had been read, imported and skipped
// (and why) up to the failure, so that a user sees more than the first problem.
class MapImportError : public InputError {
 public:
  MapImportError(const std::string& message, ImportSummary summary)
      : InputError(message), summary_(std::move(summary)) {}
  const ImportSummary& summary() const { return summary_; }

 private:
  ImportSummary summary_;
};
// Reads every building file and the optional landing-site CSV (empty path: none), then projects them into one
// map. MapImportError (an InputError) on any failure, including when nothing at all was imported.
ImportedMap ImportCityMap(std::span<const std::filesystem::path> building_files, const std::filesystem::path& sites_csv,
                          const MapImportOptions& options);

}  // namespace uascma::planning
