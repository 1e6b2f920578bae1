#include "sqlite_database.h"

#include <unistd.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <utility>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/files.h"

namespace uascma::campaign::sqlite {

bool IsDiskFull(int code) {
  const int primary = code & 0xff;
  return primary == SQLITE_FULL || code == SQLITE_IOERR_WRITE || code == SQLITE_IOERR_FSYNC ||
         code == SQLITE_IOERR_TRUNCATE || code == SQLITE_IOERR_SHMSIZE || code == SQLITE_IOERR_DIR_FSYNC;
}

std::string Describe(sqlite3* db, int code) {
  const int primary = code & 0xff;
  std::string message = db != nullptr ? sqlite3_errmsg(db) : sqlite3_errstr(code);
  if (IsDiskFull(code)) return "free disk space: the disk or database is full (" + message + ")";
  if (primary == SQLITE_NOTADB) return "an SQLite database written by 'uascma campaign' (" + message + ")";
  if (primary == SQLITE_CANTOPEN || primary == SQLITE_READONLY || primary == SQLITE_PERM) {
    return "a file and folder this user may read and write (SQLite's WAL mode makes the -wal and -shm files "
           "beside the database; a permission, not damage: " +
           message + ")";
  }
  if (primary == SQLITE_BUSY || primary == SQLITE_LOCKED) {
    return "no other process writing this database (" + message + ")";
  }
  return "a working SQLite database (" + message + ")";
}

Statement::Statement(sqlite3* db, const std::string& sql, const std::string& path) : db_(db), path_(path) {
  const int code = sqlite3_prepare_v2(db, sql.c_str(), -1, &statement_, nullptr);
  if (code != SQLITE_OK) throw InputError(path_, "prepare", Describe(db_, code));
}

Statement::~Statement() {
  if (statement_ != nullptr) sqlite3_finalize(statement_);
}

Statement::Statement(Statement&& other) noexcept
    : db_(other.db_),
      statement_(std::exchange(other.statement_, nullptr)),
      path_(std::move(other.path_)),
      last_code_(other.last_code_) {}

Statement& Statement::operator=(Statement&& other) noexcept {
  if (this != &other) {
    if (statement_ != nullptr) sqlite3_finalize(statement_);
    db_ = other.db_;
    statement_ = std::exchange(other.statement_, nullptr);
    path_ = std::move(other.path_);
    last_code_ = other.last_code_;
  }
  return *this;
}

void Statement::Bind(int index, std::int64_t value) { sqlite3_bind_int64(statement_, index, value); }
void Statement::Bind(int index, double value) {
  if (std::isnan(value)) {
    sqlite3_bind_null(statement_, index);
  } else {
    sqlite3_bind_double(statement_, index, value);
  }
}
void Statement::Bind(int index, const std::string& value) {
  sqlite3_bind_text(statement_, index, value.data(), static_cast<int>(value.size()), SQLITE_TRANSIENT);
}
void Statement::BindNull(int index) { sqlite3_bind_null(statement_, index); }

bool Statement::Step(const std::string& what) {
  last_code_ = sqlite3_step(statement_);
  if (last_code_ == SQLITE_ROW) return true;
  if (last_code_ == SQLITE_DONE) return false;
  const std::string message = Describe(db_, last_code_);
  sqlite3_reset(statement_);
  throw InputError(path_, what, message);
}

void Statement::Reset() {
  sqlite3_reset(statement_);
  sqlite3_clear_bindings(statement_);
}

bool Statement::IsNull(int column) const { return sqlite3_column_type(statement_, column) == SQLITE_NULL; }
int Statement::ColumnType(int column) const { return sqlite3_column_type(statement_, column); }
std::int64_t Statement::Integer(int column) const { return sqlite3_column_int64(statement_, column); }
double Statement::Real(int column) const {
  if (IsNull(column)) return std::numeric_limits<double>::quiet_NaN();
  return sqlite3_column_double(statement_, column);
}
std::string Statement::Text(int column) const {
  const auto* text = sqlite3_column_text(statement_, column);
  if (text == nullptr) return {};
  return {reinterpret_cast<const char*>(text), static_cast<std::size_t>(sqlite3_column_bytes(statement_, column))};
}

Database::Database(const std::string& file, int flags, const std::string& name_in_errors)
    : path_(name_in_errors.empty() ? file : name_in_errors) {
  const int code = sqlite3_open_v2(file.c_str(), &db_, flags, nullptr);
  if (code != SQLITE_OK) {
    const std::string message = Describe(db_, code);
    Close();
    throw InputError(path_, "open", message);
  }
  sqlite3_extended_result_codes(db_, 1);
}

namespace {

// Whether a first read of `db` succeeds; its result code otherwise.
int FirstReadCode(sqlite3* db) {
  sqlite3_stmt* statement = nullptr;
  int code = sqlite3_prepare_v2(db, "SELECT count(*) FROM sqlite_master", -1, &statement, nullptr);
  if (code == SQLITE_OK) {
    code = sqlite3_step(statement);
    if (code == SQLITE_ROW || code == SQLITE_DONE) code = SQLITE_OK;
  }
  sqlite3_finalize(statement);
  return code;
}

// `file` as an SQLite URI: every character outside the unreserved set written as %HH (RFC 3986).
std::string FileUri(const std::string& file) {
  const std::string absolute = std::filesystem::absolute(file).string();
  std::string uri = "file:";
  for (const char c : absolute) {
    const auto byte = static_cast<unsigned char>(c);
    if (std::isalnum(byte) || c == '/' || c == '-' || c == '_' || c == '.' || c == '~') {
      uri += c;
    } else {
      uri += fmt::format("%{:02X}", byte);
    }
  }
  return uri + "?immutable=1";
}

}  // namespace

Database Database::OpenForReading(const std::string& file, const std::string& name_in_errors, ReadAccess* access) {
  *access = ReadAccess::kShared;
  Database shared(file, SQLITE_OPEN_READONLY, name_in_errors);
  if (FirstReadCode(shared.handle()) == SQLITE_OK || ::access(ContainingFolder(file).c_str(), W_OK) == 0) return shared;
  // The folder cannot be written, so no -shm can be made there: a permission, not damage. The file alone is read
  // as immutable, which a -wal holding data would contradict.
  std::error_code ec;
  const std::string wal = file + "-wal";
  const auto wal_bytes = std::filesystem::exists(wal, ec) ? std::filesystem::file_size(wal, ec) : 0;
  if (!ec && wal_bytes > 0) {
    throw InputError(shared.path(), "folder",
                     fmt::format("a folder this user can write, or a -wal file that is empty: {} cannot be written, "
                                 "and {}-wal holds {} bytes of the database not yet in the main file (copy both "
                                 "files to a folder you can write and read the copy)",
                                 ContainingFolder(file).string(), shared.path(), wal_bytes));
  }
  Database immutable(FileUri(file), SQLITE_OPEN_READONLY | SQLITE_OPEN_URI, shared.path());
  if (FirstReadCode(immutable.handle()) != SQLITE_OK) return shared;  // not the folder: reported as before
  *access = ReadAccess::kImmutable;
  return immutable;
}

Database::~Database() { Close(); }

Database::Database(Database&& other) noexcept : db_(std::exchange(other.db_, nullptr)), path_(std::move(other.path_)) {}

Database& Database::operator=(Database&& other) noexcept {
  if (this != &other) {
    Close();
    db_ = std::exchange(other.db_, nullptr);
    path_ = std::move(other.path_);
  }
  return *this;
}

void Database::Execute(const std::string& sql, const std::string& what) {
  char* error = nullptr;
  const int code = sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &error);
  if (error != nullptr) sqlite3_free(error);
  if (code != SQLITE_OK) throw InputError(path_, what, Describe(db_, code));
}

void Database::RollbackQuietly() {
  if (db_ != nullptr && sqlite3_get_autocommit(db_) == 0) sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
}

void Database::Close() {
  if (db_ != nullptr) {
    sqlite3_close_v2(db_);
    db_ = nullptr;
  }
}

}  // namespace uascma::campaign::sqlite
