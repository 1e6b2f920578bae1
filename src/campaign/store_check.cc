// The results store's check (store.h: CheckStore): SQLite's own checks, then the schema's invariants.
#include "store_check.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "store_schema.h"
#include "uascma/campaign/config.h"
#include "uascma/campaign/policies.h"
#include "uascma/campaign/sampler.h"
#include "uascma/common/error.h"
#include "uascma/common/text.h"
#include "uascma/sim/outcome.h"

namespace uascma::campaign {
namespace {

using store_internal::CheckDatabase;
using store_internal::ColumnList;
using store_internal::ReadHeader;
using store_internal::SchemaVersion;

// Collects problems by kind, listing at most kMaxListed of each.
class ProblemList {
 public:
  explicit ProblemList(StoreCheckResult* result) : result_(result) {}
  void Add(const std::string& kind, const std::string& text) {
    ++result_->problems_total;
    if (++listed_[kind] <= StoreCheckResult::kMaxListed) result_->problems.push_back(text);
  }
  void NoteOmitted() {
    for (const auto& [kind, count] : listed_) {
      if (count > StoreCheckResult::kMaxListed) {
        result_->problems.push_back(
            fmt::format("({} more problems of the kind '{}' not listed)", count - StoreCheckResult::kMaxListed, kind));
      }
    }
  }

 private:
  StoreCheckResult* result_;
  std::map<std::string, std::int64_t> listed_;
};

bool TableExists(sqlite::Database& db, const std::string& name) {
  sqlite::Statement select = db.Prepare("SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name = ?");
  select.Bind(1, name);
  select.Step("read the schema");
  return select.Integer(0) == 1;
}

std::set<std::string> ColumnsOf(sqlite::Database& db, const std::string& table) {
  std::set<std::string> columns;
  sqlite::Statement info = db.Prepare(fmt::format("PRAGMA table_info({})", table));
  while (info.Step("read the schema")) columns.insert(info.Text(1));
  return columns;
}

// The SQLite storage classes a column of this record field type may hold (store.h's schema).
template <typename T>
std::vector<int> AllowedStorage() {
  if constexpr (std::is_same_v<T, double>) return {SQLITE_FLOAT, SQLITE_INTEGER};
  if constexpr (std::is_same_v<T, std::optional<double>>) return {SQLITE_FLOAT, SQLITE_INTEGER, SQLITE_NULL};
  if constexpr (std::is_same_v<T, std::string>) return {SQLITE_TEXT};
  return {SQLITE_INTEGER};  // std::int64_t, std::uint64_t (bit pattern), bool
}

const char* StorageName(int type) {
  switch (type) {
    case SQLITE_INTEGER:
      return "an integer";
    case SQLITE_FLOAT:
      return "a real number";
    case SQLITE_TEXT:
      return "text";
    case SQLITE_BLOB:
      return "a blob";
    default:
      return "NULL";
  }
}

// The JSON text columns of a record and the shape each holds (record.h); empty when the text is right.
std::string JsonColumnError(const std::string& column, const std::string& text) {
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception&) {
    return "valid JSON";
  }
  if (!json.is_array()) return "a JSON list";
  if (column == "initial_cell_voltage_v") {
    if (json.size() != 6) return "a JSON list of 6 cell voltages";
    for (const auto& v : json) {
      if (!v.is_number()) return "a JSON list of 6 cell voltages (numbers)";
    }
  } else if (column == "actions") {
    for (const auto& pair : json) {
      if (!pair.is_array() || pair.size() != 2 || !pair[0].is_number() || !pair[1].is_string()) {
        return "a JSON list of [time_s, action name] pairs";
      }
    }
  } else if (column == "substitutions") {
    for (const auto& item : json) {
      if (!item.is_string()) return "a JSON list of \"Chosen->Taken\" names";
    }
  }
  return {};
}

bool IsJsonColumn(const std::string& column) {
  return column == "initial_cell_voltage_v" || column == "actions" || column == "substitutions";
}

// The select's column of the record field `name` (campaign_hash is column 0, the record's fields follow).
int RecordColumn(std::string_view name) {
  int column = 1;
  int found = -1;
  const RunRecord shape;
  VisitRecordFields(shape, [&](const char* field, const auto&) {
    if (field == name) found = column;
    ++column;
  });
  UASCMA_CHECK(found > 0, "a field of RunRecord");
  return found;
}

// A row whose values, each well typed, contradict each other or the header: an outcome that is no outcome or
// disagrees with `failure` (sim::IsFailure), a run_seed that is not RunSeed(the campaign's seed, run_index) (the
// flight would not replay), a negative energy or cell voltage.
void CheckRowAgreement(const sqlite::Statement& select, const CampaignHeader& header, std::int64_t run_index,
                       const std::string& where, ProblemList& problems) {
  static const int kOutcome = RecordColumn("outcome"), kFailure = RecordColumn("failure");
  static const int kRunSeed = RecordColumn("run_seed");
  const std::string outcome = select.Text(kOutcome);
  std::optional<sim::Outcome> known;
  std::string names;
  for (int o = static_cast<int>(sim::Outcome::kCompleted); o <= static_cast<int>(sim::Outcome::kLandedOffSite); ++o) {
    const auto candidate = static_cast<sim::Outcome>(o);
    names += (names.empty() ? "" : ", ") + std::string(sim::OutcomeName(candidate));
    if (outcome == sim::OutcomeName(candidate)) known = candidate;
  }
  const bool failure = select.Integer(kFailure) != 0;
  if (!known) {
    problems.Add("outcome", fmt::format("{}: outcome: one of {}, got '{}'", where, names, BriefForMessage(outcome)));
  } else if (sim::IsFailure(*known) != failure) {
    problems.Add("outcome", fmt::format("{}: failure: {} for the outcome '{}', got {} (the row contradicts itself)",
                                        where, sim::IsFailure(*known) ? 1 : 0, outcome, failure ? 1 : 0));
  }
  const auto run_seed = static_cast<std::uint64_t>(select.Integer(kRunSeed));
  if (run_index >= 0 && run_seed != RunSeed(header.seed, run_index)) {
    problems.Add("run_seed", fmt::format("{}: run_seed: {} (from the campaign's seed {} and run_index {}), got {} "
                                         "(the flight would not replay)",
                                         where, RunSeed(header.seed, run_index), header.seed, run_index, run_seed));
  }
  for (const char* name : {"energy_wh", "min_cell_voltage_v", "initial_cell_voltage_min_v"}) {
    const double value = select.Real(RecordColumn(name));
    if (value < 0.0) problems.Add("values", fmt::format("{}: {}: 0 or more, got {}", where, name, value));
  }
}

void CheckFlightRows(sqlite::Database& db, const CampaignHeader& header, const std::map<std::string, int>& slots,
                     ProblemList& problems, StoreCheckResult* result) {
  const std::int64_t policy_count = static_cast<std::int64_t>(slots.size());
  sqlite::Statement select = db.Prepare(fmt::format("SELECT campaign_hash, {} FROM runs", ColumnList()));
  std::int64_t row = 0;
  while (select.Step("read the runs")) {
    ++row;
    // Identity first: how the problems below name the row.
    const auto type = [&select](int column) { return select.ColumnType(column); };
    const std::int64_t run_index = select.Integer(2);
    const std::string policy = type(3) == SQLITE_TEXT ? select.Text(3) : "?";
    const std::string where = fmt::format("runs row {} (run_index {}, policy '{}')", row, run_index,
                                          IsValidUtf8(policy) ? policy : EscapeInvalidUtf8(policy));
    if (type(0) != SQLITE_TEXT || select.Text(0) != header.campaign_hash) {
      problems.Add("campaign_hash", where + ": campaign_hash: this campaign's hash " + header.campaign_hash);
      continue;
    }
    ++result->flights;
    int column = 1;
    const RunRecord shape;
    bool typed = true;
    VisitRecordFields(shape, [&](const char* name, const auto& field) {
      const std::vector<int> allowed = AllowedStorage<std::decay_t<decltype(field)>>();
      const int stored = type(column);
      if (std::find(allowed.begin(), allowed.end(), stored) == allowed.end()) {
        typed = false;
        problems.Add("types", fmt::format("{}: {}: {} (the column's type), got {}", where, name,
                                          StorageName(allowed.front()), StorageName(stored)));
      } else if (stored == SQLITE_TEXT) {
        const std::string text = select.Text(column);
        if (!IsValidUtf8(text)) {
          typed = false;
          problems.Add("text", fmt::format("{}: {}: text in UTF-8, got '{}'", where, name, EscapeInvalidUtf8(text)));
        } else if (IsJsonColumn(name)) {
          const std::string error = JsonColumnError(name, text);
          if (!error.empty()) {
            typed = false;
            problems.Add("json", fmt::format("{}: {}: {}", where, name, error));
          }
        }
      } else if constexpr (std::is_same_v<std::decay_t<decltype(field)>, bool>) {
        if (select.Integer(column) != 0 && select.Integer(column) != 1) {
          typed = false;
          problems.Add("types", fmt::format("{}: {}: 0 or 1, got {}", where, name, select.Integer(column)));
        }
      } else if constexpr (std::is_same_v<std::decay_t<decltype(field)>, double> ||
                           std::is_same_v<std::decay_t<decltype(field)>, std::optional<double>>) {
        if (stored != SQLITE_NULL && !std::isfinite(select.Real(column))) {
          typed = false;
          problems.Add("types", fmt::format("{}: {}: a finite number", where, name));
        }
      }
      ++column;
    });
    if (!typed) continue;
    const auto slot = slots.find(policy);
    if (slot == slots.end()) {
      problems.Add("policy", fmt::format("{}: policy: one of the policies table, but '{}' is not there (a deleted "
                                         "policies row?)",
                                         where, policy));
      continue;
    }
    if (run_index < 0 || run_index >= header.runs_requested) {
      problems.Add("run_index",
                   fmt::format("{}: run_index: 0 to runs_requested - 1 = {}", where, header.runs_requested - 1));
    }
    const std::int64_t flight_id = select.Integer(1);
    if (flight_id != run_index * policy_count + slot->second) {
      problems.Add("flight_id",
                   fmt::format("{}: flight_id: run_index x {} policies + slot {} = {}, got {}", where, policy_count,
                               slot->second, run_index * policy_count + slot->second, flight_id));
    }
    CheckRowAgreement(select, header, run_index, where, problems);
  }
}

void CheckClaims(sqlite::Database& db, const CampaignHeader& header, ProblemList& problems, StoreCheckResult* result) {
  sqlite::Statement select = db.Prepare("SELECT campaign_hash, run_index, worker FROM claims");
  while (select.Step("read the claims")) {
    ++result->claims;
    const std::string where = fmt::format("claims row (run_index {}, worker {})", select.Integer(1), select.Integer(2));
    if (select.Text(0) != header.campaign_hash) {
      problems.Add("claims", where + ": campaign_hash: this campaign's hash " + header.campaign_hash);
    } else if (select.Integer(1) < 0 || select.Integer(1) >= header.runs_requested) {
      problems.Add("claims",
                   fmt::format("{}: run_index: 0 to runs_requested - 1 = {}", where, header.runs_requested - 1));
    }
  }
}

// 1. SQLite's own checks. A file that fails them is not read further: its rows cannot be trusted.
void CheckIntegrity(sqlite::Database& db, ProblemList& problems) {
  sqlite::Statement integrity = db.Prepare("PRAGMA integrity_check(100)");
  while (integrity.Step("run SQLite's integrity check")) {
    const std::string line = integrity.Text(0);
    if (line != "ok") problems.Add("integrity", "SQLite integrity check: " + EscapeInvalidUtf8(line));
  }
}

// 2. The schema: its version and tables, a runs column for every record field, the foreign keys. False when
// the checks after it cannot run.
bool CheckSchema(sqlite::Database& db, ProblemList& problems, StoreCheckResult* result) {
  result->schema_version = SchemaVersion(db);
  if (result->schema_version != 1 && result->schema_version != kStoreSchemaVersion) {
    problems.Add("schema", fmt::format("schema: version 1 to {} (PRAGMA user_version), got {}", kStoreSchemaVersion,
                                       result->schema_version));
    return false;
  }
  std::vector<std::string> tables = {"campaign", "policies", "runs"};
  if (result->schema_version >= 2) tables.insert(tables.end(), {"workers", "claims"});
  for (const std::string& table : tables) {
    if (!TableExists(db, table))
      problems.Add("schema", fmt::format("schema: the table '{}', but it is missing", table));
  }
  if (!result->ok()) return false;
  {
    const std::set<std::string> columns = ColumnsOf(db, "runs");
    const RunRecord shape;
    std::vector<std::string> missing =
        columns.count("campaign_hash") ? std::vector<std::string>{} : std::vector<std::string>{"campaign_hash"};
    VisitRecordFields(shape, [&](const char* name, const auto&) {
      if (columns.count(name) == 0) missing.emplace_back(name);
    });
    for (const std::string& name : missing) {
      problems.Add("schema", fmt::format("schema: runs.{}: a column of every flight row (written by another uascma "
                                         "version?), but it is missing",
                                         name));
    }
  }
  if (!result->ok()) return false;
  if (result->schema_version >= 2) {
    sqlite::Statement foreign = db.Prepare("PRAGMA foreign_key_check");
    while (foreign.Step("run SQLite's foreign key check")) {
      problems.Add("foreign key", fmt::format("{} row {}: refers to a {} row that does not exist", foreign.Text(0),
                                              foreign.Integer(1), foreign.Text(2)));
    }
  }
  return true;
}

// 3. The campaign row: exactly one, each column of its type, its texts UTF-8. False when the checks after it
// cannot run.
bool CheckCampaignRow(sqlite::Database& db, ProblemList& problems, StoreCheckResult* result) {
  {
    sqlite::Statement count = db.Prepare("SELECT count(*), sum(id = 1) FROM campaign");
    count.Step("read the campaign");
    if (count.Integer(0) != 1 || count.Integer(1) != 1) {
      problems.Add("campaign", fmt::format("campaign: exactly one row (id 1), got {}", count.Integer(0)));
      return false;
    }
  }
  sqlite::Statement campaign = db.Prepare(
      "SELECT typeof(name), typeof(config_yaml), typeof(config_hash), typeof(campaign_hash), typeof(seed), "
      "typeof(runs_requested), typeof(code_version), typeof(created_utc) FROM campaign WHERE id = 1");
  campaign.Step("read the campaign");
  const std::array<const char*, 8> campaign_columns = {"name", "config_yaml",    "config_hash",  "campaign_hash",
                                                       "seed", "runs_requested", "code_version", "created_utc"};
  for (int c = 0; c < 8; ++c) {
    const std::string expected = (c == 4 || c == 5) ? "integer" : "text";
    if (campaign.Text(c) != expected) {
      problems.Add("campaign",
                   fmt::format("campaign: {}: {}, got {}", campaign_columns[c], expected, campaign.Text(c)));
    }
  }
  if (!result->ok()) return false;
  {
    sqlite::Statement texts =
        db.Prepare("SELECT name, config_yaml, config_hash, campaign_hash, code_version, created_utc FROM campaign");
    texts.Step("read the campaign");
    for (int c = 0; c < 6; ++c) {
      if (!IsValidUtf8(texts.Text(c))) {
        problems.Add("campaign", fmt::format("campaign: {}: text in UTF-8", campaign_columns[c < 4 ? c : c + 2]));
      }
    }
  }
  return result->ok();
}

// 4. The policies, read as every reader reads them, into `header`, and the slot of each policy name. False
// when the header cannot be read.
bool CheckStoredPolicies(sqlite::Database& db, ProblemList& problems, StoreCheckResult* result, CampaignHeader* header,
                         std::map<std::string, int>* slots) {
  std::int64_t schema = 0;
  try {
    *header = ReadHeader(db, &schema);
  } catch (const InputError& e) {
    problems.Add("policies", e.what());
    return false;
  }
  result->campaign_name = header->name;
  result->campaign_hash = header->campaign_hash;
  result->runs_requested = header->runs_requested;
  result->policies = static_cast<std::int64_t>(header->policies.size());
  sqlite::Statement select = db.Prepare("SELECT slot, name FROM policies ORDER BY slot");
  int expected = 0;
  while (select.Step("read the policies")) {
    if (select.Integer(0) != expected) {
      problems.Add("policies", fmt::format("policies: slots 0, 1, … without gaps, but slot {} follows slot {} (a "
                                           "deleted policies row?)",
                                           select.Integer(0), expected - 1));
    }
    if (!IsValidUtf8(select.Text(1))) {
      problems.Add("policies", fmt::format("policies[{}]: name: text in UTF-8", select.Integer(0)));
    }
    (*slots)[select.Text(1)] = static_cast<int>(select.Integer(0));
    expected = static_cast<int>(select.Integer(0)) + 1;
  }
  return true;
}

// The header's own consistency: at least one policy, runs_requested not negative, and the configuration and the
// two hashes that tie the campaign row to the policies table.
void CheckHeader(const CampaignHeader& header, ProblemList& problems) {
  if (header.policies.empty()) problems.Add("policies", "policies: at least one policy, but the table is empty");
  if (header.runs_requested < 0) {
    problems.Add("campaign", fmt::format("campaign: runs_requested: 0 or more, got {}", header.runs_requested));
  }
  try {
    const CampaignConfig config = ParseCampaignConfig(header.config_yaml, "campaign.config_yaml");
    if (CampaignConfigHash(config) != header.config_hash) {
      problems.Add("campaign",
                   "campaign: config_hash: the hash of config_yaml (edited, or written by another uascma "
                   "version?)");
    }
    if (config.seed != header.seed) {  // the seed column is what the report prints and --resume flies with
      problems.Add("campaign", fmt::format("campaign: seed: the seed of config_yaml (hashed into config_hash), {}, "
                                           "got {} (edited?)",
                                           config.seed, header.seed));
    }
  } catch (const InputError& e) {
    problems.Add("campaign", std::string("campaign: config_yaml: a campaign configuration (") + e.what() + ")");
  }
  if (header.campaign_hash != header.config_hash + "-" + PolicySetHash(header.policies)) {
    problems.Add("policies",
                 fmt::format("policies: the policy set the campaign was created with (campaign_hash {}), but the {} "
                             "row{} of the table hash to {} (a policies row deleted, added or edited?)",
                             header.campaign_hash, header.policies.size(), header.policies.size() == 1 ? "" : "s",
                             header.config_hash + "-" + PolicySetHash(header.policies)));
  }
}

}  // namespace

namespace store_internal {

void CheckDatabase(sqlite::Database& db, StoreCheckResult* result) {
  ProblemList problems(result);
  CheckIntegrity(db, problems);
  if (!result->ok()) {
    problems.NoteOmitted();
    return;
  }
  if (!CheckSchema(db, problems, result)) return;
  if (!CheckCampaignRow(db, problems, result)) return;
  CampaignHeader header;
  std::map<std::string, int> slots;
  if (!CheckStoredPolicies(db, problems, result, &header, &slots)) return;
  CheckHeader(header, problems);
  // 5. and 6. The flights and the claims.
  CheckFlightRows(db, header, slots, problems, result);
  if (result->schema_version >= 2) {
    CheckClaims(db, header, problems, result);
    sqlite::Statement workers = db.Prepare("SELECT count(*) FROM workers");
    workers.Step("count the workers");
    result->workers = workers.Integer(0);
  }
  problems.NoteOmitted();
}

void RequireUndamaged(sqlite::Database& db) {
  StoreCheckResult result;
  try {
    db.Execute("BEGIN", "check the database");
    CheckDatabase(db, &result);
    db.Execute("COMMIT", "check the database");
  } catch (...) {
    db.RollbackQuietly();
    throw;
  }
  if (result.ok()) return;
  throw InputError(
      db.path(), "database",
      fmt::format("an undamaged campaign database, but {}{} (it is not read, resumed into or replayed "
                  "from; 'uascma store check {}' lists every problem)",
                  result.problems.front(),
                  result.problems_total > 1 ? fmt::format(" and {} more problems", result.problems_total - 1) : "",
                  db.path()));
}

}  // namespace store_internal

StoreCheckResult CheckStore(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(path.string(), "file", "an existing campaign database");
  }
  sqlite::ReadAccess access = sqlite::ReadAccess::kShared;
  sqlite::Database db = sqlite::Database::OpenForReading(path.string(), path.string(), &access);
  sqlite3_busy_timeout(db.handle(), StoreOptions{}.busy_timeout_ms);
  StoreCheckResult result;
  result.read_immutable = access == sqlite::ReadAccess::kImmutable;
  try {
    db.Execute("BEGIN", "check the database");
    CheckDatabase(db, &result);
    db.Execute("COMMIT", "check the database");
  } catch (const InputError& e) {
    // SQLite refused to read further (not a database, a page it cannot decode): that is the finding.
    db.RollbackQuietly();
    ++result.problems_total;
    result.problems.push_back(e.what());
  }
  return result;
}

}  // namespace uascma::campaign
