#pragma once
// Shared by the results-store tests (tests/campaign/store_test.cc, tests/apps/campaign_concurrency_test.cc):
// looks at a campaign database from outside, as another process would.
#include <sqlite3.h>

#include <cstdint>
#include <exception>
#include <filesystem>
#include <string>

#include "uascma/campaign/store.h"

namespace uascma::campaign::testing_support {

// SQLite's PRAGMA integrity_check through a read-only connection of its own: "ok" for a sound file.
inline std::string IntegrityCheck(const std::filesystem::path& path) {
  sqlite3* db = nullptr;
  sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* statement = nullptr;
  sqlite3_prepare_v2(db, "PRAGMA integrity_check", -1, &statement, nullptr);
  std::string result = sqlite3_step(statement) == SQLITE_ROW
                           ? reinterpret_cast<const char*>(sqlite3_column_text(statement, 0))
                           : "no answer";
  sqlite3_finalize(statement);
  sqlite3_close(db);
  return result;
}

// The flights stored in `db`; 0 while it does not exist (yet) or cannot be read.
inline std::int64_t StoredFlightsOrZero(const std::filesystem::path& db) {
  std::error_code ec;
  if (!std::filesystem::exists(db, ec)) return 0;
  try {
    return ResultsStore::Open(db).CountFlights();
  } catch (const std::exception&) {
    return 0;
  }
}

}  // namespace uascma::campaign::testing_support
