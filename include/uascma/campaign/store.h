#pragma once
// The results store of a campaign: one SQLite file per campaign (scripts/install-deps.sh), written
// by one or several processes at once.
//
// Schema (PRAGMA user_version = 2, journal_mode = WAL):
//   campaign(id = 1, name, config_yaml, config_hash, campaign_hash, seed, runs_requested,
//            code_version, created_utc)
//       config_yaml: the canonical configuration (campaign/config.h), enough to resample every run;
//       config_hash: CampaignConfigHash; campaign_hash: config_hash + the policy set (PolicySetHash);
//       seed: the campaign seed as a signed 64-bit integer (bit pattern of the unsigned seed).
//   policies(slot PRIMARY KEY, name UNIQUE, kind, source, hash, actions_json)
//       actions_json: the action name of each CMA state for kind "table" (so runs replay without files).
//   runs(campaign_hash, run_index, policy, <every RunRecord field, record.h>,
//        PRIMARY KEY (campaign_hash, run_index, policy))
//       unsigned fields (run_seed) are stored by their 64-bit pattern as INTEGER; optional values NULL.
//   view run_outcomes: runs with the columns most reports need.
//   workers(id INTEGER PRIMARY KEY, host, boot_id, pid_namespace, pid, start_ticks, started_utc,
//           heartbeat_s, retired)                                                   (since version 2)
//       one row per process that took part (WorkerIdentity); heartbeat_s: Unix time of its last sign of
//       life; retired = 1 once it stopped (success or error).
//   claims(campaign_hash, run_index, worker REFERENCES workers(id), claimed_s,
//          PRIMARY KEY (campaign_hash, run_index))                                   (since version 2)
//       the worker that flies (or flew) the missing flights of a run. Rows stay after the flights are
//       stored: they record who flew what.
//   Version 1 files (no workers, claims) are read as they are and raised to version 2, in one
//   transaction, by the first process that joins them as a worker (JoinAsWorker).
//
// Crash safety. The file is created whole (schema, campaign row and the creator's worker row written to
// a temporary file beside it, then hard-linked to `path`, which fails if `path` appeared meanwhile), so
// a killed or failed creation never leaves a half-made database, and of several processes creating the
// same file exactly one succeeds (TryCreate). Rows are inserted in one transaction per batch with
// INSERT OR IGNORE on the primary key: a batch is either all in or not at all, and inserting the same
// flight twice (a resumed campaign, a repeated batch) changes nothing. A full disk (SQLITE_FULL, or an
// I/O error from a file-size limit) rolls the batch back and throws an InputError naming the file; the
// database keeps every batch committed before. Every error names the user's path, never the temporary
// file, and the temporary file is removed on every error.
//
// Damage. Every Open first checks the file (CheckStore: SQLite's integrity check, then the schema's own
// invariants) and refuses a damaged one with an InputError naming the file and the first problem: nothing
// reports on it, resumes into it or replays from it. `uascma store check DB` lists every problem.
//
// Several processes. Each process writing the campaign registers as a worker and claims a run (in a
// BEGIN IMMEDIATE transaction, the same discipline as the inserts) before flying it; a run is claimable
// when it has flights missing and no claim, or its claim is held by a worker that is no longer alive:
//   - same kernel and pid namespace (equal boot_id and pid_namespace): alive while its pid runs with the
//     same start time (a reused pid is told apart; a zombie counts as dead) and it is not retired;
//     inside one process, while the worker's ResultsStore is open (several stores per process: tests);
//   - another machine (or container): alive until kClaimLeaseSeconds after its last heartbeat (every
//     kHeartbeatPeriodSeconds), which assumes clocks agree to well within the lease.
// So a kill -9 frees its claims at once for processes on the same machine. Where SQLite locking does not
// work the store cannot be shared: WAL mode keeps its lock state in shared memory (the -shm file), which
// works only between processes of one kernel. Several machines on one network file system (NFS, SMB,
// Lustre, …) must not write one database at once, even where POSIX locks work; JoinAsWorker refuses when
// a live worker of another machine is registered (MPI is the way to spread a campaign over machines:
// rank 0 alone writes). On an NFS mount without locks (nolock) even one machine's processes are unsafe.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "uascma/campaign/config.h"
#include "uascma/campaign/policies.h"
#include "uascma/campaign/record.h"

namespace uascma::campaign {

inline constexpr int kStoreSchemaVersion = 2;

// A live worker renews its heartbeat this often (our estimate: one short write every few seconds costs
// nothing next to the flights, and keeps a lease far from expiring while the worker lives).
inline constexpr double kHeartbeatPeriodSeconds = 5.0;
// A worker of another machine whose heartbeat is older than this is taken for dead and its claims are
// free (our estimate: twelve missed heartbeats; tolerates clocks that disagree by tens of seconds).
inline constexpr double kClaimLeaseSeconds = 60.0;

struct CampaignHeader {
  std::string name;
  std::string config_yaml;
  std::string config_hash;
  std::string campaign_hash;
  std::uint64_t seed = 0;
  std::int64_t runs_requested = 0;
  std::string code_version;
  std::string created_utc;
  std::vector<CampaignPolicy> policies;  // in slot order
};

// The header of a campaign about to run (code version and creation time filled in).
CampaignHeader MakeCampaignHeader(const CampaignConfig& config, const std::vector<CampaignPolicy>& policies);

struct StoreOptions {
  // PRAGMA max_page_count for this connection (0: SQLite's default). Tests use it to fill the
  // "disk" without a small filesystem.
  std::int64_t max_page_count = 0;
  int busy_timeout_ms = 10000;
  double claim_lease_s = kClaimLeaseSeconds;  // see the header comment
  // Open only to read (report, simulate --replay, Python's readers): a sound file in a folder this user cannot
  // write is read as immutable (StoreCheckResult::read_immutable) instead of failing; writes then fail.
  bool read_only = false;
};

// One run index and the policy slots still to fly on it.
struct FlightTask {
  std::int64_t run_index = 0;
  std::vector<int> slots;
};

// Who a worker is: enough to tell, from another process, whether it still runs.
struct WorkerIdentity {
  std::string host;           // gethostname(), for messages
  std::string boot_id;        // /proc/sys/kernel/random/boot_id: equal <=> the same running kernel
  std::string pid_namespace;  // /proc/self/ns/pid: equal (with boot_id) <=> pids can be compared
  std::int64_t pid = 0;
  std::int64_t start_ticks = 0;  // field 22 of /proc/PID/stat (clock ticks after boot); 0 when unknown
};
WorkerIdentity ThisProcessIdentity();
// Whether `pid` runs (not a zombie) and, when start_ticks is known, started at start_ticks. Only
// meaningful for a pid of this kernel and pid namespace.
bool ProcessIsRunning(std::int64_t pid, std::int64_t start_ticks);

// What one ClaimRuns call found, for the candidates it examined (a prefix of those given).
struct ClaimResult {
  std::vector<FlightTask> claimed;  // now held by this worker, with the slots still missing
  std::vector<std::int64_t> held;   // flights missing, claim held by a live worker (this one included)
  std::size_t examined = 0;         // candidates looked at; the others were left for the next call
  // Candidates examined and in none of the lists had every flight stored.
};

// What CheckStore found in a database file.
struct StoreCheckResult {
  std::int64_t schema_version = 0;
  std::string campaign_name;
  std::string campaign_hash;
  std::int64_t runs_requested = 0;
  std::int64_t policies = 0;
  std::int64_t flights = 0;
  std::int64_t workers = 0;
  std::int64_t claims = 0;
  // The file's folder cannot be written, so SQLite could not make the -shm its WAL mode reads through: the
  // file was read as immutable (no other process may be writing it then; a -wal holding data is refused).
  bool read_immutable = false;
  // Each "table or row: what is wrong", at most kMaxListed per kind of check; problems_total counts all.
  std::vector<std::string> problems;
  std::int64_t problems_total = 0;
  static constexpr std::int64_t kMaxListed = 20;
  bool ok() const { return problems_total == 0; }
};

// Checks the campaign database at `path` without changing it, in one read transaction (a consistent
// snapshot while other processes write):
//   1. SQLite's PRAGMA integrity_check and foreign_key_check (claims refer to existing workers);
//   2. the schema: version 1 or 2, the tables of that version, a runs column for every RunRecord field;
//   3. the campaign row: exactly one; its configuration parses and has config_hash; campaign_hash is
//      config_hash + the hash of the policies table (so a deleted, added or edited policies row shows);
//   4. the policies: slots 0..P-1, each row's actions and hash as MakeStoredPolicy reads them;
//   5. every flight row: of this campaign, its policy in the policies table, 0 <= run_index <
//      runs_requested, flight_id = run_index x P + slot, each column of its declared type (integer, real,
//      NULL only where optional, text), booleans 0/1, text UTF-8, the JSON columns lists of the documented
//      shape (initial_cell_voltage_v: 6 numbers; actions: [time_s, name] pairs; substitutions: names);
//   6. claims of this campaign only, and for runs below runs_requested.
// InputError naming `path` when the file is missing or cannot be opened as SQLite at all; every other
// finding is a problem in the result.
StoreCheckResult CheckStore(const std::filesystem::path& path);

class ResultsStore {
 public:
  // A new store at `path`; InputError naming `path` when it exists (or appears while being created).
  static ResultsStore Create(const std::filesystem::path& path, const CampaignHeader& header,
                             const StoreOptions& options = {});
  // A new store at `path`, or nothing when a file is already there or another process created it first
  // (exactly one of several concurrent creators gets a store). With `as_worker` the creator is
  // registered as the first worker in the same file, so the database is never seen without a live
  // worker while its creator runs. InputError naming `path` (never the temporary file) when the folder
  // is missing or not writable; no temporary file survives.
  static std::optional<ResultsStore> TryCreate(const std::filesystem::path& path, const CampaignHeader& header,
                                               const StoreOptions& options = {}, bool as_worker = false);
  // An existing store; InputError naming the file when it is missing, not SQLite, not a campaign, or
  // damaged (CheckStore finds a problem: the first is named, with the count).
  static ResultsStore Open(const std::filesystem::path& path, const StoreOptions& options = {});

  ResultsStore(ResultsStore&&) noexcept;
  ResultsStore& operator=(ResultsStore&&) noexcept;
  ~ResultsStore();  // retires this store's worker, if it joined as one

  const std::filesystem::path& path() const { return path_; }
  const CampaignHeader& header() const { return header_; }
  // Opened to read from a folder this user cannot write, as an unchanging file (StoreOptions::read_only).
  bool read_immutable() const;
  // The configuration the runs were sampled with (parsed back from config_yaml and checked against
  // config_hash).
  CampaignConfig config() const;

  // Raises runs_requested (never lowers it).
  void RecordRunsRequested(std::int64_t runs);
  // Inserts the records in one transaction; records already present are left as they are.
  void Insert(const std::vector<RunRecord>& records);
  // (run_index, policy) of every stored flight.
  std::vector<std::pair<std::int64_t, std::string>> StoredFlights() const;
  std::int64_t CountFlights() const;
  // Every record, ordered by run_index then policy slot.
  std::vector<RunRecord> ReadRecords() const;
  // One record, if stored.
  std::optional<RunRecord> ReadRecord(std::int64_t run_index, const std::string& policy) const;
  std::optional<RunRecord> ReadRecordByFlightId(std::int64_t flight_id) const;

  // ---- sharing the work between processes (header comment) -----------------------------------------
  // A store is not thread-safe: a process that claims from several threads guards it with a mutex.
  //
  // Registers this process as a worker (raising a version-1 file to version 2 first) and returns its
  // id; joining twice returns the same id. InputError naming the file when a live worker of another
  // machine is registered (SQLite's WAL mode works only within one machine).
  std::int64_t JoinAsWorker();
  std::int64_t worker_id() const { return worker_id_; }  // 0 until joined
  // Workers other than this store's that are alive (header comment); 0 for a version-1 file.
  std::int64_t CountLiveWorkers() const;
  // Renews this worker's heartbeat (call at least every kHeartbeatPeriodSeconds).
  void Heartbeat();
  // Marks this worker retired: its claims on runs with missing flights become free at once. Idempotent;
  // errors are swallowed (the worker is dead for everyone once its process ends anyway).
  void Retire() noexcept;
  // Examines `candidates` (run indices) in order in one write transaction and claims for this worker
  // the first `max_claims` runs that have flights missing and no claim held by a live worker.
  ClaimResult ClaimRuns(const std::vector<std::int64_t>& candidates, std::size_t max_claims);
  // The worker holding the claim on run `run_index`, if any (0 when none).
  std::int64_t ClaimHolder(std::int64_t run_index) const;
  // Who worker `worker` is, for a message to the user (a waiting --resume says what it waits
  // for): "pid P on this machine (stopped: ...)" with what the process is doing as far as this machine can tell
  // (running, stopped by Ctrl-Z or SIGSTOP, ended), or "a process on host H" for another machine's worker.
  std::string DescribeWorker(std::int64_t worker) const;

 private:
  struct Connection;
  ResultsStore(std::filesystem::path path, std::unique_ptr<Connection> connection, CampaignHeader header,
               StoreOptions options);
  bool WorkerIsAlive(std::int64_t worker) const;
  std::filesystem::path path_;
  std::unique_ptr<Connection> connection_;
  CampaignHeader header_;
  StoreOptions options_;
  std::int64_t worker_id_ = 0;
};

}  // namespace uascma::campaign
