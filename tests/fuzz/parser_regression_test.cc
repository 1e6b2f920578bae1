// Regression tests for the inputs that broke a parser: each is a crash, an escaped exception
// or undefined behaviour found by a libFuzzer harness of fuzz/ or while writing them. The rule they pin
// down: on malformed input every parser throws uascma::InputError (exit code 2 in the CLI) naming the
// source and the field, and nothing else.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "uascma/campaign/config.h"
#include "uascma/common/error.h"
#include "uascma/decision/battery_mdp_file.h"
#include "uascma/decision/cma_mdp.h"
#include "uascma/decision/policy_file.h"
#include "uascma/planning/map_geojson.h"
#include "uascma/planning/map_import.h"
#include "uascma/planning/map_osm.h"
#include "uascma/planning/mission_file.h"

namespace uascma {
namespace {

// `parse` must throw InputError whose message contains every one of `named`.
void ExpectInputError(const std::function<void()>& parse, std::initializer_list<std::string> named) {
  try {
    parse();
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    for (const auto& text : named) EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "escaped as " << typeid(e).name() << ": " << e.what();
  }
}

std::string Slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::filesystem::path WriteScratch(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("uascma_regression_" + std::to_string(::getpid()) + name);
  std::ofstream(path) << text;
  return path;
}

// A mapping key that is itself a sequence ("? [a]") escaped RequireOnlyKeys as YAML::TypedBadConversion
// (an internal error, exit 1).
TEST(ParserRegressionTest, CampaignYamlWithANonScalarKey) {
  ExpectInputError([] { campaign::ParseCampaignConfig("? [a]\n: 1\n", "c.yaml"); }, {"c.yaml", "(top level)"});
  ExpectInputError([] { campaign::ParseCampaignConfig("wind: {? {x: 1}: 2}\n", "c.yaml"); }, {"c.yaml", "wind"});
}

// 1e300 blocks was cast to int before the range check (undefined behaviour; INT_MIN in practice), and a
// count of 2^32 + 1 cells wrapped to 1 and passed the check.
TEST(ParserRegressionTest, CampaignYamlIntegersAreBoundedBeforeTheirConversion) {
  ExpectInputError([] { campaign::ParseCampaignConfig("map: {blocks_north: 1e300}\n", "c.yaml"); },
                   {"c.yaml", "map.blocks_north", "1 to 200 blocks"});
  ExpectInputError([] { campaign::ParseCampaignConfig("runs: -1e300\n", "c.yaml"); }, {"c.yaml", "runs"});
  ExpectInputError([] { campaign::ParseCampaignConfig("fault: {motors: [4294967297]}\n", "c.yaml"); },
                   {"c.yaml", "fault.motors[0]"});
}

// The seed is one unsigned 64-bit type: "-1" no longer wraps to 2^64-1, and the procedural city's seed
// no longer goes through a double (which lost every seed above 2^53).
TEST(ParserRegressionTest, CampaignYamlSeeds) {
  ExpectInputError([] { campaign::ParseCampaignConfig("seed: -1\n", "c.yaml"); }, {"c.yaml", "seed", "2^64-1"});
  ExpectInputError([] { campaign::ParseCampaignConfig("map: {procedural_seed: 1.5}\n", "c.yaml"); },
                   {"c.yaml", "map.procedural_seed"});
  const auto config = campaign::ParseCampaignConfig("map: {procedural_seed: 18446744073709551615}\n", "c.yaml");
  EXPECT_EQ(config.map.procedural_seed, 18446744073709551615ULL);
}

TEST(ParserRegressionTest, WeightsYamlWithANonScalarKeyOrAnUnknownTopLevelKey) {
  const std::string weights =
      "  end_states: {C: 0.163, FL: 0.408, T: 0, E: 0}\n"
      "  actions: {NoOp: 0.082, Terminate: 0, LandASAP: 0.02, LandPract: 0.041}\n";
  const auto nested = WriteScratch("nested.yaml", "weights:\n" + weights +
                                                      "  state_features: {FS: 0, MH: 0, MM: 0.082, BH: 0.041, RM: "
                                                      "0.163, ? [x]: 1}\n");
  ExpectInputError([&] { decision::LoadCmaConfig(nested); }, {"weights.state_features"});
  const auto typo =
      WriteScratch("typo.yaml", "gama: 0.9\nweights:\n" + weights +
                                    "  state_features: {FS: 0, MH: 0, MM: 0.082, BH: 0.041, RM: 0.163}\n");
  ExpectInputError([&] { decision::LoadCmaConfig(typo); }, {"gama"});
  std::filesystem::remove(nested);
  std::filesystem::remove(typo);
}

// Found by geojson_fuzzer and policy_json_fuzzer: a number beyond the range of double ("40.73e0699" in a
// coordinate, "0.09000E0010000099" in a weight) makes nlohmann::json throw out_of_range, not parse_error;
// it escaped the parsers (std::terminate under the fuzzer, "internal error", exit 1, in the CLI).
TEST(ParserRegressionTest, JsonNumbersBeyondDoubleAreInputErrors) {
  ExpectInputError(
      [] {
        planning::GeoMapData data;
        planning::ParseGeoJsonBuildings(R"({"type": "FeatureCollection", "features": [{"type": "Feature",
            "geometry": {"type": "Polygon", "coordinates": [[[-73.99, 40.73e0699]]]}}]})",
                                        "city.geojson", planning::MapImportOptions{}, &data);
      },
      {"city.geojson", "features[0].geometry.coordinates", "double's range"});
  const auto policy = WriteScratch("policy.json", R"({"format": "uascma-policy/1", "gamma": 0.09000E0010000099})");
  ExpectInputError([&] { decision::ReadPolicyFile(policy); }, {policy.string(), "gamma", "double's range"});
  std::filesystem::remove(policy);
}

// Found by mission_wpl_fuzzer: a whole number beyond int's range in a .waypoints integer field (frame
// 1088888888888888) was cast to int (undefined behaviour); in a .plan, nlohmann::json's get<int> wrapped a
// command of 2^32 + 16 to 16 (NAV_WAYPOINT). Both are InputErrors naming the field now.
TEST(ParserRegressionTest, MissionIntegersBeyondIntAreInputErrors) {
  const std::string home = "QGC WPL 110\n0\t1\t0\t16\t0\t0\t0\t0\t40.775\t-73.955\t12\t1\n";
  ExpectInputError(
      [&] {
        planning::ParseMission(home + "1\t0\t1088888888888888\t16\t0\t0\t0\t0\t40.776\t-73.955\t40\t1\n", "m.waypoints",
                               planning::MissionFormat::kQgcWpl);
      },
      {"m.waypoints", "line 3 frame"});
  ExpectInputError(
      [&] {
        planning::ParseMission(home + "1\t0\t3\t-1e300\t0\t0\t0\t0\t40.776\t-73.955\t40\t1\n", "m.waypoints",
                               planning::MissionFormat::kQgcWpl);
      },
      {"m.waypoints", "line 3 command"});
  ExpectInputError(
      [] {
        planning::ParseMission(R"({"fileType": "Plan", "version": 1, "mission": {"version": 2,
            "plannedHomePosition": [40.77, -73.96, 10], "items": [{"type": "SimpleItem", "command": 4294967312,
            "frame": 3, "params": [0, 0, 0, null, 40.771, -73.96, 30]}]}})",
                               "m.plan", planning::MissionFormat::kQgcPlan);
      },
      {"m.plan", "command", "4294967312"});
}

// Found by osm_xml_fuzzer and osm_pbf_fuzzer: undefined behaviour inside libosmium's own headers (a coordinate
// "-73.9E96" overflows its int64 while scaled, osmium/osm/location.hpp:182; a blob header without a type makes
// it call strncmp with a null pointer, pbf_input_format.hpp:196; a dense node's timestamp overflows,
// pbf_decoder.hpp:707). Suppressed for exactly those files by scripts/ubsan-suppressions.txt; what we answer is
// still an InputError naming the file. The overflowed coordinate comes back from libosmium as a wrong but valid
// longitude (-36.99°), which the import refuses as 3,223 km from the map's origin; each file is read, then
// projected, as `uascma map` and the fuzzers do.
TEST(ParserRegressionTest, OsmInputsThatHitLibosmiumUndefinedBehaviourAreInputErrors) {
  const auto xml = WriteScratch(".osm", R"(<?xml version="1.0" encoding="UTF-8"?>
<osm version="0.6" generator="uascma test">
  <node id="1" version="1" lat="40.7500" lon="-73.9800"/>
  <node id="2" version="1" lat="40.7500" lon="-73.9E96"/>
  <node id="3" version="1" lat="40.7506" lon="-73.9792"/>
  <way id="100" version="1"><nd ref="1"/><nd ref="2"/><nd ref="3"/><nd ref="1"/><tag k="building" v="yes"/>
    <tag k="height" v="10"/></way>
</osm>
)");
  // A 13-byte BlobHeader whose only fields are an unknown field 5 ("OSMHeader") and datasize 50: no type.
  const auto pbf = WriteScratch("-blob.osm.pbf", std::string("\x00\x00\x00\x0d\x2a\x09OSMHeader\x18\x32", 17));
  // A dense-node block whose delta-coded timestamps overflow int64 when scaled (pbf_decoder.hpp:707): the fuzzer's
  // own input, kept in tests/data/fuzz (mutated from the seeds of fuzz/osm_seeds.cc, not OSM data).
  const auto dense = WriteScratch("-dense.osm.pbf", Slurp(std::filesystem::path(UASCMA_SOURCE_DIR) / "tests" / "data" /
                                                          "fuzz" / "dense-node-timestamp-overflow.osm.pbf"));
  ASSERT_EQ(std::filesystem::file_size(dense), 673u);
  for (const auto& path : {xml, pbf, dense}) {
    SCOPED_TRACE(path.string());
    ExpectInputError(
        [&] {
          planning::GeoMapData geo;
          planning::ReadOsmBuildings(path, planning::MapImportOptions{}, &geo);
          planning::ImportSummary summary = geo.summary;
          (void)planning::ProjectToCityMap(geo, planning::MapImportOptions{}, &summary);
        },
        {path.string()});
    std::filesystem::remove(path);
  }
}

// Found by osm_pbf_fuzzer: a .osm.pbf string holding a NUL byte splits a tag of the copied tag list, libosmium's
// walk over key/value pairs then overshoots the list and reads past the buffer (AddressSanitizer: heap-buffer-
// overflow in osmium::Tag::after_null, from TagList::has_tag). The import now checks a list's bytes before reading
// any tag (src/planning/map_osm.cc TagsWellFormed) and answers an InputError naming the file and the object: a way
// read by our handler, and a relation read by libosmium's multipolygon manager in the first pass
// (MultipolygonManager::new_relation → TagList::get_value_by_key, found once the way was guarded).
TEST(ParserRegressionTest, OsmTagStringsWithANulByteAreInputErrorsNotOverReads) {
  for (const char* name : {"tag-string-with-nul.osm.pbf", "relation-tag-string-with-nul.osm.pbf"}) {
    SCOPED_TRACE(name);
    const auto pbf = WriteScratch(std::string("-") + name,
                                  Slurp(std::filesystem::path(UASCMA_SOURCE_DIR) / "tests" / "data" / "fuzz" / name));
    ExpectInputError(
        [&] {
          planning::GeoMapData geo;
          planning::ReadOsmBuildings(pbf, planning::MapImportOptions{}, &geo);
        },
        {pbf.string()});
    std::filesystem::remove(pbf);
  }
}

// Found by mission_plan_fuzzer: an item whose "type" (or the file's "fileType") is not a string made
// nlohmann::json's value() throw type_error, which escaped the parser (std::terminate under the fuzzer,
// "internal error", exit 1, in the CLI).
TEST(ParserRegressionTest, MissionPlanMembersOfTheWrongTypeAreInputErrors) {
  const std::string head = R"({"fileType": "Plan", "version": 1, "mission": {"version": 2,
      "plannedHomePosition": [40.77, -73.96, 10], "items": [)";
  ExpectInputError(
      [&] {
        planning::ParseMission(head + R"({"type": 5, "params": [0, 0, 0, 0, 1, 0, 0]}]}})", "m.plan",
                               planning::MissionFormat::kQgcPlan);
      },
      {"m.plan", "mission.items[0].type", "got 5"});
  ExpectInputError(
      [] { planning::ParseMission(R"({"fileType": 1, "mission": {}})", "m.plan", planning::MissionFormat::kQgcPlan); },
      {"m.plan", "fileType"});
}

// Found while reading the battery policy reader for its harness: the optional "solver" and "stats" members were
// read with json::value(), so a mistyped one (a number status, a string count) threw type_error and a count of
// 1e300 was cast to int (undefined behaviour). They are typed now, checked before the file's hash.
TEST(ParserRegressionTest, BatteryPolicySolverAndStatsMembersAreTyped) {
  const nlohmann::json good = decision::BatteryPolicyToJson(decision::SolveBatteryPolicies(decision::BatteryModel{}));
  ASSERT_NO_THROW((void)decision::BatteryPolicyFromJson(good, "p.json"));
  const std::vector<std::pair<std::string, nlohmann::json>> cases = {
      {"solver.status", 5},         {"solver.iterations", 1e300}, {"solver.iterations", "many"},
      {"solver.residual", "small"}, {"stats.learned_rows", -1},   {"stats.transitions", 1.5}};
  for (const auto& [member, value] : cases) {
    SCOPED_TRACE(member);
    nlohmann::json bad = good;
    const auto dot = member.find('.');
    bad["policies"][0][member.substr(0, dot)][member.substr(dot + 1)] = value;
    ExpectInputError([&] { (void)decision::BatteryPolicyFromJson(bad, "p.json"); }, {"p.json", member});
  }
}

// Found by osm_pbf_fuzzer: every malformed .osm.pbf left its file descriptor open (libosmium's reader did not
// close the file when parsing failed), so after ~20,000 inputs the harness could not open its scratch file. The
// OSM reader must close what it opens whatever the outcome.
TEST(ParserRegressionTest, MalformedOsmFilesLeaveNoFileOpen) {
  auto open_files = [] {
    return std::distance(std::filesystem::directory_iterator("/proc/self/fd"), std::filesystem::directory_iterator{});
  };
  const auto pbf = WriteScratch("-leak.osm.pbf", std::string("\x00\x00\x00\x0d\x2a\x09OSMHeader\x18\x32", 17));
  const auto dense =
      WriteScratch("-leak-dense.osm.pbf", Slurp(std::filesystem::path(UASCMA_SOURCE_DIR) / "tests" / "data" / "fuzz" /
                                                "dense-node-timestamp-overflow.osm.pbf"));
  const auto xml = WriteScratch("-leak.osm", "<osm version=\"0.6\"><node id=\"1\" lat=\"x\"");
  for (const auto& path : {pbf, dense, xml}) {
    SCOPED_TRACE(path.string());
    const auto before = open_files();
    for (int i = 0; i < 20; ++i) {
      try {
        planning::GeoMapData geo;
        planning::ReadOsmBuildings(path, planning::MapImportOptions{}, &geo);
        planning::ImportSummary summary = geo.summary;
        (void)planning::ProjectToCityMap(geo, planning::MapImportOptions{}, &summary);
      } catch (const InputError&) {
      }
    }
    EXPECT_EQ(open_files(), before);
    std::filesystem::remove(path);
  }
}

}  // namespace
}  // namespace uascma
