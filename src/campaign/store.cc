#include "uascma/campaign/store.h"

#include <sys/stat.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "store_check.h"
#include "store_connection.h"
#include "store_schema.h"
#include "store_workers.h"
#include "uascma/campaign/config.h"
#include "uascma/campaign/policies.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/common/version.h"

// Creating, opening, writing and reading a results store. The schema and the row codec are in store_schema.cc,
// the check of a file in store_check.cc, the work shared between processes in store_workers.cc.
namespace uascma::campaign {
namespace {

// The (device, inode) of the file at `path`, nothing when there is none.
std::optional<std::pair<std::uint64_t, std::uint64_t>> FileIdentity(const std::filesystem::path& path) {
  struct stat status {};
  if (::stat(path.c_str(), &status) != 0) return std::nullopt;
  return std::pair<std::uint64_t, std::uint64_t>{status.st_dev, status.st_ino};
}

// The database was renamed, replaced or deleted while a campaign wrote it. SQLite keeps writing the file it
// opened, but its -wal stays at the old name and, once the file has moved, SQLite refuses to write or checkpoint
// (SQLITE_READONLY_DBMOVED): the flights committed so far are in that -wal, which reads only beside its file.
InputError MovedDatabaseError(const std::filesystem::path& path) {
  std::error_code ec;
  const bool something_there = std::filesystem::exists(path, ec);
  return InputError(
      path.string(), "file",
      fmt::format("the database this campaign opened, but it was {} while the campaign ran; the campaign stopped "
                  "and wrote nothing more. The flights committed before are in '{}-wal' (kept at this path) and "
                  "the moved file: to recover them, put the moved file back at {} beside that -wal (a deleted "
                  "file cannot be: run the campaign again), then 'uascma store check {}' and continue with "
                  "--resume",
                  something_there ? "replaced by another file" : "renamed or deleted", path.string(), path.string(),
                  path.string()));
}

using store_internal::ApplyConnectionOptions;
using store_internal::BindRecord;
using store_internal::ColumnList;
using store_internal::InsertWorker;
using store_internal::kSchemaSql;
using store_internal::kViewSql;
using store_internal::kWorkSchemaSql;
using store_internal::OpenWorkers;
using store_internal::OpenWorkersMutex;
using store_internal::ReadHeader;
using store_internal::ReadRow;
using store_internal::RequireUndamaged;
using store_internal::RunsTableSql;
using store_internal::UtcNow;
using store_internal::WriteHeader;

// A campaign resumed into or joined writes rows into the file and its -wal and -shm beside it: a file or a folder
// this user cannot write is said to be one here, before SQLite meets it at its first statement with an error that
// names no permission.
void RequireWritable(const std::filesystem::path& path) {
  const std::filesystem::path folder = ContainingFolder(path);
  const bool file_writable = ::access(path.c_str(), W_OK) == 0;
  if (file_writable && ::access(folder.c_str(), W_OK) == 0) return;
  throw InputError(path.string(), file_writable ? "folder" : "file",
                   fmt::format("a campaign database this user can write, in a folder where its -wal and -shm can be "
                               "made (a campaign adds its flights there), but {} cannot be written ('uascma report' "
                               "and 'uascma store check' read it as it is)",
                               (file_writable ? folder : path).string()));
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
  std::filesystem::directory_iterator entries(ContainingFolder(path), ec);
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

// Fails with "PATH: folder: …" unless `folder` exists and this process can write in it.
void RequireWritableFolder(const std::filesystem::path& folder, const std::string& name) {
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec)) {
    throw InputError(name, "folder",
                     fmt::format("an existing folder, but '{}' {}", folder.string(),
                                 std::filesystem::exists(folder, ec) ? "is not a folder" : "does not exist"));
  }
  if (::access(folder.c_str(), W_OK | X_OK) != 0) {
    throw InputError(
        name, "folder",
        fmt::format("a folder you can write, but '{}' is not writable ({})", folder.string(), std::strerror(errno)));
  }
}

// Writes the whole new database to `temporary` (the schema, the campaign and, with a worker identity, the
// creator's worker row), checkpoints it into the main file and checks it as it will be published. Returns the
// worker id (0 without a worker). Errors name `name`, the user's path.
std::int64_t WriteNewDatabase(const std::filesystem::path& temporary, const std::string& name,
                              const CampaignHeader& header, const StoreOptions& options,
                              const WorkerIdentity* worker_identity) {
  std::int64_t worker = 0;
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
  if (worker_identity != nullptr) worker = InsertWorker(db, *worker_identity);
  db.Execute("COMMIT", "create");
  // Everything into the main file before it is published: the link below publishes that file alone,
  // without its -wal. Closing checkpoints too, but a checkpoint that fails there (a full disk) goes
  // unreported and would leave the committed pages only in the -wal (a truncated database at
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
  return worker;
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

ResultsStore::ResultsStore(std::filesystem::path path, std::unique_ptr<Connection> connection, CampaignHeader header,
                           StoreOptions options)
    : path_(std::move(path)),
      connection_(std::move(connection)),
      header_(std::move(header)),
      options_(std::move(options)) {}

ResultsStore::ResultsStore(ResultsStore&& other) noexcept
    : path_(std::move(other.path_)),
      connection_(std::move(other.connection_)),
      header_(std::move(other.header_)),
      options_(std::move(other.options_)),
      worker_id_(std::exchange(other.worker_id_, 0)) {}

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
  const std::filesystem::path folder = ContainingFolder(path);
  RequireWritableFolder(folder, name);
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
    worker = WriteNewDatabase(temporary, name, header, options, as_worker ? &me : nullptr);
    linked = LinkIntoPlace(temporary, path);
  } catch (const std::filesystem::filesystem_error& e) {
    RemoveSqliteFiles(temporary);
    throw InputError(name, "create",
                     std::string("a writable location (") + e.code().message() + "); nothing was created");
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

ResultsStore ResultsStore::Open(const std::filesystem::path& path, const StoreOptions& options) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(path.string(), "file", "an existing campaign database");
  }
  if (!options.read_only) RequireWritable(path);
  auto connection = std::make_unique<Connection>();
  sqlite::ReadAccess access = sqlite::ReadAccess::kShared;
  connection->db = options.read_only ? sqlite::Database::OpenForReading(path.string(), path.string(), &access)
                                     : sqlite::Database(path.string(), SQLITE_OPEN_READWRITE);
  connection->read_immutable = access == sqlite::ReadAccess::kImmutable;
  connection->identity = FileIdentity(path);
  ApplyConnectionOptions(connection->db, options);
  RequireUndamaged(connection->db);  // a damaged file is named, never read or resumed into (store.h)
  CampaignHeader header = ReadHeader(connection->db, &connection->schema_version);
  connection->insert = connection->db.Prepare(
      fmt::format("INSERT OR IGNORE INTO runs (campaign_hash, {}) VALUES (?{})", ColumnList(), [] {
        std::string marks;
        const RunRecord empty;
        VisitRecordFields(empty, [&marks](const char*, const auto&) { marks += ", ?"; });
        return marks;
      }()));
  connection->open_key = std::filesystem::weakly_canonical(path, ec).string();
  if (ec) connection->open_key = std::filesystem::absolute(path, ec).string();
  return ResultsStore(path, std::move(connection), std::move(header), options);
}

bool ResultsStore::read_immutable() const { return connection_->read_immutable; }

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
    if (FileIdentity(path_) != connection_->identity) throw MovedDatabaseError(path_);
    db.Execute("COMMIT", "write");
  } catch (const InputError& e) {
    const int code = sqlite3_extended_errcode(db.handle());
    insert.Reset();
    db.RollbackQuietly();
    if (code == SQLITE_READONLY_DBMOVED || FileIdentity(path_) != connection_->identity) {
      throw MovedDatabaseError(path_);
    }
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
  sqlite::Statement select = connection_->db.Prepare(
      fmt::format("SELECT {} FROM runs WHERE campaign_hash = ? AND run_index = ? AND policy = ?", ColumnList()));
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

}  // namespace uascma::campaign
