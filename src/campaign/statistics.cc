#include "uascma/campaign/statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include <fmt/format.h>

namespace uascma::campaign {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

nlohmann::json Number(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr); }

std::string Percent(const Estimate& e) {
  if (!std::isfinite(e.value)) return "-";
  return fmt::format("{:5.1f} ± {:4.1f}", 100.0 * e.value, 100.0 * e.sem);
}

std::string Plain(const Estimate& e) {
  if (!std::isfinite(e.value)) return "-";
  return fmt::format("{:+.4f} ± {:.4f}", e.value, e.sem);
}

}  // namespace

Estimate EstimateRate(std::int64_t successes, std::int64_t trials) {
  if (trials <= 0) return {kNaN, kNaN};
  const double p = static_cast<double>(successes) / static_cast<double>(trials);
  return {p, std::sqrt(p * (1.0 - p) / static_cast<double>(trials))};
}

Estimate EstimateMean(const std::vector<double>& values) {
  if (values.empty()) return {kNaN, kNaN};
  const double n = static_cast<double>(values.size());
  double sum = 0.0;
  for (double v : values) sum += v;
  const double mean = sum / n;
  if (values.size() == 1) return {mean, 0.0};
  double squares = 0.0;
  for (double v : values) squares += (v - mean) * (v - mean);
  return {mean, std::sqrt(squares / (n - 1.0)) / std::sqrt(n)};
}

std::vector<GroupStatistics> Summarise(const std::vector<RunRecord>& records,
                                       const std::vector<std::string>& policy_order) {
  std::vector<std::string> policies = policy_order;
  std::vector<std::string> others;
  for (const RunRecord& r : records) {
    if (std::find(policies.begin(), policies.end(), r.policy) == policies.end() &&
        std::find(others.begin(), others.end(), r.policy) == others.end()) {
      others.push_back(r.policy);
    }
  }
  std::sort(others.begin(), others.end());
  policies.insert(policies.end(), others.begin(), others.end());

  std::vector<GroupStatistics> groups;
  for (const std::string& policy : policies) {
    for (const char* health : kHealthGroups) {
      GroupStatistics g;
      g.policy = policy;
      g.battery_health = health;
      std::vector<double> average, minimum;
      for (const RunRecord& r : records) {
        if (r.policy != policy || (g.battery_health != "all" && r.battery_health != g.battery_health)) continue;
        ++g.runs;
        if (r.failure) {
          ++g.failures;
        } else if (r.outcome == "completed") {
          ++g.completions;
        } else if (r.outcome == "emergency_landing") {
          ++g.emergency_landings;
        } else if (r.outcome == "terminated") {
          ++g.terminations;
        }
        average.push_back(r.average_reward);
        minimum.push_back(r.min_reward);
      }
      g.failure_rate = EstimateRate(g.failures, g.runs);
      g.completion_rate = EstimateRate(g.completions, g.runs);
      g.emergency_landing_rate = EstimateRate(g.emergency_landings, g.runs);
      g.termination_rate = EstimateRate(g.terminations, g.runs);
      g.average_reward = EstimateMean(average);
      g.min_reward = EstimateMean(minimum);
      groups.push_back(std::move(g));
    }
  }
  return groups;
}

nlohmann::json StatisticsToJson(const std::vector<GroupStatistics>& groups) {
  nlohmann::json policies = nlohmann::json::object();
  nlohmann::json order = nlohmann::json::array();
  for (const GroupStatistics& g : groups) {
    if (!policies.contains(g.policy)) {
      policies[g.policy] = nlohmann::json::object();
      order.push_back(g.policy);
    }
    policies[g.policy][g.battery_health] = {
        {"runs", g.runs},
        {"failures", g.failures},
        {"completions", g.completions},
        {"emergency_landings", g.emergency_landings},
        {"terminations", g.terminations},
        {"failure_rate", Number(g.failure_rate.value)},
        {"failure_rate_sem", Number(g.failure_rate.sem)},
        {"completion_rate", Number(g.completion_rate.value)},
        {"completion_rate_sem", Number(g.completion_rate.sem)},
        {"emergency_landing_rate", Number(g.emergency_landing_rate.value)},
        {"emergency_landing_rate_sem", Number(g.emergency_landing_rate.sem)},
        {"termination_rate", Number(g.termination_rate.value)},
        {"termination_rate_sem", Number(g.termination_rate.sem)},
        {"average_reward", Number(g.average_reward.value)},
        {"average_reward_sem", Number(g.average_reward.sem)},
        {"min_reward", Number(g.min_reward.value)},
        {"min_reward_sem", Number(g.min_reward.sem)},
    };
  }
  return {{"policies", policies},
          {"policy_order", order},
          {"dissertation",
           {{"source", "dissertation §5.5.3 (Fig. 5.30), shared/spec/README.md"},
            {"poor_health_failure_rate", {{"cma", kDissertationPoorHealthFailureRateCma},
                                          {"noop", kDissertationPoorHealthFailureRateNoOp}}}}}};
}

std::string StatisticsTable(const std::vector<GroupStatistics>& groups) {
  std::string out = fmt::format("{:<10} {:<3} {:>6}  {:>13}  {:>13}  {:>13}  {:>13}  {:>17}  {:>17}\n", "policy",
                                "BH", "runs", "failure %", "completed %", "em. landing %", "terminated %",
                                "avg reward", "min reward");
  out += std::string(118, '-') + "\n";
  std::string previous;
  for (const GroupStatistics& g : groups) {
    if (!previous.empty() && g.policy != previous) out += "\n";
    previous = g.policy;
    out += fmt::format("{:<10} {:<3} {:>6}  {:>13}  {:>13}  {:>13}  {:>13}  {:>17}  {:>17}\n", g.policy,
                       g.battery_health, g.runs, Percent(g.failure_rate), Percent(g.completion_rate),
                       Percent(g.emergency_landing_rate), Percent(g.termination_rate), Plain(g.average_reward),
                       Plain(g.min_reward));
  }
  out += "Rates in % ± binomial SEM; rewards: per-flight mean and minimum of R(S,A) per 1 Hz epoch ± SEM.\n";
  // The dissertation's headline beside ours (§5.5.3, Fig. 5.30).
  auto poor = [&groups](const std::string& policy) -> const GroupStatistics* {
    for (const GroupStatistics& g : groups) {
      if (g.policy == policy && g.battery_health == "P") return &g;
    }
    return nullptr;
  };
  out += "\nPoor battery health (BH = P), failure rate: ours vs the dissertation's (§5.5.3, Fig. 5.30)\n";
  const struct {
    const char* policy;
    double dissertation;
  } headline[] = {{"cma", kDissertationPoorHealthFailureRateCma}, {"noop", kDissertationPoorHealthFailureRateNoOp}};
  for (const auto& h : headline) {
    const GroupStatistics* g = poor(h.policy);
    out += fmt::format("  {:<5} ours {:>13} %  (n = {:>4})   dissertation {:5.1f} %\n", h.policy,
                       g != nullptr ? Percent(g->failure_rate) : std::string("-"), g != nullptr ? g->runs : 0,
                       100.0 * h.dissertation);
  }
  return out;
}

}  // namespace uascma::campaign
