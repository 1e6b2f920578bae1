#pragma once
// Replaying one stored campaign flight (`uascma simulate --replay DB RUN_ID`): the flight's scenario is
// resampled from the configuration and campaign seed stored in the results store (campaign/store.h)
// and flown again by the policy stored with it. Because a flight depends only on (configuration,
// campaign seed, run index, policy) (campaign/runner.h), the replay reproduces the stored record bit for
// bit, wall_time_s aside.
#include <filesystem>
#include <string>

#include "uascma/campaign/config.h"
#include "uascma/campaign/metrics.h"
#include "uascma/campaign/policies.h"
#include "uascma/campaign/record.h"
#include "uascma/campaign/sampler.h"

namespace uascma::campaign {

// A flight loaded back for replay: its scenario resampled from the stored configuration and run seed,
// the policy that flew it, and what was recorded.
struct ReplayFlight {
  CampaignConfig config;
  SampledRun run;         // run.scenario is what to fly
  CampaignPolicy policy;  // MakeDecisionPolicy(policy) flies it
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
