// Sharing a campaign's work between processes (store.h: workers, claims, heartbeats).
#include "store_workers.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "store_connection.h"
#include "store_schema.h"
#include "uascma/common/error.h"

namespace uascma::campaign {
namespace {

using store_internal::InsertWorker;
using store_internal::kWorkSchemaSql;
using store_internal::OpenWorkers;
using store_internal::OpenWorkersMutex;
using store_internal::SchemaVersion;
using store_internal::UnixNowSeconds;

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

}  // namespace

namespace store_internal {

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

std::mutex& OpenWorkersMutex() {
  static std::mutex mutex;
  return mutex;
}
std::set<std::pair<std::string, std::int64_t>>& OpenWorkers() {
  static std::set<std::pair<std::string, std::int64_t>> workers;
  return workers;
}

}  // namespace store_internal

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
          "ON CONFLICT (campaign_hash, run_index) DO UPDATE SET worker = excluded.worker, claimed_s = "
          "excluded.claimed_s");
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

std::string ResultsStore::DescribeWorker(std::int64_t worker) const {
  sqlite::Statement select =
      connection_->db.Prepare("SELECT host, boot_id, pid_namespace, pid, start_ticks FROM workers WHERE id = ?");
  select.Bind(1, worker);
  if (!select.Step("read a worker")) return fmt::format("worker {} (no longer registered)", worker);
  if (connection_->me.pid == 0) connection_->me = ThisProcessIdentity();
  const WorkerIdentity& me = connection_->me;
  const std::int64_t pid = select.Integer(3);
  if (select.Text(1) != me.boot_id || select.Text(2) != me.pid_namespace) {
    return fmt::format("a process on host {} (pid {} there)", select.Text(0), pid);
  }
  if (pid == me.pid) return fmt::format("this process (pid {})", pid);
  const auto stat = ReadProcessStat(pid);
  if (!stat || (select.Integer(4) != 0 && stat->start_ticks != select.Integer(4)) || stat->state == 'Z' ||
      stat->state == 'X') {
    return fmt::format("pid {} on this machine (ended)", pid);
  }
  if (stat->state == 'T' || stat->state == 't') {
    return fmt::format(
        "pid {} on this machine (stopped: suspended by Ctrl-Z or SIGSTOP; 'fg' in its terminal or "
        "'kill -CONT {}' resumes it)",
        pid, pid);
  }
  return fmt::format("pid {} on this machine (running)", pid);
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
