#pragma once
// The report of a stored campaign (what `uascma report` and `uascma campaign` print): the campaign's
// identity, how many flights are stored, and the statistics of campaign/statistics.h.
#include <string>

#include <nlohmann/json.hpp>

#include "uascma/campaign/landing_causes.h"
#include "uascma/campaign/statistics.h"
#include "uascma/campaign/store.h"

namespace uascma::campaign {

struct CampaignReport {
  CampaignHeader header;
  std::int64_t flights = 0;                        // stored
  std::int64_t complete_runs = 0;                  // runs flown by every policy
  std::vector<GroupStatistics> groups;             // policies in slot order × G, M, P, all
  std::vector<PairedComparison> comparisons;       // McNemar per pair of policies × G, M, P, all
  std::vector<LandingCauseCounts> landing_causes;  // unnecessary landings by cause (campaign/landing_causes.h)
};

// Statistics over the runs flown by every policy of the campaign (an interrupted campaign may hold a
// run flown by only some policies; leaving it out keeps the comparison paired).
CampaignReport MakeCampaignReport(const ResultsStore& store);

// {"campaign": {name, seed, config_hash, campaign_hash, code_version, created_utc, runs_requested,
//  flights, complete_runs, policies: [...]}, "policies": {...}, "policy_order": [...], "confidence_level",
//  "paired_comparisons": [...], "dissertation": {...}} (campaign/statistics.h), "unnecessary_landing_causes":
//  {policy: {group: {cause: n}}} (campaign/landing_causes.h)
nlohmann::json CampaignReportJson(const CampaignReport& report);
std::string CampaignReportText(const CampaignReport& report);

}  // namespace uascma::campaign
