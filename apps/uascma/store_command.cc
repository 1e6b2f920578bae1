// uascma store check — checks a campaign database the way every command that opens one does (campaign/store.h:
// CheckStore): SQLite's integrity check, then the schema's own invariants. Exit 0 when it is sound; exit 2 with
// every problem listed when it is damaged (a damaged database is never reported on, resumed into or replayed
// from).
#include <cstdio>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "commands.h"
#include "output.h"
#include "uascma/campaign/store.h"
#include "uascma/common/error.h"

namespace uascma::cli {
namespace {

nlohmann::json CheckJson(const std::string& db, const campaign::StoreCheckResult& result) {
  return {{"db", db},
          {"ok", result.ok()},
          {"schema_version", result.schema_version},
          {"campaign", result.campaign_name},
          {"campaign_hash", result.campaign_hash},
          {"runs_requested", result.runs_requested},
          {"policies", result.policies},
          {"flights", result.flights},
          {"workers", result.workers},
          {"claims", result.claims},
          {"read_immutable", result.read_immutable},
          {"problems_total", result.problems_total},
          {"problems", result.problems}};
}

void PrintCheck(const std::string& db, const campaign::StoreCheckResult& result) {
  if (!result.campaign_hash.empty()) {
    std::printf(
        "%s: campaign '%s' (hash %s, schema version %lld): %lld policies, %lld flights stored, %lld runs "
        "requested, %lld workers, %lld claims\n",
        db.c_str(), result.campaign_name.c_str(), result.campaign_hash.c_str(),
        static_cast<long long>(result.schema_version), static_cast<long long>(result.policies),
        static_cast<long long>(result.flights), static_cast<long long>(result.runs_requested),
        static_cast<long long>(result.workers), static_cast<long long>(result.claims));
  }
  if (result.read_immutable) {
    std::printf(
        "%s: read as an unchanging file: its folder cannot be written, so SQLite's shared-memory file "
        "(-shm) could not be made there; that is a permission, not damage\n",
        db.c_str());
  }
  if (result.ok()) {
    std::printf("%s: sound (SQLite's integrity check and the campaign's invariants hold)\n", db.c_str());
    return;
  }
  std::printf("%s: damaged, %lld problem%s:\n", db.c_str(), static_cast<long long>(result.problems_total),
              result.problems_total == 1 ? "" : "s");
  for (const std::string& problem : result.problems) std::printf("  %s\n", problem.c_str());
}

}  // namespace

void AddStoreCommand(CLI::App& app) {
  CLI::App* store = app.add_subcommand("store", "Campaign databases (the SQLite files of 'uascma campaign --db')");
  store->require_subcommand(1);
  auto db = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  CLI::App* check = store->add_subcommand(
      "check",
      "Checks a campaign database as report, campaign --resume and simulate --replay do before they use it:\n"
      "SQLite's integrity check, then the campaign's invariants (every policy row present, every flight of a\n"
      "stored policy and a requested run, each column of its type, JSON columns well formed, text UTF-8).\n"
      "Exit 0 when sound, 2 when damaged (every problem listed)");
  check->add_option("db", *db, "SQLite file written by 'uascma campaign'")->required();
  check->add_flag("--json", *json, "Print the findings as JSON");
  check->callback([db, json] {
    const campaign::StoreCheckResult result = campaign::CheckStore(*db);
    if (*json) {
      PrintJson(CheckJson(*db, result));
    } else {
      PrintCheck(*db, result);
    }
    std::fflush(stdout);
    if (!result.ok()) {
      throw InputError(
          *db, "database",
          fmt::format("an undamaged campaign database, but {} problem{} (listed {})", result.problems_total,
                      result.problems_total == 1 ? "" : "s", *json ? "in the JSON" : "above"));
    }
  });
}

}  // namespace uascma::cli
