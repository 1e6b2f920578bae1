#include "uascma/campaign/store.h"

#include <unistd.h>

#include <bit>
#include <cstring>
#include <ctime>
#include <type_traits>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sqlite_database.h"
#include "uascma/common/error.h"
#include "uascma/common/version.h"

namespace uascma::campaign {
namespace {

// Column type of a record field (record.h lists the field types).
template <typename T>
constexpr const char* SqlType() {
  if constexpr (std::is_same_v<T, double>) return "REAL NOT NULL";
  if constexpr (std::is_same_v<T, std::optional<double>>) return "REAL";
  if constexpr (std::is_same_v<T, std::string>) return "TEXT NOT NULL";
  return "INTEGER NOT NULL";  // std::int64_t, std::uint64_t (bit pattern), bool
}

std::string RunsTableSql() {
  std::string sql = "CREATE TABLE runs (\n  campaign_hash TEXT NOT NULL";
  const RunRecord record;
  VisitRecordFields(record, [&sql](const char* name, const auto& field) {
    sql += fmt::format(",\n  {} {}", name, SqlType<std::decay_t<decltype(field)>>());
  });
  sql += ",\n  PRIMARY KEY (campaign_hash, run_index, policy)\n);\n";
  sql += "CREATE UNIQUE INDEX runs_by_flight ON runs (campaign_hash, flight_id);\n";
  return sql;
}

std::string ColumnList() {
  std::string columns;
  const RunRecord record;
  VisitRecordFields(record, [&columns](const char* name, const auto&) {
    columns += (columns.empty() ? "" : ", ") + std::string(name);
  });
  return columns;
}

constexpr const char* kSchemaSql = R"sql(
CREATE TABLE campaign (
  id INTEGER PRIMARY KEY CHECK (id = 1),
  name TEXT NOT NULL,
  config_yaml TEXT NOT NULL,
  config_hash TEXT NOT NULL,
  campaign_hash TEXT NOT NULL,
  seed INTEGER NOT NULL,
  runs_requested INTEGER NOT NULL,
  code_version TEXT NOT NULL,
  created_utc TEXT NOT NULL
);
CREATE TABLE policies (
  slot INTEGER PRIMARY KEY,
  name TEXT NOT NULL UNIQUE,
  kind TEXT NOT NULL,
  source TEXT NOT NULL,
  hash TEXT NOT NULL,
  actions_json TEXT NOT NULL
);
)sql";

constexpr const char* kViewSql = R"sql(
CREATE VIEW run_outcomes AS
  SELECT run_index, policy, battery_health, fault, outcome, failure, sim_time_s, plan_duration_s,
         first_emergency_action, first_emergency_action_s, min_cell_voltage_v, average_reward, min_reward
  FROM runs;
)sql";

std::string UtcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

std::int64_t AsSigned(std::uint64_t value) { return std::bit_cast<std::int64_t>(value); }
std::uint64_t AsUnsigned(std::int64_t value) { return std::bit_cast<std::uint64_t>(value); }

void ApplyConnectionOptions(sqlite::Database& db, const StoreOptions& options) {
  sqlite3_busy_timeout(db.handle(), options.busy_timeout_ms);
  db.Execute("PRAGMA synchronous = NORMAL", "configure");
  if (options.max_page_count > 0) {
    db.Execute(fmt::format("PRAGMA max_page_count = {}", options.max_page_count), "configure");
  }
}

void BindRecord(sqlite::Statement& statement, const std::string& campaign_hash, const RunRecord& record) {
  int index = 1;
  statement.Bind(index++, campaign_hash);
  VisitRecordFields(record, [&](const char*, const auto& field) {
    using T = std::decay_t<decltype(field)>;
    if constexpr (std::is_same_v<T, std::optional<double>>) {
      if (field) {
        statement.Bind(index, *field);
      } else {
        statement.BindNull(index);
      }
    } else if constexpr (std::is_same_v<T, std::uint64_t>) {
      statement.Bind(index, AsSigned(field));
    } else if constexpr (std::is_same_v<T, bool>) {
      statement.Bind(index, static_cast<std::int64_t>(field ? 1 : 0));
    } else if constexpr (std::is_same_v<T, std::int64_t>) {
      statement.Bind(index, field);
    } else {
      statement.Bind(index, field);
    }
    ++index;
  });
}

RunRecord ReadRow(const sqlite::Statement& statement) {
  RunRecord record;
  int column = 0;
  VisitRecordFields(record, [&](const char*, auto& field) {
    using T = std::decay_t<decltype(field)>;
    if constexpr (std::is_same_v<T, std::optional<double>>) {
      if (statement.IsNull(column)) {
        field.reset();
      } else {
        field = statement.Real(column);
      }
    } else if constexpr (std::is_same_v<T, double>) {
      field = statement.Real(column);
    } else if constexpr (std::is_same_v<T, std::string>) {
      field = statement.Text(column);
    } else if constexpr (std::is_same_v<T, std::uint64_t>) {
      field = AsUnsigned(statement.Integer(column));
    } else if constexpr (std::is_same_v<T, bool>) {
      field = statement.Integer(column) != 0;
    } else {
      field = statement.Integer(column);
    }
    ++column;
  });
  return record;
}

void WriteHeader(sqlite::Database& db, const CampaignHeader& header) {
  sqlite::Statement campaign = db.Prepare(
      "INSERT INTO campaign (id, name, config_yaml, config_hash, campaign_hash, seed, runs_requested, "
      "code_version, created_utc) VALUES (1, ?, ?, ?, ?, ?, ?, ?, ?)");
  campaign.Bind(1, header.name);
  campaign.Bind(2, header.config_yaml);
  campaign.Bind(3, header.config_hash);
  campaign.Bind(4, header.campaign_hash);
  campaign.Bind(5, AsSigned(header.seed));
  campaign.Bind(6, header.runs_requested);
  campaign.Bind(7, header.code_version);
  campaign.Bind(8, header.created_utc);
  campaign.Step("write the campaign");
  sqlite::Statement policy = db.Prepare(
      "INSERT INTO policies (slot, name, kind, source, hash, actions_json) VALUES (?, ?, ?, ?, ?, ?)");
  for (std::size_t slot = 0; slot < header.policies.size(); ++slot) {
    const CampaignPolicy& p = header.policies[slot];
    policy.Reset();
    policy.Bind(1, static_cast<std::int64_t>(slot));
    policy.Bind(2, p.name);
    policy.Bind(3, p.kind);
    policy.Bind(4, p.source);
    policy.Bind(5, p.hash);
    policy.Bind(6, nlohmann::json(PolicyActionNames(p)).dump());
    policy.Step("write the policies");
  }
}

CampaignHeader ReadHeader(sqlite::Database& db) {
  const std::string& path = db.path();
  sqlite::Statement version = db.Prepare("PRAGMA user_version");
  version.Step("read the schema version");
  const std::int64_t schema = version.Integer(0);
  if (schema != kStoreSchemaVersion) {
    throw InputError(path, "schema",
                     fmt::format("a uascma campaign database (schema version {}), got version {}", kStoreSchemaVersion,
                                 schema));
  }
  CampaignHeader header;
  sqlite::Statement campaign = db.Prepare(
      "SELECT name, config_yaml, config_hash, campaign_hash, seed, runs_requested, code_version, created_utc "
      "FROM campaign WHERE id = 1");
  if (!campaign.Step("read the campaign")) throw InputError(path, "campaign", "a campaign row");
  header.name = campaign.Text(0);
  header.config_yaml = campaign.Text(1);
  header.config_hash = campaign.Text(2);
  header.campaign_hash = campaign.Text(3);
  header.seed = AsUnsigned(campaign.Integer(4));
  header.runs_requested = campaign.Integer(5);
  header.code_version = campaign.Text(6);
  header.created_utc = campaign.Text(7);
  sqlite::Statement policies =
      db.Prepare("SELECT slot, name, kind, source, hash, actions_json FROM policies ORDER BY slot");
  while (policies.Step("read the policies")) {
    const std::string where = fmt::format("{}: policies[{}]", path, policies.Integer(0));
    std::vector<std::string> actions;
    try {
      actions = nlohmann::json::parse(policies.Text(5)).get<std::vector<std::string>>();
    } catch (const nlohmann::json::exception&) {
      throw InputError(where, "actions_json", "a JSON list of action names");
    }
    CampaignPolicy policy = MakeStoredPolicy(policies.Text(1), policies.Text(2), policies.Text(3), actions, where);
    if (policy.hash != policies.Text(4)) throw InputError(where, "hash", "the hash of its actions");
    header.policies.push_back(std::move(policy));
  }
  return header;
}

}  // namespace

CampaignHeader MakeCampaignHeader(const CampaignConfig& config, const std::vector<CampaignPolicy>& policies) {
  CampaignHeader header;
  header.name = config.name;
  header.config_yaml = CampaignConfigYaml(config);
  header.config_hash = CampaignConfigHash(config);
  header.campaign_hash = header.config_hash + "-" + PolicySetHash(policies);
  header.seed = config.seed;
  header.runs_requested = config.runs;
  header.code_version = kVersion;
  header.created_utc = UtcNow();
  header.policies = policies;
  return header;
}

struct ResultsStore::Connection {
  sqlite::Database db;
  sqlite::Statement insert;
};

ResultsStore::ResultsStore(std::filesystem::path path, std::unique_ptr<Connection> connection, CampaignHeader header)
    : path_(std::move(path)), connection_(std::move(connection)), header_(std::move(header)) {}
ResultsStore::ResultsStore(ResultsStore&&) noexcept = default;
ResultsStore& ResultsStore::operator=(ResultsStore&&) noexcept = default;
ResultsStore::~ResultsStore() = default;

ResultsStore ResultsStore::Create(const std::filesystem::path& path, const CampaignHeader& header,
                                  const StoreOptions& options) {
  std::error_code ec;
  if (std::filesystem::exists(path, ec)) {
    throw InputError(path.string(), "file", "a new database file, but it exists (continue its campaign with --resume)");
  }
  // Build the whole file under a temporary name and rename it: a failed or killed creation never leaves
  // a half-made database at `path`.
  const std::filesystem::path temporary =
      path.string() + fmt::format(".creating-{}", static_cast<long long>(::getpid()));
  for (const char* suffix : {"", "-wal", "-shm", "-journal"}) std::filesystem::remove(temporary.string() + suffix, ec);
  try {
    sqlite::Database db(temporary.string(), SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
    ApplyConnectionOptions(db, options);
    db.Execute("PRAGMA journal_mode = WAL", "create");
    db.Execute("BEGIN IMMEDIATE", "create");
    db.Execute(kSchemaSql, "create the schema");
    db.Execute(RunsTableSql(), "create the schema");
    db.Execute(kViewSql, "create the schema");
    db.Execute(fmt::format("PRAGMA user_version = {}", kStoreSchemaVersion), "create the schema");
    WriteHeader(db, header);
    db.Execute("COMMIT", "create");
    db.Close();  // checkpoints the WAL into the file
    std::filesystem::rename(temporary, path);
  } catch (const std::filesystem::filesystem_error& e) {
    for (const char* suffix : {"", "-wal", "-shm", "-journal"}) std::filesystem::remove(temporary.string() + suffix, ec);
    throw InputError(path.string(), "create", std::string("a writable location (") + e.what() + ")");
  } catch (...) {
    for (const char* suffix : {"", "-wal", "-shm", "-journal"}) std::filesystem::remove(temporary.string() + suffix, ec);
    throw;
  }
  return Open(path, options);
}

ResultsStore ResultsStore::Open(const std::filesystem::path& path, const StoreOptions& options) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(path.string(), "file", "an existing campaign database");
  }
  auto connection = std::make_unique<Connection>();
  connection->db = sqlite::Database(path.string(), SQLITE_OPEN_READWRITE);
  ApplyConnectionOptions(connection->db, options);
  CampaignHeader header = ReadHeader(connection->db);
  connection->insert = connection->db.Prepare(
      fmt::format("INSERT OR IGNORE INTO runs (campaign_hash, {}) VALUES (?{})", ColumnList(),
                  [] {
                    std::string marks;
                    const RunRecord empty;
                    VisitRecordFields(empty, [&marks](const char*, const auto&) { marks += ", ?"; });
                    return marks;
                  }()));
  return ResultsStore(path, std::move(connection), std::move(header));
}

CampaignConfig ResultsStore::config() const {
  CampaignConfig config = ParseCampaignConfig(header_.config_yaml, path_.string() + ": campaign.config_yaml");
  if (CampaignConfigHash(config) != header_.config_hash) {
    throw InputError(path_.string(), "campaign.config_hash",
                     "the hash of the stored configuration (was it written by another uascma version?)");
  }
  return config;
}

void ResultsStore::RecordRunsRequested(std::int64_t runs) {
  sqlite::Database& db = connection_->db;
  sqlite::Statement update = db.Prepare("UPDATE campaign SET runs_requested = max(runs_requested, ?) WHERE id = 1");
  update.Bind(1, runs);
  update.Step("record the runs requested");
  header_.runs_requested = std::max(header_.runs_requested, runs);
}

void ResultsStore::Insert(const std::vector<RunRecord>& records) {
  if (records.empty()) return;
  sqlite::Database& db = connection_->db;
  sqlite::Statement& insert = connection_->insert;
  try {
    db.Execute("BEGIN IMMEDIATE", "write");
    for (const RunRecord& record : records) {
      insert.Reset();
      BindRecord(insert, header_.campaign_hash, record);
      insert.Step("write");
    }
    db.Execute("COMMIT", "write");
  } catch (...) {
    insert.Reset();
    db.RollbackQuietly();
    throw;
  }
}

std::vector<std::pair<std::int64_t, std::string>> ResultsStore::StoredFlights() const {
  sqlite::Statement select = connection_->db.Prepare("SELECT run_index, policy FROM runs WHERE campaign_hash = ?");
  select.Bind(1, header_.campaign_hash);
  std::vector<std::pair<std::int64_t, std::string>> flights;
  while (select.Step("read the stored flights")) flights.emplace_back(select.Integer(0), select.Text(1));
  return flights;
}

std::int64_t ResultsStore::CountFlights() const {
  sqlite::Statement count = connection_->db.Prepare("SELECT count(*) FROM runs WHERE campaign_hash = ?");
  count.Bind(1, header_.campaign_hash);
  count.Step("count the flights");
  return count.Integer(0);
}

std::vector<RunRecord> ResultsStore::ReadRecords() const {
  sqlite::Statement select = connection_->db.Prepare(
      fmt::format("SELECT {} FROM runs WHERE campaign_hash = ? ORDER BY run_index, flight_id", ColumnList()));
  select.Bind(1, header_.campaign_hash);
  std::vector<RunRecord> records;
  while (select.Step("read the runs")) records.push_back(ReadRow(select));
  return records;
}

std::optional<RunRecord> ResultsStore::ReadRecord(std::int64_t run_index, const std::string& policy) const {
  sqlite::Statement select = connection_->db.Prepare(fmt::format(
      "SELECT {} FROM runs WHERE campaign_hash = ? AND run_index = ? AND policy = ?", ColumnList()));
  select.Bind(1, header_.campaign_hash);
  select.Bind(2, run_index);
  select.Bind(3, policy);
  if (!select.Step("read a run")) return std::nullopt;
  return ReadRow(select);
}

std::optional<RunRecord> ResultsStore::ReadRecordByFlightId(std::int64_t flight_id) const {
  sqlite::Statement select = connection_->db.Prepare(
      fmt::format("SELECT {} FROM runs WHERE campaign_hash = ? AND flight_id = ?", ColumnList()));
  select.Bind(1, header_.campaign_hash);
  select.Bind(2, flight_id);
  if (!select.Step("read a run")) return std::nullopt;
  return ReadRow(select);
}

ReplayFlight LoadReplay(const std::filesystem::path& db, const std::string& run_id) {
  const ResultsStore store = ResultsStore::Open(db);
  std::optional<RunRecord> record;
  const auto colon = run_id.find(':');
  auto parse_index = [&run_id](const std::string& text) {
    std::size_t used = 0;
    long long value = -1;
    try {
      value = std::stoll(text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != text.size() || value < 0) {
      throw InputError("run id", run_id, "a flight id (\"17\") or RUN_INDEX:POLICY (\"8:cma\")");
    }
    return static_cast<std::int64_t>(value);
  };
  if (colon == std::string::npos) {
    record = store.ReadRecordByFlightId(parse_index(run_id));
  } else {
    record = store.ReadRecord(parse_index(run_id.substr(0, colon)), run_id.substr(colon + 1));
  }
  if (!record) throw InputError(db.string(), "run " + run_id, "a flight stored in this campaign");

  ReplayFlight flight;
  flight.config = store.config();
  flight.num_policies = static_cast<int>(store.header().policies.size());
  flight.policy_slot = -1;
  for (int slot = 0; slot < flight.num_policies; ++slot) {
    if (store.header().policies[slot].name == record->policy) {
      flight.policy = store.header().policies[slot];
      flight.policy_slot = slot;
    }
  }
  if (flight.policy_slot < 0) throw InputError(db.string(), "policies", "the policy '" + record->policy + "'");
  flight.run = SampleRun(flight.config, store.header().seed, record->run_index);
  if (flight.run.run_seed != record->run_seed || flight.run.distance_m != record->distance_m ||
      flight.run.cruise_speed_mps != record->cruise_speed_mps ||
      CellHealthCode(flight.run.scenario.battery.cell_health) != record->cell_health) {
    throw InputError(db.string(), "run " + run_id,
                     "a scenario the sampler reproduces; the sampler changed since the campaign ran (code version " +
                         store.header().code_version + ", now " + kVersion + ")");
  }
  flight.recorded = std::move(*record);
  return flight;
}

RunRecord ReplayRun(const ReplayFlight& flight, const PlannerFactory& planner_factory) {
  const sim::Simulator simulator(flight.run.scenario);
  return FlyRun(simulator, flight.run, flight.policy, flight.policy_slot, flight.num_policies, planner_factory);
}

}  // namespace uascma::campaign
