#pragma once
// The results store's schema (store.h: the tables, the view, schema versions 1 and 2), the codec of its rows
// (RunRecord to and from a statement) and its campaign header, for the units of the store (store.cc,
// store_check.cc, store_workers.cc; defined in store_schema.cc).
#include <bit>
#include <cstdint>
#include <string>

#include "sqlite_database.h"
#include "uascma/campaign/record.h"
#include "uascma/campaign/store.h"

namespace uascma::campaign::store_internal {

// The tables of schema version 1 but the runs table (RunsTableSql), and the view.
inline constexpr const char* kSchemaSql = R"sql(
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
inline constexpr const char* kWorkSchemaSql = R"sql(
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

inline constexpr const char* kViewSql = R"sql(
CREATE VIEW run_outcomes AS
  SELECT run_index, policy, battery_health, fault, outcome, failure, sim_time_s, plan_duration_s,
         first_emergency_action, first_emergency_action_s, min_cell_voltage_v, average_reward, min_reward
  FROM runs;
)sql";

std::string RunsTableSql();
// The runs columns of every RunRecord field, in record order ("run_index, policy, …").
std::string ColumnList();
std::string UtcNow();
// Unix time in seconds (heartbeats and leases compare it between machines).
double UnixNowSeconds();
inline std::int64_t AsSigned(std::uint64_t value) { return std::bit_cast<std::int64_t>(value); }
inline std::uint64_t AsUnsigned(std::int64_t value) { return std::bit_cast<std::uint64_t>(value); }
void ApplyConnectionOptions(sqlite::Database& db, const StoreOptions& options);
void BindRecord(sqlite::Statement& statement, const std::string& campaign_hash, const RunRecord& record);
RunRecord ReadRow(const sqlite::Statement& statement);
void WriteHeader(sqlite::Database& db, const CampaignHeader& header);
std::int64_t SchemaVersion(sqlite::Database& db);
// Version 1 files lack only the work-sharing tables; they are read as they are.
CampaignHeader ReadHeader(sqlite::Database& db, std::int64_t* schema_version);

}  // namespace uascma::campaign::store_internal
