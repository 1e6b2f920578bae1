// The results store's schema, its rows and its campaign header (store.h; store_schema.h).
#include "store_schema.h"

#include <chrono>
#include <cstdint>
#include <ctime>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include <fmt/format.h>

#include "uascma/campaign/policies.h"
#include "uascma/common/error.h"

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

}  // namespace

namespace store_internal {

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
  sqlite::Statement policy =
      db.Prepare("INSERT INTO policies (slot, name, kind, source, hash, actions_json) VALUES (?, ?, ?, ?, ?, ?)");
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

}  // namespace store_internal
}  // namespace uascma::campaign
