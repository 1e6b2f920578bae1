// GeoJSON building reader (RFC 7946 FeatureCollection, as Overpass exports it): Polygon and MultiPolygon features
// tagged building=* with a height; the rules are in include/uascma/planning/map_import.h.
#include "uascma/planning/map_geojson.h"

#include <nlohmann/json.hpp>

#include <fmt/format.h>

#include "map_import_detail.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/common/json_reader.h"
#include "uascma/planning/map_projection.h"

namespace uascma::planning {
namespace {

// A property as text: strings as they are, numbers printed; nullopt when absent or null.
std::optional<std::string> Property(const nlohmann::json& properties, const char* key) {
  if (!properties.is_object()) return std::nullopt;
  const auto it = properties.find(key);
  if (it == properties.end() || it->is_null()) return std::nullopt;
  if (it->is_string()) return it->get<std::string>();
  if (it->is_number()) return fmt::format("{}", it->get<double>());
  return it->dump();
}

// "features[12] (way/248773492)": the index always, the OSM id ("@id" as Overpass writes it, else "id") if any.
std::string FeatureName(const nlohmann::json& feature, std::size_t index) {
  std::string id;
  if (feature.is_object()) {
    const auto properties = feature.find("properties");
    if (properties != feature.end()) {
      if (auto at_id = Property(*properties, "@id")) id = *at_id;
    }
    if (id.empty()) {
      const auto it = feature.find("id");
      if (it != feature.end() && !it->is_null()) id = it->is_string() ? it->get<std::string>() : it->dump();
    }
  }
  return id.empty() ? fmt::format("features[{}]", index) : fmt::format("features[{}] ({})", index, id);
}

// One linear ring: an array of at least 4 [lon, lat] positions, the last equal to the first (RFC 7946 §3.1.6).
// `ring`'s path starts with the feature's name ("features[12] (way/248773492)"), `ring_name` says which ring.
std::vector<GeoPoint> ReadRing(const JsonValue& ring, const std::string& feature, const std::string& ring_name) {
  const std::string& source = ring.source();
  if (!ring.IsArray()) throw InputError(source, feature, ring_name + " as an array of [lon, lat] positions");
  if (ring.size() < 4) {
    throw InputError(
        source, feature,
        fmt::format("{} of at least 4 positions (3 corners and the closing one), got {}", ring_name, ring.size()));
  }
  std::vector<GeoPoint> points;
  points.reserve(ring.size());
  const std::vector<JsonValue> positions = ring.Elements();
  for (std::size_t k = 0; k < positions.size(); ++k) {
    const JsonValue& position = positions[k];
    const std::vector<JsonValue> lon_lat = position.IsArray() ? position.Elements() : std::vector<JsonValue>{};
    if (lon_lat.size() < 2 || !lon_lat[0].IsNumber() || !lon_lat[1].IsNumber()) {
      throw InputError(source, feature,
                       fmt::format("{} position {} as [lon, lat] numbers, got {}", ring_name, k, position.Brief()));
    }
    const GeoPoint p{lon_lat[1].Number(), lon_lat[0].Number()};
    detail::CheckGeoPoint(p, source, fmt::format("{} {} position {}", feature, ring_name, k));
    points.push_back(p);
  }
  const GeoPoint& first = points.front();
  const GeoPoint& last = points.back();
  if (first.lat_deg != last.lat_deg || first.lon_deg != last.lon_deg) {
    throw InputError(source, feature, ring_name + " closed (its last position equal to its first)");
  }
  return detail::CleanRing(points, source, feature, ring_name);
}

// The rings of a Polygon's coordinates (outer ring, then holes), appended to `rings`.
void ReadPolygon(const JsonValue& polygon, const std::string& feature, const std::string& name,
                 std::vector<std::vector<GeoPoint>>* rings) {
  if (!polygon.IsArray() || polygon.size() == 0) {
    throw InputError(polygon.source(), feature, name + " as a non-empty array of rings");
  }
  const std::vector<JsonValue> elements = polygon.Elements();
  for (std::size_t r = 0; r < elements.size(); ++r) {
    rings->push_back(ReadRing(elements[r], feature, fmt::format("{} ring {}", name, r)));
  }
}

// The rings of a Polygon or MultiPolygon geometry, appended to `rings`.
void ReadGeometryRings(const JsonValue& geometry, bool multi, const std::string& feature,
                       std::vector<std::vector<GeoPoint>>* rings) {
  const JsonValue coordinates = geometry.Member("coordinates");
  if (coordinates.IsMissing()) throw InputError(geometry.source(), feature, "geometry.coordinates");
  if (!multi) {
    ReadPolygon(coordinates, feature, "polygon", rings);
    return;
  }
  if (!coordinates.IsArray() || coordinates.size() == 0) {
    throw InputError(geometry.source(), feature, "MultiPolygon coordinates as a non-empty array of polygons");
  }
  const std::vector<JsonValue> polygons = coordinates.Elements();
  for (std::size_t p = 0; p < polygons.size(); ++p) {
    ReadPolygon(polygons[p], feature, fmt::format("polygon {}", p), rings);
  }
}

// One feature of the collection (its paths start with its name): a building appended to `data`, or a skip
// recorded in its summary.
void ReadFeature(const JsonValue& feature, const std::string& name, const MapImportOptions& options, GeoMapData* data) {
  const std::string& source = feature.source();
  ImportSummary& summary = data->summary;
  if (!feature.IsObject() || feature.Member("type").OptionalString().value_or("") != "Feature") {
    throw InputError(source, name, "a GeoJSON Feature object");
  }
  ++summary.features;
  const JsonValue geometry = feature.Member("geometry");
  const std::string geometry_type =
      geometry.IsObject() ? geometry.Member("type").OptionalString().value_or("") : "null";
  if (geometry_type != "Polygon" && geometry_type != "MultiPolygon") {
    detail::RecordSkip(&summary, source, name, SkipReason::kNotPolygon, "geometry " + geometry_type);
    return;
  }
  const nlohmann::json empty = nlohmann::json::object();
  const JsonValue properties_value = feature.Member("properties");
  const nlohmann::json& properties = properties_value.IsMissing() ? empty : properties_value.json();
  const bool multi = geometry_type == "MultiPolygon";
  if (!detail::IsBuildingValue(Property(properties, "building"))) {
    const auto kind = options.sites_from_map
                          ? detail::OpenAreaKind([&](const char* key) { return Property(properties, key); })
                          : std::nullopt;
    if (!kind) {
      detail::RecordSkip(&summary, source, name, SkipReason::kNotBuilding, "no building tag");
      return;
    }
    GeoOpenArea area;
    area.id = Property(properties, "@id").value_or(name);
    area.kind = *kind;
    ReadGeometryRings(geometry, multi, name, &area.rings);
    data->open_areas.push_back(std::move(area));
    ++summary.open_areas;
    return;
  }

  GeoBuilding building;
  building.id = Property(properties, "@id").value_or(name);
  ReadGeometryRings(geometry, multi, name, &building.rings);
  const detail::BuildingTags tags{Property(properties, "building"), Property(properties, "height"),
                                  Property(properties, "building:levels"), Property(properties, "roof:shape")};
  building.flat_roof = !tags.roof_shape || *tags.roof_shape == "flat";
  const auto height = detail::ResolveHeight(tags, source, name, options, &summary);
  if (!height) return;  // skipped and counted
  building.height = *height;
  data->buildings.push_back(std::move(building));
  ++summary.buildings;
}

}  // namespace

void ParseGeoJsonBuildings(std::string_view text, const std::string& source, const MapImportOptions& options,
                           GeoMapData* data) {
  const JsonDocument document = JsonDocument::Parse(text, source);  // common/json_reader.h (duplicate keys too)
  const JsonValue root = document.root();
  if (!root.IsObject() || root.Member("type").OptionalString().value_or("") != "FeatureCollection") {
    throw InputError(source, "type", "a GeoJSON FeatureCollection");
  }
  const std::vector<JsonValue> features = root.Member("features").Elements("an array of GeoJSON features");
  ImportSummary& summary = data->summary;
  summary.sources.push_back(source);
  const int missing_before = summary.skipped_count(SkipReason::kMissingHeight);
  for (std::size_t index = 0; index < features.size(); ++index) {
    const std::string name = FeatureName(features[index].json(), index);
    // The feature's members named under its name, OSM id included: "features[3] (way/7).geometry.type".
    ReadFeature(JsonValue(&features[index].json(), &source, name), name, options, data);
  }
  detail::RequireHeightsResolved(missing_before, source, options, summary);
}

void ReadGeoJsonBuildings(const std::filesystem::path& path, const MapImportOptions& options, GeoMapData* data) {
  ParseGeoJsonBuildings(ReadFile(path), path.string(), options, data);
}

}  // namespace uascma::planning
