// What `uascma battery` reports of a policy (decision/battery_mdp_report.h): the states that can occur and a policy's
// choices, counted in closed form for policies that take one action everywhere.
#include "uascma/decision/battery_mdp_report.h"

#include <cstddef>

#include <gtest/gtest.h>

namespace uascma::decision {
namespace {

using models::PackAction;

BatteryContextPolicy Everywhere(PackAction action) {
  BatteryContextPolicy policy;
  policy.action.assign(kBatteryNumStates, static_cast<ActionIndex>(action));
  return policy;
}

TEST(BatteryMdpReportTest, SeventyTwoStatesOfEachSwitchPairAndNoneWithBothOff) {
  int possible = 0, both_in = 0;
  for (StateIndex s = 0; s < kBatteryFailureState; ++s) {
    possible += IsPossibleBatteryState(s) ? 1 : 0;
    both_in += BothPacksIn(s) ? 1 : 0;
    EXPECT_TRUE(!BothPacksIn(s) || IsPossibleBatteryState(s));
  }
  EXPECT_EQ(possible, 216);  // 3 × 72: one pack in (either) or both
  EXPECT_EQ(both_in, 72);
  EXPECT_TRUE(IsPossibleBatteryState(kBatteryFailureState));
  EXPECT_FALSE(BothPacksIn(kBatteryFailureState));
}

TEST(BatteryMdpReportTest, UseBothEverywhereSwitchesInEveryOnePackState) {
  const BatteryPolicyChoices choices = CountBatteryPolicyChoices(Everywhere(PackAction::kUseBoth));
  EXPECT_EQ(choices.both_in[static_cast<std::size_t>(PackAction::kUseBoth)], 72);
  EXPECT_EQ(choices.both_in[static_cast<std::size_t>(PackAction::kUseBatt1)], 0);
  EXPECT_EQ(choices.both_in[static_cast<std::size_t>(PackAction::kUseBatt2)], 0);
  EXPECT_EQ(choices.one_in_switches, 144);  // every one-pack state is switched to both
  EXPECT_EQ(choices.flagged_both_in, 0);    // the dissertation's 289 states hold no flagged state
}

TEST(BatteryMdpReportTest, UseBatt1EverywhereSwitchesOnlyWherePackTwoIsIn) {
  const BatteryPolicyChoices choices = CountBatteryPolicyChoices(Everywhere(PackAction::kUseBatt1));
  EXPECT_EQ(choices.both_in[static_cast<std::size_t>(PackAction::kUseBatt1)], 72);
  EXPECT_EQ(choices.one_in_switches, 72);  // the 72 with pack 2 alone; pack 1 alone already matches
}

}  // namespace
}  // namespace uascma::decision
