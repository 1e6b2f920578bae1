// Regression tests for the inputs that broke a parser (issue 16): each is a crash, an escaped exception
// or undefined behaviour found by a libFuzzer harness of fuzz/ or while writing them. The rule they pin
// down: on malformed input every parser throws uascma::InputError (exit code 2 in the CLI) naming the
// source and the field, and nothing else.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include <gtest/gtest.h>

#include "uascma/campaign/config.h"
#include "uascma/common/error.h"
#include "uascma/decision/cma_mdp.h"
#include "uascma/decision/policy_file.h"
#include "uascma/planning/map_import.h"

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
  const auto typo = WriteScratch("typo.yaml", "gama: 0.9\nweights:\n" + weights +
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
      {"city.geojson", "JSON"});
  const auto policy = WriteScratch("policy.json", R"({"format": "uascma-policy/1", "gamma": 0.09000E0010000099})");
  ExpectInputError([&] { decision::ReadPolicyFile(policy); }, {policy.string(), "JSON"});
  std::filesystem::remove(policy);
}

}  // namespace
}  // namespace uascma
