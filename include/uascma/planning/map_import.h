#pragma once
// Importers that turn real map data into a CityMap (include/uascma/planning/city_map.h): building outlines
// and heights from OpenStreetMap (GeoJSON as exported by Overpass, or .osm / .osm.pbf files read with
// libosmium) and landing sites from CSV (shared/spec/dependencies.md, "map import"). Data © OpenStreetMap
// contributors (ODbL).
//
// Two steps, so that files of different kinds share one local frame:
//  1. the readers collect geodetic records (WGS84 latitude/longitude in degrees — the only place degrees
//     appear) into a GeoMapData, counting what they skip in its ImportSummary;
//  2. ProjectToCityMap projects everything to the local frame W with PROJ and builds the CityMap.
// ImportCityMap does both for a list of files.
//
// Projection. The local frame is a transverse Mercator projection of the WGS84 ellipsoid centred on the
// origin (PROJ "+proj=tmerc +lat_0=φ0 +lon_0=λ0 +k_0=1 +ellps=WGS84"): easting and northing in metres with
// unit scale at the origin, so x (north) = northing and y (east) = easting, z down from the ground. Its scale
// error grows as (d/R)²/2 with the distance d from the central meridian (1e-8 at 1 km, 3e-5 at 50 km), which
// is why the importers refuse data farther than MapImportOptions::max_distance_from_origin from the origin.
// The default origin is the centre of the data's latitude/longitude bounding box (buildings and sites
// together); give one explicitly to share a frame between maps.
//
// What is a building. A feature is imported when its geometry is a polygon (GeoJSON Polygon/MultiPolygon; an
// OSM closed way or a type=multipolygon relation) and it carries a `building` tag other than "no". Its height
// comes from the `height` tag in metres ("44.6", "44.6 m" or a JSON number). Everything else is skipped and
// counted by reason in the ImportSummary: not a polygon (points, lines, open ways), not a building, a missing
// height (only when allowed, below), a multipolygon relation whose members are not all in the file.
//
// A missing height is an error naming the feature, unless allowed by an option: `height_from_levels` uses
// `building:levels` × `metres_per_level` (3 m per storey: a typical floor-to-floor height of residential
// buildings; an estimate, not in the dissertation), and `skip_missing_height` skips and counts the feature.
// In the Upper East Side file of shared/data/osm, 11 of 1,239 buildings have no height (2 of them have levels):
// importing it needs one of the options (the CLI's --skip-missing-height / --height-from-levels).
//
// Malformed input — bad JSON or XML, a ring with fewer than 4 positions (3 corners and the closing one) or
// fewer than 3 distinct corners, an unclosed GeoJSON ring, a height that is not a positive number of metres,
// coordinates out of range, a landing-site row that does not parse — throws InputError naming the file, the
// feature (its OSM id and its index) and what was expected.
//
// Landing-site CSV (RFC 4180, planning/csv.h: quoted fields may hold commas, doubled quotes and line breaks):
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
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "uascma/planning/city_map.h"

namespace uascma::planning {

struct GeoPoint {
  double lat_deg = 0.0;  // WGS84 latitude, degrees north
  double lon_deg = 0.0;  // WGS84 longitude, degrees east
};

// The local transverse Mercator frame centred on `origin` (see the header comment). Holds a PROJ object,
// which is not thread-safe: use one LocalProjection per thread (copies are independent).
class LocalProjection {
 public:
  // Throws InputError when the origin is not a valid latitude/longitude.
  explicit LocalProjection(const GeoPoint& origin);
  LocalProjection(const LocalProjection& other);
  LocalProjection& operator=(const LocalProjection& other);
  LocalProjection(LocalProjection&&) noexcept;
  LocalProjection& operator=(LocalProjection&&) noexcept;
  ~LocalProjection();

  const GeoPoint& origin() const { return origin_; }
  // p_NE (m): x north, y east of the origin.
  Eigen::Vector2d ToLocal(const GeoPoint& point) const;
  GeoPoint ToGeodetic(const Eigen::Vector2d& p_NE) const;
  // The PROJ pipeline used, for the record.
  std::string Definition() const;

 private:
  struct Proj;
  GeoPoint origin_;
  std::unique_ptr<Proj> proj_;
};

struct MapImportOptions {
  bool height_from_levels = false;  // a building without `height`: building:levels × metres_per_level
  double metres_per_level = 3.0;    // m per storey (estimate; see the header comment)
  bool skip_missing_height = false;  // a building still without a height is skipped and counted, not an error
  std::optional<GeoPoint> origin;    // the local frame's origin; default: the centre of the data
  // Refuse data farther than this (m) from the origin: the local frame is a flat projection (header comment).
  double max_distance_from_origin = 50'000.0;
  CityMapOptions map;
  bool IsValid(std::string* error) const;
};

enum class SkipReason { kNotPolygon = 0, kNotBuilding, kMissingHeight, kIncompleteRelation };
inline constexpr int kNumSkipReasons = 4;
// "not_polygon", "not_building", "missing_height", "incomplete_relation".
std::string SkipReasonName(SkipReason reason);

// Skipped features are all counted, but only this many of each reason are listed (a city extract has
// hundreds of thousands of tagged nodes).
inline constexpr int kMaxRecordedSkipsPerReason = 1000;

struct SkippedFeature {
  std::string source;   // the file
  std::string feature;  // "features[12] (node/2296577459)", "way/123"
  SkipReason reason = SkipReason::kNotPolygon;
  std::string detail;   // e.g. "geometry Point", "no building tag"
};

struct ImportSummary {
  std::vector<std::string> sources;  // the files read, in order
  int features = 0;                  // map features seen (GeoJSON features; OSM objects with tags)
  int buildings = 0;                 // imported
  int heights_from_levels = 0;       // of which the height came from building:levels
  std::array<int, kNumSkipReasons> skipped{};  // by SkipReason
  std::vector<SkippedFeature> skipped_features;  // the first kMaxRecordedSkipsPerReason of each reason
  int sites = 0;                     // landing sites imported
  int rooftop_sites = 0;             // of which on the roof of an imported building (set by ProjectToCityMap)
  // Set by ProjectToCityMap:
  GeoPoint origin;                   // the local frame's origin
  bool origin_from_data = true;      // false when it was given
  GeoPoint south_west, north_east;   // latitude/longitude bounds of the data
  Eigen::AlignedBox2d bounds;        // m, the map's horizontal extent in the local frame
  std::string tallest_building;      // id, empty without buildings
  double tallest_height = 0.0;       // m

  int skipped_total() const;
  int skipped_count(SkipReason reason) const { return skipped[static_cast<int>(reason)]; }
  // One paragraph for people: counts, skipped by reason, sites, extent, tallest building.
  std::string BriefReport() const;
};

// Geodetic records collected by the readers.
struct GeoBuilding {
  std::string id;                              // "way/248773492", "relation/…"
  std::vector<std::vector<GeoPoint>> rings;    // even-odd interior (map_geometry.h), closing vertex dropped
  double height = 0.0;                         // m
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
  ImportSummary summary;
};

enum class MapFileFormat { kGeoJson, kOsm };
// By extension: .geojson/.json → GeoJSON; .osm, .osm.pbf, .pbf, .osm.gz, .osm.bz2 → OSM. InputError otherwise.
MapFileFormat DetectMapFormat(const std::filesystem::path& path);

// The readers append to `data` (buildings or sites, and the summary) and throw InputError on malformed input.
void ParseGeoJsonBuildings(std::string_view text, const std::string& source, const MapImportOptions& options,
                           GeoMapData* data);
void ReadGeoJsonBuildings(const std::filesystem::path& path, const MapImportOptions& options, GeoMapData* data);
// Reads ways and multipolygon relations tagged building=* (libosmium's area assembler builds the polygons).
void ReadOsmBuildings(const std::filesystem::path& path, const MapImportOptions& options, GeoMapData* data);
// GeoJSON or OSM by DetectMapFormat.
void ReadBuildings(const std::filesystem::path& path, const MapImportOptions& options, GeoMapData* data);
void ParseLandingSitesCsv(std::string_view text, const std::string& source, const MapImportOptions& options,
                          GeoMapData* data);
void ReadLandingSitesCsv(const std::filesystem::path& path, const MapImportOptions& options, GeoMapData* data);

// Projects the records to the local frame (origin: options.origin or the centre of the data) and builds the
// CityMap; fills the projection and extent fields of `summary` (which may be &data.summary's copy).
CityMap ProjectToCityMap(const GeoMapData& data, const MapImportOptions& options, ImportSummary* summary);

struct ImportedMap {
  CityMap map;
  ImportSummary summary;
};
// Reads every building file and the optional landing-site CSV (empty path: none), then projects them into one
// map. InputError when nothing at all was imported.
ImportedMap ImportCityMap(std::span<const std::filesystem::path> building_files,
                          const std::filesystem::path& sites_csv, const MapImportOptions& options);

}  // namespace uascma::planning
