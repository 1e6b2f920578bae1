#pragma once
// The results store of a campaign: one SQLite file per campaign (shared/spec/dependencies.md).
//
// Schema (PRAGMA user_version = 1, journal_mode = WAL):
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
//
// Crash safety. The file is created whole (schema and campaign row written to a temporary file, then
// renamed), so a killed or failed creation leaves no half-made database. Rows are inserted in one
// transaction per batch with INSERT OR IGNORE on the primary key: a batch is either all in or not at
// all, and inserting the same flight twice (a resumed campaign, a repeated batch) changes nothing. A
// full disk (SQLITE_FULL, or an I/O error from a file-size limit) rolls the batch back and throws an
// InputError naming the file; the database keeps every batch committed before.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "uascma/campaign/config.h"
#include "uascma/campaign/metrics.h"
#include "uascma/campaign/policies.h"
#include "uascma/campaign/record.h"
#include "uascma/campaign/sampler.h"

namespace uascma::campaign {

inline constexpr int kStoreSchemaVersion = 1;

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
};

class ResultsStore {
 public:
  // A new store at `path`, which must not exist (InputError otherwise).
  static ResultsStore Create(const std::filesystem::path& path, const CampaignHeader& header,
                             const StoreOptions& options = {});
  // An existing store; InputError naming the file when it is missing, not SQLite, or not a campaign.
  static ResultsStore Open(const std::filesystem::path& path, const StoreOptions& options = {});

  ResultsStore(ResultsStore&&) noexcept;
  ResultsStore& operator=(ResultsStore&&) noexcept;
  ~ResultsStore();

  const std::filesystem::path& path() const { return path_; }
  const CampaignHeader& header() const { return header_; }
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

 private:
  struct Connection;
  ResultsStore(std::filesystem::path path, std::unique_ptr<Connection> connection, CampaignHeader header);
  std::filesystem::path path_;
  std::unique_ptr<Connection> connection_;
  CampaignHeader header_;
};

// A flight loaded back for replay (`uascma simulate --replay DB RUN_ID`): its scenario resampled from
// the stored configuration and run seed, the policy that flew it, and what was recorded.
struct ReplayFlight {
  CampaignConfig config;
  SampledRun run;          // run.scenario is what to fly
  CampaignPolicy policy;   // MakeDecisionPolicy(policy) flies it
  int policy_slot = 0;
  int num_policies = 0;
  RunRecord recorded;
};
// `run_id` is a flight_id ("17") or "RUN_INDEX:POLICY" ("8:cma"). InputError naming the file or the
// id when it is unknown, or when the resampled scenario no longer matches the record (the sampler
// changed since the campaign ran).
ReplayFlight LoadReplay(const std::filesystem::path& db, const std::string& run_id);
// Flies the flight again; its record equals `recorded` except wall_time_s (FirstDifference).
RunRecord ReplayRun(const ReplayFlight& flight, const PlannerFactory& planner_factory = {});

}  // namespace uascma::campaign
