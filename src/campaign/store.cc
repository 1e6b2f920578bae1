#include "uascma/campaign/store.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cerrno>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <type_traits>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sqlite_database.h"
#include "uascma/common/error.h"
#include "uascma/common/text.h"
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

// The work-sharing tables of schema version 2 (store.h).
constexpr const char* kWorkSchemaSql = R"sql(
CREATE TABLE workers (
  id INTEGER PRIMARY KEY,
  host TEXT NOT NULL,
  boot_id TEXT NOT NULL,
  pid_namespace TEXT NOT NULL,
  pid INTEGER NOT NULL,
  start_ticks INTEGER NOT NULL,
  started_utc TEXT NOT NULL,
  heartbeat_s REAL NOT NULL,
  retired INTEGER NOT NULL DEFAULT 0
);
CREATE TABLE claims (
  campaign_hash TEXT NOT NULL,
  run_index INTEGER NOT NULL,
  worker INTEGER NOT NULL REFERENCES workers (id),
  claimed_s REAL NOT NULL,
  PRIMARY KEY (campaign_hash, run_index)
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

// Unix time in seconds (heartbeats and leases compare it between machines).
double UnixNowSeconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

std::string FirstLine(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  return line;
}

struct ProcessStat {
  char state = '?';
  std::int64_t start_ticks = 0;
};

// /proc/PID/stat: "pid (comm) state ppid …", starttime is field 22. comm may hold spaces and
// parentheses, so the fields are counted from the last ')'.
std::optional<ProcessStat> ReadProcessStat(std::int64_t pid) {
  const std::string line = FirstLine(fmt::format("/proc/{}/stat", pid));
  const auto close = line.rfind(')');
  if (close == std::string::npos) return std::nullopt;
  std::istringstream fields(line.substr(close + 1));
  ProcessStat stat;
  fields >> stat.state;
  std::string skipped;
  for (int field = 4; field < 22 && fields >> skipped; ++field) {
  }
  if (!(fields >> stat.start_ticks)) return std::nullopt;
  return stat;
}

// The folder a database file lives in.
std::filesystem::path FolderOf(const std::filesystem::path& path) {
  return path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
}

// "<file>.creating-<host>-<boot>-": the prefix of this machine's temporary files for `path`; then
// "<pid>-<n>", n counting the creations of this process. Each creator builds its own, so concurrent
// creators (processes or threads) never share one.
std::string TemporaryPrefix(const std::filesystem::path& path, const WorkerIdentity& me) {
  return path.filename().string() + ".creating-" + me.host + "-" + me.boot_id.substr(0, 8) + "-";
}

constexpr std::array<const char*, 4> kSqliteFileSuffixes = {"", "-wal", "-shm", "-journal"};

void RemoveSqliteFiles(const std::filesystem::path& file) {
  std::error_code ec;
  for (const char* suffix : kSqliteFileSuffixes) std::filesystem::remove(file.string() + suffix, ec);
}

// Temporary files that creators on this machine left when they were killed (a kill -9 skips every
// clean-up); those of running creators are left alone.
void RemoveStaleTemporaries(const std::filesystem::path& path, const WorkerIdentity& me) {
  const std::string prefix = TemporaryPrefix(path, me);
  std::error_code ec;
  std::filesystem::directory_iterator entries(FolderOf(path), ec);
  if (ec) return;
  for (const auto& entry : entries) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) != 0) continue;
    std::int64_t pid = 0;
    std::size_t used = 0;
    try {
      pid = std::stoll(name.substr(prefix.size()), &used);
    } catch (const std::exception&) {
      continue;
    }
    std::string rest = name.substr(prefix.size() + used);  // "-<n>" and an SQLite suffix
    if (rest.size() < 2 || rest[0] != '-' || std::isdigit(static_cast<unsigned char>(rest[1])) == 0) continue;
    rest.erase(0, rest.find_first_not_of("0123456789", 1));
    if (rest != "" && rest != "-wal" && rest != "-shm" && rest != "-journal") continue;
    if (!ProcessIsRunning(pid, 0)) std::filesystem::remove(entry.path(), ec);
  }
}

// Puts the finished temporary file at `path` unless something is there already: link(2) fails with
// EEXIST rather than replace (atomic on local file systems and on NFS); where hard links are not
// supported, renameat2(RENAME_NOREPLACE) does the same. True when linked, false when `path` exists.
bool LinkIntoPlace(const std::filesystem::path& temporary, const std::filesystem::path& path) {
  if (::link(temporary.c_str(), path.c_str()) == 0) return true;
  int error = errno;
  if (error == EEXIST) return false;
  if (error == EPERM || error == ENOTSUP || error == EOPNOTSUPP || error == ENOSYS || error == EMLINK) {
    if (::renameat2(AT_FDCWD, temporary.c_str(), AT_FDCWD, path.c_str(), RENAME_NOREPLACE) == 0) return true;
    error = errno;
    if (error == EEXIST) return false;
    throw InputError(path.string(), "create",
                     fmt::format("a file system that can create a file exclusively (hard links or "
                                 "RENAME_NOREPLACE): {}",
                                 std::strerror(error)));
  }
  throw InputError(path.string(), "create", fmt::format("a writable location ({})", std::strerror(error)));
}

std::int64_t InsertWorker(sqlite::Database& db, const WorkerIdentity& me) {
  sqlite::Statement insert = db.Prepare(
      "INSERT INTO workers (host, boot_id, pid_namespace, pid, start_ticks, started_utc, heartbeat_s, retired) "
      "VALUES (?, ?, ?, ?, ?, ?, ?, 0)");
  insert.Bind(1, me.host);
  insert.Bind(2, me.boot_id);
  insert.Bind(3, me.pid_namespace);
  insert.Bind(4, me.pid);
  insert.Bind(5, me.start_ticks);
  insert.Bind(6, UtcNow());
  insert.Bind(7, UnixNowSeconds());
  insert.Step("register this process as a worker");
  return sqlite3_last_insert_rowid(db.handle());
}

// The workers that are open in this process, by (database, worker id): a worker of this very process is
// alive exactly while its ResultsStore is open.
std::mutex& OpenWorkersMutex() {
  static std::mutex mutex;
  return mutex;
}
std::set<std::pair<std::string, std::int64_t>>& OpenWorkers() {
  static std::set<std::pair<std::string, std::int64_t>> workers;
  return workers;
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
    policy.Bind(6, PolicyActionsJson(p));
    policy.Step("write the policies");
  }
}

std::int64_t SchemaVersion(sqlite::Database& db) {
  sqlite::Statement version = db.Prepare("PRAGMA user_version");
  version.Step("read the schema version");
  return version.Integer(0);
}

// Version 1 files lack only the work-sharing tables; they are read as they are.
CampaignHeader ReadHeader(sqlite::Database& db, std::int64_t* schema_version) {
  const std::string& path = db.path();
  const std::int64_t schema = SchemaVersion(db);
  if (schema != kStoreSchemaVersion && schema != 1) {
    throw InputError(path, "schema",
                     fmt::format("a uascma campaign database (schema version 1 to {}), got version {}",
                                 kStoreSchemaVersion, schema));
  }
  *schema_version = schema;
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
    CampaignPolicy policy =
        MakeStoredPolicy(policies.Text(1), policies.Text(2), policies.Text(3), policies.Text(5), where);
    if (policy.hash != policies.Text(4)) throw InputError(where, "hash", "the hash of its actions");
    header.policies.push_back(std::move(policy));
  }
  return header;
}

// ---- the store check (store.h: CheckStore) ----------------------------------------------------------------

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
    case SQLITE_INTEGER: return "an integer";
    case SQLITE_FLOAT: return "a real number";
    case SQLITE_TEXT: return "text";
    case SQLITE_BLOB: return "a blob";
    default: return "NULL";
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
      problems.Add("run_index", fmt::format("{}: run_index: 0 to runs_requested - 1 = {}", where,
                                            header.runs_requested - 1));
    }
    const std::int64_t flight_id = select.Integer(1);
    if (flight_id != run_index * policy_count + slot->second) {
      problems.Add("flight_id", fmt::format("{}: flight_id: run_index x {} policies + slot {} = {}, got {}", where,
                                            policy_count, slot->second, run_index * policy_count + slot->second,
                                            flight_id));
    }
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
      problems.Add("claims", fmt::format("{}: run_index: 0 to runs_requested - 1 = {}", where, header.runs_requested - 1));
    }
  }
}

// The checks of CheckStore on an open connection (store.h lists them).
void CheckDatabase(sqlite::Database& db, StoreCheckResult* result) {
  ProblemList problems(result);
  // 1. SQLite's own checks. A file that fails them is not read further: its rows cannot be trusted.
  {
    sqlite::Statement integrity = db.Prepare("PRAGMA integrity_check(100)");
    while (integrity.Step("run SQLite's integrity check")) {
      const std::string line = integrity.Text(0);
      if (line != "ok") problems.Add("integrity", "SQLite integrity check: " + EscapeInvalidUtf8(line));
    }
  }
  if (!result->ok()) {
    problems.NoteOmitted();
    return;
  }
  // 2. The schema.
  result->schema_version = SchemaVersion(db);
  if (result->schema_version != 1 && result->schema_version != kStoreSchemaVersion) {
    problems.Add("schema", fmt::format("schema: version 1 to {} (PRAGMA user_version), got {}", kStoreSchemaVersion,
                                       result->schema_version));
    return;
  }
  std::vector<std::string> tables = {"campaign", "policies", "runs"};
  if (result->schema_version >= 2) tables.insert(tables.end(), {"workers", "claims"});
  for (const std::string& table : tables) {
    if (!TableExists(db, table)) problems.Add("schema", fmt::format("schema: the table '{}', but it is missing", table));
  }
  if (!result->ok()) return;
  {
    const std::set<std::string> columns = ColumnsOf(db, "runs");
    const RunRecord shape;
    std::vector<std::string> missing = columns.count("campaign_hash") ? std::vector<std::string>{}
                                                                      : std::vector<std::string>{"campaign_hash"};
    VisitRecordFields(shape, [&](const char* name, const auto&) {
      if (columns.count(name) == 0) missing.emplace_back(name);
    });
    for (const std::string& name : missing) {
      problems.Add("schema", fmt::format("schema: runs.{}: a column of every flight row (written by another uascma "
                                         "version?), but it is missing",
                                         name));
    }
  }
  if (!result->ok()) return;
  if (result->schema_version >= 2) {
    sqlite::Statement foreign = db.Prepare("PRAGMA foreign_key_check");
    while (foreign.Step("run SQLite's foreign key check")) {
      problems.Add("foreign key", fmt::format("{} row {}: refers to a {} row that does not exist", foreign.Text(0),
                                              foreign.Integer(1), foreign.Text(2)));
    }
  }
  // 3. The campaign row.
  {
    sqlite::Statement count = db.Prepare("SELECT count(*), sum(id = 1) FROM campaign");
    count.Step("read the campaign");
    if (count.Integer(0) != 1 || count.Integer(1) != 1) {
      problems.Add("campaign", fmt::format("campaign: exactly one row (id 1), got {}", count.Integer(0)));
      return;
    }
  }
  sqlite::Statement campaign = db.Prepare(
      "SELECT typeof(name), typeof(config_yaml), typeof(config_hash), typeof(campaign_hash), typeof(seed), "
      "typeof(runs_requested), typeof(code_version), typeof(created_utc) FROM campaign WHERE id = 1");
  campaign.Step("read the campaign");
  const std::array<const char*, 8> campaign_columns = {"name",           "config_yaml",  "config_hash",
                                                       "campaign_hash",  "seed",         "runs_requested",
                                                       "code_version",   "created_utc"};
  for (int c = 0; c < 8; ++c) {
    const std::string expected = (c == 4 || c == 5) ? "integer" : "text";
    if (campaign.Text(c) != expected) {
      problems.Add("campaign", fmt::format("campaign: {}: {}, got {}", campaign_columns[c], expected, campaign.Text(c)));
    }
  }
  if (!result->ok()) return;
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
  if (!result->ok()) return;
  // 4. The policies, read as every reader reads them.
  std::int64_t schema = 0;
  CampaignHeader header;
  try {
    header = ReadHeader(db, &schema);
  } catch (const InputError& e) {
    problems.Add("policies", e.what());
    return;
  }
  result->campaign_name = header.name;
  result->campaign_hash = header.campaign_hash;
  result->runs_requested = header.runs_requested;
  result->policies = static_cast<std::int64_t>(header.policies.size());
  std::map<std::string, int> slots;
  {
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
      slots[select.Text(1)] = static_cast<int>(select.Integer(0));
      expected = static_cast<int>(select.Integer(0)) + 1;
    }
  }
  if (header.policies.empty()) problems.Add("policies", "policies: at least one policy, but the table is empty");
  if (header.runs_requested < 0) {
    problems.Add("campaign", fmt::format("campaign: runs_requested: 0 or more, got {}", header.runs_requested));
  }
  // The configuration and the two hashes tie the campaign row to the policies table.
  try {
    const CampaignConfig config = ParseCampaignConfig(header.config_yaml, "campaign.config_yaml");
    if (CampaignConfigHash(config) != header.config_hash) {
      problems.Add("campaign", "campaign: config_hash: the hash of config_yaml (edited, or written by another uascma "
                               "version?)");
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

// "PATH: database: an undamaged campaign database, but …" for Open.
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
  throw InputError(db.path(), "database",
                   fmt::format("an undamaged campaign database, but {}{} (it is not read, resumed into or replayed "
                               "from; 'uascma store check {}' lists every problem)",
                               result.problems.front(),
                               result.problems_total > 1 ? fmt::format(" and {} more problems", result.problems_total - 1)
                                                         : "",
                               db.path()));
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

WorkerIdentity ThisProcessIdentity() {
  WorkerIdentity me;
  char host[256] = {};
  if (::gethostname(host, sizeof host - 1) == 0) me.host = host;
  if (me.host.empty()) me.host = "unknown-host";
  me.boot_id = FirstLine("/proc/sys/kernel/random/boot_id");
  std::error_code ec;
  me.pid_namespace = std::filesystem::read_symlink("/proc/self/ns/pid", ec).string();
  me.pid = static_cast<std::int64_t>(::getpid());
  if (const auto stat = ReadProcessStat(me.pid)) me.start_ticks = stat->start_ticks;
  return me;
}

bool ProcessIsRunning(std::int64_t pid, std::int64_t start_ticks) {
  if (pid <= 0) return false;
  if (const auto stat = ReadProcessStat(pid)) {
    if (stat->state == 'Z' || stat->state == 'X') return false;  // killed, not yet reaped
    return start_ticks == 0 || stat->start_ticks == start_ticks;
  }
  // No /proc entry: gone, or a system without /proc (then kill(pid, 0) still tells).
  if (::kill(static_cast<pid_t>(pid), 0) == 0) return true;
  return errno == EPERM;
}

struct ResultsStore::Connection {
  sqlite::Database db;
  sqlite::Statement insert;
  std::int64_t schema_version = kStoreSchemaVersion;
  std::string open_key;  // the canonical path: OpenWorkers() key
  WorkerIdentity me;
};

ResultsStore::ResultsStore(std::filesystem::path path, std::unique_ptr<Connection> connection, CampaignHeader header,
                           StoreOptions options)
    : path_(std::move(path)), connection_(std::move(connection)), header_(std::move(header)),
      options_(std::move(options)) {}

ResultsStore::ResultsStore(ResultsStore&& other) noexcept
    : path_(std::move(other.path_)), connection_(std::move(other.connection_)), header_(std::move(other.header_)),
      options_(std::move(other.options_)), worker_id_(std::exchange(other.worker_id_, 0)) {}

ResultsStore& ResultsStore::operator=(ResultsStore&& other) noexcept {
  if (this != &other) {
    Retire();
    path_ = std::move(other.path_);
    connection_ = std::move(other.connection_);
    header_ = std::move(other.header_);
    options_ = std::move(other.options_);
    worker_id_ = std::exchange(other.worker_id_, 0);
  }
  return *this;
}

ResultsStore::~ResultsStore() { Retire(); }

ResultsStore ResultsStore::Create(const std::filesystem::path& path, const CampaignHeader& header,
                                  const StoreOptions& options) {
  std::optional<ResultsStore> store = TryCreate(path, header, options);
  if (!store) {
    throw InputError(path.string(), "file", "a new database file, but it exists (continue its campaign with --resume)");
  }
  return std::move(*store);
}

std::optional<ResultsStore> ResultsStore::TryCreate(const std::filesystem::path& path, const CampaignHeader& header,
                                                    const StoreOptions& options, bool as_worker) {
  const std::string name = path.string();
  std::error_code ec;
  if (std::filesystem::exists(std::filesystem::symlink_status(path, ec))) return std::nullopt;
  const std::filesystem::path folder = FolderOf(path);
  if (!std::filesystem::is_directory(folder, ec)) {
    throw InputError(name, "folder",
                     fmt::format("an existing folder, but '{}' {}", folder.string(),
                                 std::filesystem::exists(folder, ec) ? "is not a folder" : "does not exist"));
  }
  if (::access(folder.c_str(), W_OK | X_OK) != 0) {
    throw InputError(name, "folder",
                     fmt::format("a folder you can write, but '{}' is not writable ({})", folder.string(),
                                 std::strerror(errno)));
  }
  // Build the whole file under a temporary name beside `path`, then link it into place: a failed or
  // killed creation never leaves a half-made database at `path`, and only one creator can win.
  const WorkerIdentity me = ThisProcessIdentity();
  RemoveStaleTemporaries(path, me);
  static std::atomic<std::int64_t> creations{0};
  const std::filesystem::path temporary =
      folder / fmt::format("{}{}-{}", TemporaryPrefix(path, me), me.pid, creations.fetch_add(1));
  RemoveSqliteFiles(temporary);
  bool linked = false;
  std::int64_t worker = 0;
  try {
    sqlite::Database db(temporary.string(), SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, name);
    ApplyConnectionOptions(db, options);
    db.Execute("PRAGMA journal_mode = WAL", "create");
    db.Execute("BEGIN IMMEDIATE", "create");
    db.Execute(kSchemaSql, "create the schema");
    db.Execute(RunsTableSql(), "create the schema");
    db.Execute(kViewSql, "create the schema");
    db.Execute(kWorkSchemaSql, "create the schema");
    db.Execute(fmt::format("PRAGMA user_version = {}", kStoreSchemaVersion), "create the schema");
    WriteHeader(db, header);
    if (as_worker) worker = InsertWorker(db, me);
    db.Execute("COMMIT", "create");
    // Everything into the main file before it is published: the link below publishes that file alone,
    // without its -wal. Closing checkpoints too, but a checkpoint that fails there (a full disk) goes
    // unreported and would leave the committed pages only in the -wal (issue 26: a truncated database at
    // the user's path), so the checkpoint is made, and its result checked, here.
    {
      sqlite::Statement checkpoint = db.Prepare("PRAGMA wal_checkpoint(TRUNCATE)");
      checkpoint.Step("write the new database");
      if (checkpoint.Integer(0) != 0 || checkpoint.Integer(1) != checkpoint.Integer(2)) {
        throw InputError(name, "create",
                         fmt::format("the new database written whole, but its checkpoint stopped ({} of {} pages)",
                                     checkpoint.Integer(2), checkpoint.Integer(1)));
      }
    }
    db.Close();
    // The file as it will be published, read back and checked (store.h: CheckStore) on its own.
    std::error_code size_ec;
    if (std::filesystem::file_size(temporary.string() + "-wal", size_ec) > 0 && !size_ec) {
      throw InputError(name, "create", "the new database written whole, but part of it is still in its -wal file");
    }
    {
      sqlite::Database check(temporary.string(), SQLITE_OPEN_READWRITE, name);
      RequireUndamaged(check);
      check.Close();
    }
    linked = LinkIntoPlace(temporary, path);
  } catch (const std::filesystem::filesystem_error& e) {
    RemoveSqliteFiles(temporary);
    throw InputError(name, "create", std::string("a writable location (") + e.code().message() + "); nothing was created");
  } catch (const InputError& e) {
    RemoveSqliteFiles(temporary);
    throw InputError(std::string(e.what()) + "; nothing was created");
  } catch (...) {
    RemoveSqliteFiles(temporary);
    throw;
  }
  RemoveSqliteFiles(temporary);
  if (!linked) return std::nullopt;
  ResultsStore store = Open(path, options);
  if (as_worker) {
    store.worker_id_ = worker;
    store.connection_->me = me;
    const std::lock_guard lock(OpenWorkersMutex());
    OpenWorkers().insert({store.connection_->open_key, worker});
  }
  return store;
}

StoreCheckResult CheckStore(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(path.string(), "file", "an existing campaign database");
  }
  sqlite::Database db(path.string(), SQLITE_OPEN_READONLY);
  sqlite3_busy_timeout(db.handle(), StoreOptions{}.busy_timeout_ms);
  StoreCheckResult result;
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

ResultsStore ResultsStore::Open(const std::filesystem::path& path, const StoreOptions& options) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(path.string(), "file", "an existing campaign database");
  }
  auto connection = std::make_unique<Connection>();
  connection->db = sqlite::Database(path.string(), SQLITE_OPEN_READWRITE);
  ApplyConnectionOptions(connection->db, options);
  RequireUndamaged(connection->db);  // a damaged file is named, never read or resumed into (store.h)
  CampaignHeader header = ReadHeader(connection->db, &connection->schema_version);
  connection->insert = connection->db.Prepare(
      fmt::format("INSERT OR IGNORE INTO runs (campaign_hash, {}) VALUES (?{})", ColumnList(),
                  [] {
                    std::string marks;
                    const RunRecord empty;
                    VisitRecordFields(empty, [&marks](const char*, const auto&) { marks += ", ?"; });
                    return marks;
                  }()));
  connection->open_key = std::filesystem::weakly_canonical(path, ec).string();
  if (ec) connection->open_key = std::filesystem::absolute(path, ec).string();
  return ResultsStore(path, std::move(connection), std::move(header), options);
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
  } catch (const InputError& e) {
    const int code = sqlite3_extended_errcode(db.handle());
    insert.Reset();
    db.RollbackQuietly();
    if (sqlite::IsDiskFull(code)) {
      throw InputError(std::string(e.what()) + "; every batch committed before is kept, continue with --resume");
    }
    throw;
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

std::int64_t ResultsStore::JoinAsWorker() {
  if (worker_id_ != 0) return worker_id_;
  sqlite::Database& db = connection_->db;
  const WorkerIdentity me = ThisProcessIdentity();
  const double now_s = UnixNowSeconds();
  std::int64_t worker = 0;
  try {
    db.Execute("BEGIN IMMEDIATE", "join the campaign");
    if (SchemaVersion(db) == 1) {  // raise a version-1 file (store.h)
      db.Execute(kWorkSchemaSql, "add the work-sharing tables");
      db.Execute(fmt::format("PRAGMA user_version = {}", kStoreSchemaVersion), "add the work-sharing tables");
    }
    // WAL mode shares its locks through memory: writers of another kernel would corrupt the file.
    sqlite::Statement others = db.Prepare(
        "SELECT id, host, pid, heartbeat_s FROM workers WHERE retired = 0 AND boot_id <> ? ORDER BY heartbeat_s DESC");
    others.Bind(1, me.boot_id);
    while (others.Step("read the workers")) {
      const double age_s = now_s - others.Real(3);
      if (age_s > options_.claim_lease_s) continue;
      throw InputError(
          path_.string(), "workers",
          fmt::format("writers on one machine only (SQLite's WAL mode shares its locks through memory), but worker "
                      "{} on host '{}' (pid {}) wrote it {:.0f} s ago; spread a campaign over machines with mpirun, "
                      "or retry once that process has stopped (its claims lapse {:.0f} s after its last heartbeat)",
                      others.Integer(0), others.Text(1), others.Integer(2), std::max(0.0, age_s),
                      options_.claim_lease_s));
    }
    worker = InsertWorker(db, me);
    db.Execute("COMMIT", "join the campaign");
  } catch (...) {
    db.RollbackQuietly();
    throw;
  }
  connection_->schema_version = kStoreSchemaVersion;
  connection_->me = me;
  worker_id_ = worker;
  const std::lock_guard lock(OpenWorkersMutex());
  OpenWorkers().insert({connection_->open_key, worker});
  return worker_id_;
}

bool ResultsStore::WorkerIsAlive(std::int64_t worker) const {
  sqlite::Statement select = connection_->db.Prepare(
      "SELECT boot_id, pid_namespace, pid, start_ticks, heartbeat_s, retired FROM workers WHERE id = ?");
  select.Bind(1, worker);
  if (!select.Step("read a worker")) return false;
  if (select.Integer(5) != 0) return false;  // retired
  if (connection_->me.pid == 0) connection_->me = ThisProcessIdentity();
  const WorkerIdentity& me = connection_->me;
  if (select.Text(0) == me.boot_id && select.Text(1) == me.pid_namespace) {
    const std::int64_t pid = select.Integer(2);
    const std::int64_t start_ticks = select.Integer(3);
    if (pid == me.pid && start_ticks == me.start_ticks) {
      const std::lock_guard lock(OpenWorkersMutex());
      return OpenWorkers().count({connection_->open_key, worker}) != 0;
    }
    return ProcessIsRunning(pid, start_ticks);
  }
  return UnixNowSeconds() - select.Real(4) <= options_.claim_lease_s;
}

std::int64_t ResultsStore::CountLiveWorkers() const {
  if (connection_->schema_version < 2) return 0;
  std::vector<std::int64_t> candidates;
  {
    sqlite::Statement select = connection_->db.Prepare("SELECT id FROM workers WHERE retired = 0 AND id <> ?");
    select.Bind(1, worker_id_);
    while (select.Step("read the workers")) candidates.push_back(select.Integer(0));
  }
  std::int64_t alive = 0;
  for (const std::int64_t worker : candidates) alive += WorkerIsAlive(worker) ? 1 : 0;
  return alive;
}

void ResultsStore::Heartbeat() {
  if (worker_id_ == 0) return;
  sqlite::Statement update = connection_->db.Prepare("UPDATE workers SET heartbeat_s = ? WHERE id = ?");
  update.Bind(1, UnixNowSeconds());
  update.Bind(2, worker_id_);
  update.Step("renew this worker's heartbeat");
}

void ResultsStore::Retire() noexcept {
  if (worker_id_ == 0 || !connection_) return;
  try {
    connection_->db.RollbackQuietly();
    sqlite::Statement update = connection_->db.Prepare("UPDATE workers SET retired = 1, heartbeat_s = ? WHERE id = ?");
    update.Bind(1, UnixNowSeconds());
    update.Bind(2, worker_id_);
    update.Step("retire this worker");
  } catch (...) {
    // A full disk or a lost lock: the worker is taken for dead once this process ends anyway.
  }
  try {
    const std::lock_guard lock(OpenWorkersMutex());
    OpenWorkers().erase({connection_->open_key, worker_id_});
  } catch (...) {
  }
  worker_id_ = 0;
}

ClaimResult ResultsStore::ClaimRuns(const std::vector<std::int64_t>& candidates, std::size_t max_claims) {
  UASCMA_CHECK(worker_id_ != 0, "ClaimRuns needs JoinAsWorker first");
  ClaimResult result;
  if (candidates.empty() || max_claims == 0) return result;
  sqlite::Database& db = connection_->db;
  const double now_s = UnixNowSeconds();
  std::map<std::int64_t, bool> alive;  // per holder, within this transaction
  try {
    db.Execute("BEGIN IMMEDIATE", "claim runs");
    for (std::size_t i = 0; i < candidates.size() && result.claimed.size() < max_claims; ++i) {
      const std::int64_t run_index = candidates[i];
      result.examined = i + 1;
      // The flights of the run still missing, in slot order.
      std::set<std::string> stored;
      {
        sqlite::Statement select = db.Prepare("SELECT policy FROM runs WHERE campaign_hash = ? AND run_index = ?");
        select.Bind(1, header_.campaign_hash);
        select.Bind(2, run_index);
        while (select.Step("read the stored flights")) stored.insert(select.Text(0));
      }
      FlightTask task{run_index, {}};
      for (int slot = 0; slot < static_cast<int>(header_.policies.size()); ++slot) {
        if (stored.count(header_.policies[slot].name) == 0) task.slots.push_back(slot);
      }
      if (task.slots.empty()) continue;  // flown already
      std::int64_t holder = 0;
      {
        sqlite::Statement select = db.Prepare("SELECT worker FROM claims WHERE campaign_hash = ? AND run_index = ?");
        select.Bind(1, header_.campaign_hash);
        select.Bind(2, run_index);
        if (select.Step("read a claim")) holder = select.Integer(0);
      }
      if (holder != 0) {
        auto known = alive.find(holder);
        if (known == alive.end()) known = alive.emplace(holder, holder == worker_id_ || WorkerIsAlive(holder)).first;
        if (known->second) {
          result.held.push_back(run_index);
          continue;
        }
      }
      sqlite::Statement claim = db.Prepare(
          "INSERT INTO claims (campaign_hash, run_index, worker, claimed_s) VALUES (?, ?, ?, ?) "
          "ON CONFLICT (campaign_hash, run_index) DO UPDATE SET worker = excluded.worker, claimed_s = excluded.claimed_s");
      claim.Bind(1, header_.campaign_hash);
      claim.Bind(2, run_index);
      claim.Bind(3, worker_id_);
      claim.Bind(4, now_s);
      claim.Step("claim a run");
      result.claimed.push_back(std::move(task));
    }
    db.Execute("COMMIT", "claim runs");
  } catch (...) {
    db.RollbackQuietly();
    throw;
  }
  return result;
}

std::int64_t ResultsStore::ClaimHolder(std::int64_t run_index) const {
  if (connection_->schema_version < 2) return 0;
  sqlite::Statement select =
      connection_->db.Prepare("SELECT worker FROM claims WHERE campaign_hash = ? AND run_index = ?");
  select.Bind(1, header_.campaign_hash);
  select.Bind(2, run_index);
  return select.Step("read a claim") ? select.Integer(0) : 0;
}

}  // namespace uascma::campaign
