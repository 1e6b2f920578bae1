// GeoJSON building reader (RFC 7946 FeatureCollection, as Overpass exports it): Polygon and MultiPolygon features
// tagged building=* with a height; the rules are in include/uascma/planning/map_import.h.
#include <nlohmann/json.hpp>

#include <fmt/format.h>

#include "map_import_detail.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/common/json_io.h"
#include "uascma/planning/map_import.h"

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
std::vector<GeoPoint> ReadRing(const nlohmann::json& ring, const std::string& source, const std::string& feature,
                               const std::string& ring_name) {
  if (!ring.is_array()) throw InputError(source, feature, ring_name + " as an array of [lon, lat] positions");
  if (ring.size() < 4) {
    throw InputError(source, feature,
                     fmt::format("{} of at least 4 positions (3 corners and the closing one), got {}", ring_name,
                                 ring.size()));
  }
  std::vector<GeoPoint> points;
  points.reserve(ring.size());
  for (std::size_t k = 0; k < ring.size(); ++k) {
    const auto& position = ring[k];
    if (!position.is_array() || position.size() < 2 || !position[0].is_number() || !position[1].is_number()) {
      throw InputError(source, feature, fmt::format("{} position {} as [lon, lat] numbers, got {}", ring_name, k,
                                                    position.dump()));
    }
    const GeoPoint p{position[1].get<double>(), position[0].get<double>()};
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
void ReadPolygon(const nlohmann::json& polygon, const std::string& source, const std::string& feature,
                 const std::string& name, std::vector<std::vector<GeoPoint>>* rings) {
  if (!polygon.is_array() || polygon.empty()) {
    throw InputError(source, feature, name + " as a non-empty array of rings");
  }
  for (std::size_t r = 0; r < polygon.size(); ++r) {
    rings->push_back(ReadRing(polygon[r], source, feature, fmt::format("{} ring {}", name, r)));
  }
}

// One feature of the collection: a building appended to `data`, or a skip recorded in its summary.
void ReadFeature(const nlohmann::json& feature, const std::string& name, const std::string& source,
                 const MapImportOptions& options, GeoMapData* data) {
  ImportSummary& summary = data->summary;
  if (!feature.is_object() || feature.value("type", "") != "Feature") {
    throw InputError(source, name, "a GeoJSON Feature object");
  }
  ++summary.features;
  const auto geometry_it = feature.find("geometry");
  const std::string geometry_type =
      (geometry_it != feature.end() && geometry_it->is_object()) ? geometry_it->value("type", "") : "null";
  if (geometry_type != "Polygon" && geometry_type != "MultiPolygon") {
    detail::RecordSkip(&summary, source, name, SkipReason::kNotPolygon, "geometry " + geometry_type);
    return;
  }
  const nlohmann::json empty = nlohmann::json::object();
  const auto properties_it = feature.find("properties");
  const nlohmann::json& properties = properties_it != feature.end() ? *properties_it : empty;
  const auto coordinates = geometry_it->find("coordinates");
  auto read_rings = [&](std::vector<std::vector<GeoPoint>>* rings) {
    if (coordinates == geometry_it->end()) throw InputError(source, name, "geometry.coordinates");
    if (geometry_type == "Polygon") {
      ReadPolygon(*coordinates, source, name, "polygon", rings);
      return;
    }
    if (!coordinates->is_array() || coordinates->empty()) {
      throw InputError(source, name, "MultiPolygon coordinates as a non-empty array of polygons");
    }
    for (std::size_t p = 0; p < coordinates->size(); ++p) {
      ReadPolygon((*coordinates)[p], source, name, fmt::format("polygon {}", p), rings);
    }
  };
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
    read_rings(&area.rings);
    data->open_areas.push_back(std::move(area));
    ++summary.open_areas;
    return;
  }

  GeoBuilding building;
  building.id = Property(properties, "@id").value_or(name);
  read_rings(&building.rings);
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
  nlohmann::json document;
  try {
    document = nlohmann::json::parse(text);
    CheckJsonKeysUnique(text, source);  // common/json_io.h (issue 26 item 6)
  } catch (const nlohmann::json::exception& e) {  // parse_error, or out_of_range for a number like 1e999
    throw InputError(source, "JSON", fmt::format("valid JSON ({})", e.what()));
  }
  const auto type = document.is_object() ? document.find("type") : document.end();
  if (!document.is_object() || type == document.end() || *type != "FeatureCollection") {
    throw InputError(source, "type", "a GeoJSON FeatureCollection");
  }
  const auto features = document.find("features");
  if (features == document.end() || !features->is_array()) {
    throw InputError(source, "features", "an array of GeoJSON features");
  }
  ImportSummary& summary = data->summary;
  summary.sources.push_back(source);
  const int missing_before = summary.skipped_count(SkipReason::kMissingHeight);
  for (std::size_t index = 0; index < features->size(); ++index) {
    const nlohmann::json& feature = (*features)[index];
    const std::string name = FeatureName(feature, index);
    try {
      ReadFeature(feature, name, source, options, data);
    } catch (const nlohmann::json::exception& e) {  // a member of the wrong JSON type
      throw InputError(source, name, fmt::format("well-typed GeoJSON members ({})", e.what()));
    }
  }
  detail::RequireHeightsResolved(missing_before, source, options, summary);
}

void ReadGeoJsonBuildings(const std::filesystem::path& path, const MapImportOptions& options, GeoMapData* data) {
  ParseGeoJsonBuildings(ReadFile(path), path.string(), options, data);
}

}  // namespace uascma::planning
