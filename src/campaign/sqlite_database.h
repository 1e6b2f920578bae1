#pragma once
// A thin RAII layer over the SQLite C API for the results store (private to src/campaign). Every failure
// becomes an InputError naming the database file and what was being done, with SQLite's message.
#include <sqlite3.h>

#include <cstdint>
#include <optional>
#include <string>

namespace uascma::campaign::sqlite {

// The error text of a failed call; a full disk gets a message that says so.
std::string Describe(sqlite3* db, int code);
// Whether an (extended) result code means the disk, or the database's page limit, is full: SQLITE_FULL, or an
// I/O error writing, syncing or growing the file (a file-size limit, an ENOSPC seen as EIO).
bool IsDiskFull(int code);

class Statement {
 public:
  Statement() = default;
  Statement(sqlite3* db, const std::string& sql, const std::string& path);
  ~Statement();
  Statement(Statement&& other) noexcept;
  Statement& operator=(Statement&& other) noexcept;
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  // Parameters are 1-based, as in SQLite.
  void Bind(int index, std::int64_t value);
  void Bind(int index, double value);
  void Bind(int index, const std::string& value);
  void BindNull(int index);
  // Advances; true while a row is available. Throws InputError on failure (`what` names the step).
  bool Step(const std::string& what);
  void Reset();

  // Columns are 0-based.
  bool IsNull(int column) const;
  int ColumnType(int column) const;  // SQLITE_INTEGER, SQLITE_FLOAT, SQLITE_TEXT, SQLITE_BLOB or SQLITE_NULL
  std::int64_t Integer(int column) const;
  double Real(int column) const;  // NULL → NaN
  std::string Text(int column) const;

  int last_code() const { return last_code_; }

 private:
  sqlite3* db_ = nullptr;
  sqlite3_stmt* statement_ = nullptr;
  std::string path_;
  int last_code_ = SQLITE_OK;
};

class Database;

// How OpenForReading opened a database.
enum class ReadAccess {
  kShared,     // as any reader: SQLite keeps its WAL index in <file>-shm beside the file
  kImmutable,  // the folder cannot be written, so no -shm can be made: read as an unchanging file
};

class Database {
 public:
  Database() = default;
  // Opens `file` only to read it. A sound database in a folder this process cannot write (SQLite cannot create
  // the -shm its WAL mode needs there, and says "unable to open database file") is opened with the URI parameter
  // immutable=1 instead, and *access says so. Its -wal, if it holds anything, would then not be read: that is
  // refused, naming the -wal and how to read it. Other failures are InputErrors as the constructor's.
  static Database OpenForReading(const std::string& file, const std::string& name_in_errors, ReadAccess* access);
  // Opens `file` with the given flags (SQLITE_OPEN_*). Errors name `name_in_errors` (default: `file`), so
  // a file built under a temporary name reports the user's path; path() returns that name too.
  Database(const std::string& file, int flags, const std::string& name_in_errors = "");
  ~Database();
  Database(Database&& other) noexcept;
  Database& operator=(Database&& other) noexcept;
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;

  sqlite3* handle() const { return db_; }
  const std::string& path() const { return path_; }
  // Runs SQL without results; InputError naming the path and `what` on failure.
  void Execute(const std::string& sql, const std::string& what);
  Statement Prepare(const std::string& sql) const { return Statement(db_, sql, path_); }
  // Ends an open transaction without raising (used on the error path).
  void RollbackQuietly();
  void Close();

 private:
  sqlite3* db_ = nullptr;
  std::string path_;
};

}  // namespace uascma::campaign::sqlite
