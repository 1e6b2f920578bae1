#pragma once
// What one `uascma campaign` (or uascma.run_campaign) invocation did, with its two forms: the line the
// CLI prints before the report, and the JSON object the CLI's --json puts under "run" and Python's run_campaign
// returns (with the campaign hash beside it). Formatted once here; the CLI and Python only print it.
#include <string>

#include <nlohmann/json.hpp>

#include "uascma/campaign/runner.h"

namespace uascma::campaign {

struct CampaignRunSummary {
  std::string db;           // the results database as the caller named it
  CampaignOutcome outcome;  // RunCampaign's

  double flights_per_s() const;  // flown by this invocation over its wall time (0 for none)
  // "flew N flights (B already stored, O flown meanwhile by other processes, T in the campaign) in W s: R flights/s
  // on K rank(s) x J thread(s); results in DB\n".
  std::string Text() const;
  // {db, flights_total, flights_before, flights_flown, flights_by_others, wall_time_s, flights_per_s,
  // jobs_per_rank, ranks}.
  nlohmann::json Json() const;
};

}  // namespace uascma::campaign
