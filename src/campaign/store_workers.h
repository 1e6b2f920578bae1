#pragma once
// The worker registry of a results store (store.h: workers, claims, heartbeats), defined in store_workers.cc; store.cc
// registers the worker of a store opened to write and retires it on close.
#include <cstdint>
#include <mutex>
#include <set>
#include <string>
#include <utility>

#include "sqlite_database.h"
#include "uascma/campaign/store.h"

namespace uascma::campaign::store_internal {

std::int64_t InsertWorker(sqlite::Database& db, const WorkerIdentity& me);
// The workers that are open in this process, by (database, worker id): a worker of this very process is
// alive exactly while its ResultsStore is open.
std::mutex& OpenWorkersMutex();
std::set<std::pair<std::string, std::int64_t>>& OpenWorkers();

}  // namespace uascma::campaign::store_internal
