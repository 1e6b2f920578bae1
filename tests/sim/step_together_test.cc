// StepTogether and StepTogetherToNextEpoch (sim/flight.h): flights stepped in lanes are, bit for
// bit, the flights stepped alone with Step: the whole state at every decision epoch and at the end, the events and the
// telemetry's thrusts and positions. Groups of four and of three flights of one model (different seeds: different
// winds, sensor noise and ends), with turbulence, with a spall that jams a motor (the IMM's isolation moves a flight's
// control out of the lanes while the others stay), and without the feed-forward (no flight's control in lanes).
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "same_flight.h"
#include "test_scenarios.h"
#include "uascma/sim/act.h"
#include "uascma/sim/epoch.h"
#include "uascma/sim/flight.h"
#include "uascma/sim/initial_state.h"
#include "uascma/sim/lockstep.h"
#include "uascma/sim/policy.h"
#include "uascma/sim/scenario.h"

namespace uascma::sim {
namespace {

using testing_scenarios::ScenarioOne;
using testing_scenarios::ShortJam;

// How Fly steps its flights: each alone with Step, together with StepTogether one step at a time, or together to
// their next epochs with StepTogetherToNextEpoch (which keeps its lanes' working memory from step to step).
enum class Stepping { kAlone, kTogether, kTogetherToEpochs };

// The NoOp policy's epoch, then the steps, for each flight, stepped as `stepping` says. Returns the flights at their
// ends; `at_epochs` holds each flight's state at every epoch.
struct Flown {
  std::vector<FlightState> states;
  std::vector<FlightLog> logs;
  std::vector<std::vector<FlightState>> at_epochs;
};

Flown Fly(const std::vector<const FlightModel*>& models, const std::vector<std::uint64_t>& seeds, Stepping stepping) {
  Flown flown;
  const std::size_t n = seeds.size();
  for (std::size_t k = 0; k < n; ++k) flown.states.push_back(MakeInitialState(*models[k], seeds[k]));
  flown.logs.resize(n);
  flown.at_epochs.resize(n);
  for (FlightLog& log : flown.logs) log.record_telemetry = true;
  NoOpPolicy noop;
  std::vector<FlightState*> states;
  std::vector<FlightLog*> logs;
  for (std::size_t k = 0; k < n; ++k) {
    states.push_back(&flown.states[k]);
    logs.push_back(&flown.logs[k]);
  }
  auto all_done = [&] {
    for (const FlightState& state : flown.states) {
      if (!state.done()) return false;
    }
    return true;
  };
  while (!all_done()) {
    for (std::size_t k = 0; k < n; ++k) {
      const FlightModel& model = *models[k];
      FlightState& state = flown.states[k];
      if (state.done() || !IsDecisionEpoch(model, state)) continue;
      flown.at_epochs[k].push_back(state);
      Act(model, state, noop.Decide(Observe(model, state, &flown.logs[k])), {}, &flown.logs[k]);
    }
    switch (stepping) {
      case Stepping::kAlone:
        for (std::size_t k = 0; k < n; ++k) Step(*models[k], flown.states[k], &flown.logs[k]);
        break;
      case Stepping::kTogether:
        StepTogether(models, states, logs);
        break;
      case Stepping::kTogetherToEpochs:
        StepTogetherToNextEpoch(models, states, logs);
        break;
    }
  }
  return flown;
}

// Flights of `scenarios` (one model each; they must share a vehicle) with `seeds`, together and alone.
void ExpectTogetherAsAlone(const std::vector<Scenario>& scenarios, const std::vector<std::uint64_t>& seeds) {
  std::vector<std::unique_ptr<FlightModel>> owned;
  std::vector<const FlightModel*> models;
  for (const Scenario& scenario : scenarios) {
    owned.push_back(std::make_unique<FlightModel>(scenario));
    models.push_back(owned.back().get());
  }
  const Flown alone = Fly(models, seeds, Stepping::kAlone);
  for (const Stepping stepping : {Stepping::kTogether, Stepping::kTogetherToEpochs}) {
    SCOPED_TRACE(stepping == Stepping::kTogether ? "StepTogether" : "StepTogetherToNextEpoch");
    const Flown together = Fly(models, seeds, stepping);
    for (std::size_t k = 0; k < seeds.size(); ++k) {
      SCOPED_TRACE("seed " + std::to_string(seeds[k]));
      ASSERT_EQ(alone.at_epochs[k].size(), together.at_epochs[k].size());
      for (std::size_t e = 0; e < alone.at_epochs[k].size(); ++e) {
        ASSERT_TRUE(alone.at_epochs[k][e] == together.at_epochs[k][e]) << "first difference at epoch " << e;
      }
      ExpectSameFlight(alone.states[k], together.states[k]);
      const FlightLog& a = alone.logs[k];
      const FlightLog& b = together.logs[k];
      ASSERT_EQ(a.events.size(), b.events.size());
      for (std::size_t i = 0; i < a.events.size(); ++i) {
        EXPECT_EQ(a.events[i].time_s, b.events[i].time_s);
        EXPECT_EQ(a.events[i].what, b.events[i].what);
      }
      ASSERT_EQ(a.telemetry.size(), b.telemetry.size());
      for (std::size_t i = 0; i < a.telemetry.size(); ++i) {
        ASSERT_TRUE(a.telemetry[i].p_W == b.telemetry[i].p_W) << "telemetry row " << i;
        ASSERT_TRUE(a.telemetry[i].rotor_thrust == b.telemetry[i].rotor_thrust) << "telemetry row " << i;
        ASSERT_EQ(a.telemetry[i].bus_voltage, b.telemetry[i].bus_voltage) << "telemetry row " << i;
      }
    }
  }
}

TEST(StepTogetherTest, FourTurbulentFlightsOfOneModelAsEachAlone) {
  const Scenario one = ScenarioOne();
  ExpectTogetherAsAlone({one, one, one, one}, {1, 2, 3, 4});
}

TEST(StepTogetherTest, FourFlightsOfDifferentModelsSharingAVehicleAsEachAlone) {
  // Different missions, winds and packs (each flight's own model), one vehicle: the lockstep of a campaign.
  std::vector<Scenario> scenarios;
  for (int k = 0; k < 4; ++k) {
    Scenario scenario = ShortJam();
    scenario.fault.enabled = false;
    scenario.mission.destination_NE = Eigen::Vector2d(150.0 + 60.0 * k, -40.0 * k);
    scenario.wind.mean_speed = 0.5 + k;
    scenario.wind.direction_rad = 0.8 * k;
    for (auto& branch : scenario.battery.initial_cell_voltage_v) {
      for (double& v : branch) v = 4.05 + 0.02 * k;
    }
    scenarios.push_back(scenario);
  }
  const FlightModel first(scenarios[0]);
  for (const Scenario& scenario : scenarios) EXPECT_TRUE(SharesVehicle(first, FlightModel(scenario)));
  ExpectTogetherAsAlone(scenarios, {21, 22, 23, 24});
}

TEST(StepTogetherTest, ThreeFlightsWithAJammedMotorAsEachAlone) {
  // The spall jams motor 2 and the IMM isolates it in every flight, at times that differ with the seed.
  const Scenario scenario = ShortJam();
  ExpectTogetherAsAlone({scenario, scenario, scenario}, {5, 6, 7});
  // The jam and its isolation happened (the control left the lanes for the quadcopter allocation).
  const FlightModel model(scenario);
  const Flown flown = Fly({&model}, {5}, Stepping::kTogether);
  EXPECT_NE(flown.states[0].faults.jammed_rotor, 0);
  EXPECT_NE(flown.states[0].faults.allocation_failure, 0);
}

TEST(StepTogetherTest, FlightsWithoutTheFeedForwardAsEachAlone) {
  Scenario scenario = ShortJam();
  scenario.fault.enabled = false;
  scenario.options.drag_feedforward = false;
  ExpectTogetherAsAlone({scenario, scenario, scenario, scenario}, {8, 9, 10, 11});
}

TEST(StepTogetherTest, AnotherVehicleIsNotShared) {
  Scenario pusher = ShortJam();
  pusher.configuration = models::PropellerConfiguration::kPusher;
  Scenario heavier = ShortJam();
  heavier.body.mass += 0.1;
  // The LQR's options, each part the lanes read (a limit of the errors or the tilt) or that changes the gain (a
  // weight).
  Scenario tighter_tilt = ShortJam();
  tighter_tilt.lqr.max_tilt = 0.5;
  Scenario stiffer = ShortJam();
  stiffer.lqr.weights.position = 0.8;
  Scenario without_feedforward = ShortJam();
  without_feedforward.options.drag_feedforward = false;
  const FlightModel tractor_model(ShortJam());
  EXPECT_TRUE(SharesVehicle(tractor_model, FlightModel(ShortJam())));
  for (const Scenario& other : {pusher, heavier, tighter_tilt, stiffer, without_feedforward}) {
    EXPECT_FALSE(SharesVehicle(tractor_model, FlightModel(other))) << other.name;
    EXPECT_FALSE(SharesVehicle(FlightModel(other), tractor_model)) << other.name;
  }
}

}  // namespace
}  // namespace uascma::sim
