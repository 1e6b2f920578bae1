// Unkind input through the CLI: each case exits 2 with one line naming the file (or option) and the key, and
// writes nothing; none crashes. A JSON document nested 100,000 deep, a second YAML document, a nominal plan
// through a building at a low cruise altitude, a campaign sampler's error, an option given an empty value.
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include <gtest/gtest.h>

#include "cli_runner.h"

namespace uascma {
namespace {

using testing_support::ExpectBadInput;
using testing_support::RunCli;
using testing_support::ScratchDir;

const std::string kExamples = std::string(UASCMA_SOURCE_DIR) + "/examples/";

void Write(const std::filesystem::path& path, const std::string& text) { std::ofstream(path) << text; }

// SIGSEGV before: the message writer dumped the 100,000-deep value recursively to quote 60 characters of it.
TEST(UnkindInputCliTest, APolicyFileNested100000DeepIsRefusedNamingFileAndPath) {
  ScratchDir scratch("unkind_deep");
  const auto policy = scratch.path / "deep.json";
  Write(policy, "{\"format\": " + std::string(100000, '[') + std::string(100000, ']') + "}");
  const auto result = RunCli("simulate " + kExamples + "nominal.yaml --policy " + policy.string());
  ExpectBadInput(result, policy.string() + ": format[0][0][0][0][0][0][0]… (65 levels): JSON nested at most 64");
}

// A second document after `---` was ignored: the vehicle flew the first.
TEST(UnkindInputCliTest, ASecondYamlDocumentIsRefusedNamingItsLine) {
  ScratchDir scratch("unkind_yaml");
  const auto scenario = scratch.path / "two.yaml";
  Write(scenario, "name: two\nseed: 1\n---\nseed: 2\n");
  ExpectBadInput(RunCli("simulate " + scenario.string()),
                 scenario.string() + ": line 3: one YAML document, but a second one starts here");
}

// "LandPract: nominal_plan: …" named neither the scenario file nor the key that put the plan inside a building.
TEST(UnkindInputCliTest, APlanThroughABuildingNamesTheScenarioAndTheCruiseAltitude) {
  ScratchDir scratch("unkind_landpract");
  const auto scenario = scratch.path / "low.yaml";
  Write(scenario,
        "name: low\nmap: {procedural: {seed: 3}}\nmission:\n  home_ne_m: [0, 222]\n  destination_ne_m: [920, 640]\n"
        "  cruise_altitude_m: 3\n");
  const auto result = RunCli("simulate " + scenario.string() + " --out " + (scratch.path / "out").string());
  ExpectBadInput(result, scenario.string() +
                             ": mission.cruise_altitude_m: a nominal plan clear of the buildings, "
                             "but LandPract's checkpoint");
  EXPECT_FALSE(std::filesystem::exists(scratch.path / "out"));
}

// A campaign's sampler knows no file: its errors named "campaign" (`campaign: mission.wall_clearance_m: …`), not
// the file that set the key. A campaign's own nominal plans never reach a building (the sampler cruises 10 m above
// the tallest one under the route, campaign/sampler.cc), so the sampler's error here is a clearance that leaves no
// open ground for a home.
TEST(UnkindInputCliTest, ACampaignsSamplerErrorNamesTheCampaignFile) {
  ScratchDir scratch("unkind_campaign_sampler");
  const auto campaign = scratch.path / "wide.yaml";
  Write(campaign, "runs: 2\nmap: {procedural_seed: 3}\nmission: {wall_clearance_m: 100}\n");
  const auto db = scratch.path / "c.db";
  ExpectBadInput(RunCli("campaign " + campaign.string() + " --db " + db.string() + " --jobs 1"),
                 campaign.string() + ": mission.wall_clearance_m: a clearance that leaves open ground in the city");
  EXPECT_FALSE(std::filesystem::exists(db));
}

// `--out ""` exited 0 and wrote nothing (an empty path reads as "not given").
TEST(UnkindInputCliTest, AnOptionGivenAnEmptyValueIsRefused) {
  ExpectBadInput(RunCli("simulate " + kExamples + "nominal.yaml --out \"\""),
                 "--out: value: a value that is not empty, got an empty string");
  ExpectBadInput(RunCli("simulate " + kExamples + "nominal.yaml --out="),
                 "--out: value: a value that is not empty, got an empty string");
}

}  // namespace
}  // namespace uascma
