#pragma once
// What the parts of the results store share (store.h; store.cc creates and reads, store_schema.cc holds the schema
// and the row codec, store_check.cc checks a file, store_workers.cc shares the work between processes).
#include <bit>
#include <cstdint>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <utility>

#include "sqlite_database.h"
#include "uascma/campaign/record.h"
#include "uascma/campaign/store.h"

namespace uascma::campaign {

struct ResultsStore::Connection {
  bool read_immutable = false;  // opened to read, as an unchanging file (StoreOptions::read_only)
  // The file opened (device, inode), compared with what the path names at each commit: a database renamed,
  // replaced or deleted under a running campaign is found at the next batch, not at the end.
  std::optional<std::pair<std::uint64_t, std::uint64_t>> identity;
  sqlite::Database db;
  sqlite::Statement insert;
  std::int64_t schema_version = kStoreSchemaVersion;
  std::string open_key;  // the canonical path: store_internal::OpenWorkers() key
  WorkerIdentity me;
};

namespace store_internal {

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

// ---- store_schema.cc: the schema, the rows, the campaign header -----------------------------------------------
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

// ---- store_check.cc ----------------------------------------------------------------------------------------
// The checks of CheckStore on an open connection (store.h lists them).
void CheckDatabase(sqlite::Database& db, StoreCheckResult* result);
// "PATH: database: an undamaged campaign database, but …" for Open.
void RequireUndamaged(sqlite::Database& db);

// ---- store_workers.cc --------------------------------------------------------------------------------------
std::int64_t InsertWorker(sqlite::Database& db, const WorkerIdentity& me);
// The workers that are open in this process, by (database, worker id): a worker of this very process is
// alive exactly while its ResultsStore is open.
std::mutex& OpenWorkersMutex();
std::set<std::pair<std::string, std::int64_t>>& OpenWorkers();

}  // namespace store_internal
}  // namespace uascma::campaign
