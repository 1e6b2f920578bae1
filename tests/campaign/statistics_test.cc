// Campaign statistics (§5.5.3): the SEM formulas checked by hand and the summary of hand-made records.
#include "uascma/campaign/statistics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "uascma/common/error.h"

namespace uascma::campaign {
namespace {

constexpr double kTolerance = 1e-12;

RunRecord Flight(const std::string& policy, const std::string& health, const std::string& outcome, double average,
                 double minimum) {
  RunRecord r;
  r.policy = policy;
  r.battery_health = health;
  r.outcome = outcome;
  r.failure = outcome.rfind("failed", 0) == 0 || outcome == "timeout";
  r.average_reward = average;
  r.min_reward = minimum;
  return r;
}

TEST(StatisticsTest, BinomialSemByHand) {
  // 3 failures in 10: p = 0.3, SEM = √(0.3 · 0.7 / 10) = √0.021 = 0.144913767…
  const Estimate e = EstimateRate(3, 10);
  EXPECT_NEAR(e.value, 0.3, kTolerance);
  EXPECT_NEAR(e.sem, 0.14491376746189438, kTolerance);
  // All or nothing: no spread.
  EXPECT_NEAR(EstimateRate(0, 7).sem, 0.0, kTolerance);
  EXPECT_NEAR(EstimateRate(7, 7).sem, 0.0, kTolerance);
  EXPECT_TRUE(std::isnan(EstimateRate(0, 0).value));
}

TEST(StatisticsTest, MeanSemByHand) {
  // {1, 2, 3, 6}: mean 3, s² = (4 + 1 + 0 + 9) / 3 = 14/3, SEM = √(14/3) / 2 = 1.0801234…
  const Estimate e = EstimateMean({1.0, 2.0, 3.0, 6.0});
  EXPECT_NEAR(e.value, 3.0, kTolerance);
  EXPECT_NEAR(e.sem, std::sqrt(14.0 / 3.0) / 2.0, kTolerance);
  EXPECT_NEAR(EstimateMean({2.5}).sem, 0.0, kTolerance);
  EXPECT_TRUE(std::isnan(EstimateMean({}).value));
}

std::vector<RunRecord> HandMadeCampaign() {
  return {
      // cma: P → 1 failure of 4, 1 completion, 1 emergency landing, 1 termination; G → 1 completion.
      Flight("cma", "P", "failed_battery", -0.1, -0.4),
      Flight("cma", "P", "completed", 0.2, 0.1),
      Flight("cma", "P", "emergency_landing", 0.3, 0.1),
      Flight("cma", "P", "terminated", 0.1, 0.0),
      Flight("cma", "G", "completed", 0.4, 0.2),
      // noop: P → 3 failures of 4 (one of each failure kind but control), G → 1 completion.
      Flight("noop", "P", "failed_battery", -0.2, -0.4),
      Flight("noop", "P", "failed_collision", -0.2, -0.4),
      Flight("noop", "P", "timeout", -0.1, -0.4),
      Flight("noop", "P", "completed", 0.3, 0.1),
      Flight("noop", "G", "completed", 0.4, 0.2),
  };
}

const GroupStatistics& Find(const std::vector<GroupStatistics>& groups, const std::string& policy,
                            const std::string& health) {
  for (const auto& g : groups) {
    if (g.policy == policy && g.battery_health == health) return g;
  }
  static GroupStatistics none;
  ADD_FAILURE() << "no group " << policy << " " << health;
  return none;
}

TEST(StatisticsTest, HandMadeCampaignGivesTheExpectedTable) {
  const auto groups = Summarise(HandMadeCampaign(), {"noop", "cma"});
  ASSERT_EQ(groups.size(), 8u);              // 2 policies × G, M, P, all
  EXPECT_EQ(groups.front().policy, "noop");  // the requested order
  const GroupStatistics& cma_p = Find(groups, "cma", "P");
  EXPECT_EQ(cma_p.runs, 4);
  EXPECT_NEAR(cma_p.failure_rate.value, 0.25, kTolerance);
  EXPECT_NEAR(cma_p.failure_rate.sem, std::sqrt(0.25 * 0.75 / 4.0), kTolerance);
  EXPECT_NEAR(cma_p.completion_rate.value, 0.25, kTolerance);
  EXPECT_NEAR(cma_p.emergency_landing_rate.value, 0.25, kTolerance);
  EXPECT_NEAR(cma_p.termination_rate.value, 0.25, kTolerance);
  EXPECT_NEAR(cma_p.average_reward.value, 0.125, kTolerance);
  EXPECT_NEAR(cma_p.min_reward.value, -0.05, kTolerance);
  const GroupStatistics& noop_p = Find(groups, "noop", "P");
  EXPECT_EQ(noop_p.failures, 3);
  EXPECT_NEAR(noop_p.failure_rate.value, 0.75, kTolerance);
  EXPECT_NEAR(noop_p.completion_rate.value, 0.25, kTolerance);
  const GroupStatistics& noop_m = Find(groups, "noop", "M");
  EXPECT_EQ(noop_m.runs, 0);
  EXPECT_TRUE(std::isnan(noop_m.failure_rate.value));
  const GroupStatistics& cma_all = Find(groups, "cma", "all");
  EXPECT_EQ(cma_all.runs, 5);
  EXPECT_NEAR(cma_all.completion_rate.value, 0.4, kTolerance);
  // Rates of a group sum to one.
  for (const auto& g : groups) {
    if (g.runs == 0) continue;
    EXPECT_NEAR(
        g.failure_rate.value + g.completion_rate.value + g.emergency_landing_rate.value + g.termination_rate.value, 1.0,
        kTolerance);
  }
}

TEST(StatisticsTest, JsonAndTableCarryTheFigures) {
  const auto groups = Summarise(HandMadeCampaign(), {"cma", "noop"});
  const nlohmann::json json = StatisticsToJson(groups);
  EXPECT_EQ(json["policies"]["noop"]["P"]["runs"], 4);
  EXPECT_NEAR(json["policies"]["noop"]["P"]["failure_rate"].get<double>(), 0.75, kTolerance);
  EXPECT_NEAR(json["policies"]["noop"]["P"]["failure_rate_sem"].get<double>(), std::sqrt(0.75 * 0.25 / 4.0),
              kTolerance);
  EXPECT_TRUE(json["policies"]["cma"]["M"]["failure_rate"].is_null());
  EXPECT_NEAR(json["dissertation"]["poor_health_failure_rate"]["noop"].get<double>(), 0.71, kTolerance);
  const std::string table = StatisticsTable(groups);
  EXPECT_NE(table.find(" 75.0 ± 21.7"), std::string::npos) << table;  // noop P: 75 % ± 21.65 %
  EXPECT_NE(table.find("dissertation  71.0 %"), std::string::npos) << table;
}

// Every row of the outcome and failure tables puts its columns where the header does, whatever the policies' names:
// here one longer than the old fixed 10-character column.
TEST(StatisticsTest, ColumnsStayAlignedForALongPolicyName) {
  std::vector<RunRecord> records = HandMadeCampaign();
  const std::string long_name = "cma-vehicle-risk@0.25";
  for (RunRecord& r : records) {
    if (r.policy == "cma") r.policy = long_name;
  }
  const std::string table = StatisticsTable(Summarise(records, {long_name, "noop"}));
  std::istringstream lines(table);
  std::string line;
  std::size_t header_bh = std::string::npos;
  int rows = 0;
  while (std::getline(lines, line)) {
    if (line.starts_with("policy ")) {
      header_bh = line.find(" BH ");
      ASSERT_NE(header_bh, std::string::npos) << line;
      EXPECT_GE(header_bh, long_name.size()) << line;
      continue;
    }
    const bool row = line.starts_with(long_name + " ") || line.starts_with("noop ");
    if (!row || header_bh == std::string::npos) continue;
    // The health group starts one column after the policy's, as "BH" does in the header.
    EXPECT_NE(line.find_first_not_of(' ', line.find(' ')), std::string::npos);
    EXPECT_EQ(line.find_first_not_of(' ', line.find(' ')), header_bh + 1) << line;
    ++rows;
  }
  EXPECT_GE(rows, 2 * 2 * 4);  // two tables, two policies, four health groups
}

// Published values: Clopper–Pearson 95 % for 0 of 10 is [0, 1 − 0.025^(1/10)] = [0, 0.3085] and Wilson 95 % for
// 0 of 10 is [0, z²/(n + z²)] = [0, 0.2775] (Newcombe, Stat. Med. 17 (1998), the 0/10 example). The 81/263 and
// 15/148 figures (Newcombe's other examples) are checked against an independent computation: Python mpmath,
// the regularised incomplete beta inverted by bisection, and the Wilson formula in 50-digit arithmetic, rounded
// to four decimals as the paper prints them.
constexpr double kPublishedTolerance = 5e-5;  // four printed decimals

TEST(StatisticsTest, IntervalsMatchPublishedValues) {
  const Interval cp = ClopperPearsonInterval(0, 10);
  EXPECT_NEAR(cp.low, 0.0, kTolerance);
  EXPECT_NEAR(cp.high, 1.0 - std::pow(0.025, 0.1), kTolerance);
  EXPECT_NEAR(cp.high, 0.3085, kPublishedTolerance);
  const Interval wilson = WilsonInterval(0, 10);
  EXPECT_NEAR(wilson.low, 0.0, kTolerance);
  EXPECT_NEAR(wilson.high, 0.2775, kPublishedTolerance);
  const Interval w81 = WilsonInterval(81, 263);
  EXPECT_NEAR(w81.low, 0.2553, kPublishedTolerance);
  EXPECT_NEAR(w81.high, 0.3662, kPublishedTolerance);
  const Interval cp81 = ClopperPearsonInterval(81, 263);
  EXPECT_NEAR(cp81.low, 0.2527, kPublishedTolerance);
  EXPECT_NEAR(cp81.high, 0.3676, kPublishedTolerance);
  const Interval w15 = WilsonInterval(15, 148);
  EXPECT_NEAR(w15.low, 0.0624, kPublishedTolerance);
  EXPECT_NEAR(w15.high, 0.1605, kPublishedTolerance);
  const Interval cp15 = ClopperPearsonInterval(15, 148);
  EXPECT_NEAR(cp15.low, 0.0578, kPublishedTolerance);
  EXPECT_NEAR(cp15.high, 0.1617, kPublishedTolerance);
}

TEST(StatisticsTest, IntervalsAreSymmetricAndContainTheEstimate) {
  for (int n : {1, 7, 50, 465}) {
    for (int k = 0; k <= n; k += std::max(1, n / 7)) {
      const double p = static_cast<double>(k) / n;
      for (const Interval& i : {WilsonInterval(k, n), ClopperPearsonInterval(k, n)}) {
        EXPECT_LE(i.low, p + kTolerance);
        EXPECT_GE(i.high, p - kTolerance);
        EXPECT_GE(i.low, 0.0);
        EXPECT_LE(i.high, 1.0);
      }
      // k failures of n mirror n − k successes.
      const Interval a = ClopperPearsonInterval(k, n), b = ClopperPearsonInterval(n - k, n);
      EXPECT_NEAR(a.low, 1.0 - b.high, 1e-10);
      const Interval c = WilsonInterval(k, n), d = WilsonInterval(n - k, n);
      EXPECT_NEAR(c.high, 1.0 - d.low, 1e-10);
    }
  }
  EXPECT_TRUE(std::isnan(WilsonInterval(0, 0).low));
  EXPECT_TRUE(std::isnan(ClopperPearsonInterval(0, 0).high));
  EXPECT_THROW(WilsonInterval(3, 2), InputError);
  EXPECT_THROW(ClopperPearsonInterval(-1, 2), InputError);
}

TEST(StatisticsTest, McNemarByHand) {
  // b = 1, c = 9: exact p = 2 · P(X ≤ 1 | 10, ½) = 2 · (1 + 10) / 1024 = 0.021484375;
  // χ² = (|1 − 9| − 1)² / 10 = 4.9, p = erfc(√(4.9 / 2)) (χ²(1) tail) = 0.026857…
  const McNemarTest t = CalcMcNemarTest(1, 9);
  EXPECT_NEAR(t.exact_p, 22.0 / 1024.0, kTolerance);
  EXPECT_NEAR(t.chi_squared, 4.9, kTolerance);
  EXPECT_NEAR(t.chi_squared_p, std::erfc(std::sqrt(4.9 / 2.0)), 1e-10);
  // Symmetric in b and c; balanced counts give p = 1; no discordant pair: no evidence.
  EXPECT_NEAR(CalcMcNemarTest(9, 1).exact_p, t.exact_p, kTolerance);
  EXPECT_NEAR(CalcMcNemarTest(5, 5).exact_p, 1.0, kTolerance);
  EXPECT_NEAR(CalcMcNemarTest(0, 0).exact_p, 1.0, kTolerance);
  EXPECT_NEAR(CalcMcNemarTest(0, 0).chi_squared, 0.0, kTolerance);
  // b = 0, c = 6: exact p = 2 / 64.
  EXPECT_NEAR(CalcMcNemarTest(0, 6).exact_p, 2.0 / 64.0, kTolerance);
  EXPECT_THROW(CalcMcNemarTest(-1, 2), InputError);
}

RunRecord Paired(std::int64_t run, const std::string& policy, const std::string& health, const std::string& outcome) {
  RunRecord r = Flight(policy, health, outcome, 0.0, 0.0);
  r.run_index = run;
  return r;
}

TEST(StatisticsTest, PairedComparisonMatchesRunsByIndex) {
  // Runs 0–5 in P: cma fails run 0 only; noop fails runs 0, 1, 2, 3. Run 6 (G) is flown by cma only and
  // is left out of the pairs. Pairs in P: both failed 1 (run 0), b (cma only) = 0, c (noop only) = 3,
  // neither 2. A grounded flight counts as not failed.
  std::vector<RunRecord> records;
  const char* cma[] = {"failed_battery", "emergency_landing", "grounded", "terminated", "completed", "completed"};
  const char* noop[] = {"failed_collision", "failed_battery", "failed_control", "timeout", "completed", "completed"};
  for (int run = 0; run < 6; ++run) {
    records.push_back(Paired(run, "cma", "P", cma[run]));
    records.push_back(Paired(run, "noop", "P", noop[run]));
  }
  records.push_back(Paired(6, "cma", "G", "completed"));
  const auto comparisons = ComparePaired(records, {"cma", "noop"});
  ASSERT_EQ(comparisons.size(), 4u);  // one pair of policies × G, M, P, all
  const PairedComparison& p = comparisons[2];
  EXPECT_EQ(p.battery_health, "P");
  EXPECT_EQ(p.first_policy, "cma");
  EXPECT_EQ(p.pairs, 6);
  EXPECT_EQ(p.both_failed, 1);
  EXPECT_EQ(p.neither_failed, 2);
  EXPECT_EQ(p.test.only_first_failed, 0);
  EXPECT_EQ(p.test.only_second_failed, 3);
  EXPECT_NEAR(p.test.exact_p, 2.0 / 8.0, kTolerance);
  EXPECT_EQ(comparisons[0].pairs, 0);  // G: run 6 has no noop flight
  EXPECT_EQ(comparisons[3].pairs, 6);
  const nlohmann::json json = StatisticsToJson(Summarise(records, {"cma", "noop"}), comparisons);
  EXPECT_EQ(json["paired_comparisons"][2]["only_second_failed"], 3);
  EXPECT_NEAR(json["paired_comparisons"][2]["mcnemar_exact_p"].get<double>(), 0.25, kTolerance);
}

TEST(StatisticsTest, FailuresByCauseGroundedAndUnknownOutcomes) {
  std::vector<RunRecord> records = {
      Flight("noop", "P", "failed_battery", 0, 0),
      Flight("noop", "P", "failed_battery", 0, 0),
      Flight("noop", "P", "failed_control", 0, 0),
      Flight("noop", "P", "failed_collision", 0, 0),
      Flight("noop", "P", "timeout", 0, 0),
      Flight("noop", "P", "grounded", 0, 0),
      Flight("noop", "P", "landed_on_the_moon", 0, 0),
  };
  // A failure under a name this code does not know: counted as a failure of cause "other".
  RunRecord strange = Flight("noop", "P", "failed_in_a_new_way", 0, 0);
  strange.failure = true;
  records.push_back(strange);
  const auto groups = Summarise(records, {"noop"});
  const GroupStatistics& g = Find(groups, "noop", "P");
  EXPECT_EQ(g.runs, 8);
  EXPECT_EQ(g.failures, 6);
  EXPECT_EQ(g.failures_by_cause[static_cast<int>(FailureCause::kBattery)], 2);
  EXPECT_EQ(g.failures_by_cause[static_cast<int>(FailureCause::kLossOfControl)], 1);
  EXPECT_EQ(g.failures_by_cause[static_cast<int>(FailureCause::kCollision)], 1);
  EXPECT_EQ(g.failures_by_cause[static_cast<int>(FailureCause::kTimeout)], 1);
  EXPECT_EQ(g.failures_by_cause[static_cast<int>(FailureCause::kOther)], 1);
  EXPECT_EQ(g.groundings, 1);
  EXPECT_EQ(g.others, 1);
  EXPECT_NEAR(g.failure_rate.value + g.completion_rate.value + g.emergency_landing_rate.value +
                  g.termination_rate.value + g.grounded_rate.value + g.other_rate.value,
              1.0, kTolerance);
  const nlohmann::json json = StatisticsToJson(groups);
  const nlohmann::json& p = json["policies"]["noop"]["P"];
  EXPECT_EQ(p["failures_by_cause"]["battery"], 2);
  EXPECT_EQ(p["failures_by_cause"]["loss_of_control"], 1);
  EXPECT_EQ(p["groundings"], 1);
  EXPECT_NEAR(p["failure_rate_wilson_low"].get<double>(), WilsonInterval(6, 8).low, kTolerance);
  EXPECT_NEAR(p["failure_rate_clopper_pearson_high"].get<double>(), ClopperPearsonInterval(6, 8).high, kTolerance);
  const std::string table = StatisticsTable(groups);
  EXPECT_NE(table.find("other outcomes"), std::string::npos) << table;
}

TEST(StatisticsTest, FailuresByTheBatterysFades) {
  auto flight = [](const std::string& cells, const std::string& health, const std::string& outcome) {
    RunRecord r = Flight("noop", health, outcome, 0, 0);
    r.cell_health = cells;
    return r;
  };
  const std::vector<RunRecord> records = {
      flight("-,-,-|-,-,-", "G", "completed"),       flight("Q,-,-|-,-,-", "M", "failed_battery"),
      flight("Q,Q,-|-,-,-", "M", "completed"),       flight("R,-,-|-,R,-", "M", "completed"),
      flight("QR,-,-|-,-,R", "P", "failed_battery"), flight("-,R,-|QR,-,-", "P", "failed_battery"),
      flight("R,R,-|-,-,-", "M", "failed_control"),
  };
  EXPECT_EQ(BatteryFadesOf("QR,-,-|-,-,R"), BatteryFades::kCapacity);
  EXPECT_EQ(BatteryFadesOf("R,-,-|-,R,-"), BatteryFades::kPowerOnly);
  EXPECT_EQ(BatteryFadesOf("-,-,-|-,-,-"), BatteryFades::kNone);
  const auto groups = Summarise(records, {"noop"});
  const GroupStatistics& all = Find(groups, "noop", "all");
  const auto capacity = static_cast<int>(BatteryFades::kCapacity), power = static_cast<int>(BatteryFades::kPowerOnly),
             none = static_cast<int>(BatteryFades::kNone);
  EXPECT_EQ(all.runs_by_fades[capacity], 4);
  EXPECT_EQ(all.failures_by_fades[capacity], 3);
  EXPECT_EQ(all.runs_by_fades[power], 2);
  EXPECT_EQ(all.failures_by_fades[power], 1);
  EXPECT_EQ(all.runs_by_fades[none], 1);
  EXPECT_EQ(all.failures_by_fades[none], 0);
  const GroupStatistics& m = Find(groups, "noop", "M");
  EXPECT_EQ(m.runs_by_fades[capacity] + m.runs_by_fades[power] + m.runs_by_fades[none], m.runs);
  const nlohmann::json json = StatisticsToJson(groups);
  EXPECT_EQ(json["policies"]["noop"]["all"]["by_battery_fades"]["capacity"]["failures"], 3);
  EXPECT_NEAR(json["policies"]["noop"]["all"]["by_battery_fades"]["power_only"]["failure_rate"].get<double>(), 0.5,
              kTolerance);
  const std::string table = StatisticsTable(groups);
  EXPECT_NE(table.find("capacity 3/4 (75.0 %)  power_only 1/2 (50.0 %)  none 0/1 (0.0 %)"), std::string::npos) << table;
}

TEST(StatisticsTest, UnnecessaryLandingsAreLandingsWhoseNoOpTwinCompletedWithTheMargin) {
  // t_sf = 60 s in every run. NoOp: run 0 completed with 61 s of hover left, run 1 completed with 59 s, run 2
  // failed, run 3 completed with 60 s (exactly t_sf: enough). cma lands in runs 0, 1, 2 and lands off-site in run 3:
  // unnecessary in runs 0 and 3 (2 of 4). risk lands in run 1 only: none unnecessary. Pairs (cma, risk): b = 2, c = 0.
  const char* noop[] = {"completed", "completed", "failed_battery", "completed"};
  const double reserve[] = {61.0, 59.0, 0.0, 60.0};
  const char* cma[] = {"emergency_landing", "emergency_landing", "emergency_landing", "landed_off_site"};
  const char* risk[] = {"completed", "emergency_landing", "failed_battery", "completed"};
  std::vector<RunRecord> records;
  for (int run = 0; run < 4; ++run) {
    for (RunRecord r : {Paired(run, "noop", "P", noop[run]), Paired(run, "cma", "P", cma[run]),
                        Paired(run, "risk", "P", risk[run])}) {
      r.safety_margin_s = 60.0;
      r.end_reserve_s = r.policy == "noop" ? reserve[run] : 0.0;
      r.fault = run == 3;  // a spalled motor in run 3
      records.push_back(r);
    }
  }
  const auto noop_by_run = NoOpFlightsByRun(records);
  ASSERT_EQ(noop_by_run.size(), 4u);
  EXPECT_TRUE(IsUnnecessaryLanding(records[1], noop_by_run));    // run 0, cma
  EXPECT_FALSE(IsUnnecessaryLanding(records[4], noop_by_run));   // run 1, cma: NoOp had 59 s < t_sf
  EXPECT_FALSE(IsUnnecessaryLanding(records[7], noop_by_run));   // run 2, cma: NoOp failed
  EXPECT_TRUE(IsUnnecessaryLanding(records[10], noop_by_run));   // run 3, cma: off-site, NoOp had exactly t_sf
  EXPECT_FALSE(IsUnnecessaryLanding(records[11], noop_by_run));  // run 3, risk completed
  const std::vector<std::string> order = {"noop", "cma", "risk"};
  const auto groups = Summarise(records, order);
  auto group = [&groups](const std::string& policy, const std::string& health) {
    return *std::find_if(groups.begin(), groups.end(),
                         [&](const GroupStatistics& g) { return g.policy == policy && g.battery_health == health; });
  };
  EXPECT_TRUE(group("cma", "P").has_noop_twin);
  EXPECT_EQ(group("cma", "P").unnecessary_landings, 2);
  EXPECT_EQ(group("cma", "P").unnecessary_landings_fault_free, 1);  // run 0
  EXPECT_NEAR(group("cma", "P").unnecessary_landing_rate.value, 0.5, kTolerance);
  EXPECT_EQ(group("risk", "all").unnecessary_landings, 0);
  EXPECT_EQ(group("noop", "P").unnecessary_landings, 0);
  EXPECT_EQ(group("cma", "G").runs, 0);
  const auto comparisons = ComparePaired(records, order);
  const auto pair = std::find_if(comparisons.begin(), comparisons.end(), [](const PairedComparison& c) {
    return c.first_policy == "cma" && c.second_policy == "risk" && c.battery_health == "P";
  });
  ASSERT_NE(pair, comparisons.end());
  ASSERT_TRUE(pair->unnecessary_test.has_value());
  EXPECT_EQ(pair->unnecessary_test->only_first_failed, 2);
  EXPECT_EQ(pair->unnecessary_test->only_second_failed, 0);
  EXPECT_NEAR(pair->unnecessary_test->exact_p, 0.5, kTolerance);  // 2 · P(X ≤ 0), X ~ Bin(2, ½)
  const std::string table = StatisticsTable(groups, comparisons);
  EXPECT_NE(table.find("Unnecessary landings"), std::string::npos) << table;
  const nlohmann::json json = StatisticsToJson(groups, comparisons);
  EXPECT_EQ(json["policies"]["cma"]["P"]["unnecessary_landings"], 2);
}

TEST(StatisticsTest, NoUnnecessaryLandingsWithoutANoOpTwin) {
  std::vector<RunRecord> records = {Paired(0, "cma", "G", "emergency_landing")};
  const auto groups = Summarise(records, {"cma"});
  EXPECT_FALSE(groups.front().has_noop_twin);
  EXPECT_TRUE(StatisticsToJson(groups, {})["policies"]["cma"]["G"]["unnecessary_landings"].is_null());
  EXPECT_EQ(StatisticsTable(groups, {}).find("Unnecessary landings"), std::string::npos);
}

TEST(StatisticsTest, TerminationsAreCountedByTheirNoOpTwinsOutcome) {
  // cma terminates runs 0, 1 and 2; NoOp completed run 0, failed run 1 and landed on an emergency site in run 2
  // (neither completed nor failed: counted in neither column). Run 3: cma completed.
  const char* noop[] = {"completed", "failed_battery", "emergency_landing", "completed"};
  const char* cma[] = {"terminated", "terminated", "terminated", "completed"};
  std::vector<RunRecord> records;
  for (int run = 0; run < 4; ++run) {
    records.push_back(Paired(run, "noop", "M", noop[run]));
    records.push_back(Paired(run, "cma", "M", cma[run]));
  }
  const auto groups = Summarise(records, {"noop", "cma"});
  const auto cma_m = *std::find_if(groups.begin(), groups.end(), [](const GroupStatistics& g) {
    return g.policy == "cma" && g.battery_health == "M";
  });
  EXPECT_EQ(cma_m.terminations, 3);
  EXPECT_EQ(cma_m.terminations_noop_completed, 1);
  EXPECT_EQ(cma_m.terminations_noop_failed, 1);
  const nlohmann::json json = StatisticsToJson(groups, {});
  EXPECT_EQ(json["policies"]["cma"]["all"]["terminations_noop_completed"], 1);
  EXPECT_EQ(json["policies"]["noop"]["M"]["terminations_noop_failed"], 0);
  const std::string table = StatisticsTable(groups, {});
  EXPECT_NE(table.find("3 terminated: NoOp completed     1, NoOp failed     1"), std::string::npos) << table;
}

}  // namespace
}  // namespace uascma::campaign
