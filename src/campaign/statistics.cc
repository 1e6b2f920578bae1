#include "uascma/campaign/statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

#include <fmt/format.h>
#include <boost/math/distributions/binomial.hpp>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/special_functions/beta.hpp>

#include "uascma/common/error.h"
#include "uascma/sim/outcome.h"

namespace uascma::campaign {
namespace {

constexpr double kStatisticsNaN = std::numeric_limits<double>::quiet_NaN();

nlohmann::json StatisticsJsonNumber(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

void RequireCounts(std::int64_t successes, std::int64_t trials, const char* what) {
  if (trials < 0 || successes < 0 || successes > trials) {
    throw InputError(what, "counts", fmt::format("0 <= successes <= trials, got {} of {}", successes, trials));
  }
}

void RequireConfidence(double confidence, const char* what) {
  if (!(confidence > 0.0 && confidence < 1.0)) {
    throw InputError(what, "confidence", fmt::format("a level in (0, 1), got {}", confidence));
  }
}

std::string Percent(const Estimate& e) {
  if (!std::isfinite(e.value)) return "-";
  return fmt::format("{:5.1f} ± {:4.1f}", 100.0 * e.value, 100.0 * e.sem);
}

std::string PercentInterval(const Interval& i) {
  if (!std::isfinite(i.low)) return "-";
  return fmt::format("[{:5.1f}, {:5.1f}]", 100.0 * i.low, 100.0 * i.high);
}

std::string PlainEstimateText(const Estimate& e) {
  if (!std::isfinite(e.value)) return "-";
  return fmt::format("{:+.4f} ± {:.4f}", e.value, e.sem);
}

std::string PValue(double p) { return p < 1e-4 ? fmt::format("{:.1e}", p) : fmt::format("{:.4f}", p); }

// The outcome classes of statistics.h. A record's `failure` flag decides failure (the simulator's
// sim::IsFailure); the name decides the rest, unknown names landing in "other".
enum class OutcomeClass { kFailure, kCompleted, kEmergencyLanding, kTerminated, kGrounded, kLandedOffSite, kOther };

OutcomeClass ClassOf(const RunRecord& r) {
  if (r.failure) return OutcomeClass::kFailure;
  if (r.outcome == "completed") return OutcomeClass::kCompleted;
  if (r.outcome == "emergency_landing") return OutcomeClass::kEmergencyLanding;
  if (r.outcome == "terminated") return OutcomeClass::kTerminated;
  if (r.outcome == "grounded") return OutcomeClass::kGrounded;
  if (r.outcome == "landed_off_site") return OutcomeClass::kLandedOffSite;
  return OutcomeClass::kOther;
}

// Policies in the requested order, then the others by name.
std::vector<std::string> PolicyOrder(const std::vector<RunRecord>& records,
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
  return policies;
}

bool InHealthGroup(const RunRecord& r, const std::string& health) {
  return health == "all" || r.battery_health == health;
}

void CountUnnecessaryLandings(const std::vector<RunRecord>& records, std::vector<GroupStatistics>& groups) {
  const std::map<std::int64_t, const RunRecord*> noop = NoOpFlightsByRun(records);
  if (noop.empty()) return;
  for (GroupStatistics& g : groups) {
    g.has_noop_twin = true;
    for (const RunRecord& r : records) {
      if (r.policy != g.policy || !InHealthGroup(r, g.battery_health)) continue;
      if (IsUnnecessaryLanding(r, noop)) {
        ++g.unnecessary_landings;
        g.unnecessary_landings_fault_free += r.fault ? 0 : 1;
      }
      const auto twin = noop.find(r.run_index);
      if (r.outcome == sim::OutcomeName(sim::Outcome::kTerminated) && twin != noop.end()) {
        g.terminations_noop_completed += twin->second->outcome == sim::OutcomeName(sim::Outcome::kCompleted);
        g.terminations_noop_failed += twin->second->failure;
      }
    }
    g.unnecessary_landing_rate = EstimateRate(g.unnecessary_landings, g.runs);
  }
}

}  // namespace

std::map<std::int64_t, const RunRecord*> NoOpFlightsByRun(const std::vector<RunRecord>& records) {
  std::map<std::int64_t, const RunRecord*> noop;
  for (const RunRecord& r : records) {
    if (r.policy == kNoOpPolicy) noop[r.run_index] = &r;
  }
  return noop;
}

bool IsUnnecessaryLanding(const RunRecord& record, const std::map<std::int64_t, const RunRecord*>& noop_by_run) {
  const OutcomeClass outcome = ClassOf(record);
  if (outcome != OutcomeClass::kEmergencyLanding && outcome != OutcomeClass::kLandedOffSite) return false;
  const auto twin = noop_by_run.find(record.run_index);
  return twin != noop_by_run.end() && ClassOf(*twin->second) == OutcomeClass::kCompleted &&
         twin->second->end_reserve_s >= twin->second->safety_margin_s;
}

Estimate EstimateRate(std::int64_t successes, std::int64_t trials) {
  if (trials <= 0) return {kStatisticsNaN, kStatisticsNaN};
  const double p = static_cast<double>(successes) / static_cast<double>(trials);
  return {p, std::sqrt(p * (1.0 - p) / static_cast<double>(trials))};
}

Estimate EstimateMean(const std::vector<double>& values) {
  if (values.empty()) return {kStatisticsNaN, kStatisticsNaN};
  const double n = static_cast<double>(values.size());
  double sum = 0.0;
  for (double v : values) sum += v;
  const double mean = sum / n;
  if (values.size() == 1) return {mean, 0.0};
  double squares = 0.0;
  for (double v : values) squares += (v - mean) * (v - mean);
  return {mean, std::sqrt(squares / (n - 1.0)) / std::sqrt(n)};
}

Interval WilsonInterval(std::int64_t successes, std::int64_t trials, double confidence) {
  RequireCounts(successes, trials, "WilsonInterval");
  RequireConfidence(confidence, "WilsonInterval");
  if (trials == 0) return {kStatisticsNaN, kStatisticsNaN};
  // z = Φ⁻¹(1 − α/2), α = 1 − confidence (1.959964 at 95 %).
  const double z = boost::math::quantile(boost::math::normal_distribution<double>(), 0.5 + 0.5 * confidence);
  const double n = static_cast<double>(trials);
  const double k = static_cast<double>(successes);
  const double z2 = z * z;
  const double centre = (k + 0.5 * z2) / (n + z2);
  const double half = z / (n + z2) * std::sqrt(k * (n - k) / n + 0.25 * z2);
  // At k = 0 (k = n) the lower (upper) end is exactly 0 (1); clamp the round-off.
  return {successes == 0 ? 0.0 : std::max(0.0, centre - half),
          successes == trials ? 1.0 : std::min(1.0, centre + half)};
}

Interval ClopperPearsonInterval(std::int64_t successes, std::int64_t trials, double confidence) {
  RequireCounts(successes, trials, "ClopperPearsonInterval");
  RequireConfidence(confidence, "ClopperPearsonInterval");
  if (trials == 0) return {kStatisticsNaN, kStatisticsNaN};
  const double alpha = 1.0 - confidence;
  const double k = static_cast<double>(successes);
  const double n = static_cast<double>(trials);
  // The α/2 and 1 − α/2 quantiles of Beta(k, n − k + 1) and Beta(k + 1, n − k); the ends are 0 and 1.
  const double low = successes == 0 ? 0.0 : boost::math::ibeta_inv(k, n - k + 1.0, 0.5 * alpha);
  const double high = successes == trials ? 1.0 : boost::math::ibeta_inv(k + 1.0, n - k, 1.0 - 0.5 * alpha);
  return {low, high};
}

RateEstimate EstimateRateWithIntervals(std::int64_t successes, std::int64_t trials) {
  return {successes, EstimateRate(successes, trials), WilsonInterval(successes, trials),
          ClopperPearsonInterval(successes, trials)};
}

const char* FailureCauseName(FailureCause cause) {
  switch (cause) {
    case FailureCause::kBattery:
      return "battery";
    case FailureCause::kLossOfControl:
      return "loss_of_control";
    case FailureCause::kCollision:
      return "collision";
    case FailureCause::kTimeout:
      return "timeout";
    case FailureCause::kOther:
      return "other";
  }
  return "other";
}

FailureCause FailureCauseOf(const std::string& outcome) {
  if (outcome == "failed_battery") return FailureCause::kBattery;
  if (outcome == "failed_control") return FailureCause::kLossOfControl;
  if (outcome == "failed_collision") return FailureCause::kCollision;
  if (outcome == "timeout") return FailureCause::kTimeout;
  return FailureCause::kOther;
}

const char* BatteryFadesName(BatteryFades fades) {
  switch (fades) {
    case BatteryFades::kNone:
      return "none";
    case BatteryFades::kPowerOnly:
      return "power_only";
    case BatteryFades::kCapacity:
      return "capacity";
  }
  return "none";
}

BatteryFades BatteryFadesOf(const std::string& cell_health_code) {
  if (cell_health_code.find('Q') != std::string::npos) return BatteryFades::kCapacity;
  if (cell_health_code.find('R') != std::string::npos) return BatteryFades::kPowerOnly;
  return BatteryFades::kNone;
}

std::vector<GroupStatistics> Summarise(const std::vector<RunRecord>& records,
                                       const std::vector<std::string>& policy_order) {
  std::vector<GroupStatistics> groups;
  for (const std::string& policy : PolicyOrder(records, policy_order)) {
    for (const char* health : kHealthGroups) {
      GroupStatistics g;
      g.policy = policy;
      g.battery_health = health;
      std::vector<double> average, minimum;
      for (const RunRecord& r : records) {
        if (r.policy != policy || !InHealthGroup(r, g.battery_health)) continue;
        ++g.runs;
        const int fades = static_cast<int>(BatteryFadesOf(r.cell_health));
        ++g.runs_by_fades[fades];
        switch (ClassOf(r)) {
          case OutcomeClass::kFailure:
            ++g.failures;
            ++g.failures_by_fades[fades];
            ++g.failures_by_cause[static_cast<int>(FailureCauseOf(r.outcome))];
            break;
          case OutcomeClass::kCompleted:
            ++g.completions;
            break;
          case OutcomeClass::kEmergencyLanding:
            ++g.emergency_landings;
            break;
          case OutcomeClass::kTerminated:
            ++g.terminations;
            break;
          case OutcomeClass::kGrounded:
            ++g.groundings;
            break;
          case OutcomeClass::kLandedOffSite:
            ++g.off_site_landings;
            break;
          case OutcomeClass::kOther:
            ++g.others;
            break;
        }
        if (r.substitution_epochs > 0) {
          ++g.flights_with_substitution;
          g.substitution_epochs += r.substitution_epochs;
          try {
            for (const std::string& pair : nlohmann::json::parse(r.substitutions).get<std::vector<std::string>>()) {
              ++g.substitutions[pair];
            }
          } catch (const nlohmann::json::exception&) {
            throw InputError("results", "substitutions",
                             "a JSON list of \"Chosen->Taken\" names, got '" + r.substitutions + "'");
          }
        }
        average.push_back(r.average_reward);
        minimum.push_back(r.min_reward);
      }
      g.failure_rate = EstimateRate(g.failures, g.runs);
      g.completion_rate = EstimateRate(g.completions, g.runs);
      g.emergency_landing_rate = EstimateRate(g.emergency_landings, g.runs);
      g.termination_rate = EstimateRate(g.terminations, g.runs);
      g.grounded_rate = EstimateRate(g.groundings, g.runs);
      g.off_site_rate = EstimateRate(g.off_site_landings, g.runs);
      g.other_rate = EstimateRate(g.others, g.runs);
      g.failure_wilson = WilsonInterval(g.failures, g.runs);
      g.failure_clopper_pearson = ClopperPearsonInterval(g.failures, g.runs);
      g.completion_wilson = WilsonInterval(g.completions, g.runs);
      g.completion_clopper_pearson = ClopperPearsonInterval(g.completions, g.runs);
      g.average_reward = EstimateMean(average);
      g.min_reward = EstimateMean(minimum);
      groups.push_back(std::move(g));
    }
  }
  CountUnnecessaryLandings(records, groups);
  return groups;
}

McNemarTest CalcMcNemarTest(std::int64_t only_first_failed, std::int64_t only_second_failed) {
  if (only_first_failed < 0 || only_second_failed < 0) {
    throw InputError("McNemar's test", "discordant counts",
                     fmt::format("b, c >= 0, got {} and {}", only_first_failed, only_second_failed));
  }
  McNemarTest test;
  test.only_first_failed = only_first_failed;
  test.only_second_failed = only_second_failed;
  const std::int64_t discordant = only_first_failed + only_second_failed;
  if (discordant == 0) return test;  // no evidence either way: p = 1, χ² = 0
  // Exact: under H0 each discordant pair goes either way with probability ½.
  const boost::math::binomial_distribution<double> h0(static_cast<double>(discordant), 0.5);
  const double smaller = static_cast<double>(std::min(only_first_failed, only_second_failed));
  test.exact_p = std::min(1.0, 2.0 * boost::math::cdf(h0, smaller));
  // χ² with Edwards' continuity correction, one degree of freedom.
  const double excess = std::max(0.0, std::abs(static_cast<double>(only_first_failed - only_second_failed)) - 1.0);
  test.chi_squared = excess * excess / static_cast<double>(discordant);
  test.chi_squared_p =
      boost::math::cdf(boost::math::complement(boost::math::chi_squared_distribution<double>(1.0), test.chi_squared));
  return test;
}

std::vector<PairedComparison> ComparePaired(const std::vector<RunRecord>& records,
                                            const std::vector<std::string>& policy_order) {
  const std::vector<std::string> policies = PolicyOrder(records, policy_order);
  // run_index → policy → the record flown.
  std::map<std::int64_t, std::map<std::string, const RunRecord*>> runs;
  for (const RunRecord& r : records) runs[r.run_index][r.policy] = &r;
  const std::map<std::int64_t, const RunRecord*> noop = NoOpFlightsByRun(records);
  std::vector<PairedComparison> comparisons;
  for (std::size_t i = 0; i < policies.size(); ++i) {
    for (std::size_t j = i + 1; j < policies.size(); ++j) {
      for (const char* health : kHealthGroups) {
        PairedComparison c;
        c.first_policy = policies[i];
        c.second_policy = policies[j];
        c.battery_health = health;
        std::int64_t b = 0, d = 0, first_unnecessary = 0, second_unnecessary = 0;
        for (const auto& [index, flown] : runs) {
          const auto first = flown.find(c.first_policy);
          const auto second = flown.find(c.second_policy);
          if (first == flown.end() || second == flown.end() || !InHealthGroup(*first->second, c.battery_health))
            continue;
          ++c.pairs;
          const bool a_failed = first->second->failure;
          const bool b_failed = second->second->failure;
          if (a_failed && b_failed) ++c.both_failed;
          if (!a_failed && !b_failed) ++c.neither_failed;
          if (a_failed && !b_failed) ++b;
          if (!a_failed && b_failed) ++d;
          const bool a_unnecessary = IsUnnecessaryLanding(*first->second, noop);
          const bool b_unnecessary = IsUnnecessaryLanding(*second->second, noop);
          first_unnecessary += a_unnecessary && !b_unnecessary;
          second_unnecessary += b_unnecessary && !a_unnecessary;
        }
        c.test = CalcMcNemarTest(b, d);
        if (!noop.empty()) c.unnecessary_test = CalcMcNemarTest(first_unnecessary, second_unnecessary);
        comparisons.push_back(std::move(c));
      }
    }
  }
  return comparisons;
}

namespace {

// One (policy, battery health) group of StatisticsToJson.
nlohmann::json GroupJson(const GroupStatistics& g) {
  nlohmann::json causes = nlohmann::json::object();
  nlohmann::json cause_rates = nlohmann::json::object();
  for (int c = 0; c < kFailureCauseCount; ++c) {
    const char* name = FailureCauseName(static_cast<FailureCause>(c));
    causes[name] = g.failures_by_cause[c];
    cause_rates[name] = StatisticsJsonNumber(EstimateRate(g.failures_by_cause[c], g.runs).value);
  }
  nlohmann::json by_fades = nlohmann::json::object();
  for (int f = 0; f < kBatteryFadesCount; ++f) {
    by_fades[BatteryFadesName(static_cast<BatteryFades>(f))] = {
        {"runs", g.runs_by_fades[f]},
        {"failures", g.failures_by_fades[f]},
        {"failure_rate", StatisticsJsonNumber(EstimateRate(g.failures_by_fades[f], g.runs_by_fades[f]).value)}};
  }
  return {
      {"runs", g.runs},
      {"failures", g.failures},
      {"completions", g.completions},
      {"emergency_landings", g.emergency_landings},
      {"terminations", g.terminations},
      {"groundings", g.groundings},
      {"off_site_landings", g.off_site_landings},
      {"flights_with_substitution", g.flights_with_substitution},
      {"substitution_epochs", g.substitution_epochs},
      {"substitutions", g.substitutions},
      {"other_outcomes", g.others},
      {"unnecessary_landings", g.has_noop_twin ? nlohmann::json(g.unnecessary_landings) : nlohmann::json()},
      {"unnecessary_landings_fault_free",
       g.has_noop_twin ? nlohmann::json(g.unnecessary_landings_fault_free) : nlohmann::json()},
      {"unnecessary_landing_rate",
       g.has_noop_twin ? StatisticsJsonNumber(g.unnecessary_landing_rate.value) : nlohmann::json()},
      {"terminations_noop_completed",
       g.has_noop_twin ? nlohmann::json(g.terminations_noop_completed) : nlohmann::json()},
      {"terminations_noop_failed", g.has_noop_twin ? nlohmann::json(g.terminations_noop_failed) : nlohmann::json()},
      {"failure_rate", StatisticsJsonNumber(g.failure_rate.value)},
      {"failure_rate_sem", StatisticsJsonNumber(g.failure_rate.sem)},
      {"failure_rate_wilson_low", StatisticsJsonNumber(g.failure_wilson.low)},
      {"failure_rate_wilson_high", StatisticsJsonNumber(g.failure_wilson.high)},
      {"failure_rate_clopper_pearson_low", StatisticsJsonNumber(g.failure_clopper_pearson.low)},
      {"failure_rate_clopper_pearson_high", StatisticsJsonNumber(g.failure_clopper_pearson.high)},
      {"failures_by_cause", causes},
      {"by_battery_fades", by_fades},
      {"failure_rate_by_cause", cause_rates},
      {"completion_rate", StatisticsJsonNumber(g.completion_rate.value)},
      {"completion_rate_sem", StatisticsJsonNumber(g.completion_rate.sem)},
      {"completion_rate_wilson_low", StatisticsJsonNumber(g.completion_wilson.low)},
      {"completion_rate_wilson_high", StatisticsJsonNumber(g.completion_wilson.high)},
      {"completion_rate_clopper_pearson_low", StatisticsJsonNumber(g.completion_clopper_pearson.low)},
      {"completion_rate_clopper_pearson_high", StatisticsJsonNumber(g.completion_clopper_pearson.high)},
      {"emergency_landing_rate", StatisticsJsonNumber(g.emergency_landing_rate.value)},
      {"emergency_landing_rate_sem", StatisticsJsonNumber(g.emergency_landing_rate.sem)},
      {"termination_rate", StatisticsJsonNumber(g.termination_rate.value)},
      {"termination_rate_sem", StatisticsJsonNumber(g.termination_rate.sem)},
      {"grounded_rate", StatisticsJsonNumber(g.grounded_rate.value)},
      {"grounded_rate_sem", StatisticsJsonNumber(g.grounded_rate.sem)},
      {"off_site_landing_rate", StatisticsJsonNumber(g.off_site_rate.value)},
      {"off_site_landing_rate_sem", StatisticsJsonNumber(g.off_site_rate.sem)},
      {"other_outcome_rate", StatisticsJsonNumber(g.other_rate.value)},
      {"other_outcome_rate_sem", StatisticsJsonNumber(g.other_rate.sem)},
      {"average_reward", StatisticsJsonNumber(g.average_reward.value)},
      {"average_reward_sem", StatisticsJsonNumber(g.average_reward.sem)},
      {"min_reward", StatisticsJsonNumber(g.min_reward.value)},
      {"min_reward_sem", StatisticsJsonNumber(g.min_reward.sem)},
  };
}

// McNemar's paired comparisons of StatisticsToJson.
nlohmann::json PairedJson(const std::vector<PairedComparison>& comparisons) {
  nlohmann::json paired = nlohmann::json::array();
  for (const PairedComparison& c : comparisons) {
    paired.push_back(
        {{"policies", {c.first_policy, c.second_policy}},
         {"battery_health", c.battery_health},
         {"pairs", c.pairs},
         {"both_failed", c.both_failed},
         {"neither_failed", c.neither_failed},
         {"only_first_failed", c.test.only_first_failed},
         {"only_second_failed", c.test.only_second_failed},
         {"mcnemar_exact_p", StatisticsJsonNumber(c.test.exact_p)},
         {"mcnemar_chi_squared", StatisticsJsonNumber(c.test.chi_squared)},
         {"mcnemar_chi_squared_p", StatisticsJsonNumber(c.test.chi_squared_p)},
         {"unnecessary_landings",
          c.unnecessary_test ? nlohmann::json{{"only_first", c.unnecessary_test->only_first_failed},
                                              {"only_second", c.unnecessary_test->only_second_failed},
                                              {"mcnemar_exact_p", StatisticsJsonNumber(c.unnecessary_test->exact_p)}}
                             : nlohmann::json()}});
  }
  return paired;
}

}  // namespace

nlohmann::json StatisticsToJson(const std::vector<GroupStatistics>& groups,
                                const std::vector<PairedComparison>& comparisons) {
  nlohmann::json policies = nlohmann::json::object();
  nlohmann::json order = nlohmann::json::array();
  for (const GroupStatistics& g : groups) {
    if (!policies.contains(g.policy)) {
      policies[g.policy] = nlohmann::json::object();
      order.push_back(g.policy);
    }
    policies[g.policy][g.battery_health] = GroupJson(g);
  }
  const nlohmann::json paired = PairedJson(comparisons);
  return {{"policies", policies},
          {"policy_order", order},
          {"confidence_level", kConfidenceLevel},
          {"paired_comparisons", paired},
          {"dissertation",
           {{"source", "dissertation §5.5.3 (Fig. 5.30) and abstract"},
            {"poor_health_failure_rate",
             {{"cma", kDissertationPoorHealthFailureRateCma}, {"noop", kDissertationPoorHealthFailureRateNoOp}}}}}};
}

namespace {

// The policy column's width: the widest name, at least 10 characters, so any policy name keeps the columns aligned.
constexpr std::size_t kMinPolicyColumn = 10;
std::size_t PolicyColumn(const std::vector<GroupStatistics>& groups) {
  std::size_t width = kMinPolicyColumn;
  for (const GroupStatistics& g : groups) width = std::max(width, g.policy.size());
  return width;
}
// The paired comparisons' column ("first vs second"): at least 22 characters.
constexpr std::size_t kMinPairColumn = 22;
std::string PairName(const PairedComparison& c) { return c.first_policy + " vs " + c.second_policy; }
std::size_t PairColumn(const std::vector<PairedComparison>& comparisons) {
  std::size_t width = kMinPairColumn;
  for (const PairedComparison& c : comparisons) width = std::max(width, PairName(c).size());
  return width;
}

// 1. Outcome rates and rewards, one row per group.
std::string OutcomeRatesTable(const std::vector<GroupStatistics>& groups) {
  const std::size_t w = PolicyColumn(groups);
  std::string out = fmt::format("{:<{}} {:<3} {:>6}  {:>13}  {:>13}  {:>13}  {:>13}  {:>13}  {:>17}  {:>17}\n",
                                "policy", w, "BH", "runs", "failure %", "completed %", "em. landing %", "terminated %",
                                "grounded %", "avg reward", "min reward");
  out += std::string(133 + w - kMinPolicyColumn, '-') + "\n";
  std::string previous;
  for (const GroupStatistics& g : groups) {
    if (!previous.empty() && g.policy != previous) out += "\n";
    previous = g.policy;
    out += fmt::format("{:<{}} {:<3} {:>6}  {:>13}  {:>13}  {:>13}  {:>13}  {:>13}  {:>17}  {:>17}\n", g.policy, w,
                       g.battery_health, g.runs, Percent(g.failure_rate), Percent(g.completion_rate),
                       Percent(g.emergency_landing_rate), Percent(g.termination_rate), Percent(g.grounded_rate),
                       PlainEstimateText(g.average_reward), PlainEstimateText(g.min_reward));
  }
  out += "Rates in % ± binomial SEM; rewards: per-flight mean and minimum of R(S,A) per 1 Hz epoch ± SEM.\n";
  return out;
}

// Outcomes that are neither completions nor failures beyond the table's, and actions that could not be carried out.
std::string OutcomeNotes(const std::vector<GroupStatistics>& groups) {
  std::string out;
  bool any_other = false;
  for (const GroupStatistics& g : groups) any_other = any_other || g.others > 0;
  std::string off_site, substituted;
  for (const GroupStatistics& g : groups) {
    if (g.off_site_landings > 0) {
      off_site += fmt::format("  {} {}: {} of {} ({})\n", g.policy, g.battery_health, g.off_site_landings, g.runs,
                              Percent(g.off_site_rate));
    }
    if (g.flights_with_substitution > 0) {
      std::string pairs;
      for (const auto& [pair, flights] : g.substitutions) pairs += fmt::format(" {} in {};", pair, flights);
      substituted += fmt::format("  {} {}: {} of {} flights, {} epochs:{}\n", g.policy, g.battery_health,
                                 g.flights_with_substitution, g.runs, g.substitution_epochs, pairs);
    }
  }
  out += off_site.empty() ? "Landed off-site (a gentle touchdown on open ground outside the landing radius): none.\n"
                          : "Landed off-site (a gentle touchdown on open ground outside the landing radius; neither "
                            "completed nor failed):\n" +
                                off_site;
  out += substituted.empty()
             ? "Actions that could not be carried out (docs/modelling-choices.md#unavailable-actions): none.\n"
             : "Actions that could not be carried out (docs/modelling-choices.md#unavailable-actions: no plan found, "
               "the next-highest Q taken):\n" +
                   substituted;
  if (any_other) {
    out += "Some flights ended with an outcome this report does not know; they are counted as other outcomes:\n";
    for (const GroupStatistics& g : groups) {
      if (g.others > 0) out += fmt::format("  {} {}: {} of {}\n", g.policy, g.battery_health, g.others, g.runs);
    }
  }
  return out;
}

// 2. Failure rate with its intervals, and the failures by cause.
std::string FailureRatesTable(const std::vector<GroupStatistics>& groups) {
  const std::size_t w = PolicyColumn(groups);
  std::string out = fmt::format("\nFailure rate with {:.0f} % intervals, and failures by cause (flights)\n",
                                100.0 * kConfidenceLevel);
  out += fmt::format("{:<{}} {:<3} {:>6} {:>8}  {:>9}  {:>16}  {:>16}  {:>7} {:>7} {:>9} {:>7} {:>5}\n", "policy", w,
                     "BH", "runs", "failures", "failure %", "Wilson", "Clopper-Pearson", "battery", "control",
                     "collision", "timeout", "other");
  out += std::string(118 + w - kMinPolicyColumn, '-') + "\n";
  std::string previous;
  for (const GroupStatistics& g : groups) {
    if (!previous.empty() && g.policy != previous) out += "\n";
    previous = g.policy;
    const auto& c = g.failures_by_cause;
    out += fmt::format("{:<{}} {:<3} {:>6} {:>8}  {:>9}  {:>16}  {:>16}  {:>7} {:>7} {:>9} {:>7} {:>5}\n", g.policy, w,
                       g.battery_health, g.runs, g.failures,
                       std::isfinite(g.failure_rate.value) ? fmt::format("{:.1f}", 100.0 * g.failure_rate.value) : "-",
                       PercentInterval(g.failure_wilson), PercentInterval(g.failure_clopper_pearson), c[0], c[1], c[2],
                       c[3], c[4]);
  }
  return out;
}

// 3. McNemar's paired comparisons.
std::string PairedTable(const std::vector<PairedComparison>& comparisons) {
  std::string out;
  if (!comparisons.empty()) {
    out +=
        "\nPaired comparison of failures on the same flights (McNemar): b = only the first failed, c = only the "
        "second\n";
    const std::size_t w = PairColumn(comparisons);
    out += fmt::format("{:<{}} {:<3} {:>6} {:>6} {:>6} {:>6} {:>10}  {:>8} {:>10}\n", "policies", w, "BH", "pairs", "b",
                       "c", "both", "exact p", "chi2(cc)", "chi2 p");
    out += std::string(86 + w - kMinPairColumn, '-') + "\n";
    for (const PairedComparison& c : comparisons) {
      out += fmt::format("{:<{}} {:<3} {:>6} {:>6} {:>6} {:>6} {:>10}  {:>8.3f} {:>10}\n", PairName(c), w,
                         c.battery_health, c.pairs, c.test.only_first_failed, c.test.only_second_failed, c.both_failed,
                         PValue(c.test.exact_p), c.test.chi_squared, PValue(c.test.chi_squared_p));
    }
  }
  return out;
}

// 3b. Unnecessary landings and terminations per group by the NoOp twin, and the paired comparison ("" without a NoOp
// twin).
std::string UnnecessaryLandingsTable(const std::vector<GroupStatistics>& groups,
                                     const std::vector<PairedComparison>& comparisons) {
  if (groups.empty() || !groups.front().has_noop_twin) return "";
  const std::size_t w = PolicyColumn(groups);
  const std::size_t pair_w = PairColumn(comparisons);
  std::string out =
      "\nUnnecessary landings: an emergency landing in a run whose NoOp flight completed with t_sf of hover left\n"
      "(of them, in runs without a motor fault: for the battery, or a spall alarm with no spall)\n";
  for (const GroupStatistics& g : groups) {
    out += fmt::format("  {:<{}} {:<3} {:>5} of {:>5} ({} %), {:>5} without a fault\n", g.policy, w, g.battery_health,
                       g.unnecessary_landings, g.runs, Percent(g.unnecessary_landing_rate),
                       g.unnecessary_landings_fault_free);
  }
  out += "Terminations, by the NoOp flight's outcome: it completed its plan, it failed\n";
  for (const GroupStatistics& g : groups) {
    out += fmt::format("  {:<{}} {:<3} {:>5} terminated: NoOp completed {:>5}, NoOp failed {:>5}\n", g.policy, w,
                       g.battery_health, g.terminations, g.terminations_noop_completed, g.terminations_noop_failed);
  }
  out += "Paired (McNemar): b = only the first landed unnecessarily, c = only the second\n";
  for (const PairedComparison& c : comparisons) {
    if (!c.unnecessary_test) continue;
    out += fmt::format("  {:<{}} {:<3} b {:>5}  c {:>5}  exact p {}\n", PairName(c), pair_w, c.battery_health,
                       c.unnecessary_test->only_first_failed, c.unnecessary_test->only_second_failed,
                       PValue(c.unnecessary_test->exact_p));
  }
  return out;
}

// 4. The dissertation's headline beside ours (§5.5.3, Fig. 5.30), and the failures by the fades the batteries carry.
std::string HeadlineTable(const std::vector<GroupStatistics>& groups) {
  std::string out;
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
    out += fmt::format("  {:<5} ours {:>13} %  Wilson {:>16} %  (n = {:>4})   dissertation {:5.1f} %\n", h.policy,
                       g != nullptr ? Percent(g->failure_rate) : std::string("-"),
                       g != nullptr ? PercentInterval(g->failure_wilson) : std::string("-"), g != nullptr ? g->runs : 0,
                       100.0 * h.dissertation);
  }
  // Where the rates come from: every health group's failures by the fades its batteries carry (Table 3.2).
  out +=
      "\nFailures by the fades the battery carries (all health groups): a capacity-faded cell (0.8 Q, Table 3.2) is\n"
      "what runs a pack to the 3.3 V cut-off; power fade alone (2 R0) rarely does\n";
  const std::size_t w = PolicyColumn(groups);
  for (const GroupStatistics& g : groups) {
    if (g.battery_health != "all") continue;
    out += fmt::format("  {:<{}}", g.policy, w);
    for (int f = kBatteryFadesCount; f-- > 0;) {
      const Estimate rate = EstimateRate(g.failures_by_fades[f], g.runs_by_fades[f]);
      out +=
          fmt::format("  {} {}/{} ({} %)", BatteryFadesName(static_cast<BatteryFades>(f)), g.failures_by_fades[f],
                      g.runs_by_fades[f], std::isfinite(rate.value) ? fmt::format("{:.1f}", 100.0 * rate.value) : "-");
    }
    out += "\n";
  }
  return out;
}

}  // namespace

std::string StatisticsTable(const std::vector<GroupStatistics>& groups,
                            const std::vector<PairedComparison>& comparisons) {
  return OutcomeRatesTable(groups) + OutcomeNotes(groups) + FailureRatesTable(groups) + PairedTable(comparisons) +
         UnnecessaryLandingsTable(groups, comparisons) + HeadlineTable(groups);
}

}  // namespace uascma::campaign
