// The map importers: the local projection in closed form, GeoJSON / OSM / CSV readers on small hand-made inputs
// (well-formed and malformed), and the real OpenStreetMap files of data/osm.
#include <gtest/gtest.h>

// GCC 12 reports a false -Wstringop-overread inside libosmium's builders; see src/planning/map_osm.cc.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wstringop-overread"
#include <osmium/io/pbf_output.hpp>
#include <osmium/io/reader.hpp>
#include <osmium/io/writer.hpp>
#include <osmium/io/xml_input.hpp>
#pragma GCC diagnostic pop

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <string>

#include "../support/data_paths.h"
#include "uascma/common/error.h"
#include "uascma/common/random.h"
#include "uascma/planning/map_geojson.h"
#include "uascma/planning/map_import.h"
#include "uascma/planning/map_osm.h"
#include "uascma/planning/map_projection.h"
#include "uascma/planning/map_sites_csv.h"

namespace uascma::planning {
namespace {

constexpr double kProjectionTolerance = 1e-4;    // m: tmerc against the closed-form arc lengths over 100 m
constexpr double kRoundTripTolerance = 1e-10;    // degrees (~1e-5 m)
constexpr double kSameGeometryTolerance = 1e-9;  // m, two readers projecting the same coordinates
constexpr double kHeightTolerance = 1e-9;        // m

// WGS84 (NIMA TR8350.2): semi-major axis and first eccentricity squared.
constexpr double kWgs84A = 6378137.0;
constexpr double kWgs84E2 = 6.69437999014e-3;

using ::uascma::testing_support::OsmDataDir;

// A scratch folder for the files a test writes, removed at the end.
struct Scratch {
  explicit Scratch(const std::string& name)
      : path(std::filesystem::temp_directory_path() /
             ("uascma_map_import_" + name + "_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~Scratch() { std::filesystem::remove_all(path); }
  std::filesystem::path Write(const std::string& file, const std::string& content) const {
    std::ofstream(path / file) << content;
    return path / file;
  }
  std::filesystem::path path;
};

// Expects an InputError whose one-line message contains every one of `parts`.
template <typename F>
void ExpectInputError(F&& f, std::initializer_list<std::string> parts) {
  try {
    f();
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    for (const auto& part : parts)
      EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
  }
}

// --- projection --------------------------------------------------------------------------------------------

TEST(LocalProjectionTest, ArcLengthsMatchTheEllipsoidInClosedForm) {
  const GeoPoint origin{40.7387, -73.9894};
  const LocalProjection projection(origin);
  EXPECT_NEAR(projection.ToLocal(origin).norm(), 0.0, kProjectionTolerance);
  const double phi = origin.lat_deg * std::numbers::pi / 180.0;
  const double w = 1.0 - kWgs84E2 * std::sin(phi) * std::sin(phi);
  // 0.001° north: the meridian arc M Δφ, M = a(1 − e²)/w^{3/2}, straight up the x axis.
  const double meridian_radius = kWgs84A * (1.0 - kWgs84E2) / std::pow(w, 1.5);
  const Eigen::Vector2d north = projection.ToLocal({origin.lat_deg + 0.001, origin.lon_deg});
  EXPECT_NEAR(north.x(), meridian_radius * 0.001 * std::numbers::pi / 180.0, kProjectionTolerance);
  EXPECT_NEAR(north.y(), 0.0, kProjectionTolerance);
  EXPECT_NEAR(north.x(), 111.2, 0.005 * 111.2);  // the familiar ~111 km per degree
  // 0.001° east: the parallel's arc N cos φ Δλ, N = a / √w, along +y.
  const double normal_radius = kWgs84A / std::sqrt(w);
  const Eigen::Vector2d east = projection.ToLocal({origin.lat_deg, origin.lon_deg + 0.001});
  EXPECT_GT(east.y(), 0.0);
  EXPECT_NEAR(east.y(), normal_radius * std::cos(phi) * 0.001 * std::numbers::pi / 180.0, kProjectionTolerance);
  EXPECT_NEAR(east.x(), 0.0, 1e-3);  // a parallel curves north of the tangent by ~Δλ² N sinφ cosφ / 2 ≈ 0.5 mm
  EXPECT_LT(projection.ToLocal({origin.lat_deg - 0.001, origin.lon_deg}).x(), 0.0);
  EXPECT_LT(projection.ToLocal({origin.lat_deg, origin.lon_deg - 0.001}).y(), 0.0);
}

TEST(LocalProjectionTest, RoundTripReturnsThePoint) {
  const LocalProjection projection({40.7790, -73.9550});
  RandomStream random(31);
  for (int k = 0; k < 200; ++k) {
    const GeoPoint p{40.7790 + random.Uniform(-0.05, 0.05), -73.9550 + random.Uniform(-0.05, 0.05)};
    const GeoPoint back = projection.ToGeodetic(projection.ToLocal(p));
    EXPECT_NEAR(back.lat_deg, p.lat_deg, kRoundTripTolerance);
    EXPECT_NEAR(back.lon_deg, p.lon_deg, kRoundTripTolerance);
  }
  const LocalProjection copy = projection;  // an independent PROJ object, same frame
  EXPECT_NEAR((copy.ToLocal({40.78, -73.95}) - projection.ToLocal({40.78, -73.95})).norm(), 0.0, 1e-12);
  EXPECT_THROW(LocalProjection({95.0, 0.0}), InputError);
}

// --- GeoJSON -----------------------------------------------------------------------------------------------

// A FeatureCollection around Broadway & 14th: a building with a courtyard, a MultiPolygon building, a point,
// a polygon that is not a building, and a building whose height comes only from its levels.
const char* kGeoJson = R"({
  "type": "FeatureCollection",
  "features": [
    {"type": "Feature", "properties": {"@id": "way/1", "building": "yes", "height": "20 m"},
     "geometry": {"type": "Polygon", "coordinates": [
       [[-73.9900, 40.7380], [-73.9890, 40.7380], [-73.9890, 40.7385], [-73.9900, 40.7385], [-73.9900, 40.7380]],
       [[-73.9897, 40.7382], [-73.9893, 40.7382], [-73.9893, 40.7383], [-73.9897, 40.7383], [-73.9897, 40.7382]]]}},
    {"type": "Feature", "properties": {"@id": "relation/2", "building": "office", "height": 55.5},
     "geometry": {"type": "MultiPolygon", "coordinates": [
       [[[-73.9880, 40.7380], [-73.9875, 40.7380], [-73.9875, 40.7383], [-73.9880, 40.7380]]],
       [[[-73.9870, 40.7380], [-73.9865, 40.7380], [-73.9865, 40.7383], [-73.9870, 40.7380]]]]}},
    {"type": "Feature", "properties": {"@id": "node/3"}, "geometry": {"type": "Point", "coordinates": [-73.99, 40.738]}},
    {"type": "Feature", "properties": {"@id": "way/4", "leisure": "park"},
     "geometry": {"type": "Polygon", "coordinates": [
       [[-73.9860, 40.7380], [-73.9855, 40.7380], [-73.9855, 40.7383], [-73.9860, 40.7380]]]}},
    {"type": "Feature", "properties": {"@id": "way/5", "building": "yes", "building:levels": "4"},
     "geometry": {"type": "Polygon", "coordinates": [
       [[-73.9850, 40.7380], [-73.9845, 40.7380], [-73.9845, 40.7383], [-73.9850, 40.7380]]]}}
  ]})";

TEST(GeoJsonImportTest, ReadsPolygonsMultiPolygonsAndCountsWhatItSkips) {
  MapImportOptions options;
  options.height_from_levels = true;
  GeoMapData data;
  ParseGeoJsonBuildings(kGeoJson, "test.geojson", options, &data);
  const ImportSummary& summary = data.summary;
  EXPECT_EQ(summary.features, 5);
  EXPECT_EQ(summary.buildings, 3);
  EXPECT_EQ(summary.heights_from_levels, 1);
  EXPECT_EQ(summary.skipped_count(SkipReason::kNotPolygon), 1);
  EXPECT_EQ(summary.skipped_count(SkipReason::kNotBuilding), 1);
  ASSERT_EQ(summary.skipped_features.size(), 2u);
  EXPECT_EQ(summary.skipped_features[0].feature, "features[2] (node/3)");
  EXPECT_EQ(summary.skipped_features[0].detail, "geometry Point");
  ASSERT_EQ(data.buildings.size(), 3u);
  EXPECT_EQ(data.buildings[0].id, "way/1");
  EXPECT_EQ(data.buildings[0].rings.size(), 2u);     // outer + courtyard
  EXPECT_EQ(data.buildings[0].rings[0].size(), 4u);  // the closing position dropped
  EXPECT_NEAR(data.buildings[0].height, 20.0, kHeightTolerance);
  EXPECT_EQ(data.buildings[1].rings.size(), 2u);  // two parts
  EXPECT_NEAR(data.buildings[1].height, 55.5, kHeightTolerance);
  EXPECT_NEAR(data.buildings[2].height, 4 * options.metres_per_level, kHeightTolerance);

  // Projected: the courtyard is outside the building, the ring around it inside.
  ImportSummary projected = summary;
  const CityMap map = ProjectToCityMap(data, options, &projected);
  const LocalProjection frame(projected.origin);
  const Eigen::Vector2d courtyard = frame.ToLocal({40.73825, -73.9895});
  const Eigen::Vector2d wing = frame.ToLocal({40.73810, -73.9895});
  EXPECT_EQ(map.BuildingContaining({courtyard.x(), courtyard.y(), -1.0}), kNoBuilding);
  EXPECT_EQ(map.BuildingContaining({wing.x(), wing.y(), -1.0}), 0);
  EXPECT_EQ(projected.tallest_building, "relation/2");
  EXPECT_TRUE(projected.origin_from_data);
  EXPECT_NEAR(projected.origin.lat_deg, 0.5 * (40.7380 + 40.7385), 1e-12);
  EXPECT_NEAR(projected.origin.lon_deg, 0.5 * (-73.9900 - 73.9845), 1e-12);
}

std::string FeatureCollection(const std::string& feature) {
  return R"({"type": "FeatureCollection", "features": [)" + feature + "]}";
}

std::string BuildingFeature(const std::string& properties, const std::string& coordinates) {
  return R"({"type": "Feature", "properties": {)" + properties +
         R"(}, "geometry": {"type": "Polygon", "coordinates": )" + coordinates + "}}";
}

const char* kSquare = "[[[-73.99, 40.738], [-73.989, 40.738], [-73.989, 40.739], [-73.99, 40.738]]]";

TEST(GeoJsonImportTest, MalformedInputNamesTheFileTheFeatureAndWhatWasExpected) {
  const MapImportOptions options;
  auto parse = [&](const std::string& text) {
    GeoMapData data;
    ParseGeoJsonBuildings(text, "bad.geojson", options, &data);
  };
  ExpectInputError([&] { parse("{\"type\": \"FeatureCollection\", \"features\": [}"); }, {"bad.geojson", "JSON"});
  ExpectInputError([&] { parse("{\"type\": \"Feature\"}"); }, {"bad.geojson", "FeatureCollection"});
  // Too few points: 3 positions.
  ExpectInputError(
      [&] {
        parse(FeatureCollection(BuildingFeature(R"("@id": "way/7", "building": "yes", "height": "10")",
                                                "[[[-73.99, 40.738], [-73.989, 40.738], [-73.99, 40.738]]]")));
      },
      {"bad.geojson", "features[0] (way/7)", "at least 4 positions"});
  // 4 positions but only 2 distinct corners.
  ExpectInputError(
      [&] {
        parse(FeatureCollection(
            BuildingFeature(R"("@id": "way/8", "building": "yes", "height": "10")",
                            "[[[-73.99, 40.738], [-73.989, 40.738], [-73.989, 40.738], [-73.99, 40.738]]]")));
      },
      {"bad.geojson", "way/8", "3 distinct corners"});
  // An unclosed ring.
  ExpectInputError(
      [&] {
        parse(FeatureCollection(
            BuildingFeature(R"("@id": "way/9", "building": "yes", "height": "10")",
                            "[[[-73.99, 40.738], [-73.989, 40.738], [-73.989, 40.739], [-73.99, 40.739]]]")));
      },
      {"bad.geojson", "way/9", "closed"});
  // A missing height, then one that is not a number of metres.
  ExpectInputError([&] { parse(FeatureCollection(BuildingFeature(R"("@id": "way/10", "building": "yes")", kSquare))); },
                   {"bad.geojson", "features[0] (way/10)", "'height'"});
  ExpectInputError(
      [&] {
        parse(FeatureCollection(BuildingFeature(R"("@id": "way/11", "building": "yes", "height": "40'")", kSquare)));
      },
      {"bad.geojson", "way/11", "metres", "40'"});
  ExpectInputError(
      [&] {
        parse(FeatureCollection(BuildingFeature(R"("@id": "way/12", "building": "yes", "height": "-3")", kSquare)));
      },
      {"way/12", "> 0"});
  // Coordinates out of range (latitude 95°).
  ExpectInputError(
      [&] {
        parse(FeatureCollection(
            BuildingFeature(R"("@id": "way/13", "building": "yes", "height": "10")",
                            "[[[-73.99, 95.0], [-73.989, 40.738], [-73.989, 40.739], [-73.99, 95.0]]]")));
      },
      {"bad.geojson", "way/13", "latitude in [-90, 90]"});
  // A member of the wrong JSON type.
  ExpectInputError(
      [&] {
        parse(FeatureCollection(
            R"({"type": "Feature", "properties": {"@id": "way/14"}, "geometry": {"type": 5, "coordinates": []}})"));
      },
      {"bad.geojson", "features[0] (way/14).geometry.type", "a string, got 5"});
  // Without an id, the index names the feature.
  ExpectInputError([&] { parse(FeatureCollection(BuildingFeature(R"("building": "yes")", kSquare))); },
                   {"bad.geojson", "features[0]", "'height'"});
}

TEST(GeoJsonImportTest, MissingHeightCanBeSkippedOrTakenFromLevels) {
  const std::string text =
      FeatureCollection(BuildingFeature(R"("@id": "way/1", "building": "yes", "height": "10")", kSquare) + "," +
                        BuildingFeature(R"("@id": "way/2", "building": "yes", "building:levels": "5")", kSquare) + "," +
                        BuildingFeature(R"("@id": "way/3", "building": "yes")", kSquare));
  MapImportOptions options;
  options.skip_missing_height = true;
  GeoMapData skipped;
  ParseGeoJsonBuildings(text, "t.geojson", options, &skipped);
  EXPECT_EQ(skipped.summary.buildings, 1);
  EXPECT_EQ(skipped.summary.skipped_count(SkipReason::kMissingHeight), 2);
  options.height_from_levels = true;
  GeoMapData levels;
  ParseGeoJsonBuildings(text, "t.geojson", options, &levels);
  EXPECT_EQ(levels.summary.buildings, 2);
  EXPECT_EQ(levels.summary.heights_from_levels, 1);
  EXPECT_EQ(levels.summary.skipped_count(SkipReason::kMissingHeight), 1);
  options.skip_missing_height = false;  // levels only: way/3 has neither
  GeoMapData strict;
  ExpectInputError([&] { ParseGeoJsonBuildings(text, "t.geojson", options, &strict); },
                   {"t.geojson", "features[2] (way/3)", "'building:levels'"});
}

// --- CSV ---------------------------------------------------------------------------------------------------

TEST(LandingSiteCsvTest, AcceptsBothHeaderSpellingsAndRejectsBadRows) {
  const MapImportOptions options;
  GeoMapData plain, aliased;
  ParseLandingSitesCsv("osm_id, lat, lon, alt, risk, radius\n7, 40.74, -73.99, 12.5, 0.25, 3\n", "a.csv", options,
                       &plain);
  ParseLandingSitesCsv("radius,landing_site_risk,gps.alt,gps.lon,gps.lat,osm_id\r\n3,0.25,12.5,-73.99,40.74,7\r\n\r\n",
                       "b.csv", options, &aliased);
  ASSERT_EQ(plain.sites.size(), 1u);
  ASSERT_EQ(aliased.sites.size(), 1u);
  for (const auto* data : {&plain, &aliased}) {
    const GeoLandingSite& s = data->sites[0];
    EXPECT_EQ(s.id, "7");
    EXPECT_NEAR(s.position.lat_deg, 40.74, 1e-12);
    EXPECT_NEAR(s.position.lon_deg, -73.99, 1e-12);
    EXPECT_NEAR(s.altitude, 12.5, kHeightTolerance);
    EXPECT_NEAR(s.risk, 0.25, 1e-12);
    EXPECT_NEAR(s.radius, 3.0, kHeightTolerance);
  }
  auto parse = [&](const std::string& text) {
    GeoMapData data;
    ParseLandingSitesCsv(text, "sites.csv", options, &data);
  };
  ExpectInputError([&] { parse("osm_id,lat,lon,alt,radius\n1,40,-73,0,2\n"); }, {"sites.csv", "header", "'risk'"});
  ExpectInputError([&] { parse("osm_id,lat,lon,alt,risk,radius\n1,40,-73,abc,0.5,2\n"); },
                   {"sites.csv", "line 2", "alt", "'abc'"});
  ExpectInputError([&] { parse("osm_id,lat,lon,alt,risk,radius\n1,40,-73,0,1.5,2\n"); },
                   {"sites.csv", "line 2 (site 1)", "risk in [0, 1]"});
  ExpectInputError([&] { parse("osm_id,lat,lon,alt,risk,radius\n1,40,-73,0,0.5,0\n"); },
                   {"sites.csv", "radius", "0.1 to 1000 m, got 0"});
  // The upper bounds of alt and radius (1e9 m was accepted).
  ExpectInputError([&] { parse("osm_id,lat,lon,alt,risk,radius\n1,40,-73,1e9,0.5,2\n"); },
                   {"sites.csv", "line 2 (site 1) alt", "0 to 1000 m, got 1e+09"});
  ExpectInputError([&] { parse("osm_id,lat,lon,alt,risk,radius\n1,40,-73,0,0.5,1e9\n"); },
                   {"sites.csv", "line 2 (site 1) radius", "0.1 to 1000 m, got 1e+09"});
  ExpectInputError([&] { parse("osm_id,lat,lon,alt,risk,radius\n1,40,-190,0,0.5,2\n"); },
                   {"sites.csv", "longitude in [-180, 180]"});
  ExpectInputError([&] { parse("osm_id,lat,lon,alt,risk,radius\n1,40,-73\n"); }, {"sites.csv", "line 2", "fields"});
}

// A column given twice was read from its first copy, silently; a file with CR-only line endings was one line whose
// whole text the header message quoted; control characters and bytes that are not UTF-8 were echoed raw.
TEST(LandingSiteCsvTest, ColumnsGivenTwiceLoneCarriageReturnsAndRawBytesAreRefusedOrEscaped) {
  auto error_of = [](const std::string& text) {
    GeoMapData data;
    try {
      ParseLandingSitesCsv(text, "sites.csv", MapImportOptions{}, &data);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error_of("osm_id,lat,lon,alt,risk,radius,lat\n1,40,-73,0,0.5,2,41\n"),
            "sites.csv: line 1 column 7: each column once, but 'lat' is column 2 and 'lat' column 7 (both name lat): "
            "remove one");
  EXPECT_NE(error_of("osm_id,lat,lon,alt,risk,radius,latitude\n1,40,-73,0,0.5,2,41\n").find("both name lat"),
            std::string::npos);
  EXPECT_EQ(error_of("osm_id,lat,lon,alt,risk,radius\r1,40,-73,0,0.5,2\r"),
            "sites.csv: line 1: lines ending in LF or CRLF (RFC 4180), but this line holds a carriage return alone "
            "(classic Mac line endings? convert them to LF)");
  EXPECT_EQ(error_of("osm_id,lat,lon,alt,risk,radius\n1,40,-73,\x1b[2J\xFF,0.5,2\n"),
            "sites.csv: line 2 column alt: a number, got '\\x1B[2J\\xFF'");
  EXPECT_EQ(error_of("osm_id,lat,lon,alt,risk,radius\n\"a\rb\",40,-73,0,0.5,2\r\n"), "");  // inside quotes: text
}

// --- OSM (.osm and .osm.pbf) -------------------------------------------------------------------------------

// Nodes of the little map: a rectangle (1–4) for a building way, an outer (5–8) and inner (9–12) ring for a
// multipolygon building with a courtyard, a rectangle (13–16) for a building with levels only, and a park.
std::string OsmNodes() {
  return R"(
  <node id="1" version="1" lat="40.7380" lon="-73.9900"/>
  <node id="2" version="1" lat="40.7380" lon="-73.9890"/>
  <node id="3" version="1" lat="40.7385" lon="-73.9890"/>
  <node id="4" version="1" lat="40.7385" lon="-73.9900"/>
  <node id="5" version="1" lat="40.7390" lon="-73.9900"/>
  <node id="6" version="1" lat="40.7390" lon="-73.9880"/>
  <node id="7" version="1" lat="40.7396" lon="-73.9880"/>
  <node id="8" version="1" lat="40.7396" lon="-73.9900"/>
  <node id="9" version="1" lat="40.7392" lon="-73.9895"/>
  <node id="10" version="1" lat="40.7392" lon="-73.9885"/>
  <node id="11" version="1" lat="40.7394" lon="-73.9885"/>
  <node id="12" version="1" lat="40.7394" lon="-73.9895"/>
  <node id="13" version="1" lat="40.7400" lon="-73.9900"/>
  <node id="14" version="1" lat="40.7400" lon="-73.9895"/>
  <node id="15" version="1" lat="40.7403" lon="-73.9895"/>
  <node id="16" version="1" lat="40.7403" lon="-73.9900"/>
  <node id="50" version="1" lat="40.7387" lon="-73.9899"><tag k="shop" v="bakery"/></node>)";
}

std::string Osm(const std::string& body) {
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<osm version=\"0.6\" generator=\"uascma test\">" + body +
         "\n</osm>\n";
}

std::string GoodOsm() {
  return Osm(OsmNodes() + R"(
  <way id="100" version="1"><nd ref="1"/><nd ref="2"/><nd ref="3"/><nd ref="4"/><nd ref="1"/>
    <tag k="building" v="yes"/><tag k="height" v="25.5"/></way>
  <way id="101" version="1"><nd ref="5"/><nd ref="6"/><nd ref="7"/><nd ref="8"/><nd ref="5"/></way>
  <way id="102" version="1"><nd ref="9"/><nd ref="10"/><nd ref="11"/><nd ref="12"/><nd ref="9"/></way>
  <way id="103" version="1"><nd ref="13"/><nd ref="14"/><nd ref="15"/><nd ref="16"/><nd ref="13"/>
    <tag k="building" v="yes"/><tag k="building:levels" v="4"/></way>
  <way id="104" version="1"><nd ref="1"/><nd ref="5"/><tag k="highway" v="residential"/></way>
  <way id="105" version="1"><nd ref="2"/><nd ref="6"/><nd ref="10"/><nd ref="2"/><tag k="leisure" v="park"/></way>
  <relation id="200" version="1"><member type="way" ref="101" role="outer"/><member type="way" ref="102" role="inner"/>
    <tag k="type" v="multipolygon"/><tag k="building" v="yes"/><tag k="height" v="40"/></relation>)");
}

void ConvertToPbf(const std::filesystem::path& xml, const std::filesystem::path& pbf) {
  osmium::io::Reader reader{xml.string()};
  osmium::io::Writer writer{pbf.string(), reader.header(), osmium::io::overwrite::allow};
  while (osmium::memory::Buffer buffer = reader.read()) writer(std::move(buffer));
  writer.close();
  reader.close();
}

TEST(OsmImportTest, ReadsBuildingWaysAndMultipolygonsFromXmlAndPbfAlike) {
  Scratch scratch("osm");
  const auto xml = scratch.Write("little.osm", GoodOsm());
  const auto pbf = scratch.path / "little.osm.pbf";
  ConvertToPbf(xml, pbf);
  MapImportOptions options;
  options.height_from_levels = true;
  options.origin = GeoPoint{40.7390, -73.9890};  // one frame for both files and the GeoJSON below
  for (const auto& path : {xml, pbf}) {
    SCOPED_TRACE(path.string());
    const std::vector<std::filesystem::path> files = {path};
    const ImportedMap imported = ImportCityMap(files, {}, options);
    const ImportSummary& s = imported.summary;
    EXPECT_EQ(s.features, 6);  // node 50, ways 100 103 104 105, relation 200 (101 and 102 carry no tags)
    EXPECT_EQ(s.buildings, 3);
    EXPECT_EQ(s.heights_from_levels, 1);
    EXPECT_EQ(s.skipped_count(SkipReason::kNotPolygon), 2);   // the shop node, the open highway
    EXPECT_EQ(s.skipped_count(SkipReason::kNotBuilding), 1);  // the park
    EXPECT_EQ(s.tallest_building, "relation/200");
    const CityMap& map = imported.map;
    ASSERT_EQ(map.buildings().size(), 3u);
    const LocalProjection frame(*options.origin);
    auto building_at = [&](double lat, double lon, double altitude) {
      const Eigen::Vector2d p = frame.ToLocal({lat, lon});
      const int k = map.BuildingContaining({p.x(), p.y(), -altitude});
      return k == kNoBuilding ? std::string("none") : map.building(k).id;
    };
    EXPECT_EQ(building_at(40.73825, -73.9895, 25.0), "way/100");
    EXPECT_EQ(building_at(40.73825, -73.9895, 26.0), "none");  // above its 25.5 m roof
    EXPECT_EQ(building_at(40.7391, -73.9890, 39.0), "relation/200");
    EXPECT_EQ(building_at(40.7393, -73.9890, 1.0), "none");        // the courtyard
    EXPECT_EQ(building_at(40.74015, -73.98975, 11.0), "way/103");  // 4 levels × 3 m

    // The same rectangle through the GeoJSON reader lands on the same local coordinates.
    GeoMapData json;
    ParseGeoJsonBuildings(
        FeatureCollection(BuildingFeature(R"("@id": "way/100", "building": "yes", "height": "25.5")",
                                          "[[[-73.9900, 40.7380], [-73.9890, 40.7380], [-73.9890, 40.7385], [-73.9900, "
                                          "40.7385], [-73.9900, 40.7380]]]")),
        "same.geojson", options, &json);
    ImportSummary json_summary = json.summary;
    const CityMap json_map = ProjectToCityMap(json, options, &json_summary);
    int osm_index = -1;
    for (int k = 0; k < 3; ++k) {
      if (map.building(k).id == "way/100") osm_index = k;
    }
    ASSERT_GE(osm_index, 0);
    const Ring& osm_ring = map.building(osm_index).rings[0];
    const Ring& json_ring = json_map.building(0).rings[0];
    ASSERT_EQ(osm_ring.size(), json_ring.size());
    // libosmium may start or orient a way's ring differently: match each corner to the nearest one.
    for (const auto& corner : json_ring) {
      double nearest = std::numeric_limits<double>::infinity();
      for (const auto& other : osm_ring) nearest = std::min(nearest, (other - corner).norm());
      EXPECT_NEAR(nearest, 0.0, kSameGeometryTolerance);
    }
  }
}

TEST(OsmImportTest, MalformedAndIncompleteInput) {
  Scratch scratch("osm_bad");
  const MapImportOptions options;
  auto read = [&](const std::string& name, const std::string& content) {
    const auto path = scratch.Write(name, content);
    GeoMapData data;
    ReadOsmBuildings(path, options, &data);
    return data.summary;
  };
  // A closed "ring" of 3 nodes (2 corners).
  ExpectInputError(
      [&] {
        read("few.osm", Osm(OsmNodes() + R"(<way id="300" version="1"><nd ref="1"/><nd ref="2"/><nd ref="1"/>
          <tag k="building" v="yes"/><tag k="height" v="10"/></way>)"));
      },
      {"few.osm", "way/300", "at least 4 nodes"});
  // A node that is not in the file.
  ExpectInputError(
      [&] {
        read("missing.osm", Osm(OsmNodes() + R"(<way id="301" version="1"><nd ref="1"/><nd ref="2"/><nd ref="999"/>
          <nd ref="1"/><tag k="building" v="yes"/><tag k="height" v="10"/></way>)"));
      },
      {"missing.osm", "way/301", "node 999"});
  // A multipolygon whose only outer way does not close.
  ExpectInputError(
      [&] {
        read("open.osm", Osm(OsmNodes() + R"(<way id="302" version="1"><nd ref="5"/><nd ref="6"/><nd ref="7"/></way>
          <relation id="400" version="1"><member type="way" ref="302" role="outer"/>
          <tag k="type" v="multipolygon"/><tag k="building" v="yes"/><tag k="height" v="10"/></relation>)"));
      },
      {"open.osm", "relation/400", "valid polygon"});
  // A missing height.
  ExpectInputError(
      [&] {
        read("noheight.osm", Osm(OsmNodes() + R"(<way id="303" version="1"><nd ref="1"/><nd ref="2"/><nd ref="3"/>
          <nd ref="4"/><nd ref="1"/><tag k="building" v="yes"/></way>)"));
      },
      {"noheight.osm", "way/303", "'height'"});
  ExpectInputError([&] { read("broken.osm", "<osm><node id='1' lat='40' lon="); }, {"broken.osm", "OSM data"});
  ExpectInputError(
      [&] {
        GeoMapData d;
        ReadOsmBuildings(scratch.path / "absent.osm", options, &d);
      },
      {"absent.osm", "readable"});
  // A multipolygon with a member outside the file (an extract cut through it) is skipped and counted.
  const ImportSummary summary = read("cut.osm", Osm(OsmNodes() + R"(
      <way id="304" version="1"><nd ref="5"/><nd ref="6"/><nd ref="7"/><nd ref="8"/><nd ref="5"/></way>
      <relation id="401" version="1"><member type="way" ref="304" role="outer"/><member type="way" ref="9999" role="inner"/>
      <tag k="type" v="multipolygon"/><tag k="building" v="yes"/><tag k="height" v="10"/></relation>)"));
  EXPECT_EQ(summary.buildings, 0);
  EXPECT_EQ(summary.skipped_count(SkipReason::kIncompleteRelation), 1);
}

TEST(MapImportTest, UnknownExtensionAndEmptyMapsAreInputErrors) {
  ExpectInputError([] { DetectMapFormat("city.shp"); }, {"city.shp", ".geojson"});
  EXPECT_EQ(DetectMapFormat("a/b/City.OSM.PBF"), MapFileFormat::kOsm);
  EXPECT_EQ(DetectMapFormat("x.json"), MapFileFormat::kGeoJson);
  GeoMapData empty;
  ParseGeoJsonBuildings(R"({"type": "FeatureCollection", "features": []})", "empty.geojson", {}, &empty);
  ImportSummary summary = empty.summary;
  ExpectInputError([&] { ProjectToCityMap(empty, {}, &summary); }, {"empty.geojson", "at least one building"});
  // Data farther from a given origin than the local frame allows.
  GeoMapData far;
  ParseLandingSitesCsv("osm_id,lat,lon,alt,risk,radius\n1,40.74,-73.99,0,0.5,2\n", "far.csv", {}, &far);
  MapImportOptions options;
  options.origin = GeoPoint{41.74, -73.99};  // ~111 km south
  summary = far.summary;
  ExpectInputError([&] { ProjectToCityMap(far, options, &summary); }, {"far.csv", "site 1", "within 50 km"});
}

// --- the real files ----------------------------------------------------------------------------------------

TEST(RealOsmDataTest, BroadwayFourteenthImportsAllSixtySevenBuildings) {
  const std::vector<std::filesystem::path> files = {OsmDataDir() / "broadway-14th-buildings.geojson"};
  const ImportedMap imported = ImportCityMap(files, {}, {});
  EXPECT_EQ(imported.summary.features, 67);
  EXPECT_EQ(imported.summary.buildings, 67);
  EXPECT_EQ(imported.summary.skipped_total(), 0);
  EXPECT_NEAR(imported.summary.tallest_height, 83.6, kHeightTolerance);
  // The extent is a few hundred metres around the origin: 0.0029° of latitude ≈ 326 m.
  const Eigen::Vector2d size = imported.map.bounds().sizes();
  EXPECT_NEAR(size.x(), (40.7396178 - 40.7366858) * 111'030.0, 2.0);
  for (const Building& b : imported.map.buildings()) EXPECT_GT(std::abs(TwiceSignedArea(b.rings[0])), 0.0);
}

TEST(RealOsmDataTest, UpperEastSideNeedsAPolicyForItsElevenBuildingsWithoutHeight) {
  const std::vector<std::filesystem::path> files = {OsmDataDir() / "upper-east-side-buildings.geojson"};
  // By default a missing height is an error naming the first such feature.
  ExpectInputError([&] { ImportCityMap(files, {}, {}); },
                   {"upper-east-side-buildings.geojson", "way/266916493", "'height'"});
  MapImportOptions options;
  options.skip_missing_height = true;
  const ImportedMap skipped = ImportCityMap(files, {}, options);
  EXPECT_EQ(skipped.summary.features, 1286);
  EXPECT_EQ(skipped.summary.buildings, 1228);
  EXPECT_EQ(skipped.summary.skipped_count(SkipReason::kNotPolygon), 47);  // nodes exported as Points
  EXPECT_EQ(skipped.summary.skipped_count(SkipReason::kMissingHeight), 11);
  EXPECT_EQ(skipped.summary.skipped_count(SkipReason::kNotBuilding), 0);
  EXPECT_NEAR(skipped.summary.tallest_height, 160.0, kHeightTolerance);
  options.height_from_levels = true;  // 2 of the 11 have building:levels (15 and 1)
  const ImportedMap levels = ImportCityMap(files, {}, options);
  EXPECT_EQ(levels.summary.buildings, 1230);
  EXPECT_EQ(levels.summary.heights_from_levels, 2);
  EXPECT_EQ(levels.summary.skipped_count(SkipReason::kMissingHeight), 9);

  // On real outlines too, the grid answers as a scan over every building does.
  const CityMap& map = skipped.map;
  std::vector<std::vector<Edge2>> edges;
  for (const Building& b : map.buildings()) edges.push_back(EdgesOfRings(b.rings));
  RandomStream random(41);
  int hits = 0;
  for (int k = 0; k < 300; ++k) {
    const Eigen::Vector3d a(random.Uniform(map.bounds().min().x(), map.bounds().max().x()),
                            random.Uniform(map.bounds().min().y(), map.bounds().max().y()), -random.Uniform(0, 50));
    const Eigen::Vector3d b =
        a + Eigen::Vector3d(random.Uniform(-150, 150), random.Uniform(-150, 150), random.Uniform(-10, 10));
    bool expected = false;
    for (std::size_t i = 0; i < edges.size() && !expected; ++i) {
      expected = FirstEntryIntoPrism(edges[i], map.building(i).height, a, b).has_value();
    }
    EXPECT_EQ(map.SegmentCollides(a, b), expected) << "segment " << k;
    hits += expected;
  }
  EXPECT_GT(hits, 30);
  EXPECT_LT(hits, 270);
}

TEST(RealOsmDataTest, MidtownLandingSitesReadWithTheirColumnAliases) {
  const ImportedMap imported = ImportCityMap({}, OsmDataDir() / "midtown-landing-sites.csv", {});
  EXPECT_EQ(imported.summary.sites, 1828);
  EXPECT_EQ(imported.summary.rooftop_sites, 0);  // no buildings imported with them
  double min_radius = 1e9, max_risk = 0.0;
  for (const LandingSite& s : imported.map.sites()) {
    min_radius = std::min(min_radius, s.radius);
    max_risk = std::max(max_risk, s.risk);
  }
  EXPECT_NEAR(min_radius, 2.000086, 1e-6);  // the file's extremes, read exactly
  EXPECT_NEAR(max_risk, 0.786929, 1e-6);
  // About 3 km (north–south) by 1.5 km of Midtown.
  EXPECT_NEAR(imported.map.bounds().sizes().x(), 2995.0, 50.0);
}

// --- buildings without heights, sites from the map ---------------------------------------------

std::filesystem::path NoHeightsOsm() {
  return std::filesystem::path(UASCMA_SOURCE_DIR) / "tests" / "data" / "maps" / "no-heights.osm";
}

TEST(BuildingTypeHeightTest, StoreysTimesTheCtbuhStoreyHeight) {
  int storeys = 0;
  double storey = 0.0;
  // Residential/hotel 3.1 m, office 3.9 m, unknown or mixed 3.5 m (CTBUH; map_import.h).
  EXPECT_NEAR(BuildingTypeHeight("house", &storeys, &storey), 2 * 3.1, kHeightTolerance);
  EXPECT_EQ(storeys, 2);
  EXPECT_NEAR(BuildingTypeHeight("apartments"), 5 * 3.1, kHeightTolerance);
  EXPECT_NEAR(BuildingTypeHeight("office"), 5 * 3.9, kHeightTolerance);
  EXPECT_NEAR(BuildingTypeHeight("garage"), 3.1, kHeightTolerance);
  EXPECT_NEAR(BuildingTypeHeight("yes", &storeys, &storey), 3 * 3.5, kHeightTolerance);
  EXPECT_NEAR(storey, 3.5, kHeightTolerance);
  EXPECT_NEAR(BuildingTypeHeight("no_such_value"), 3 * 3.5, kHeightTolerance);
}

TEST(OsmImportTest, BuildingsWithoutHeightsFailWithWhatWasRead) {
  // Five of the six buildings carry no height tag: without a fall-back the import fails after reading the whole
  // file, naming the first and counting them, and the summary of what was read travels with the error.
  try {
    (void)ImportCityMap(std::vector<std::filesystem::path>{NoHeightsOsm()}, {}, {});
    ADD_FAILURE() << "expected a MapImportError";
  } catch (const MapImportError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_NE(message.find("way/101"), std::string::npos) << message;
    EXPECT_NE(message.find("5 of the 6 buildings"), std::string::npos) << message;
    EXPECT_NE(message.find("--height-from-type"), std::string::npos) << message;
    EXPECT_EQ(e.summary().buildings, 1);
    EXPECT_EQ(e.summary().skipped_count(SkipReason::kMissingHeight), 5);
    EXPECT_EQ(e.summary().height_count(HeightSource::kTag), 1);
  }
}

TEST(OsmImportTest, BuildingsWithoutHeightsImportWithTheirHeightSourceCounted) {
  MapImportOptions options;
  options.height_from_levels = true;
  options.height_from_type = true;
  const ImportedMap imported = ImportCityMap(std::vector<std::filesystem::path>{NoHeightsOsm()}, {}, options);
  const ImportSummary& s = imported.summary;
  EXPECT_EQ(s.buildings, 6);
  EXPECT_EQ(s.height_count(HeightSource::kTag), 1);           // way/106, 14.5 m
  EXPECT_EQ(s.height_count(HeightSource::kLevels), 1);        // way/104, 4 levels
  EXPECT_EQ(s.height_count(HeightSource::kBuildingType), 4);  // house, apartments, yes, garage
  EXPECT_EQ(s.height_count(HeightSource::kDefault), 0);
  EXPECT_EQ(s.skipped_count(SkipReason::kMissingHeight), 0);
  EXPECT_NE(s.BriefReport().find("4 from the building type"), std::string::npos) << s.BriefReport();
  std::map<std::string, double> heights;
  for (const Building& b : imported.map.buildings()) heights[b.id] = b.height;
  EXPECT_NEAR(heights.at("way/101"), BuildingTypeHeight("house"), kHeightTolerance);
  EXPECT_NEAR(heights.at("way/102"), BuildingTypeHeight("apartments"), kHeightTolerance);
  EXPECT_NEAR(heights.at("way/103"), BuildingTypeHeight("yes"), kHeightTolerance);
  EXPECT_NEAR(heights.at("way/104"), 4 * options.metres_per_level, kHeightTolerance);
  EXPECT_NEAR(heights.at("way/105"), BuildingTypeHeight("garage"), kHeightTolerance);
  EXPECT_NEAR(heights.at("way/106"), 14.5, kHeightTolerance);

  // A default height instead of the table: every building still without one gets it.
  options.height_from_type = false;
  options.default_height = 8.0;
  const ImportedMap by_default = ImportCityMap(std::vector<std::filesystem::path>{NoHeightsOsm()}, {}, options);
  EXPECT_EQ(by_default.summary.height_count(HeightSource::kDefault), 4);
  EXPECT_EQ(by_default.summary.height_count(HeightSource::kLevels), 1);
  options.default_height = 0.5;  // below kDefaultHeightBounds
  ExpectInputError([&] { (void)ImportCityMap(std::vector<std::filesystem::path>{NoHeightsOsm()}, {}, options); },
                   {"default_height"});
}

TEST(OsmImportTest, MapSuppliesSitesOnFlatRoofsAndOpenAreas) {
  MapImportOptions options;
  options.height_from_type = true;
  options.sites_from_map = true;
  const ImportedMap imported = ImportCityMap(std::vector<std::filesystem::path>{NoHeightsOsm()}, {}, options);
  const ImportSummary& s = imported.summary;
  // Flat roofs: every building but the gabled garage (way/105). Each 20 m square's centroid is 10 m from its
  // walls, the 30 m one's 15 m.
  EXPECT_EQ(s.derived_rooftop_sites, 5);
  // Open areas: the park and the surface car park (the underground one is no landing site). The 100 m park holds
  // a 3 x 3 grid 40 m apart, the outer points 10 m from its edge; the 30 m x 50 m car park its centre, 15 m from
  // the edge, capped at 12 m.
  EXPECT_EQ(s.open_areas, 2);
  EXPECT_EQ(s.derived_open_sites, 10);
  EXPECT_EQ(s.sites, 15);
  EXPECT_EQ(s.rooftop_sites, 5);                      // the CityMap puts each rooftop site on its building
  constexpr double kProjectedSquareTolerance = 0.05;  // m: the test file's squares are laid out with a rounded scale
  for (const LandingSite& site : imported.map.sites()) {
    EXPECT_GE(site.radius, kMinDerivedSiteRadius);
    EXPECT_NEAR(site.risk, DerivedSiteRisk(site.radius), 1e-12);
    if (site.on_rooftop()) {
      EXPECT_NEAR(site.altitude(), imported.map.building(site.building).height, kHeightTolerance);
      const double expected = imported.map.building(site.building).id == "way/102" ? 15.0 : 10.0;
      EXPECT_NEAR(site.radius, expected, kProjectedSquareTolerance) << site.id;
    } else {
      EXPECT_EQ(site.altitude(), 0.0);
      EXPECT_FALSE(imported.map.IsInsideBuilding(site.p_W + Eigen::Vector3d(0, 0, -0.1))) << site.id;
      EXPECT_NE(site.id.find(site.id.rfind("amenity=parking", 0) == 0 ? "way/202" : "leisure=park"), std::string::npos)
          << site.id;
    }
  }
  // Risk falls with the clear radius (procedural_city.h's fit): 0.698 − 0.192 ln 10.
  EXPECT_NEAR(DerivedSiteRisk(10.0), 0.698 - 0.192 * std::log(10.0), 1e-12);
  EXPECT_EQ(DerivedSiteRisk(1e6), 0.0);
}

TEST(RealOsmDataTest, UpperEastSideBuildingsImportWithTypeHeightsAndSupplyRooftopSites) {
  MapImportOptions options;
  options.height_from_levels = true;
  options.height_from_type = true;
  options.sites_from_map = true;
  const ImportedMap imported = ImportCityMap(
      std::vector<std::filesystem::path>{OsmDataDir() / "upper-east-side-buildings.geojson"}, {}, options);
  const ImportSummary& s = imported.summary;
  EXPECT_EQ(s.buildings, 1239);  // every building, 11 of them without a height tag
  EXPECT_EQ(s.height_count(HeightSource::kTag), 1228);
  EXPECT_EQ(s.height_count(HeightSource::kLevels), 2);
  EXPECT_EQ(s.height_count(HeightSource::kBuildingType), 9);
  EXPECT_GT(s.derived_rooftop_sites, 500);  // most Manhattan roofs are flat and wider than 4 m
  EXPECT_EQ(s.rooftop_sites, s.derived_rooftop_sites);
}

}  // namespace
}  // namespace uascma::planning
