// The battery MDP's learning flights (§4.3.2, Fig. 4.3): one parameter draw flown with its three pack actions
// together (campaign::FlyBatteryFlights, sim::StepFollowing) equals each action flown alone, bit for bit — also
// after a pack has capped a rotor differently and its flight went on alone.
#include "uascma/campaign/battery_flights.h"

#include <gtest/gtest.h>

#include <array>

namespace uascma::campaign {
namespace {

using models::PackAction;

BatterySwitchController Hold(PackAction action) {
  return [action](double, const decision::BatteryObservation&, decision::StateIndex) { return action; };
}

void ExpectSameFlight(const BatteryFlightResult& together, const BatteryFlightResult& alone, const std::string& what) {
  EXPECT_EQ(together.outcome, alone.outcome) << what;
  EXPECT_EQ(together.end_time_s, alone.end_time_s) << what;  // exact: the same GNC steps
  EXPECT_EQ(together.states, alone.states) << what;
  ASSERT_EQ(together.epochs.size(), alone.epochs.size()) << what;
  for (std::size_t e = 0; e < alone.epochs.size(); ++e) {
    EXPECT_EQ(together.epochs[e].total_current_a, alone.epochs[e].total_current_a) << what << " epoch " << e;
    EXPECT_EQ(together.epochs[e].eod_s, alone.epochs[e].eod_s) << what << " epoch " << e;
    EXPECT_EQ(together.epochs[e].min_cell_voltage_v, alone.epochs[e].min_cell_voltage_v) << what << " epoch " << e;
  }
}

TEST(BatteryFlightsTest, ActionsFlownTogetherEqualEachFlownAlone) {
  const BatteryFlightRanges ranges;
  const std::array<PackAction, 3> actions = {PackAction::kUseBatt1, PackAction::kUseBatt2, PackAction::kUseBoth};
  int diverged = 0;
  // Draws 0–2 of seed 1, and draw 80, in which UseBatt2's sagging pack caps a rotor that UseBatt1's does not, so
  // that flight leaves the group and goes on alone (found by search; another draw serves if the model changes).
  for (const std::int64_t d : {0, 1, 2, 80}) {
    const BatteryFlightParams params = SampleBatteryFlight(ranges, 1, d);
    std::vector<BatteryFlightController> flights;
    for (PackAction a : actions) flights.push_back({a, Hold(a)});
    BatteryFlightSharing sharing;
    const std::vector<BatteryFlightResult> together = FlyBatteryFlights(params, flights, {}, &sharing);
    ASSERT_EQ(together.size(), actions.size());
    EXPECT_GT(sharing.shared_steps, 0);
    diverged += sharing.alone_steps > 0 ? 1 : 0;
    for (std::size_t k = 0; k < actions.size(); ++k) {
      ExpectSameFlight(together[k], FlyBatteryFlight(params, actions[k], Hold(actions[k])),
                       "draw " + std::to_string(d) + " " + models::PackActionName(actions[k]));
    }
  }
  EXPECT_GE(diverged, 1) << "no draw exercised a flight leaving its group";
}

TEST(BatteryFlightsTest, APolicyThatSwitchesInFlightFliesTheSameTogether) {
  // A controller that changes the switches in flight (as π* does) and one holding UseBoth, flown together.
  const BatteryFlightParams params = SampleBatteryFlight(BatteryFlightRanges{}, 5, 2);
  const BatterySwitchController alternate = [](double t, const decision::BatteryObservation&, decision::StateIndex) {
    return static_cast<int>(t) % 60 < 30 ? PackAction::kUseBatt1 : PackAction::kUseBatt2;
  };
  const std::vector<BatteryFlightController> flights = {{PackAction::kUseBoth, alternate},
                                                        {PackAction::kUseBoth, Hold(PackAction::kUseBoth)}};
  const std::vector<BatteryFlightResult> together = FlyBatteryFlights(params, flights);
  ExpectSameFlight(together[0], FlyBatteryFlight(params, PackAction::kUseBoth, alternate), "alternating");
  ExpectSameFlight(together[1], FlyBatteryFlight(params, PackAction::kUseBoth, Hold(PackAction::kUseBoth)), "UseBoth");
  EXPECT_GT(together[0].switches.size(), 2u);
}

}  // namespace
}  // namespace uascma::campaign
