// Hardening end to end: each finding reproduced from its description through the CLI. A damaged database is named
// and never resumed into (`store check`, report, campaign --resume); names that are not UTF-8 stop every writer with
// exit 2 before anything is written; duplicate keys are refused naming both lines; campaign errors leave no
// database; a vehicle that cannot hover is refused before flying; the Maclaurin series warns where it is wrong.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <nlohmann/json.hpp>

#include "cli_runner.h"

namespace uascma {
namespace {

using testing_support::ExpectBadInput;
using testing_support::RunCli;
using testing_support::ScratchDir;

const std::string kExamples = std::string(UASCMA_SOURCE_DIR) + "/examples/";

void Write(const std::filesystem::path& path, const std::string& text) { std::ofstream(path) << text; }

void ExecuteSql(const std::filesystem::path& path, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr), SQLITE_OK);
  EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK) << sql;
  sqlite3_close(db);
}

std::int64_t Count(const std::filesystem::path& path, const std::string& sql) {
  sqlite3* db = nullptr;
  sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* statement = nullptr;
  sqlite3_prepare_v2(db, sql.c_str(), -1, &statement, nullptr);
  const std::int64_t n = sqlite3_step(statement) == SQLITE_ROW ? sqlite3_column_int64(statement, 0) : -1;
  sqlite3_finalize(statement);
  sqlite3_close(db);
  return n;
}

// A database with a deleted policies row: `--resume` exited 0 with 7 of 8 flights and the report dropped the
// policy. Now every reader refuses it, naming the damage, and nothing is written into it.
TEST(HardenCliTest, ADatabaseWithADeletedPolicyRowIsNamedAndNeverResumedInto) {
  ScratchDir scratch("harden_policies");
  const auto db = scratch.path / "c.db";
  ASSERT_EQ(RunCli("campaign --runs 4 --jobs 1 --db " + db.string()).exit_code, 0);
  const auto sound = RunCli("store check " + db.string());
  EXPECT_EQ(sound.exit_code, 0) << sound.err;
  EXPECT_NE(sound.out.find("sound"), std::string::npos) << sound.out;
  ExecuteSql(db, "DELETE FROM policies WHERE slot = 1; DELETE FROM runs WHERE run_index = 3 AND policy = 'cma';");
  const std::int64_t rows = Count(db, "SELECT count(*) FROM runs");
  for (const std::string& command : {"report " + db.string(), "campaign --runs 4 --jobs 1 --resume --db " + db.string(),
                                     "simulate --replay " + db.string() + " 0"}) {
    SCOPED_TRACE(command);
    const auto result = RunCli(command);
    ExpectBadInput(result, db.string() + ": database: an undamaged campaign database, but policies:");
    EXPECT_NE(result.err.find("a policies row deleted"), std::string::npos) << result.err;
    EXPECT_NE(result.err.find("uascma store check " + db.string()), std::string::npos) << result.err;
  }
  EXPECT_EQ(Count(db, "SELECT count(*) FROM runs"), rows);  // not resumed into
  const auto check = RunCli("store check --json " + db.string());
  EXPECT_EQ(check.exit_code, 2);
  const nlohmann::json json = nlohmann::json::parse(check.out);
  EXPECT_FALSE(json.at("ok").get<bool>());
  EXPECT_EQ(json.at("policies"), 1);
  EXPECT_GE(json.at("problems_total").get<int>(), 2);  // the policy set, and the flights of 'noop'
}

// Names that are not UTF-8 ended five writers with an uncaught JSON type_error.316 (exit 1).
TEST(HardenCliTest, NamesThatAreNotUtf8StopEveryWriterWithExitTwoWritingNothing) {
  ScratchDir scratch("harden_utf8");
  const auto out = scratch.path / "out";
  const std::string bad_name = "name: \"flight \xFF\"\n";
  Write(scratch.path / "s.yaml", bad_name + "mission: {destination_ne_m: [30, 0]}\n");
  Write(scratch.path / "c.yaml", bad_name + "runs: 1\n");
  Write(scratch.path / "n\xFF.yaml", "mission: {destination_ne_m: [30, 0]}\n");  // no name: key, the file's name is
  ASSERT_EQ(RunCli("policy solve --model cma --out " + (scratch.path / "p.json").string()).exit_code, 0);
  std::filesystem::copy_file(scratch.path / "p.json", scratch.path / "p\xFF.json");
  const std::string nominal = kExamples + "nominal.yaml";
  struct Case {
    std::string arguments;
    std::string named;
  };
  const std::vector<Case> cases = {
      {"simulate " + (scratch.path / "s.yaml").string() + " --out " + out.string(), "s.yaml: line 1"},
      {"simulate '" + (scratch.path / "n\xFF.yaml").string() + "' --out " + out.string(), "name (taken from the file"},
      {"simulate " + nominal + " --out '" + out.string() + "\xFF'", "--out: folder name"},
      {"simulate " + nominal + " --policy '" + (scratch.path / "p\xFF.json").string() + "' --out " + out.string(),
       "name (the policy's name is the file's name)"},
      {"battery case-study 1 --out '" + out.string() + "\xFF'", "--out: folder name"},
      {"campaign " + (scratch.path / "c.yaml").string() + " --db " + (scratch.path / "c.db").string(),
       "c.yaml: line 1"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.arguments);
    ExpectBadInput(RunCli(c.arguments), c.named);
  }
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_FALSE(std::filesystem::exists(scratch.path / "c.db"));
  // A database whose campaign name was edited to bytes that are not UTF-8: report --plots and --replay --out.
  const auto db = scratch.path / "r.db";
  ASSERT_EQ(RunCli("campaign --runs 1 --jobs 1 --db " + db.string()).exit_code, 0);
  ExecuteSql(db, "UPDATE campaign SET name = CAST(X'6E61FF6D65' AS TEXT)");
  ExpectBadInput(RunCli("report " + db.string() + " --plots " + out.string()), "campaign: name: text in UTF-8");
  ExpectBadInput(RunCli("simulate --replay " + db.string() + " 0 --out " + out.string()),
                 "campaign: name: text in UTF-8");
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(HardenCliTest, DuplicateKeysAreRefusedNamingBothLines) {
  ScratchDir scratch("harden_duplicates");
  const auto scenario = scratch.path / "s.yaml";
  Write(scenario, "wind:\n  speed_mps: 1\n  direction_deg: 10\n  speed_mps: 3\n");
  ExpectBadInput(RunCli("simulate " + scenario.string()),
                 "s.yaml: line 4: each key once per mapping, but 'speed_mps' "
                 "is also given on line 2");
  const auto campaign = scratch.path / "c.yaml";
  Write(campaign, "runs: 1\nseed: 3\nruns: 2\n");
  ExpectBadInput(RunCli("campaign " + campaign.string() + " --db " + (scratch.path / "c.db").string()),
                 "c.yaml: line 3: each key once per mapping, but 'runs' is also given on line 1");
  const auto weights = scratch.path / "w.yaml";
  Write(weights, testing_support::Slurp(kExamples + "cma-weights.yaml") + "\n" +
                     testing_support::Slurp(kExamples + "cma-weights.yaml"));
  ExpectBadInput(RunCli("policy solve --model cma --weights " + weights.string()), "is also given on line");
  // A policy file with its "name"... key twice: the first key of the file repeated at its end.
  ASSERT_EQ(RunCli("policy solve --model cma --out " + (scratch.path / "p.json").string()).exit_code, 0);
  std::string policy = testing_support::Slurp(scratch.path / "p.json");
  const auto first_key_end = policy.find(',', policy.find('{'));
  const std::string first_member = policy.substr(policy.find('{') + 1, first_key_end - policy.find('{') - 1);
  policy.insert(policy.rfind('}'), "," + first_member);
  Write(scratch.path / "q.json", policy);
  ExpectBadInput(RunCli("simulate " + kExamples + "nominal.yaml --policy " + (scratch.path / "q.json").string()),
                 "each key once per object");
  EXPECT_FALSE(std::filesystem::exists(scratch.path / "c.db"));
}

// A missing sites file or routes that cannot fit exited 2 but left an empty database that blocked the corrected run.
TEST(HardenCliTest, CampaignErrorsAreFoundBeforeTheDatabaseIsCreated) {
  ScratchDir scratch("harden_campaign");
  const auto db = scratch.path / "c.db";
  Write(scratch.path / "city.geojson", R"({"type": "FeatureCollection", "features": [{"type": "Feature",
    "properties": {"height": 20}, "geometry": {"type": "Polygon", "coordinates": [[[-73.96, 40.77], [-73.959, 40.77],
    [-73.959, 40.771], [-73.96, 40.771], [-73.96, 40.77]]]}}]})");
  Write(scratch.path / "no-sites.yaml", "runs: 2\nmap: {buildings: [city.geojson], sites: missing.csv}\n");
  Write(scratch.path / "no-fit.yaml", "runs: 2\nmission: {distance_m: [40000, 50000]}\n");
  for (const char* file : {"no-sites.yaml", "no-fit.yaml"}) {
    SCOPED_TRACE(file);
    const auto result = RunCli("campaign " + (scratch.path / file).string() + " --jobs 1 --db " + db.string());
    EXPECT_EQ(result.exit_code, 2) << result.err;
    EXPECT_FALSE(std::filesystem::exists(db)) << result.err;
  }
}

TEST(HardenCliTest, AVehicleThatCannotHoverIsRefusedBeforeFlying) {
  ScratchDir scratch("harden_hover");
  Write(scratch.path / "heavy.yaml", "vehicle: {mass_kg: 25}\nbattery: {packs: [P, P]}\n");
  const auto heavy =
      RunCli("simulate " + (scratch.path / "heavy.yaml").string() + " --out " + (scratch.path / "out").string());
  ExpectBadInput(heavy, "vehicle.mass_kg 25 kg");
  EXPECT_NE(heavy.err.find("hovering needs 245.2 N, the six rotors give at most 26.85 N"), std::string::npos)
      << heavy.err;
  EXPECT_FALSE(std::filesystem::exists(scratch.path / "out"));
  // Just below the rotors' limit the vehicle flies, with physical numbers: cells above 2.5 V (the Li-ion absolute
  // minimum, models::kCutoffVoltageBounds) and energy drawn >= 0.
  Write(scratch.path / "limit.yaml", "vehicle: {mass_kg: 2.7}\nmission: {destination_ne_m: [20, 0]}\n");
  const auto limit = RunCli("simulate " + (scratch.path / "limit.yaml").string() + " --json");
  ASSERT_EQ(limit.exit_code, 0) << limit.err;
  const nlohmann::json summary = nlohmann::json::parse(limit.out);
  EXPECT_GT(summary.at("min_cell_voltage_v").get<double>(), 2.5) << limit.out;
  EXPECT_GE(summary.at("energy_wh").get<double>(), 0.0) << limit.out;
}

TEST(HardenCliTest, TheMaclaurinSeriesWarnsWhereItIsNotAccurate) {
  const auto wrong = RunCli("footprint --speed-mps 9 --eod-s 100 --maclaurin 5 --json");
  ASSERT_EQ(wrong.exit_code, 0) << wrong.err;
  EXPECT_NE(wrong.err.find("warning: --maclaurin: the order-5 Maclaurin series is not accurate"), std::string::npos)
      << wrong.err;
  EXPECT_GT(nlohmann::json::parse(wrong.out).at("series_relative_error").get<double>(), 0.01);
  const auto right = RunCli("footprint --speed-mps 9 --eod-s 0.5 --drag-slope 0.55 --maclaurin 5 --json");
  ASSERT_EQ(right.exit_code, 0) << right.err;
  EXPECT_TRUE(right.err.empty()) << right.err;
  EXPECT_LT(nlohmann::json::parse(right.out).at("series_relative_error").get<double>(), 0.01);
}

}  // namespace
}  // namespace uascma
