#pragma once
// The connection of an open results store (store.h), shared by the units that hold one: store.cc creates, opens,
// writes and reads; store_workers.cc shares the work between processes. The schema and the row codec are in
// store_schema.h, the check of a file in store_check.h, the worker registry in store_workers.h.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include "sqlite_database.h"
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
  std::string open_key;  // the canonical path: store_internal::OpenWorkers() key (store_workers.h)
  WorkerIdentity me;
};

}  // namespace uascma::campaign
