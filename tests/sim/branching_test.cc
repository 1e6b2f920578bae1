// sim/branching.h: flights that share a vehicle equal the same flights flown alone, every part of the state bit for
// bit; a follower is the leader's vehicle part with its own power system; the parts' == sees a change in any part; a
// branch point is an epoch.
#include "uascma/sim/branching.h"

#include <gtest/gtest.h>

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "same_flight.h"
#include "uascma/campaign/battery_flights.h"
#include "uascma/common/error.h"
#include "uascma/sim/act.h"
#include "uascma/sim/flight.h"
#include "uascma/sim/initial_state.h"

namespace uascma::sim {
namespace {

using models::PackAction;

// A battery executor that holds one pack action (Ch. IV's learning flights, §4.3.2).
class Hold final : public BatterySwitchPolicy {
 public:
  explicit Hold(PackAction action) : action_(action) {}
  PackAction Decide(const FlightModel&, const FlightState&) override { return action_; }

 private:
  PackAction action_;
};

// Fig. 4.3's loop for one flight alone: the battery executor at each epoch, then the GNC steps to the next.
FlightState FlyAlone(const FlightModel& model, FlightState state, BatterySwitchPolicy& executor) {
  while (!state.done()) {
    DecideBattery(model, state, executor);
    StepToNextEpoch(model, state);
  }
  return state;
}

constexpr std::array<PackAction, 3> kActions = {PackAction::kUseBatt1, PackAction::kUseBatt2, PackAction::kUseBoth};

// Draws 0 and 1 of seed 1, and draw 80, in which UseBatt2's sagging pack caps a rotor that UseBatt1's does not, so
// that flight leaves the group and goes on alone (tests/campaign/battery_flights_test.cc).
TEST(BranchingTest, FlightsFlownFollowingEqualEachFlownAloneInEveryPart) {
  int diverged = 0;
  for (const std::int64_t draw : {0, 1, 80}) {
    SCOPED_TRACE("draw " + std::to_string(draw));
    const campaign::BatteryFlightParams params = campaign::SampleBatteryFlight({}, 1, draw);
    const FlightModel model(campaign::MakeBatteryScenario(params));
    std::vector<FlightState> states;
    std::vector<Hold> holds;
    for (PackAction action : kActions) {
      states.push_back(MakeInitialState(model, params.seed));
      SwitchPacks(states.back(), action);
      holds.emplace_back(action);
    }
    std::vector<BatterySwitchPolicy*> executors;
    for (Hold& hold : holds) executors.push_back(&hold);
    const std::vector<FlightState> initial = states;
    const SharingCounts counts = FlyFollowing(model, states, executors);
    EXPECT_GT(counts.shared_steps, 0);
    diverged += counts.alone_steps > 0 ? 1 : 0;
    for (std::size_t k = 0; k < kActions.size(); ++k) {
      SCOPED_TRACE(models::PackActionName(kActions[k]));
      ASSERT_TRUE(states[k].done());
      ExpectSameFlight(states[k], FlyAlone(model, initial[k], holds[k]));
    }
  }
  EXPECT_GE(diverged, 1) << "no draw exercised a flight leaving its group";
}

// One step of a shared vehicle: the follower ends with the leader's vehicle part and the power system it has when it
// takes the same step alone; its own power system differs from the leader's (another pack flies).
TEST(BranchingTest, AFollowerHasTheLeadsVehicleAndItsOwnPowerSystem) {
  const campaign::BatteryFlightParams params = campaign::SampleBatteryFlight({}, 1, 0);
  const FlightModel model(campaign::MakeBatteryScenario(params));
  FlightState lead = MakeInitialState(model, params.seed);
  for (int epoch = 0; epoch < 30; ++epoch) StepToNextEpoch(model, lead);  // 30 s into the flight, both packs on
  ASSERT_FALSE(lead.done());
  FlightState follower = lead;
  SwitchPacks(follower, PackAction::kUseBatt1);
  FlightState alone = follower;
  std::array<FlightState*, 1> followers = {&follower};
  std::array<bool, 1> stepped = {false};
  StepFollowing(model, lead, followers, stepped);
  Step(model, alone);
  ASSERT_TRUE(stepped[0]);
  EXPECT_TRUE(follower.vehicle == lead.vehicle);
  EXPECT_FALSE(follower.power == lead.power);
  ExpectSameFlight(follower, alone);
}

// Each part's == compares every member: a change in any one part makes the states unequal, and a load profile
// built twice from the same plan compares equal (by value, not by pointer).
TEST(BranchingTest, ThePartsCompareWholeAndTheLoadProfileByValue) {
  const campaign::BatteryFlightParams params = campaign::SampleBatteryFlight({}, 1, 0);
  const FlightModel model(campaign::MakeBatteryScenario(params));
  const FlightState state = MakeInitialState(model, params.seed);
  EXPECT_TRUE(state == FlightState(state));
  FlightState changed = state;
  changed.vehicle.wind_random.Next();
  EXPECT_FALSE(changed.vehicle == state.vehicle);
  changed = state;
  changed.vehicle.body.q_WB.coeffs()[1] = 1e-300;
  EXPECT_FALSE(changed == state);
  changed = state;
  changed.power.pack.cells[1][2].hysteresis = 0.5;
  EXPECT_FALSE(changed.power == state.power);
  changed = state;
  changed.faults.jammed_rotor = 3;
  EXPECT_FALSE(changed.faults == state.faults);
  changed = state;
  changed.decision.battery_action = PackAction::kUseBatt2;
  EXPECT_FALSE(changed.decision == state.decision);
  changed = state;
  changed.guidance.footprint_NE.emplace_back(1.0, 2.0);
  EXPECT_FALSE(changed.guidance == state.guidance);

  FlightState a = state, b = state;
  a.decision.load_forecast.profile =
      std::make_shared<const LoadProfile>(model.nominal_plan(), model.steady_load(), models::kRotorCount);
  b.decision.load_forecast.profile =
      std::make_shared<const LoadProfile>(model.nominal_plan(), model.steady_load(), models::kRotorCount);
  EXPECT_TRUE(a.decision == b.decision);
  b.decision.load_forecast.profile =
      std::make_shared<const LoadProfile>(model.nominal_plan(), model.steady_load(), models::kRotorCount - 2);
  EXPECT_FALSE(a.decision == b.decision);
}

TEST(BranchingTest, ABranchPointIsAnEpochOrTheEnd) {
  const campaign::BatteryFlightParams params = campaign::SampleBatteryFlight({}, 1, 0);
  const FlightModel model(campaign::MakeBatteryScenario(params));
  FlightState state = MakeInitialState(model, params.seed);
  EXPECT_TRUE(IsBranchPoint(model, state));
  Step(model, state);
  EXPECT_FALSE(IsBranchPoint(model, state));
  EXPECT_THROW(RequireBranchPoint(model, state, "test"), InputError);
  StepToNextEpoch(model, state);
  EXPECT_EQ(&RequireBranchPoint(model, state, "test"), &state);
}

}  // namespace
}  // namespace uascma::sim
