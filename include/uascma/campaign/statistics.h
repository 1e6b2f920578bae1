#pragma once
// Campaign statistics (§5.5.3, Figs. 5.30–5.32) for the paired design of a campaign: every policy flies the
// same sampled flights (campaign/sampler.h), so the outcomes of two policies on one run are a matched pair.
//
// Per policy and battery health (G/M/P, and all together):
//   rate p = k / n over the n flights of the group, SEM = √(p (1 − p) / n)          (binomial, as Fig. 5.30)
//   95 % intervals of p that stay meaningful at k = 0 or k = n (where the SEM is 0 ± 0):
//     Wilson score:     (k + z²/2) / (n + z²) ± z / (n + z²) · √(k (n − k) / n + z²/4),  z = Φ⁻¹(1 − α/2)
//     Clopper–Pearson:  [B⁻¹(α/2; k, n − k + 1), B⁻¹(1 − α/2; k + 1, n − k)]  (exact, conservative),
//                       B⁻¹ the inverse regularised incomplete beta function (Boost.Math); 0 and 1 at the ends
//   mean m of a per-flight metric, SEM = s / √n, s the sample standard deviation (n − 1)
// Outcomes (sim::OutcomeName): failure (the record's `failure` flag: battery, loss of control, collision,
// timeout), original-plan completion, emergency landing, termination, grounded (an emergency action chosen
// before take-off: the vehicle stays on the ground, safe and not completed,
// docs/modelling-choices.md#outcomes-refined), and any other name this code does not know (counted as "other", never
// dropped); the rates sum to one. Failures are broken down by cause: battery, loss of control, collision, timeout,
// other (a failure whose name is not one of those). Reward metrics: the per-flight average reward per time step and
// minimum instantaneous reward (campaign/metrics.h), averaged over flights. An empty group has n = 0 and NaN estimates
// (null in JSON).
//
// Paired comparison of two policies A and B on the same runs (McNemar's test): over the runs flown by both,
// b = runs A failed and B did not, c = runs B failed and A did not (the concordant pairs carry no
// information about the difference). Under H0 (equal failure probabilities) b ~ Binomial(b + c, ½):
//   exact two-sided p = min(1, 2 · P(X ≤ min(b, c))),  X ~ Binomial(b + c, ½)
//   χ² with continuity correction = (|b − c| − 1)² / (b + c), p from χ²(1)  (0 and p = 1 when b + c = 0)
// The exact p is the one to read at campaign sizes (b + c is often below 25); χ² is printed beside it.
#include <array>
#include <cstdint>
#include <map>
#include <optional>
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

// Two-sided confidence level of every interval the campaign reports.
inline constexpr double kConfidenceLevel = 0.95;

struct Interval {
  double low = 0.0;
  double high = 0.0;
};
// The Wilson score interval of k successes in n trials at `confidence` (0 < confidence < 1); NaN for n = 0.
// InputError unless 0 ≤ k ≤ n.
Interval WilsonInterval(std::int64_t successes, std::int64_t trials, double confidence = kConfidenceLevel);
// The Clopper–Pearson (exact) interval; NaN for n = 0. InputError unless 0 ≤ k ≤ n.
Interval ClopperPearsonInterval(std::int64_t successes, std::int64_t trials, double confidence = kConfidenceLevel);

// A rate with its SEM and both intervals.
struct RateEstimate {
  std::int64_t count = 0;
  Estimate estimate;
  Interval wilson;
  Interval clopper_pearson;
};
RateEstimate EstimateRateWithIntervals(std::int64_t successes, std::int64_t trials);

// Why a flight failed.
enum class FailureCause { kBattery = 0, kLossOfControl, kCollision, kTimeout, kOther };
inline constexpr int kFailureCauseCount = 5;
// "battery", "loss_of_control", "collision", "timeout", "other".
const char* FailureCauseName(FailureCause cause);
// The cause of a failed flight from its outcome name (sim::OutcomeName): failed_battery, failed_control,
// failed_collision, timeout; anything else is kOther.
FailureCause FailureCauseOf(const std::string& outcome);

// The fades a flight's battery carries (RunRecord::cell_health, Table 3.2): a capacity-faded cell (with or without
// power fade), power fade only, or none. What runs a pack to the 3.3 V cut-off is the capacity-faded cell; the
// report breaks failures down by it, so a reader sees where the health groups' rates come from.
enum class BatteryFades { kNone = 0, kPowerOnly, kCapacity };
inline constexpr int kBatteryFadesCount = 3;
const char* BatteryFadesName(BatteryFades fades);  // "none", "power_only", "capacity"
BatteryFades BatteryFadesOf(const std::string& cell_health_code);

struct GroupStatistics {
  std::string policy;
  std::string battery_health;  // "G", "M", "P" or "all"
  std::int64_t runs = 0;
  std::int64_t failures = 0, completions = 0, emergency_landings = 0, terminations = 0, groundings = 0,
               off_site_landings = 0, others = 0;
  Estimate failure_rate, completion_rate, emergency_landing_rate, termination_rate, grounded_rate, off_site_rate,
      other_rate;
  // Unavailable actions (docs/modelling-choices.md#unavailable-actions): flights in which a chosen action could not be
  // carried out and another was taken, the epochs of it, and each "Chosen->Taken" pair with the flights it happened in.
  std::int64_t flights_with_substitution = 0, substitution_epochs = 0;
  std::map<std::string, std::int64_t> substitutions;
  Interval failure_wilson, failure_clopper_pearson;                  // of failure_rate
  Interval completion_wilson, completion_clopper_pearson;            // of completion_rate
  std::array<std::int64_t, kFailureCauseCount> failures_by_cause{};  // indexed by FailureCause; sums to failures
  std::array<std::int64_t, kBatteryFadesCount> runs_by_fades{}, failures_by_fades{};  // indexed by BatteryFades
  Estimate average_reward, min_reward;
  // Unnecessary landings (CountUnnecessaryLandings): counted only when the campaign flew the NoOp policy.
  bool has_noop_twin = false;
  std::int64_t unnecessary_landings = 0;
  // Those of them in runs without a motor fault (RunRecord::fault false): a landing for a battery the flight did not
  // need to fear, or for a spall alarm with no spall; the rest follow a real spall or jam (the policy's choice for
  // its motor-health state, which the NoOp flight survived).
  std::int64_t unnecessary_landings_fault_free = 0;
  Estimate unnecessary_landing_rate;
  // Terminations by the NoOp twin's outcome (counted with the unnecessary landings): the twin completed its original
  // plan (the termination ended a flight that would have come home), or it failed.
  std::int64_t terminations_noop_completed = 0, terminations_noop_failed = 0;
};

inline constexpr const char* kHealthGroups[] = {"G", "M", "P", "all"};

// One group per (policy, health) with policies in `policy_order` (others after, by name) and health
// in kHealthGroups order.
std::vector<GroupStatistics> Summarise(const std::vector<RunRecord>& records,
                                       const std::vector<std::string>& policy_order = {});

// McNemar's test from the discordant counts b and c (≥ 0; InputError otherwise).
struct McNemarTest {
  std::int64_t only_first_failed = 0;   // b
  std::int64_t only_second_failed = 0;  // c
  double exact_p = 1.0;                 // two-sided exact binomial p
  double chi_squared = 0.0;             // continuity-corrected statistic
  double chi_squared_p = 1.0;           // its p from χ²(1)
};
McNemarTest CalcMcNemarTest(std::int64_t only_first_failed, std::int64_t only_second_failed);

// The paired failure comparison of two policies in one health group.
struct PairedComparison {
  std::string first_policy, second_policy;
  std::string battery_health;  // "G", "M", "P" or "all" (the run's BH, the same for every policy)
  std::int64_t pairs = 0;      // runs flown by both
  std::int64_t both_failed = 0, neither_failed = 0;
  McNemarTest test;
  // McNemar on unnecessary landings (b = only the first landed unnecessarily), when the campaign flew NoOp.
  std::optional<McNemarTest> unnecessary_test;
};
// For every pair of policies (in Summarise's order, first before second) and every health group: the runs
// flown by both policies, matched by run_index.
std::vector<PairedComparison> ComparePaired(const std::vector<RunRecord>& records,
                                            const std::vector<std::string>& policy_order = {});

// Unnecessary landings: an emergency landing, on a site or off it, in a run whose NoOp flight (policy
// kNoOpPolicy) completed with at least t_sf of hover left (RunRecord::end_reserve_s >= safety_margin_s, the run's
// own t_sf): the landing kept the vehicle safe from nothing. Summarise counts them per group (has_noop_twin,
// unnecessary_landings), ComparePaired tests them per pair (unnecessary_test), StatisticsTable prints them.
inline constexpr const char* kNoOpPolicy = "noop";
// The NoOp flight of each run (empty when the campaign flew no NoOp).
std::map<std::int64_t, const RunRecord*> NoOpFlightsByRun(const std::vector<RunRecord>& records);
bool IsUnnecessaryLanding(const RunRecord& record, const std::map<std::int64_t, const RunRecord*>& noop_by_run);

// The dissertation's headline for comparison (§5.5.3 and the abstract): poor battery health,
// failure rate of CMA 1.3 % vs NoOp 71 %.
inline constexpr double kDissertationPoorHealthFailureRateCma = 0.013;
inline constexpr double kDissertationPoorHealthFailureRateNoOp = 0.71;

// {"policies": {"cma": {"G": {"runs", "failure_rate", "failure_rate_sem", "failure_rate_wilson_low", …,
//   "failures_by_cause": {"battery": k, …}}, …}, …}, "policy_order": [...], "confidence_level": 0.95,
//  "paired_comparisons": [{"policies": [a, b], "battery_health", "pairs", "only_first_failed", …,
//   "mcnemar_exact_p", …}], "dissertation": {…}}
nlohmann::json StatisticsToJson(const std::vector<GroupStatistics>& groups,
                                const std::vector<PairedComparison>& comparisons = {});
// Text tables: the outcome rates (percent ± SEM) and rewards per policy and health; the failure rate with
// its 95 % Wilson and Clopper–Pearson intervals and the failures by cause; McNemar's paired comparisons;
// then the dissertation's headline beside ours.
std::string StatisticsTable(const std::vector<GroupStatistics>& groups,
                            const std::vector<PairedComparison>& comparisons = {});

}  // namespace uascma::campaign
