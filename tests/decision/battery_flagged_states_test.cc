// Ours' flagged states (decision/battery_mdp.h ours item 10): the pack-fault indicator's flag in the battery MDP's
// state, its labels, the abstraction, the offers, the counts in the model file, and a solved table that isolates a
// flagged pack because its learned rows say so.
#include <gtest/gtest.h>

#include <set>

#include "uascma/decision/battery_mdp_file.h"

namespace uascma::decision {
namespace {

using models::HealthClass;
using models::PackAction;

constexpr double kExactTolerance = 1e-6;  // dense LU on 394 states, values up to 3e4

TEST(BatteryFlaggedStates, OursHas394StatesWhoseFirst289AreTheDissertations) {
  const auto& ours = BatteryFormulationStateLabels(BatteryFormulation::kOurs);
  const auto& dissertation = BatteryFormulationStateLabels(BatteryFormulation::kDissertation);
  ASSERT_EQ(static_cast<int>(ours.size()), kOursNumStates);
  ASSERT_EQ(static_cast<int>(dissertation.size()), kBatteryNumStates);
  EXPECT_TRUE(std::equal(dissertation.begin(), dissertation.end(), ours.begin()));
  EXPECT_EQ(ours[kBatteryCompleteState], "COMPLETE");
  EXPECT_EQ(std::set<std::string>(ours.begin(), ours.end()).size(), ours.size());
  // 2 (flagged pack) × 2 (I) × 2 (its switch) × 12 (the other pack) + 2 (I) × 2 × 2 (both flagged).
  EXPECT_EQ(kOursNumStates - kBatteryFirstFlaggedState, 2 * 2 * 2 * 12 + 2 * 2 * 2);
  for (StateIndex s = kBatteryFirstFlaggedState; s < kOursNumStates; ++s) {
    ASSERT_TRUE(IsFlaggedBatteryState(s));
    const BatteryFeatures f = BatteryStateFeatures(s);
    EXPECT_TRUE(f.pack[0].flagged || f.pack[1].flagged) << ours[s];
    EXPECT_EQ(BatteryStateIndex(f), s) << ours[s];
    EXPECT_EQ(ParseBatteryState(ours[s], "test"), s);
  }
  EXPECT_FALSE(IsFlaggedBatteryState(kBatteryFailureState));
  EXPECT_FALSE(IsFlaggedBatteryState(kBatteryCompleteState));
  // The label names the flagged pack's switch and FLT in place of its energy and voltage.
  const BatteryFeatures f = BatteryStateFeatures(ParseBatteryState("IHONFLTONS1C0", "test"));
  EXPECT_EQ(f.current, CurrentLevel::kHigh);
  EXPECT_TRUE(f.pack[0].flagged && f.pack[0].switch_on);
  EXPECT_FALSE(f.pack[1].flagged);
  EXPECT_EQ(f.pack[1].energy, EnergyState::kS1);
  EXPECT_EQ(f.pack[1].voltage, VoltageState::kC0);
  EXPECT_EQ(BatteryStateLabel(ApplySwitches(ParseBatteryState("IHONFLTONS1C0", "t"), PackAction::kUseBatt2)),
            "IHOFFFLTONS1C0");
  EXPECT_EQ(BatteryStateLabel(ApplySwitches(ParseBatteryState("ILONFLTONFLT", "t"), PackAction::kUseBatt1)),
            "ILONFLTOFFFLT");
}

TEST(BatteryFlaggedStates, OnlyOursReadsTheFlagAndNotTheFlaggedPacksEnergyOrVoltage) {
  BatteryObservation o;
  o.total_current_a = 30.0;  // I_H: above 0.2 × 105 A
  o.remaining_flight_s = 300.0;
  o.safety_margin_s = 5.0;
  o.eod_s = {600.0, 400.0};            // pack 1 S1, pack 2 S1
  o.min_cell_voltage_v = {3.9, 3.35};  // pack 2 C1
  o.actual_min_cell_voltage_v = {3.9, 3.8};
  o.pack_fault = {true, false};
  EXPECT_EQ(BatteryStateLabel(AbstractBatteryState(o)), "IHONS1C0ONS1C1");
  EXPECT_EQ(BatteryStateLabel(AbstractBatteryState(o, {}, BatteryFormulation::kOurs)), "IHONFLTONS1C1");
  o.eod_s[0] = 10.0;  // the flagged pack's energy and voltage changed: the same state
  o.min_cell_voltage_v[0] = 3.35;
  EXPECT_EQ(BatteryStateLabel(AbstractBatteryState(o, {}, BatteryFormulation::kOurs)), "IHONFLTONS1C1");
  o.actual_min_cell_voltage_v[0] = 3.3;  // a switched-in cell at the cut-off: FAILURE in both
  EXPECT_EQ(AbstractBatteryState(o, {}, BatteryFormulation::kOurs), kBatteryFailureState);
  o.actual_min_cell_voltage_v[0] = 3.9;
  o.pack_fault = {false, false};  // no flag: the two abstractions agree
  EXPECT_EQ(AbstractBatteryState(o, {}, BatteryFormulation::kOurs), AbstractBatteryState(o));
}

TEST(BatteryFlaggedStates, OursOffersTheUnflaggedPackAloneWhateverItsEnergyAndVoltage) {
  const StateIndex both_in = ParseBatteryState("ILONFLTONS3C1", "t");
  const BatteryFeatures f = BatteryStateFeatures(both_in);
  EXPECT_TRUE(OursOffers(f, PackAction::kUseBatt2));   // onto the unflagged pack, though S3 and C1
  EXPECT_TRUE(OursOffers(f, PackAction::kUseBoth));    // the hold
  EXPECT_FALSE(OursOffers(f, PackAction::kUseBatt1));  // never onto the flagged pack alone
  // The unflagged pack in S3 and C1 without a flag: item 7 offers no drop onto it.
  EXPECT_FALSE(OursOffers(BatteryStateFeatures(ParseBatteryState("ILONS1C0ONS3C1", "t")), PackAction::kUseBatt2));
  // The flagged pack set aside stays aside.
  const BatteryFeatures aside = BatteryStateFeatures(ParseBatteryState("ILOFFFLTONS2C0", "t"));
  EXPECT_TRUE(OursOffers(aside, PackAction::kUseBatt2));
  EXPECT_FALSE(OursOffers(aside, PackAction::kUseBoth));
  EXPECT_FALSE(OursOffers(aside, PackAction::kUseBatt1));
  const BatteryFeatures aside2 = BatteryStateFeatures(ParseBatteryState("ILONS2C0OFFFLT", "t"));
  EXPECT_TRUE(OursOffers(aside2, PackAction::kUseBatt1));   // the hold
  EXPECT_FALSE(OursOffers(aside2, PackAction::kUseBatt2));  // never onto the flagged pack
  EXPECT_FALSE(OursOffers(aside2, PackAction::kUseBoth));
  // Left on the flagged pack alone, the state says the pack left in is the faulted one: the other may come back.
  const BatteryFeatures flagged_alone = BatteryStateFeatures(ParseBatteryState("ILONFLTOFFS2C0", "t"));
  EXPECT_TRUE(OursOffers(flagged_alone, PackAction::kUseBatt1));  // the hold
  EXPECT_TRUE(OursOffers(flagged_alone, PackAction::kUseBatt2));  // the unflagged pack back in, alone
  EXPECT_FALSE(OursOffers(flagged_alone, PackAction::kUseBoth));
}

// A context's counts in ours' abstraction: from the flagged state with both in, UseBoth (flown on) fails in 6 of 10
// epochs, the flagged pack set aside completes in 9 of 10 and fails in 1.
BatteryModel FlaggedModel(const BatteryContext& context, StateIndex both_in, StateIndex aside) {
  BatteryModel model;
  model.ours_counts.emplace();
  BatteryTransitionCounts& counts = *model.ours_counts;
  counts.Add(context, both_in, PackAction::kUseBoth, kBatteryFailureState, 6);
  counts.Add(context, both_in, PackAction::kUseBoth, both_in, 4);
  counts.AddCompletion(context, aside, PackAction::kUseBatt2, 9);
  counts.Add(context, aside, PackAction::kUseBatt2, kBatteryFailureState, 1);
  return model;
}

TEST(BatteryFlaggedStates, TheSolvedTableIsolatesAFlaggedPackWhenItsRowsSaySo) {
  const BatteryContext context{HealthClass::kM, HealthClass::kG, TemperatureClass::kHigh};
  const StateIndex both_in = ParseBatteryState("IHONFLTONS3C0", "t");
  const StateIndex aside = ParseBatteryState("IHOFFFLTONS3C0", "t");
  const BatteryModel model = FlaggedModel(context, both_in, aside);
  const double gamma = 0.999;
  const BatteryPolicySet set = SolveOursBatteryPolicies(model, gamma);
  const BatteryContextPolicy& p = set.Select(context);
  ASSERT_EQ(static_cast<int>(p.action.size()), kOursNumStates);
  EXPECT_EQ(p.action[both_in], static_cast<int>(PackAction::kUseBatt2));
  // By hand: a flagged pack is charged as S3 (−25: F2 against F1) and C1 (−10), pack 2 in S3 (−20), w = (0.2, 0.3,
  // 0.5); COMPLETE 0, FAILURE −30 per epoch.
  const double state_reward = 0.2 * (-25.0 - 20.0) / 2.0 + 0.3 * (-10.0) / 2.0;
  const double v_failure = -30.0 / (1.0 - gamma);
  const double v_aside = state_reward + gamma * 0.1 * v_failure;
  EXPECT_NEAR(p.value[aside], v_aside, kExactTolerance);
  EXPECT_NEAR(p.value[both_in], state_reward - 0.5 + gamma * (0.1 * v_failure), kExactTolerance);
  // The dissertation's π* of the same model reads `counts`, where no flagged row exists: its policy keeps 289 states.
  EXPECT_EQ(SolveBatteryPolicies(model).Select(context).action.size(), static_cast<std::size_t>(kBatteryNumStates));
}

TEST(BatteryFlaggedStates, OursCountsRoundTripThroughTheModelFileAndChangeTheHashOnlyWhenKept) {
  const BatteryContext context{HealthClass::kM, HealthClass::kG, TemperatureClass::kHigh};
  BatteryModel model =
      FlaggedModel(context, ParseBatteryState("IHONFLTONS3C0", "t"), ParseBatteryState("IHOFFFLTONS3C0", "t"));
  const BatteryModel read = BatteryModelFromJson(BatteryModelToJson(model), "m.json");
  ASSERT_TRUE(read.ours_counts.has_value());
  EXPECT_EQ(BatteryModelHash(read), BatteryModelHash(model));
  EXPECT_EQ(read.ours_counts->Row(context, ParseBatteryState("IHONFLTONS3C0", "t"), PackAction::kUseBoth),
            model.ours_counts->Row(context, ParseBatteryState("IHONFLTONS3C0", "t"), PackAction::kUseBoth));
  const std::string with = BatteryModelHash(model);
  model.ours_counts.reset();
  EXPECT_NE(BatteryModelHash(model), with);
  EXPECT_FALSE(BatteryModelFromJson(BatteryModelToJson(model), "m.json").ours_counts.has_value());
  // A flagged state in the dissertation's counts is refused.
  nlohmann::json json = BatteryModelToJson(
      FlaggedModel(context, ParseBatteryState("IHONFLTONS3C0", "t"), ParseBatteryState("IHOFFFLTONS3C0", "t")));
  json["contexts"] = json["ours_contexts"];
  EXPECT_THROW(BatteryModelFromJson(json, "m.json"), InputError);
}

TEST(BatteryFlaggedStates, OursPolicyFilesKeepTheFlaggedStates) {
  const BatteryContext context{HealthClass::kM, HealthClass::kG, TemperatureClass::kHigh};
  const StateIndex both_in = ParseBatteryState("IHONFLTONS3C0", "t");
  const BatteryPolicySet set =
      SolveOursBatteryPolicies(FlaggedModel(context, both_in, ParseBatteryState("IHOFFFLTONS3C0", "t")), 0.999);
  const BatteryPolicySet read = BatteryPolicyFromJson(BatteryPolicyToJson(set), "p.json");
  EXPECT_EQ(read.Select(context).action, set.Select(context).action);
  const BatteryPolicyExecutor executor(read, context);
  EXPECT_EQ(executor.Decide(both_in), PackAction::kUseBatt2);
  BatteryObservation o;
  o.total_current_a = 30.0;
  o.remaining_flight_s = 300.0;
  o.safety_margin_s = 5.0;
  o.eod_s = {100.0, 100.0};  // S3, S3
  o.min_cell_voltage_v = {3.9, 3.9};
  o.actual_min_cell_voltage_v = {3.9, 3.9};
  o.pack_fault = {true, false};
  EXPECT_EQ(executor.Abstract(o), both_in);
  EXPECT_EQ(executor.Decide(o), PackAction::kUseBatt2);
}

}  // namespace
}  // namespace uascma::decision
