// OpenStreetMap building reader (.osm XML, .osm.pbf and the other formats libosmium reads): closed ways and
// type=multipolygon relations tagged building=*, assembled into polygons by libosmium's area assembler; the
// rules are in include/uascma/planning/map_import.h.
//
// Two passes over the file, as libosmium's multipolygon support works: the first collects the multipolygon
// relations, the second stores node locations, hands ways to the relations that need them and assembles areas
// (one per building way, one per complete building relation) while a handler of ours counts every tagged object
// and checks building ways for malformed geometry.
#include "uascma/planning/map_osm.h"

// GCC 12 reports a false -Wstringop-overread inside libosmium's object builder (a flexible trailing array it
// cannot see through); silence it for libosmium's headers only.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wstringop-overread"
#include <osmium/area/assembler.hpp>
#include <osmium/area/multipolygon_manager.hpp>
#include <osmium/area/problem_reporter_stream.hpp>
#include <osmium/handler.hpp>
#include <osmium/handler/node_locations_for_ways.hpp>
#include <osmium/index/map/flex_mem.hpp>
#include <osmium/io/any_input.hpp>
#include <osmium/tags/tags_filter.hpp>
#include <osmium/visitor.hpp>
#pragma GCC diagnostic pop

#include <algorithm>
#include <cstring>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "map_import_detail.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/planning/map_projection.h"

namespace uascma::planning {
namespace {

// libosmium walks a tag list as key\0value\0 pairs until it lands exactly on the list's end. A .osm.pbf string may
// hold a NUL byte (its strings are length-delimited); copied into the list it splits a key or value in two, the
// pairs no longer land on the end, and the walk reads past the buffer (found by fuzzing: Tag::after_null,
// heap-buffer-overflow). So the bytes are checked here, with bounds, before any tag is read.
bool TagsWellFormed(const osmium::TagList& tags) {
  const char* p = reinterpret_cast<const char*>(tags.data()) + sizeof(osmium::TagList);
  const char* const end = reinterpret_cast<const char*>(tags.data()) + tags.byte_size();
  while (p < end) {
    for (int part = 0; part < 2; ++part) {  // the key, then the value
      const void* nul = std::memchr(p, 0, static_cast<std::size_t>(end - p));
      if (nul == nullptr) return false;
      p = static_cast<const char*>(nul) + 1;
    }
  }
  return p == end;
}

void RequireWellFormedTags(const osmium::TagList& tags, const std::string& source, const std::string& name) {
  if (!TagsWellFormed(tags)) throw InputError(source, name, "tags as key/value strings without NUL bytes");
}

// The guard ahead of every other handler of both passes: a way's or relation's tags are checked before our
// collector or libosmium's multipolygon manager reads them.
class TagChecker : public osmium::handler::Handler {
 public:
  explicit TagChecker(std::string source) : source_(std::move(source)) {}
  void way(const osmium::Way& way) { RequireWellFormedTags(way.tags(), source_, fmt::format("way/{}", way.id())); }
  void relation(const osmium::Relation& relation) {
    RequireWellFormedTags(relation.tags(), source_, fmt::format("relation/{}", relation.id()));
  }

 private:
  std::string source_;
};

std::optional<std::string> Tag(const osmium::TagList& tags, const char* key) {
  const char* value = tags.get_value_by_key(key);
  if (value == nullptr) return std::nullopt;
  return std::string(value);
}

std::string OneLine(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

class BuildingCollector : public osmium::handler::Handler {
 public:
  BuildingCollector(std::string source, const MapImportOptions& options, GeoMapData* data,
                    const std::ostringstream* problems)
      : source_(std::move(source)), options_(options), data_(data), problems_(problems) {}

  // Every tagged node is a map feature that is not a polygon.
  void node(const osmium::Node& node) {
    if (node.tags().empty()) return;
    ++data_->summary.features;
    detail::RecordSkip(&data_->summary, source_, fmt::format("node/{}", node.id()), SkipReason::kNotPolygon,
                       "a node (point)");
  }

  void way(const osmium::Way& way) {
    if (way.tags().empty()) return;  // untagged ways are geometry of relations, not features
    ++data_->summary.features;
    const std::string name = fmt::format("way/{}", way.id());
    const auto& nodes = way.nodes();
    if (nodes.size() < 2 || !nodes.is_closed()) {
      detail::RecordSkip(&data_->summary, source_, name, SkipReason::kNotPolygon, "an open way (a line)");
      return;
    }
    if (way.tags().has_tag("area", "no")) {
      detail::RecordSkip(&data_->summary, source_, name, SkipReason::kNotPolygon, "a closed way tagged area=no");
      return;
    }
    if (!detail::IsBuildingValue(Tag(way.tags(), "building"))) {
      if (OpenArea(way.tags())) {
        expected_.insert(name);  // an open area: its polygon comes from the assembler
        open_area_names_.insert(name);
        return;
      }
      detail::RecordSkip(&data_->summary, source_, name, SkipReason::kNotBuilding, "no building tag");
      return;
    }
    if (nodes.size() < 4) {
      throw InputError(
          source_, name,
          fmt::format("a closed way of at least 4 nodes (3 corners and the closing one), got {}", nodes.size()));
    }
    for (const auto& node_ref : nodes) {
      if (!node_ref.location().valid()) {
        throw InputError(source_, name, fmt::format("node {} in the file with a valid location", node_ref.ref()));
      }
    }
    expected_.insert(name);  // its area comes from the assembler
  }

  void relation(const osmium::Relation& relation) {
    if (relation.tags().empty()) return;
    ++data_->summary.features;
    const std::string name = fmt::format("relation/{}", relation.id());
    const char* type = relation.tags().get_value_by_key("type");
    if (type == nullptr || std::string_view(type) != "multipolygon") {
      detail::RecordSkip(&data_->summary, source_, name, SkipReason::kNotBuilding,
                         fmt::format("a relation of type {}", type ? type : "(none)"));
      return;
    }
    if (!detail::IsBuildingValue(Tag(relation.tags(), "building"))) {
      if (OpenArea(relation.tags())) {
        expected_.insert(name);
        open_area_names_.insert(name);
        return;
      }
      detail::RecordSkip(&data_->summary, source_, name, SkipReason::kNotBuilding, "no building tag");
      return;
    }
    expected_.insert(name);
  }

  // An assembled area: from a closed way (orig_id the way's) or from a multipolygon relation.
  void area(const osmium::Area& area) {
    const std::string name = fmt::format("{}/{}", area.from_way() ? "way" : "relation", area.orig_id());
    assembled_.insert(name);
    const bool building_area = detail::IsBuildingValue(Tag(area.tags(), "building"));
    if (!building_area && area.num_rings().first == 0) {  // an open area that does not close: no sites from it
      detail::RecordSkip(&data_->summary, source_, name, SkipReason::kNotPolygon, "an open area that does not close");
      return;
    }
    if (area.num_rings().first == 0) {
      // The assembler could not build a polygon; its report names the problem and the object.
      std::string problem;
      std::istringstream lines(problems_->str());
      const std::string tag = fmt::format(" on {}{} ", area.from_way() ? 'w' : 'r', area.orig_id());
      for (std::string line; std::getline(lines, line);) {
        if (line.find(tag) != std::string::npos) {
          problem = OneLine(line);
          break;
        }
      }
      throw InputError(
          source_, name,
          "rings that close into a valid polygon" + (problem.empty() ? std::string() : " (" + problem + ")"));
    }
    std::vector<std::vector<GeoPoint>> rings;
    auto add_ring = [&](const osmium::NodeRefList& ring, const std::string& ring_name) {
      std::vector<GeoPoint> points;
      points.reserve(ring.size());
      for (const auto& node_ref : ring) {
        const GeoPoint p{node_ref.location().lat(), node_ref.location().lon()};
        detail::CheckGeoPoint(p, source_, name);
        points.push_back(p);
      }
      rings.push_back(detail::CleanRing(points, source_, name, ring_name));
    };
    int outer_index = 0;
    for (const auto& outer : area.outer_rings()) {
      add_ring(outer, fmt::format("outer ring {}", outer_index));
      int inner_index = 0;
      for (const auto& inner : area.inner_rings(outer)) {
        add_ring(inner, fmt::format("inner ring {}.{}", outer_index, inner_index++));
      }
      ++outer_index;
    }
    if (!building_area) {  // an open area (sites_from_map)
      const auto kind = OpenArea(area.tags());
      if (!kind) return;
      data_->open_areas.push_back({name, *kind, std::move(rings)});
      ++data_->summary.open_areas;
      return;
    }
    GeoBuilding building;
    building.id = name;
    building.rings = std::move(rings);
    const detail::BuildingTags tags{Tag(area.tags(), "building"), Tag(area.tags(), "height"),
                                    Tag(area.tags(), "building:levels"), Tag(area.tags(), "roof:shape")};
    building.flat_roof = !tags.roof_shape || *tags.roof_shape == "flat";
    const auto height = detail::ResolveHeight(tags, source_, name, options_, &data_->summary);
    if (!height) return;
    building.height = *height;
    data_->buildings.push_back(std::move(building));
    ++data_->summary.buildings;
  }

  const std::set<std::string>& expected() const { return expected_; }

  // The open-area kind of a way's or relation's tags when sites are derived from the map, else nullopt.
  std::optional<std::string> OpenArea(const osmium::TagList& tags) const {
    if (!options_.sites_from_map) return std::nullopt;
    return detail::OpenAreaKind([&](const char* key) { return Tag(tags, key); });
  }
  const std::set<std::string>& assembled() const { return assembled_; }
  const std::set<std::string>& open_area_names() const { return open_area_names_; }

 private:
  std::string source_;
  const MapImportOptions& options_;
  GeoMapData* data_;
  const std::ostringstream* problems_;
  std::set<std::string> expected_;         // building ways and relations that should become areas
  std::set<std::string> assembled_;        // the ones that did
  std::set<std::string> open_area_names_;  // of expected_, the open areas (sites_from_map)
};

}  // namespace

void ReadOsmBuildings(const std::filesystem::path& path, const MapImportOptions& options, GeoMapData* data) {
  const std::string source = path.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(source, "file", "a readable OSM file");
  try {
    // libosmium reads the file from memory: its Reader left the descriptor of a malformed .osm.pbf open, one per
    // failed read (found by fuzz/osm_pbf_fuzzer: the process ran out of descriptors), and a buffer has
    // none. Format and compression still come from the name; a city extract is a few MB.
    const std::string contents = ReadFile(path);
    const osmium::io::File named(source);
    osmium::io::File file(contents.data(), contents.size());
    file.set_format(named.format());
    file.set_compression(named.compression());
    std::ostringstream problems;
    osmium::area::ProblemReporterStream reporter(problems);
    osmium::area::Assembler::config_type config;
    config.problem_reporter = &reporter;
    config.create_empty_areas = true;  // a failed assembly still yields an (empty) area, so it is reported
    // Buildings: a `building` tag other than "no" (the first matching rule decides).
    osmium::TagsFilter filter{false};
    filter.add_rule(false, "building", "no");
    filter.add_rule(true, "building");
    if (options.sites_from_map) {  // open areas too (map_import.h); the collector keeps the kinds it lists
      for (const char* key : {"leisure", "amenity", "landuse"}) filter.add_rule(true, key);
    }
    osmium::area::MultipolygonManager<osmium::area::Assembler> manager{config, filter};

    // Pass 1, as osmium::relations::read_relations does, with the tag guard ahead of the manager's filter.
    TagChecker checker(source);
    {
      osmium::io::Reader relations{file, osmium::osm_entity_bits::relation};
      osmium::apply(relations, checker, manager);
      relations.close();
      manager.prepare_for_lookup();
    }

    data->summary.sources.push_back(source);
    const int missing_before = data->summary.skipped_count(SkipReason::kMissingHeight);
    BuildingCollector collector(source, options, data, &problems);
    using Index = osmium::index::map::FlexMem<osmium::unsigned_object_id_type, osmium::Location>;
    Index index;
    osmium::handler::NodeLocationsForWays<Index> locations{index};
    locations.ignore_errors();        // a missing node is reported by the collector, naming the way
    osmium::io::Reader reader{file};  // pass 2
    osmium::apply(reader, checker, locations, collector,
                  manager.handler([&collector](osmium::memory::Buffer&& buffer) { osmium::apply(buffer, collector); }));
    reader.close();

    // Multipolygons with members outside the file (an extract cut through them) are skipped, not errors.
    std::set<std::string> incomplete;
    manager.for_each_incomplete_relation([&](const osmium::relations::RelationHandle& handle) {
      incomplete.insert(fmt::format("relation/{}", handle->id()));
    });
    for (const std::string& name : collector.expected()) {
      if (collector.assembled().count(name)) continue;
      if (incomplete.count(name)) {
        detail::RecordSkip(&data->summary, source, name, SkipReason::kIncompleteRelation,
                           "members missing from the file");
        continue;
      }
      if (collector.open_area_names().count(name)) {
        detail::RecordSkip(&data->summary, source, name, SkipReason::kNotPolygon,
                           "an open area libosmium cannot assemble");
        continue;
      }
      throw InputError(source, name, "a building polygon libosmium can assemble");
    }
    detail::RequireHeightsResolved(missing_before, source, options, data->summary);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(source, "OSM data", fmt::format("a readable OSM file ({})", OneLine(e.what())));
  }
}

}  // namespace uascma::planning
