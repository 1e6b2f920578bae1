#pragma once
// The report of a stored campaign (what `uascma report` and `uascma campaign` print): the campaign's
// identity, how many flights are stored, and the statistics of campaign/statistics.h.
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "uascma/campaign/config.h"
#include "uascma/campaign/landing_causes.h"
#include "uascma/campaign/statistics.h"
#include "uascma/campaign/store.h"

namespace uascma::campaign {

// The runs of one pack-fault kind (a campaign with `pack_faults:`): per policy, in slot order, runs, failures and
// completions. The fault of a run is drawn again from its record (run seed, plan duration) and the stored
// configuration, as the sampler drew it (campaign/sampler.h, step 9).
struct PackFaultGroup {
  std::string fault;  // "none" or models::PackFaultKindName; "any" for every faulted run
  std::vector<std::string> policies;
  std::vector<std::int64_t> runs, failures, completions;
};

// The pack fault the sampler drew for a run (campaign/sampler.h, step 9), drawn again from its run seed and nominal
// plan duration (both in its record) and the configuration: none without `pack_faults:`.
std::optional<models::PackFault> RedrawPackFault(const CampaignConfig& config, std::uint64_t run_seed,
                                                 double plan_duration_s);

struct CampaignReport {
  CampaignHeader header;
  std::int64_t flights = 0;                        // stored
  std::int64_t complete_runs = 0;                  // runs flown by every policy
  std::vector<GroupStatistics> groups;             // policies in slot order × G, M, P, all
  std::vector<PairedComparison> comparisons;       // McNemar per pair of policies × G, M, P, all
  std::vector<LandingCauseCounts> landing_causes;  // unnecessary landings by cause (campaign/landing_causes.h)
  std::vector<PackFaultGroup> by_pack_fault;       // with `pack_faults:` only: none, each kind flown, any
};

// Statistics over the runs flown by every policy of the campaign (an interrupted campaign may hold a
// run flown by only some policies; leaving it out keeps the comparison paired).
CampaignReport MakeCampaignReport(const ResultsStore& store);

// {"campaign": {name, seed, config_hash, campaign_hash, code_version, created_utc, runs_requested,
//  flights, complete_runs, policies: [...]}, "policies": {...}, "policy_order": [...], "confidence_level",
//  "paired_comparisons": [...], "dissertation": {...}} (campaign/statistics.h), "unnecessary_landing_causes":
//  {policy: {group: {cause: n}}} (campaign/landing_causes.h), "by_pack_fault" (with `pack_faults:`):
//  [{fault, policies: {name: {runs, failures, completions}}}]
nlohmann::json CampaignReportJson(const CampaignReport& report);
std::string CampaignReportText(const CampaignReport& report);

}  // namespace uascma::campaign
