// Judging battery policies: every policy of an evaluation run flies the same flight — the run's
// Table 4.4 draw — and each result equals that flight flown alone, bit for bit; the paired counts add up; the
// hindsight family and the schedule controller are what they say.
#include "uascma/campaign/battery_evaluation.h"
#include "uascma/campaign/battery_case_studies.h"
#include "uascma/campaign/battery_controllers.h"

#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

#include "uascma/common/error.h"

namespace uascma::campaign {
namespace {

using decision::StateIndex;
using models::PackAction;

// A hand-made policy set that switches in flight: pack 1 alone while pack 2's worst cell (alone) is in C1, pack 2
// alone while pack 1's is, else UseBoth; the same in every context.
std::shared_ptr<const decision::BatteryPolicySet> SwitchingPolicies() {
  auto set = std::make_shared<decision::BatteryPolicySet>();
  for (int c = 0; c < decision::kBatteryNumContexts; ++c) {
    auto& p = set->policies[static_cast<std::size_t>(c)];
    p.context = decision::BatteryContextFromIndex(c);
    p.action.assign(decision::kBatteryNumStates, static_cast<int>(PackAction::kUseBoth));
    p.value.assign(decision::kBatteryNumStates, 0.0);
    for (StateIndex s = 0; s < decision::kBatteryFailureState; ++s) {
      const auto f = decision::BatteryStateFeatures(s);
      if (f.pack[1].voltage == decision::VoltageState::kC1)
        p.action[s] = static_cast<int>(PackAction::kUseBatt1);
      else if (f.pack[0].voltage == decision::VoltageState::kC1)
        p.action[s] = static_cast<int>(PackAction::kUseBatt2);
    }
  }
  return set;
}

std::vector<BatteryPolicySpec> FourPolicies() {
  BatteryPolicySpec useboth, rule, table, ours;
  rule.kind = BatteryPolicyKind::kVoltageRule;
  rule.label = "rule:voltage";
  // A drop voltage high enough that the rule acts in these short flights (the default 3.31 V rarely does).
  rule.drop_voltage_v = 3.9;
  useboth.label = "useboth";
  table.kind = BatteryPolicyKind::kPiStar;
  table.label = "pistar";
  table.policies = SwitchingPolicies();
  ours.kind = BatteryPolicyKind::kOurs;  // the same table with ours' imminent-failure guard (pair EOD observed)
  ours.label = "ours";
  ours.policies = table.policies;
  return {useboth, rule, table, ours};
}

// Bit for bit: outcome, end time, switch count and the final charge and energy.
void ExpectSame(const BatteryPolicyFlight& evaluated, const BatteryFlightResult& alone, const std::string& what) {
  EXPECT_EQ(evaluated.outcome, alone.outcome) << what;
  EXPECT_EQ(std::memcmp(&evaluated.end_time_s, &alone.end_time_s, sizeof(double)), 0) << what;
  EXPECT_EQ(evaluated.switches, CountSwitches(alone)) << what;
  const double charge = alone.charge_left_ah[0] + alone.charge_left_ah[1];
  EXPECT_EQ(std::memcmp(&evaluated.charge_left_ah, &charge, sizeof(double)), 0) << what;
  EXPECT_EQ(std::memcmp(&evaluated.energy_used_wh, &alone.energy_used_wh, sizeof(double)), 0) << what;
}

TEST(BatteryEvaluationTest, EveryPolicyFliesTheRunsOneFlightBitForBit) {
  BatteryEvaluationOptions options;
  options.runs = 3;
  options.seed = 2024;
  options.jobs = 2;
  options.ranges.plan_fraction[0] = 0.25;  // short plans keep the test quick; the draw is otherwise Table 4.4's
  options.ranges.plan_fraction[1] = 0.35;
  const std::vector<BatteryPolicySpec> policies = FourPolicies();
  const BatteryEvaluation evaluation = EvaluateBatteryPolicies(policies, options);
  ASSERT_EQ(evaluation.runs.size(), 3u);
  int switched = 0;
  for (const BatteryEvaluationRun& run : evaluation.runs) {
    // The run's flight is the Table 4.4 draw of (seed, run), whatever thread flew it.
    const BatteryFlightParams expected = SampleBatteryFlight(options.ranges, options.seed, run.run);
    EXPECT_EQ(run.params.seed, expected.seed);
    EXPECT_EQ(std::memcmp(&run.params.plan_duration_s, &expected.plan_duration_s, sizeof(double)), 0);
    EXPECT_EQ(run.params.context(), expected.context());
    ASSERT_EQ(run.flights.size(), policies.size());
    for (std::size_t k = 0; k < policies.size(); ++k) {
      const BatteryFlightController controller = MakeBatteryController(policies[k], expected.context());
      const BatteryFlightResult alone = FlyBatteryFlight(expected, controller);
      ExpectSame(run.flights[k], alone, "run " + std::to_string(run.run) + " " + policies[k].label);
      switched += run.flights[k].switches > 0 ? 1 : 0;
    }
  }
  EXPECT_GT(switched, 0) << "no policy switched: the pairing was not exercised with diverging packs";
  // The paired counts partition the runs.
  ASSERT_EQ(evaluation.comparisons.size(), 6u);
  for (const auto& c : evaluation.comparisons) {
    EXPECT_EQ(c.both_completed + c.neither_completed + c.only_first_completed + c.only_second_completed, 3);
    EXPECT_GE(c.exact_p, 0.0);
    EXPECT_LE(c.exact_p, 1.0);
  }
  EXPECT_EQ(evaluation.overall[0].completions + evaluation.overall[0].failures, 3);
}

TEST(BatteryEvaluationTest, TheGuardDropsTheLimitingPackOnlyWhenFailureIsImminentAndBeforeTheEnd) {
  decision::BatteryObservation o;
  o.safety_margin_s = 7.5;
  o.remaining_flight_s = 40.0;
  o.pair_eod_s = 6.0;  // the cut-off in 6 s < t_sf, before the end: drop pack 1 (it holds the cell)
  o.pair_limiting_branch = 0;
  EXPECT_EQ(OursImminentFailureGuard(o), PackAction::kUseBatt2);
  o.pair_limiting_branch = 1;
  EXPECT_EQ(OursImminentFailureGuard(o), PackAction::kUseBatt1);
  o.pair_eod_s = 8.0;  // beyond t_sf: the MDP decides
  EXPECT_FALSE(OursImminentFailureGuard(o).has_value());
  o.pair_eod_s = 6.0;
  o.remaining_flight_s = 5.0;  // the plan ends first: nothing to save
  EXPECT_FALSE(OursImminentFailureGuard(o).has_value());
  o.remaining_flight_s = 40.0;
  o.switch_on = {false, true};  // already one pack
  EXPECT_FALSE(OursImminentFailureGuard(o).has_value());
  decision::BatteryObservation unobserved;  // pair EOD not requested: NaN
  EXPECT_FALSE(OursImminentFailureGuard(unobserved).has_value());
}

TEST(BatteryEvaluationTest, TheDropCheckKeepsATableDropOnlyOntoAPackThatCanCarryThePowerAlone) {
  decision::BatteryObservation o;
  o.safety_margin_s = 5.0;
  o.remaining_flight_s = 100.0;
  o.alone_power_eod_s = {120.0, 90.0};              // pack 1 alone: S1 (> 105 s); pack 2: S3
  o.alone_power_min_cell_voltage_v = {3.45, 3.60};  // pack 1 above 3.4 V (C0)
  EXPECT_EQ(OursDropCheck(PackAction::kUseBatt1, o), PackAction::kUseBatt1);
  EXPECT_EQ(OursDropCheck(PackAction::kUseBatt2, o), PackAction::kUseBoth);  // pack 2 cannot finish alone
  o.alone_power_min_cell_voltage_v[0] = 3.39;                                // C1: critical alone
  EXPECT_EQ(OursDropCheck(PackAction::kUseBatt1, o), PackAction::kUseBoth);
  o.alone_power_min_cell_voltage_v[0] = 3.45;
  o.alone_power_eod_s[0] = 104.0;  // S2: inside t_sf
  EXPECT_EQ(OursDropCheck(PackAction::kUseBatt1, o), PackAction::kUseBoth);
  EXPECT_EQ(OursDropCheck(PackAction::kUseBoth, o), PackAction::kUseBoth);
  o.switch_on = {true, false};  // already one pack: the table's choice stands (item 6 keeps it)
  EXPECT_EQ(OursDropCheck(PackAction::kUseBatt1, o), PackAction::kUseBatt1);
  decision::BatteryObservation unobserved;  // not requested: NaN, no evidence for a drop
  EXPECT_EQ(OursDropCheck(PackAction::kUseBatt1, unobserved), PackAction::kUseBoth);
}

TEST(BatteryEvaluationTest, TheRuleDropsAPackForGoodAndNeverBoth) {
  BatteryPolicySpec rule;
  rule.kind = BatteryPolicyKind::kVoltageRule;
  rule.drop_voltage_v = 3.9;
  const BatteryFlightController c = MakeBatteryController(rule, {});
  decision::BatteryObservation o;
  o.actual_min_cell_voltage_v = {4.0, 4.0};
  EXPECT_EQ(c.controller(0.0, o, 0), PackAction::kUseBoth);
  o.actual_min_cell_voltage_v = {4.0, 3.8};  // pack 2 below 3.9 V: dropped
  EXPECT_EQ(c.controller(1.0, o, 0), PackAction::kUseBatt1);
  o.switch_on = {true, false};
  o.actual_min_cell_voltage_v = {3.7, 4.1};  // pack 2 rested above it again, pack 1 low: still pack 1 alone
  EXPECT_EQ(c.controller(2.0, o, 0), PackAction::kUseBatt1);
}

TEST(BatteryEvaluationTest, TheTablePoliciesNeverExecuteTheirFailureRow) {
  // In FAILURE (a switched-in cell at the cut-off) pistar and ours hold the switches they have, whatever the table's
  // FAILURE row says, and count the epoch; a dropped pack is not switched back in by it.
  for (const BatteryPolicySpec& spec : FourPolicies()) {
    if (spec.kind != BatteryPolicyKind::kPiStar && spec.kind != BatteryPolicyKind::kOurs) continue;
    const BatteryFlightController c = MakeBatteryController(spec, {});
    ASSERT_NE(c.decisions, nullptr) << spec.label;
    decision::BatteryObservation o;
    o.switch_on = {false, true};  // pack 1 dropped
    EXPECT_EQ(c.controller(10.0, o, decision::kBatteryFailureState), PackAction::kUseBatt2) << spec.label;
    o.switch_on = {true, true};
    EXPECT_EQ(c.controller(11.0, o, decision::kBatteryFailureState), PackAction::kUseBoth) << spec.label;
    EXPECT_EQ(c.decisions->failure_rows_held, 2) << spec.label;
    EXPECT_EQ(c.decisions->table_isolations + c.decisions->guard_isolations, 0) << spec.label;
  }
}

TEST(BatteryEvaluationTest, ResultsAreSplitByPackFault) {
  BatteryEvaluationOptions options;
  options.runs = 6;
  options.seed = 2024;
  options.jobs = 2;
  options.ranges.plan_fraction[0] = 0.25;  // short plans keep the test quick (ours)
  options.ranges.plan_fraction[1] = 0.35;
  options.ranges.pack_faults.share = 0.5;
  const std::vector<BatteryPolicySpec> policies = FourPolicies();
  const BatteryEvaluation evaluation = EvaluateBatteryPolicies(policies, options);
  int faulted = 0;
  for (const BatteryEvaluationRun& run : evaluation.runs) {
    const BatteryFlightParams expected = SampleBatteryFlight(options.ranges, options.seed, run.run);
    ASSERT_EQ(run.params.pack_fault.has_value(), expected.pack_fault.has_value());
    if (expected.pack_fault) {
      EXPECT_EQ(*run.params.pack_fault, *expected.pack_fault);
    }
    faulted += run.params.pack_fault ? 1 : 0;
    // The flight without its fault is the fault-free draw: the share changes nothing else.
    BatteryFlightRanges plain = options.ranges;
    plain.pack_faults.share = 0.0;
    const BatteryFlightParams without = SampleBatteryFlight(plain, options.seed, run.run);
    EXPECT_EQ(without.seed, expected.seed);
    EXPECT_EQ(std::memcmp(&without.plan_duration_s, &expected.plan_duration_s, sizeof(double)), 0);
  }
  ASSERT_GT(faulted, 0) << "no run drew a pack fault";
  ASSERT_LT(faulted, 6) << "every run drew a pack fault";
  // "none" and "any" partition the runs for every policy; each kind's runs add up to "any".
  ASSERT_GE(evaluation.by_pack_fault.size(), 3u);
  EXPECT_EQ(evaluation.by_pack_fault[0].fault, "none");
  EXPECT_EQ(evaluation.by_pack_fault[1].fault, "any");
  for (std::size_t k = 0; k < policies.size(); ++k) {
    EXPECT_EQ(evaluation.by_pack_fault[0].policies[k].runs + evaluation.by_pack_fault[1].policies[k].runs, 6);
    EXPECT_EQ(evaluation.by_pack_fault[1].policies[k].runs, faulted);
    std::int64_t kinds = 0, completions = 0;
    for (std::size_t g = 2; g < evaluation.by_pack_fault.size(); ++g) {
      kinds += evaluation.by_pack_fault[g].policies[k].runs;
      completions += evaluation.by_pack_fault[g].policies[k].completions;
    }
    EXPECT_EQ(kinds, faulted);
    EXPECT_EQ(completions, evaluation.by_pack_fault[1].policies[k].completions);
  }
  EXPECT_NE(BatteryEvaluationText(evaluation).find("completed per sudden pack fault"), std::string::npos);
}

TEST(BatteryEvaluationTest, TheHindsightFamilyIsWhatTheHeaderStates) {
  // A 100 s plan: (a) UseBoth; (b) a drop for good at 20, 40, 60, 80 s (20 s grid) per pack: 8; (c) windows on a
  // 30 s grid, times 0, 30, 60, 90: (i, j) with j < 4, plus [0, end) per pack: 3 + 2 + 1 + 1 = 7 per pack: 14.
  const auto family = HindsightSchedules(100.0, 30.0, 20.0);
  ASSERT_EQ(family.size(), 1u + 8u + 14u);
  EXPECT_EQ(family.front().Describe(), "UseBoth@0");
  EXPECT_EQ(family[1].Describe(), "UseBoth@0 UseBatt1@20");
  const SwitchSchedule& window = family[1 + 8];  // pack 1 alone on [0, 30), then UseBoth
  EXPECT_EQ(window.Describe(), "UseBatt1@0 UseBoth@30");
  // When each member first leaves UseBoth: never, at its drop, at its window's start (the hindsight's from-the-onset
  // bound keeps the members that leave at or after the onset).
  EXPECT_EQ(family.front().FirstDepartureS(), std::numeric_limits<double>::infinity());
  EXPECT_EQ(family[1].FirstDepartureS(), 20.0);
  EXPECT_EQ(window.FirstDepartureS(), 0.0);
  EXPECT_EQ((SwitchSchedule{{{0.0, PackAction::kUseBoth}, {60.0, PackAction::kUseBatt2}, {90.0, PackAction::kUseBoth}}})
                .FirstDepartureS(),
            60.0);
  const BatteryFlightController c = ScheduleController(window);
  const decision::BatteryObservation o;
  EXPECT_EQ(c.controller(0.0, o, 0), PackAction::kUseBatt1);
  EXPECT_EQ(c.controller(29.0, o, 0), PackAction::kUseBatt1);
  EXPECT_EQ(c.controller(30.0, o, 0), PackAction::kUseBoth);
  BatteryFlightResult result;
  result.switches = {{0.0, PackAction::kUseBatt1}, {30.0, PackAction::kUseBoth}};
  EXPECT_EQ(CountSwitches(result), 2);
  result.switches = {{0.0, PackAction::kUseBoth}};
  EXPECT_EQ(CountSwitches(result), 0);
}

TEST(BatteryEvaluationTest, PolicyListsAreCheckedBeforeAnyFlight) {
  EXPECT_THROW(ParseBatteryPolicies("useboth,useboth", "--policies"), InputError);
  EXPECT_THROW(ParseBatteryPolicies("useboth,bogus", "--policies"), InputError);
  EXPECT_THROW(ParseBatteryPolicies("rule:voltage:3.2", "--policies"), InputError);  // below the 3.3 V cut-off
  EXPECT_THROW(ParseBatteryPolicies("pistar:/nonexistent/policy.json", "--policies"), InputError);
  const auto specs = ParseBatteryPolicies("useboth,rule:voltage:3.35", "--policies");
  ASSERT_EQ(specs.size(), 2u);
  EXPECT_EQ(specs[1].kind, BatteryPolicyKind::kVoltageRule);
  EXPECT_DOUBLE_EQ(specs[1].drop_voltage_v, 3.35);
  EXPECT_DOUBLE_EQ(ParseBatteryPolicies("rule:voltage", "--policies")[0].drop_voltage_v, kVoltageRuleDropVoltage);
}

// The evaluation's runs are flown by common/parallel_for.h: kept in run order (the same evaluation on one
// thread or three), and a failure during the work reaches the caller instead of ending the process.
TEST(BatteryEvaluationTest, RunsAreKeptInOrderAndAFailureReachesTheCaller) {
  BatteryEvaluationOptions options;
  options.runs = 4;
  options.ranges.plan_fraction[0] = 0.05;  // short plans keep the test quick (ours)
  options.ranges.plan_fraction[1] = 0.10;
  const std::vector<BatteryPolicySpec> policies = ParseBatteryPolicies("useboth,rule:voltage", "--policies");
  std::vector<std::int64_t> done;
  options.on_run_done = [&done](std::int64_t count) { done.push_back(count); };
  const BatteryEvaluation serial = EvaluateBatteryPolicies(policies, options);
  options.jobs = 3;
  const BatteryEvaluation parallel = EvaluateBatteryPolicies(policies, options);
  EXPECT_EQ(done, (std::vector<std::int64_t>{1, 2, 3, 4, 1, 2, 3, 4}));
  ASSERT_EQ(parallel.runs.size(), serial.runs.size());
  for (std::size_t r = 0; r < serial.runs.size(); ++r) {
    EXPECT_EQ(parallel.runs[r].run, static_cast<std::int64_t>(r));
    for (std::size_t k = 0; k < policies.size(); ++k) {
      const BatteryPolicyFlight& a = serial.runs[r].flights[k];
      const BatteryPolicyFlight& b = parallel.runs[r].flights[k];
      EXPECT_EQ(a.outcome, b.outcome);
      EXPECT_EQ(std::memcmp(&a.end_time_s, &b.end_time_s, sizeof(double)), 0);
      EXPECT_EQ(std::memcmp(&a.energy_used_wh, &b.energy_used_wh, sizeof(double)), 0);
      EXPECT_EQ(a.switches, b.switches);
    }
  }
  options.on_run_done = [](std::int64_t count) {
    if (count == 2) throw std::runtime_error("progress report failed");
  };
  EXPECT_THROW(EvaluateBatteryPolicies(policies, options), std::runtime_error);
}

}  // namespace
}  // namespace uascma::campaign
