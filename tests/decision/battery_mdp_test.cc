// The battery-reconfiguration MDP of dissertation §4.3 (decision/battery_mdp.h, battery_abstraction.h,
// battery_model.h, battery_policy.h) and its files (decision/battery_mdp_file.h).
#include "uascma/decision/battery_mdp_file.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "../support/input_error.h"
#include "uascma/common/random.h"
#include "uascma/decision/policy_file.h"
#include "uascma/decision/solvers.h"
#include "uascma/prognostics/eod.h"

namespace uascma::decision {
namespace {

using models::HealthClass;
using models::PackAction;
using testing_support::InputErrorMessage;

constexpr double kRewardTolerance = 1e-12;  // rewards are sums of a few products of short decimals
constexpr double kRowSumTolerance = 1e-12;  // counts / total, summed over at most 289 successors
constexpr double kValueTolerance = 1e-7;    // VI stops at a residual of 1e-10; V ≤ 30/(1 − 0.95) = 600
constexpr std::array<PackAction, 3> kAllActions = {PackAction::kUseBatt1, PackAction::kUseBatt2, PackAction::kUseBoth};

BatteryFeatures Features(CurrentLevel current, PackFeatures pack1, PackFeatures pack2) {
  BatteryFeatures f;
  f.current = current;
  f.pack = {pack1, pack2};
  return f;
}

// Synthetic flights with the shape of the real ones: energy only worsens (S1 → S2 → S3), the voltage
// falls to C1 late, FAILURE follows S3 ∧ C1, the current level flips now and then.
BatteryTransitionCounts SyntheticCounts(std::uint64_t seed, int flights_per_action) {
  BatteryTransitionCounts counts;
  RandomStream random(seed);
  for (int c = 0; c < kBatteryNumContexts; ++c) {
    const BatteryContext context = BatteryContextFromIndex(c);
    for (PackAction action : kAllActions) {
      const auto on = models::SwitchesFor(action);
      for (int f = 0; f < flights_per_action; ++f) {
        BatteryFeatures x;
        x.current = random.Bernoulli(0.3) ? CurrentLevel::kHigh : CurrentLevel::kLow;
        for (int j = 0; j < 2; ++j) {
          x.pack[j].switch_on = on[j];
          x.pack[j].energy = static_cast<EnergyState>(random.UniformIndex(3));
          x.pack[j].voltage = VoltageState::kC0;
        }
        std::vector<StateIndex> states = {BatteryStateIndex(x)};
        for (int k = 0; k < 60; ++k) {
          if (random.Bernoulli(0.1))
            x.current = x.current == CurrentLevel::kLow ? CurrentLevel::kHigh : CurrentLevel::kLow;
          bool failed = false;
          for (int j = 0; j < 2; ++j) {
            if (!on[j]) continue;
            auto& p = x.pack[j];
            if (p.energy != EnergyState::kS3 && random.Bernoulli(0.08 + 0.04 * c / 17.0)) {
              p.energy = static_cast<EnergyState>(static_cast<int>(p.energy) + 1);
            }
            if (p.energy == EnergyState::kS3 && random.Bernoulli(0.1)) p.voltage = VoltageState::kC1;
            if (p.energy == EnergyState::kS3 && p.voltage == VoltageState::kC1 && random.Bernoulli(0.2)) failed = true;
          }
          states.push_back(failed ? kBatteryFailureState : BatteryStateIndex(x));
          if (failed) break;
        }
        counts.AddFlight(context, action, states);
      }
    }
  }
  return counts;
}

TEST(BatteryMdpStates, ThereAre289WithUniqueLabelsAndRoundTrip) {
  const auto& labels = BatteryStateLabels();
  ASSERT_EQ(static_cast<int>(labels.size()), 289);  // Table 4.1: 9 × 4 × 4 × 2 + 1
  EXPECT_EQ(std::set<std::string>(labels.begin(), labels.end()).size(), labels.size());
  EXPECT_EQ(labels[kBatteryFailureState], "FAILURE");
  for (StateIndex s = 0; s < kBatteryFailureState; ++s) {
    EXPECT_EQ(BatteryStateIndex(BatteryStateFeatures(s)), s);
    EXPECT_EQ(ParseBatteryState(labels[s], "test"), s);
  }
  // Fig. 4.4's label: current, pack 1 (switch, energy, voltage), pack 2.
  const BatteryFeatures f = BatteryStateFeatures(ParseBatteryState("ILONS3C0OFFS3C0", "test"));
  EXPECT_EQ(f.current, CurrentLevel::kLow);
  EXPECT_TRUE(f.pack[0].switch_on);
  EXPECT_FALSE(f.pack[1].switch_on);
  EXPECT_EQ(f.pack[0].energy, EnergyState::kS3);
  EXPECT_EQ(f.pack[1].voltage, VoltageState::kC0);
  EXPECT_NE(InputErrorMessage([] { ParseBatteryState("ILONS4C0OFFS3C0", "f.json"); }).find("f.json"),
            std::string::npos);
}

TEST(BatteryMdpStates, Fig44SwitchExampleIsDeterministic) {
  // §4.3.2: under UseBatt1 "the topmost state ILONS3C0ONS3C0 transitions to ILONS3C0OFFS3C0 with p = 1".
  EXPECT_EQ(BatteryStateLabel(ApplySwitches(ParseBatteryState("ILONS3C0ONS3C0", "t"), PackAction::kUseBatt1)),
            "ILONS3C0OFFS3C0");
  EXPECT_EQ(BatteryStateLabel(ApplySwitches(ParseBatteryState("IHOFFS1C1ONS2C0", "t"), PackAction::kUseBoth)),
            "IHONS1C1ONS2C0");
  EXPECT_EQ(ApplySwitches(kBatteryFailureState, PackAction::kUseBoth), kBatteryFailureState);
}

// --- the abstraction's thresholds at closed-form points (Table 4.1) ---------------------------------
TEST(BatteryAbstraction, EnergyBoundariesAreRfdAndRfdPlusSafetyMargin) {
  const double rfd = 300.0, tsf = 7.0, eps = 1e-9;
  EXPECT_EQ(ClassifyEnergy(rfd + tsf + eps, rfd, tsf), EnergyState::kS1);
  EXPECT_EQ(ClassifyEnergy(rfd + tsf, rfd, tsf), EnergyState::kS2);
  EXPECT_EQ(ClassifyEnergy(rfd + 0.5 * tsf, rfd, tsf), EnergyState::kS2);
  EXPECT_EQ(ClassifyEnergy(rfd, rfd, tsf), EnergyState::kS2);
  EXPECT_EQ(ClassifyEnergy(rfd - eps, rfd, tsf), EnergyState::kS3);
  // At the end of the flight (RFD = 0) any pack with more than t_sf left is S1.
  EXPECT_EQ(ClassifyEnergy(tsf + eps, 0.0, tsf), EnergyState::kS1);
}

TEST(BatteryAbstraction, VoltageCurrentAndFailureThresholds) {
  const double eps = 1e-9;
  EXPECT_EQ(ClassifyVoltage(3.4), VoltageState::kC0);  // ≥ critical voltage
  EXPECT_EQ(ClassifyVoltage(3.4 - eps), VoltageState::kC1);
  EXPECT_EQ(ClassifyCurrent(21.0), CurrentLevel::kLow);  // 0.2 × 105 A = 21 A
  EXPECT_EQ(ClassifyCurrent(21.0 + 1e-6), CurrentLevel::kHigh);
  EXPECT_TRUE(IsCellFailure(3.3));  // "≤ 3.3 VDC"
  EXPECT_FALSE(IsCellFailure(3.3 + eps));
  BatteryThresholds custom;
  custom.max_current_a = 50.0;
  EXPECT_EQ(ClassifyCurrent(11.0, custom), CurrentLevel::kHigh);  // thresholds are configuration
}

TEST(BatteryAbstraction, ObservationToStateUsesWorstCellPerPackAndOnlySwitchedOnPacksFail) {
  BatteryObservation o;
  o.total_current_a = 25.0;
  o.remaining_flight_s = 100.0;
  o.safety_margin_s = 5.0;
  o.switch_on = {true, false};
  o.eod_s = {200.0, 102.0};
  o.min_cell_voltage_v = {3.45, 3.39};
  EXPECT_EQ(BatteryStateLabel(AbstractBatteryState(o)), "IHONS1C0OFFS2C1");
  o.min_cell_voltage_v = {3.45, 3.2};  // a resting, switched-off pack below 3.3 V is not a failure of the bus
  EXPECT_EQ(BatteryStateLabel(AbstractBatteryState(o)), "IHONS1C0OFFS2C1");
  o.min_cell_voltage_v = {3.3, 3.9};
  EXPECT_EQ(AbstractBatteryState(o), kBatteryFailureState);
  // With the actual voltages given, FAILURE follows them (the C features stay the loaded-alone ones).
  o.min_cell_voltage_v = {3.35, 3.9};
  o.actual_min_cell_voltage_v = {3.42, 3.95};
  EXPECT_EQ(BatteryStateLabel(AbstractBatteryState(o)), "IHONS1C1OFFS2C0");
  o.actual_min_cell_voltage_v = {3.3, 3.95};
  EXPECT_EQ(AbstractBatteryState(o), kBatteryFailureState);
}

TEST(BatteryAbstraction, PackFeaturesAreWhatEachPackDoesAloneAndDoNotJumpAtASwitch) {
  // Pack 1 healthy (F1), pack 2 with power and capacity fade (F3).
  models::PerCell<models::CellHealth> health{};
  for (auto& cell : health[1]) cell = models::CellHealthForClass(HealthClass::kP);
  const models::BatteryPack pack(models::MakePackParams(health));
  const double current_a = 14.0;
  const models::PackState both = pack.MakeRestingState(4.1, PackAction::kUseBoth);
  const BatteryObservation o = ObserveBattery(pack, both, current_a, 600.0, 5.0);
  for (int j = 0; j < 2; ++j) {
    models::PackState alone = both;
    alone.branch_on = {j == 0, j == 1};
    EXPECT_DOUBLE_EQ(o.eod_s[j], prognostics::CalcPackEod(pack, alone, current_a).eod_s);
    const models::PackOutputs loaded = pack.CalcOutputs(alone, current_a);
    EXPECT_DOUBLE_EQ(o.min_cell_voltage_v[j],
                     std::min({loaded.cell_voltage_v[j][0], loaded.cell_voltage_v[j][1], loaded.cell_voltage_v[j][2]}));
  }
  EXPECT_GT(o.eod_s[0], o.eod_s[1]);  // the faded pack alone runs out first (0.8 Q, 2 R0)
  // Sharing the load, the pair lasts longer than either pack alone.
  EXPECT_GT(prognostics::CalcPackEod(pack, both, current_a).eod_s, o.eod_s[0]);
  // The same cells with other switches: the same pack features (a switch changes none at once) ...
  const BatteryObservation o1 =
      ObserveBattery(pack, pack.MakeRestingState(4.1, PackAction::kUseBatt1), current_a, 600.0, 5.0);
  EXPECT_EQ(o1.eod_s, o.eod_s);
  EXPECT_EQ(o1.min_cell_voltage_v, o.min_cell_voltage_v);
  // ... while the actual voltages differ: the switched-off pack rests, the other carries everything.
  EXPECT_GT(o1.actual_min_cell_voltage_v[1], o.actual_min_cell_voltage_v[1]);
  EXPECT_LT(o1.actual_min_cell_voltage_v[0], o.actual_min_cell_voltage_v[0]);
  EXPECT_FALSE(o1.switch_on[1]);
}

TEST(BatteryAbstraction, EachPackAloneCarriesThePresentPowerAtTheClosedFormCurrent) {
  models::PerCell<models::CellHealth> health{};
  for (auto& cell : health[1]) cell = models::CellHealthForClass(HealthClass::kP);
  const models::BatteryPack pack(models::MakePackParams(health));
  const double current_a = 20.0;
  const models::PackState both = pack.MakeRestingState(3.8, PackAction::kUseBoth);
  BatteryObservation o = ObserveBattery(pack, both, current_a, 600.0, 5.0);
  ObserveAloneAtPower(pack, both, current_a, o);
  const double power_w = current_a * pack.CalcSplit(both, current_a).bus_voltage_v;
  for (int j = 0; j < 2; ++j) {
    // One branch alone: V(I) = OCV_j − R_j I (eqs. 3.6-3.7), so I·V(I) = P has the smaller root
    // I = (OCV − sqrt(OCV² − 4 R P)) / (2 R); the iteration must land on it.
    models::PackState alone = both;
    alone.branch_on = {j == 0, j == 1};
    const double ocv_v = pack.CalcBranchOcv(both, j);
    const double r_ohm = (ocv_v - pack.CalcSplit(alone, 1.0).bus_voltage_v) / 1.0;
    const double closed_a = (ocv_v - std::sqrt(ocv_v * ocv_v - 4.0 * r_ohm * power_w)) / (2.0 * r_ohm);
    EXPECT_NEAR(o.alone_power_current_a[j], closed_a, 1e-8);  // A
    EXPECT_GT(o.alone_power_current_a[j], current_a);         // one pack's bus sags more than the pair's
    // The EOD at the closed-form current: within the EOD's own root tolerance (EodOptions, 1e-6 s).
    EXPECT_NEAR(o.alone_power_eod_s[j], prognostics::CalcPackEod(pack, alone, closed_a).eod_s, 1e-6);
    EXPECT_LT(o.alone_power_eod_s[j], o.eod_s[j]);  // more current, less time
    EXPECT_LT(o.alone_power_min_cell_voltage_v[j], o.min_cell_voltage_v[j]);
  }
  // With only pack 1 in, pack 1 alone is the present bus: the same current.
  const models::PackState one = pack.MakeRestingState(3.8, PackAction::kUseBatt1);
  BatteryObservation o1 = ObserveBattery(pack, one, current_a, 600.0, 5.0);
  ObserveAloneAtPower(pack, one, current_a, o1);
  EXPECT_NEAR(o1.alone_power_current_a[0], current_a, 1e-8);
  // 120 A: the pair carries ~1.2 kW, beyond what the faded pack 2 can alone (OCV²/4R ≈ 1 kW): +inf, EOD 0.
  BatteryObservation o2 = ObserveBattery(pack, both, 120.0, 600.0, 5.0);
  ObserveAloneAtPower(pack, both, 120.0, o2);
  EXPECT_TRUE(std::isfinite(o2.alone_power_current_a[0]));
  EXPECT_TRUE(std::isinf(o2.alone_power_current_a[1]));
  EXPECT_EQ(o2.alone_power_eod_s[1], 0.0);
}

TEST(BatteryOursTest, OffersOnePackAloneOnlyWhenItCanFinishAndIsNotCritical) {
  const PackFeatures s1c0{true, EnergyState::kS1, VoltageState::kC0};
  const PackFeatures s1c1{true, EnergyState::kS1, VoltageState::kC1};
  const PackFeatures s2c0{true, EnergyState::kS2, VoltageState::kC0};
  EXPECT_TRUE(OursOffers(Features(CurrentLevel::kLow, s1c0, s1c1), PackAction::kUseBatt1));
  EXPECT_FALSE(OursOffers(Features(CurrentLevel::kLow, s1c0, s1c1), PackAction::kUseBatt2));  // C1: critical
  EXPECT_FALSE(OursOffers(Features(CurrentLevel::kLow, s2c0, s1c0), PackAction::kUseBatt1));  // S2: in the margin
  EXPECT_TRUE(OursOffers(Features(CurrentLevel::kLow, s2c0, s1c1), PackAction::kUseBoth));
}

// --- rewards (eqs. 4.1–4.9, docs/modelling-choices.md#battery-mdp-rewards) -------------------------------------------
TEST(BatteryRewards, MatchHandComputedValues) {
  const BatteryRewardWeights w{0.5, 0.3, 0.2};
  const BatteryContext f2f1{HealthClass::kM, HealthClass::kG, TemperatureClass::kHigh};
  const StateIndex s = ParseBatteryState("ILONS2C1OFFS3C0", "t");
  // Pack 1 (F2) is worse than pack 2 (F1): its S2 earns −10; pack 2 (as good or better) in S3 earns −20.
  EXPECT_NEAR(BatteryReward(s, PackAction::kUseBatt1, f2f1, w), 0.5 * -10 + 0.3 * -10 - 0.2 * 0, kRewardTolerance);
  EXPECT_NEAR(BatteryReward(s, PackAction::kUseBatt2, f2f1, w), 0.5 * -20 + 0.3 * 0 - 0.2 * 1, kRewardTolerance);
  EXPECT_NEAR(BatteryReward(s, PackAction::kUseBoth, f2f1, w),
              0.5 * (-10 - 20) / 2 + 0.3 * (-10 + 0) / 2 - 0.2 * ((1 + 0) / 2.0 - 1), kRewardTolerance);
  // Equal health: "at least as good" holds for both packs (−5 in S2, −20 in S3).
  const BatteryContext f3f3{HealthClass::kP, HealthClass::kP, TemperatureClass::kLow};
  EXPECT_NEAR(BatteryReward(s, PackAction::kUseBatt1, f3f3, w), 0.5 * -5 + 0.3 * -10, kRewardTolerance);
  const StateIndex s3 = ParseBatteryState("IHONS3C0ONS1C0", "t");
  EXPECT_NEAR(BatteryReward(s3, PackAction::kUseBatt1, f2f1, w), 0.5 * -25 - 0.2, kRewardTolerance);
  for (PackAction a : kAllActions) EXPECT_EQ(BatteryReward(kBatteryFailureState, a, f2f1, w), -30.0);
  std::string error;
  EXPECT_FALSE((BatteryRewardWeights{0.5, 0.5, 0.5}).IsValid(&error));
  EXPECT_NE(error.find("4.9"), std::string::npos);
}

// --- transitions from counts (docs/modelling-choices.md#battery-mdp-transitions) -------------------------------------
TEST(BatteryTransitions, FlightsAreCountedAt1HzAndStopAtFailure) {
  BatteryTransitionCounts counts;
  const BatteryContext context{HealthClass::kG, HealthClass::kM, TemperatureClass::kHigh};
  const StateIndex a = ParseBatteryState("ILONS1C0OFFS1C0", "t");
  const StateIndex b = ParseBatteryState("IHONS2C0OFFS1C0", "t");
  const std::vector<StateIndex> flight = {a, b, b, kBatteryFailureState, a};
  counts.AddFlight(context, PackAction::kUseBatt1, flight);
  EXPECT_EQ(counts.Row(context, a, PackAction::kUseBatt1).at(b), 1);
  EXPECT_EQ(counts.Row(context, b, PackAction::kUseBatt1).at(b), 1);
  EXPECT_EQ(counts.Row(context, b, PackAction::kUseBatt1).at(kBatteryFailureState), 1);
  EXPECT_EQ(counts.total_transitions(), 3);  // nothing after FAILURE
  EXPECT_EQ(counts.flights(context, PackAction::kUseBatt1), 1);
  // A flight whose states do not have the action's switches was not flown with that action.
  const std::vector<StateIndex> wrong = {a, b};
  EXPECT_NE(InputErrorMessage([&] { counts.AddFlight(context, PackAction::kUseBoth, wrong); }).find("states[0]"),
            std::string::npos);
}

TEST(BatteryTransitions, RowsSumToOneSwitchingIsDeterministicAndUnobservedRowsSelfLoop) {
  const BatteryTransitionCounts counts = SyntheticCounts(7, 40);
  for (int c = 0; c < kBatteryNumContexts; ++c) {
    const BatteryContext context = BatteryContextFromIndex(c);
    BatteryModelStats stats;
    const FiniteMdp mdp = BuildBatteryMdp(counts, context, {}, &stats);
    ASSERT_EQ(mdp.num_states(), 289);
    ASSERT_EQ(mdp.num_actions(), 3);
    EXPECT_EQ(stats.learned_rows, 216);  // 72 states with each action's switches × 3 actions
    EXPECT_EQ(stats.switch_rows, 3 * 288 - 216);
    int self_loops = 0;
    for (StateIndex s = 0; s < mdp.num_states(); ++s) {
      for (PackAction action : kAllActions) {
        const std::int64_t choice = mdp.FindChoice(s, static_cast<ActionIndex>(action));
        ASSERT_GE(choice, 0);
        const auto next = mdp.choice_next_states(choice);
        const auto prob = mdp.choice_probabilities(choice);
        double sum = 0.0;
        for (double p : prob) sum += p;
        EXPECT_NEAR(sum, 1.0, kRowSumTolerance);
        if (s == kBatteryFailureState) {
          ASSERT_EQ(next.size(), 1u);  // absorbing
          EXPECT_EQ(next[0], s);
          continue;
        }
        // §4.3.2: the switch works with p = 1 — every successor has the action's switch positions.
        for (StateIndex n : next) EXPECT_TRUE(n == kBatteryFailureState || SwitchesMatch(n, action));
        // The epoch runs from the switched state: its counted row, or a self-loop there when unobserved.
        const StateIndex switched = ApplySwitches(s, action);
        const auto& row = counts.Row(context, switched, action);
        const double total = static_cast<double>(counts.RowTotal(context, switched, action));
        if (total == 0.0) {
          ASSERT_EQ(next.size(), 1u);
          EXPECT_EQ(next[0], switched);
          EXPECT_EQ(prob[0], 1.0);
          if (switched == s) ++self_loops;
        } else {
          ASSERT_EQ(next.size(), row.size());
          for (std::size_t k = 0; k < next.size(); ++k) {
            EXPECT_NEAR(prob[k], static_cast<double>(row.at(next[k])) / total, kRowSumTolerance);
          }
        }
      }
    }
    EXPECT_EQ(self_loops, stats.unobserved_rows);
    EXPECT_GT(stats.unobserved_rows, 0);  // synthetic flights never touch the voltage-low S1 states
  }
  BatteryModelStats empty;
  const FiniteMdp unlearned = BuildBatteryMdp(BatteryTransitionCounts{}, BatteryContext{}, {}, &empty);
  EXPECT_EQ(empty.unobserved_rows, 216);
  // With nothing observed, Fig. 4.4's example: ILONS3C0ONS3C0 goes to ILONS3C0OFFS3C0 with p = 1 under UseBatt1.
  const std::int64_t choice = unlearned.FindChoice(ParseBatteryState("ILONS3C0ONS3C0", "t"), 0);
  ASSERT_EQ(unlearned.choice_next_states(choice).size(), 1u);
  EXPECT_EQ(unlearned.state_label(unlearned.choice_next_states(choice)[0]), "ILONS3C0OFFS3C0");
}

TEST(BatteryTransitions, ValueIterationEqualsPolicyIterationOnLearnedMdps) {
  const BatteryTransitionCounts counts = SyntheticCounts(11, 30);
  for (int c = 0; c < kBatteryNumContexts; ++c) {
    const FiniteMdp mdp = BuildBatteryMdp(counts, BatteryContextFromIndex(c), {});
    ValueIterationOptions vi_options;  // γ = 0.95
    SolverSummary vi_summary, pi_summary;
    const Policy vi = SolveValueIteration(mdp, vi_options, &vi_summary);
    const Policy pi = SolvePolicyIteration(mdp, PolicyIterationOptions{}, &pi_summary);
    ASSERT_EQ(vi_summary.status, SolverStatus::kConverged);
    ASSERT_EQ(pi_summary.status, SolverStatus::kConverged);
    for (StateIndex s = 0; s < mdp.num_states(); ++s) {
      EXPECT_NEAR(vi.value[s], pi.value[s], kValueTolerance) << mdp.state_label(s);
      // Both pick an optimal action: each one's Q equals the optimal value.
      const double q_vi = ChoiceQValue(mdp, mdp.FindChoice(s, vi.action[s]), 0.95, pi.value);
      const double q_pi = ChoiceQValue(mdp, mdp.FindChoice(s, pi.action[s]), 0.95, pi.value);
      EXPECT_NEAR(q_vi, q_pi, kValueTolerance) << mdp.state_label(s);
    }
  }
}

// --- files ------------------------------------------------------------------------------------------
BatteryModel SyntheticModel() {
  BatteryModel model;
  model.counts = SyntheticCounts(3, 5);
  model.provenance = {{"source", "synthetic test flights"}};
  return model;
}

TEST(BatteryFiles, ModelRoundTripsWithItsCountsAndHash) {
  const BatteryModel model = SyntheticModel();
  const nlohmann::json json = BatteryModelToJson(model);
  const BatteryModel back = BatteryModelFromJson(json, "m.json");
  EXPECT_EQ(BatteryModelHash(back), BatteryModelHash(model));
  EXPECT_EQ(back.counts.total_transitions(), model.counts.total_transitions());
  EXPECT_EQ(back.counts.total_flights(), 18 * 3 * 5);
}

TEST(BatteryFiles, BadModelsNameTheField) {
  const nlohmann::json good = BatteryModelToJson(SyntheticModel());
  auto message = [&](const std::function<void(nlohmann::json&)>& edit) {
    nlohmann::json bad = good;
    edit(bad);
    return InputErrorMessage([&] { BatteryModelFromJson(bad, "m.json"); });
  };
  EXPECT_NE(message([](nlohmann::json& j) { j["version"] = 2; }).find("m.json: version"), std::string::npos);
  EXPECT_NE(message([](nlohmann::json& j) { j["format"] = "uascma-policy/1"; }).find("format"), std::string::npos);
  EXPECT_NE(message([](nlohmann::json& j) { j.erase("weights"); }).find("weights"), std::string::npos);
  EXPECT_NE(message([](nlohmann::json& j) { j["weights"].erase("w2"); }).find("weights.w2"), std::string::npos);
  EXPECT_NE(message([](nlohmann::json& j) { j["contexts"][4]["b1"] = "F4"; }).find("contexts[4].b1"),
            std::string::npos);
  EXPECT_NE(message([](nlohmann::json& j) { j["contexts"][0]["temperature"] = "warm"; }).find("temperature"),
            std::string::npos);
  EXPECT_NE(message([](nlohmann::json& j) { j["contexts"].erase(3); }).find("contexts"), std::string::npos);
  EXPECT_NE(message([](nlohmann::json& j) {
              auto& next = j["contexts"][0]["rows"][0]["next"];
              next[next.begin().key()] = next.begin().value().get<int>() + 1;
            }).find("hash"),
            std::string::npos);
  EXPECT_NE(message([](nlohmann::json& j) { j["contexts"][0]["rows"][0]["action"] = "UseNone"; }).find("action"),
            std::string::npos);
}

// The files are read with the typed JSON reader (common/json_reader.h): every message is
// "<file>: <path in the document>: <what was expected>, got <what was there>".
TEST(BatteryFiles, ReadErrorsNameTheFileThePathAndWhatWasExpected) {
  const nlohmann::json good = BatteryModelToJson(SyntheticModel());
  auto message = [&](const std::function<void(nlohmann::json&)>& edit) {
    nlohmann::json bad = good;
    edit(bad);
    return InputErrorMessage([&] { BatteryModelFromJson(bad, "m.json"); });
  };
  EXPECT_EQ(message([](nlohmann::json& j) { j["contexts"][4]["b1"] = "F4"; }),
            "m.json: contexts[4].b1: F1 | F2 | F3 (Table 4.2), got 'F4'");
  EXPECT_EQ(message([](nlohmann::json& j) { j["gamma"] = 1.5; }), "m.json: gamma: in [0, 1), got 1.5");
  EXPECT_EQ(message([](nlohmann::json& j) { j["contexts"][0]["flights"]["UseBoth"] = -2; }),
            "m.json: contexts[0].flights.UseBoth: a non-negative integer count, got -2");
  EXPECT_EQ(message([](nlohmann::json& j) { j["contexts"][1]["rows"][0]["next"]["NOSUCHSTATE"] = 1; }),
            "m.json: contexts[1].rows[0].next.NOSUCHSTATE: a battery MDP state such as ILONS1C0OFFS2C0 or FAILURE, "
            "got 'NOSUCHSTATE'");
  EXPECT_EQ(message([](nlohmann::json& j) { j.erase("contexts"); }),
            "m.json: contexts: an array of contexts, but it is missing");
  const nlohmann::json policy = BatteryPolicyToJson(SolveBatteryPolicies(SyntheticModel()));
  nlohmann::json bad = policy;
  bad["policies"][3]["action"][7] = 2;
  EXPECT_EQ(InputErrorMessage([&] { BatteryPolicyFromJson(bad, "p.json"); }),
            "p.json: policies[3].action[7]: an action name, got 2");
  bad = policy;
  bad["policies"][0]["value"].erase(0);
  EXPECT_NE(InputErrorMessage([&] {
              BatteryPolicyFromJson(bad, "p.json");
            }).find("p.json: policies[0].value: an array of 289 numbers"),
            std::string::npos);
}

TEST(BatteryFiles, PolicyRoundTripsAndTheDecisionTreeSelectsTheContext) {
  const BatteryModel model = SyntheticModel();
  const BatteryPolicySet set = SolveBatteryPolicies(model);
  EXPECT_EQ(set.model_hash, BatteryModelHash(model));
  const BatteryPolicySet back = BatteryPolicyFromJson(BatteryPolicyToJson(set), "p.json");
  for (int c = 0; c < kBatteryNumContexts; ++c) {
    const BatteryContext context = BatteryContextFromIndex(c);
    EXPECT_EQ(back.Select(context).context, context);  // Fig. 4.5: the leaf of (T, B1F, B2F)
    EXPECT_EQ(back.Select(context).action, set.Select(context).action);
    EXPECT_EQ(set.Select(context).summary.status, SolverStatus::kConverged);
    const BatteryPolicyExecutor executor(back, context);
    for (StateIndex s = 0; s < kBatteryNumStates; ++s) {
      EXPECT_EQ(static_cast<ActionIndex>(executor.Decide(s)), set.Select(context).action[s]);
    }
  }
  nlohmann::json bad = BatteryPolicyToJson(set);
  bad["policies"][2]["action"][5] = bad["policies"][2]["action"][5] == "UseBoth" ? "UseBatt1" : "UseBoth";
  EXPECT_NE(InputErrorMessage([&] { BatteryPolicyFromJson(bad, "p.json"); }).find("p.json: hash"), std::string::npos);
  bad = BatteryPolicyToJson(set);
  bad["policies"][1]["b2"] = "healthy";
  EXPECT_NE(InputErrorMessage([&] { BatteryPolicyFromJson(bad, "p.json"); }).find("policies[1].b2"), std::string::npos);
  bad = BatteryPolicyToJson(set);
  bad["version"] = 0;
  EXPECT_NE(InputErrorMessage([&] { BatteryPolicyFromJson(bad, "p.json"); }).find("version"), std::string::npos);
}

TEST(BatteryContexts, HealthAndTemperatureClasses) {
  EXPECT_EQ(ClassifyTemperature(50.0), TemperatureClass::kHigh);  // Table 4.2: T_L is T < 50 °F
  EXPECT_EQ(ClassifyTemperature(49.9), TemperatureClass::kLow);
  EXPECT_EQ(ParseBatteryHealth("F3", "t"), HealthClass::kP);
  EXPECT_NE(InputErrorMessage([] { ParseBatteryHealth("G", "x.json"); }).find("F1 | F2 | F3"), std::string::npos);
  std::set<int> indices;
  for (int c = 0; c < kBatteryNumContexts; ++c) indices.insert(BatteryContextIndex(BatteryContextFromIndex(c)));
  EXPECT_EQ(indices.size(), 18u);
  models::PerCell<models::CellHealth> health{};
  health[0][1] = models::CellHealthForClass(HealthClass::kM);
  EXPECT_EQ(BatteryContextOf(health, 40.0), (BatteryContext{HealthClass::kM, HealthClass::kG, TemperatureClass::kLow}));
}

// Ours against a small case solved by hand. Context (F1,F1,TH), weights (0.2, 0.3, 0.5), γ = 0.999:
//   A  = ILONS1C0ONS1C0: UseBoth counted 1 × FAILURE and 9 completions;
//   A1 = ILONS1C0OFFS1C0 (pack 1 alone): UseBatt1 counted 10 completions;
//   B  = ILONS1C0OFFS3C0 (pack 1 alone, the idle pack 2 in S3): UseBatt1 counted 5 × B and 5 completions;
//   every other row unobserved. By hand (V_F = −30 / (1 − γ), V_COMPLETE = 0):
//   V(A1) = 0 (stay: R = 0, then COMPLETE); from A: UseBoth Q = γ (0.1 V_F) = −2997, UseBatt1 Q = −w3 + γ V(A1)
//   = −0.5 (one switch toggled) → π(A) = UseBatt1; UseBatt2 unavailable (its row unobserved).
//   V(B) = R(B) / (1 − 0.5 γ), R(B) = w1 (0 + (−20)) / 2 = −2 (the idle pack's S3 is charged; eq. 4.1 would give 0).
//   A state never observed, C = IHONS2C1ONS2C1: only UseBoth, holding: V = R / (1 − γ), R = w1 (−5 − 5)/2 +
//   w2 (−10 − 10)/2 = −4.
TEST(BatteryOursTest, ValuesMatchTheHandSolvedCase) {
  const BatteryContext context{HealthClass::kG, HealthClass::kG, TemperatureClass::kHigh};
  const PackFeatures s1c0{true, EnergyState::kS1, VoltageState::kC0};
  const PackFeatures off_s1c0{false, EnergyState::kS1, VoltageState::kC0};
  const PackFeatures off_s3c0{false, EnergyState::kS3, VoltageState::kC0};
  const PackFeatures s2c1{true, EnergyState::kS2, VoltageState::kC1};
  const StateIndex a = BatteryStateIndex(Features(CurrentLevel::kLow, s1c0, s1c0));
  const StateIndex a1 = BatteryStateIndex(Features(CurrentLevel::kLow, s1c0, off_s1c0));
  const StateIndex b = BatteryStateIndex(Features(CurrentLevel::kLow, s1c0, off_s3c0));
  const StateIndex c = BatteryStateIndex(Features(CurrentLevel::kHigh, s2c1, s2c1));
  BatteryModel model;
  model.counts.Add(context, a, PackAction::kUseBoth, kBatteryFailureState, 1);
  model.counts.AddCompletion(context, a, PackAction::kUseBoth, 9);
  model.counts.AddCompletion(context, a1, PackAction::kUseBatt1, 10);
  model.counts.Add(context, b, PackAction::kUseBatt1, b, 5);
  model.counts.AddCompletion(context, b, PackAction::kUseBatt1, 5);
  const double gamma = 0.999;
  const BatteryPolicySet set = SolveOursBatteryPolicies(model, gamma);
  EXPECT_EQ(set.formulation, BatteryFormulation::kOurs);
  const BatteryContextPolicy& p = set.Select(context);
  const double w1 = 0.2, w3 = 0.5;
  const double v_failure = -30.0 / (1.0 - gamma);
  constexpr double kExactTolerance = 1e-6;  // dense LU on 394 states, values up to 3e4
  EXPECT_NEAR(p.value[kBatteryFailureState], v_failure, kExactTolerance);
  EXPECT_NEAR(p.value[a1], 0.0, kExactTolerance);
  EXPECT_EQ(p.action[a1], static_cast<int>(PackAction::kUseBatt1));
  EXPECT_NEAR(p.value[a], -w3, kExactTolerance);
  EXPECT_EQ(p.action[a], static_cast<int>(PackAction::kUseBatt1));
  // The alternative it beat, by hand: UseBoth's 10 % failure.
  EXPECT_LT(gamma * 0.1 * v_failure, -w3);
  EXPECT_NEAR(p.value[b], (w1 * -20.0 / 2.0) / (1.0 - 0.5 * gamma), kExactTolerance);
  EXPECT_NEAR(p.value[c], (w1 * -10.0 / 2.0 + 0.3 * -20.0 / 2.0) / (1.0 - gamma), kExactTolerance);
  EXPECT_EQ(p.action[c], static_cast<int>(PackAction::kUseBoth));
  // Rewards: the idle pack charged, and eq. 4.7 as a switching cost.
  EXPECT_NEAR(OursBatteryReward(b, PackAction::kUseBatt1, context, model.weights), -2.0, kRewardTolerance);
  EXPECT_NEAR(BatteryReward(b, PackAction::kUseBatt1, context, model.weights), 0.0, kRewardTolerance);  // eq. 4.1
  EXPECT_EQ(SwitchToggles(a, PackAction::kUseBoth), 0);
  EXPECT_EQ(SwitchToggles(a, PackAction::kUseBatt2), 1);
  EXPECT_EQ(SwitchToggles(a1, PackAction::kUseBatt2), 2);
  // Unobserved choices are not offered: A's UseBatt2 row, and every row of C but the fixed rule's.
  BatteryModelStats stats;
  const FiniteMdp mdp = BuildOursBatteryMdp(model.counts, context, model.weights, &stats);
  EXPECT_EQ(mdp.FindChoice(a, static_cast<int>(PackAction::kUseBatt2)), -1);
  EXPECT_EQ(mdp.FindChoice(c, static_cast<int>(PackAction::kUseBatt1)), -1);
  EXPECT_GE(mdp.FindChoice(c, static_cast<int>(PackAction::kUseBoth)), 0);
  // The 216 of Table 4.1's states and the 78 of ours' flagged states that can occur (item 10): 72 with one pack
  // flagged, 6 with both.
  EXPECT_EQ(stats.learned_rows, 216 + 78);
  EXPECT_EQ(stats.unobserved_rows, 216 + 78 - 3);
}

TEST(BatteryOursTest, CompletionsRoundTripThroughTheModelFileAndOnlyOursSeesThem) {
  BatteryModel model;
  const BatteryContext context{HealthClass::kM, HealthClass::kG, TemperatureClass::kLow};
  const StateIndex s = ParseBatteryState("IHONS1C0ONS1C0", "test");
  const std::array<StateIndex, 2> flight = {s, s};
  model.counts.AddFlight(context, PackAction::kUseBoth, flight, /*completed=*/true);
  EXPECT_EQ(model.counts.Completions(context, s, PackAction::kUseBoth), 1);
  const BatteryModel back = BatteryModelFromJson(BatteryModelToJson(model), "test");
  EXPECT_EQ(back.counts.Completions(context, s, PackAction::kUseBoth), 1);
  EXPECT_EQ(BatteryModelHash(back), BatteryModelHash(model));
  // The dissertation's row is the counted self-transition only.
  const FiniteMdp mdp = BuildBatteryMdp(model.counts, context, model.weights);
  const auto choice = mdp.FindChoice(s, static_cast<int>(PackAction::kUseBoth));
  ASSERT_EQ(mdp.choice_next_states(choice).size(), 1u);
  EXPECT_EQ(mdp.choice_next_states(choice)[0], s);
  // A policy file keeps its formulation; a dissertation file keeps its hash without the field.
  const BatteryPolicySet ours = SolveOursBatteryPolicies(model, 0.99);
  EXPECT_EQ(BatteryPolicyFromJson(BatteryPolicyToJson(ours), "test").formulation, BatteryFormulation::kOurs);
  nlohmann::json dissertation = BatteryPolicyToJson(SolveBatteryPolicies(model));
  dissertation.erase("formulation");
  EXPECT_EQ(BatteryPolicyFromJson(dissertation, "test").formulation, BatteryFormulation::kDissertation);
  nlohmann::json relabelled = BatteryPolicyToJson(ours);
  relabelled["formulation"] = "dissertation";  // the hash covers it
  EXPECT_THROW(BatteryPolicyFromJson(relabelled, "test"), InputError);
}

}  // namespace
}  // namespace uascma::decision
