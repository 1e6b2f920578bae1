#pragma once
// The check of a results store file (store.h: CheckStore), defined in store_check.cc; store.cc refuses a damaged
// file with it when it opens one.
#include "sqlite_database.h"
#include "uascma/campaign/store.h"

namespace uascma::campaign::store_internal {

// The checks of CheckStore on an open connection (store.h lists them).
void CheckDatabase(sqlite::Database& db, StoreCheckResult* result);
// "PATH: database: an undamaged campaign database, but …" for Open.
void RequireUndamaged(sqlite::Database& db);

}  // namespace uascma::campaign::store_internal
