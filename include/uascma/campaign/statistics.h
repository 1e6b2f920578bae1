#pragma once
// Campaign statistics (§5.5.3, Figs. 5.30–5.32): per policy and battery health (G/M/P, and all
// together), the outcome rates and the reward metrics, each with its standard error of the mean.
//
//   rate p = k / n over the n flights of the group, SEM = √(p (1 − p) / n)       (binomial)
//   mean m of a per-flight metric,               SEM = s / √n, s the sample standard deviation (n − 1)
// Rates: failure (sim::IsFailure: battery, control, collision, timeout), original-plan completion,
// emergency landing, termination; they sum to one. Reward metrics: the per-flight average reward per
// time step and minimum instantaneous reward (campaign/metrics.h), averaged over flights.
// An empty group has n = 0 and NaN estimates (null in JSON).
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "uascma/campaign/record.h"

namespace uascma::campaign {

struct Estimate {
  double value = 0.0;
  double sem = 0.0;
};
// k successes of n (n > 0): p and √(p(1 − p)/n); NaN for n = 0.
Estimate EstimateRate(std::int64_t successes, std::int64_t trials);
// Mean and s/√n of the values (s with n − 1; SEM 0 for one value); NaN for none.
Estimate EstimateMean(const std::vector<double>& values);

struct GroupStatistics {
  std::string policy;
  std::string battery_health;  // "G", "M", "P" or "all"
  std::int64_t runs = 0;
  std::int64_t failures = 0, completions = 0, emergency_landings = 0, terminations = 0;
  Estimate failure_rate, completion_rate, emergency_landing_rate, termination_rate;
  Estimate average_reward, min_reward;
};

inline constexpr const char* kHealthGroups[] = {"G", "M", "P", "all"};

// One group per (policy, health) with policies in `policy_order` (others after, by name) and health
// in kHealthGroups order.
std::vector<GroupStatistics> Summarise(const std::vector<RunRecord>& records,
                                       const std::vector<std::string>& policy_order = {});

// The dissertation's headline for comparison (§5.5.3, shared/spec/README.md): poor battery health,
// failure rate of CMA 1.3 % vs NoOp 71 %.
inline constexpr double kDissertationPoorHealthFailureRateCma = 0.013;
inline constexpr double kDissertationPoorHealthFailureRateNoOp = 0.71;

// {"policies": {"cma": {"G": {"runs", "failure_rate", "failure_rate_sem", …}, …}, …},
//  "dissertation": {…}}
nlohmann::json StatisticsToJson(const std::vector<GroupStatistics>& groups);
// A text table: one row per policy and health, rates in percent ± SEM, rewards ± SEM, then the
// dissertation's headline beside ours.
std::string StatisticsTable(const std::vector<GroupStatistics>& groups);

}  // namespace uascma::campaign
