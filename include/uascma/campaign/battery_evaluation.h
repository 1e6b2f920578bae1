#pragma once
// Judging battery-reconfiguration policies on paired flights.
//
// Evaluation: run r draws its flight from Table 4.4 (SampleBatteryFlight(ranges, seed, r): pack health pair,
// temperature, t_sf, cell voltages, speed, wind, gusts, plan length) and flies it once per policy; every policy
// flies the same BatteryFlightParams (one value per run, common random numbers: the same vehicle seed, so the same
// gusts and noise), flown together by FlyBatteryFlights (one vehicle while their packs cap the rotors alike; each
// result equals the flight flown alone, bit for bit: tests/campaign/battery_evaluation_test.cc). A seed that no
// learning used makes the flights fresh.
// Per policy, overall and per (B1 health, B2 health, temperature): completions with their 95 % Wilson interval
// (campaign/statistics.h), failures and the median failure time, charge left in the packs, switches per flight
// (changes of the pack switches, the take-off UseBoth not counted: median, mean, max). Per pair of policies, the
// paired completion comparison: b = runs only the first completed, c = runs only the second completed, McNemar's
// exact two-sided p (CalcMcNemarTest).
// Policies: campaign/battery_controllers.h (ParseBatteryPolicies).
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "uascma/campaign/battery_controllers.h"
#include "uascma/campaign/battery_flights.h"
#include "uascma/campaign/statistics.h"
#include "uascma/decision/battery_mdp.h"

namespace uascma::campaign {

// --- evaluation --------------------------------------------------------------------------------------------------
struct BatteryEvaluationOptions {
  std::int64_t runs = 400;
  std::uint64_t seed = 2024;  // ours: a seed no learning of this project used (learning: 1)
  int jobs = 1;
  BatteryFlightRanges ranges;
  std::function<void(std::int64_t)> on_run_done;  // runs done; one call at a time, in run order; may be empty
};

struct BatteryPolicyFlight {
  sim::Outcome outcome = sim::Outcome::kInProgress;
  double end_time_s = 0.0;
  int switches = 0;
  double charge_left_ah = 0.0;  // both packs
  double energy_used_wh = 0.0;
  BatteryDecisionCounts decisions;         // the table's and the guard's isolations, FAILURE epochs held
  std::optional<double> fault_detected_s;  // the pack-fault indicator's first flag (either pack), none if never
  bool completed() const { return outcome == sim::Outcome::kCompleted; }
};

struct BatteryEvaluationRun {
  std::int64_t run = 0;
  BatteryFlightParams params;                // the one flight every policy flew
  std::vector<BatteryPolicyFlight> flights;  // per policy, in the order given
};

struct BatteryPolicySummary {
  std::string label;
  std::int64_t runs = 0, completions = 0, failures = 0;
  Interval completion_wilson;          // 95 %
  double median_failure_time_s = 0.0;  // NaN without failures
  double mean_charge_left_ah = 0.0;    // over completed flights (NaN without)
  double median_switches = 0.0, mean_switches = 0.0;
  int max_switches = 0;
  std::int64_t table_isolations = 0, guard_isolations = 0, failure_rows_held = 0;  // summed over the flights
  std::int64_t table_fault_isolations = 0, guard_fault_isolations = 0;  // of those, of a flagged pack
  std::int64_t detections = 0;            // flights whose pack-fault indicator flagged a pack
  double median_detection_delay_s = 0.0;  // flag − onset over the faulted flights flagged after the onset (NaN: none)
};

struct BatteryContextSummary {
  decision::BatteryContext context;
  std::vector<BatteryPolicySummary> policies;
};

struct BatteryPairComparison {
  std::string first, second;
  std::int64_t pairs = 0, both_completed = 0, neither_completed = 0;
  std::int64_t only_first_completed = 0, only_second_completed = 0;
  double exact_p = 1.0;  // McNemar, exact two-sided
};

// The flights of one pack-fault kind ("none" without a fault), with every policy's summary.
struct BatteryFaultSummary {
  std::string fault;  // "none" or models::PackFaultKindName
  std::vector<BatteryPolicySummary> policies;
  std::vector<BatteryPairComparison> comparisons;
};

struct BatteryEvaluation {
  std::vector<std::string> labels;
  std::uint64_t seed = 0;
  std::vector<BatteryEvaluationRun> runs;  // by run index
  std::vector<BatteryPolicySummary> overall;
  std::vector<BatteryContextSummary> by_context;  // the contexts flown, in Fig. 4.5's order
  std::vector<BatteryPairComparison> comparisons;
  // Split by pack fault (docs/modelling-choices.md#pack-faults): "none", then each kind flown; and "any" fault.
  std::vector<BatteryFaultSummary> by_pack_fault;
  double wall_time_s = 0.0;
};

BatteryEvaluation EvaluateBatteryPolicies(const std::vector<BatteryPolicySpec>& policies,
                                          const BatteryEvaluationOptions& options);
nlohmann::json BatteryEvaluationJson(const BatteryEvaluation& evaluation, bool with_runs = false);
std::string BatteryEvaluationText(const BatteryEvaluation& evaluation);

}  // namespace uascma::campaign
