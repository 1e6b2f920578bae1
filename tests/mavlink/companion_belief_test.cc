// The companion's belief (mavlink/companion_belief.h) against the flight it reads: Scenario I flown in process under
// NoOp, each epoch's telemetry made by the sitl's own vehicle (SitlVehicle::Telemetry), read back frame by frame
// (TelemetryReader), the belief updated and sim::Observe run on it. Two computations of the same CMA inputs: the
// in-process one on the simulator's state, the companion's on what MAVLink carries of it.
#include <gtest/gtest.h>

#include <cmath>

#include "uascma/decision/cma_abstraction.h"
#include "uascma/mavlink/companion_belief.h"
#include "uascma/mavlink/sitl_vehicle.h"
#include "uascma/sim/epoch.h"
#include "uascma/sim/initial_state.h"
#include "uascma/sim/scenario.h"

namespace uascma::mavlink {
namespace {

// s: the companion's EOD against the in-process one once its pack estimate has settled (ours: measured at most
// 0.076 s on this flight, docs/modelling-choices.md#companion-belief).
constexpr double kEodTolerance = 0.1;
// s: the pack estimate starts from rest at the scenario's charge; its RC states settle within this (ours, measured).
constexpr double kSettleS = 50.0;
// s: the plan left; after an isolation both re-plan at the capped speed from the vehicle's position, which
// LOCAL_POSITION_NED carries as float32 (ours: micrometres at a kilometre give microseconds of plan).
constexpr double kPlanTolerance = 1e-3;
// The abstract states must agree except where the in-process reach margin is within this of 0 (RM0 ⇔ RM < 0): an
// EOD within kEodTolerance of 200 s or more moves RM by at most 0.1 / 200.
constexpr double kReachMarginBand = 0.0005;

Frame AsFrame(const Outgoing& message, Address sender) {
  Frame frame;
  frame.sender = sender;
  frame.message_id = message.info.id;
  frame.payload = message.payload;
  return frame;
}

TEST(CompanionBeliefTest, TheCompanionsCmaInputsAreTheInProcessOnesWithinTolerance) {
  sim::ScenarioFile file = sim::LoadScenarioFile(std::string(UASCMA_SOURCE_DIR) + "/examples/scenario-1.yaml", {});
  const sim::FlightModel model(file.scenario);
  const Address autopilot{1, static_cast<std::uint8_t>(kMavCompIdAutopilot1)};
  SitlVehicle vehicle(model, autopilot, planning::GeoPoint{}, 0);
  TelemetryReader reader(autopilot.system_id);
  VehicleBelief belief(model);
  sim::FlightState state = sim::MakeInitialState(model, file.scenario.seed);
  sim::FlightLog log;
  log.record_telemetry = true;
  sim::NoOpPolicy noop;
  const sim::Controllers controllers{&noop, nullptr, {}};
  int compared = 0, states_compared = 0;
  double max_error_s = 0.0;
  while (!state.done()) {
    std::vector<Outgoing> out;
    vehicle.Telemetry(state, log, true, out);
    for (const Outgoing& message : out) reader.Read(AsFrame(message, autopilot));
    sim::DecideEpoch(model, state, controllers, &log);  // the in-process Observe at this epoch
    if (reader.Complete()) {
      belief.Update(reader.sample());
      const sim::DecisionInputs& believed = sim::Observe(model, belief.state());
      const sim::DecisionInputs& truth = state.decision.inputs;
      ASSERT_DOUBLE_EQ(believed.time_s, truth.time_s);
      EXPECT_EQ(believed.state.mh, truth.state.mh) << "at " << truth.time_s << " s";
      if (truth.time_s >= kSettleS && state.vehicle.airborne) {
        EXPECT_NEAR(believed.eod_value().eod_s, truth.eod_value().eod_s, kEodTolerance)
            << "at " << truth.time_s << " s";
        EXPECT_NEAR(believed.flight_time_remaining_s, truth.flight_time_remaining_s, kPlanTolerance)
            << "at " << truth.time_s << " s";
        max_error_s = std::max(max_error_s, std::abs(believed.eod_value().eod_s - truth.eod_value().eod_s));
        ++compared;
        if (std::abs(truth.eod_value().reach_margin) > kReachMarginBand) {
          EXPECT_EQ(decision::CmaStateLabel(believed.state), decision::CmaStateLabel(truth.state))
              << "at " << truth.time_s << " s, RM " << truth.eod_value().reach_margin;
          ++states_compared;
        }
      }
    }
    sim::StepToNextEpoch(model, state, &log);
    if (log.telemetry.size() > 1) log.telemetry.erase(log.telemetry.begin(), log.telemetry.end() - 1);
  }
  // NoOp runs Scenario I's pack to the cut-off at 494.6 s: every epoch from kSettleS on is compared.
  EXPECT_GT(compared, 400);
  EXPECT_GT(states_compared, 300);
  RecordProperty("max_eod_error_s", std::to_string(max_error_s));
}

TEST(CompanionBeliefTest, AnEpochIsCompleteOnlyWhenEveryGroupFollowedItsSystemTime) {
  const Address autopilot{1, static_cast<std::uint8_t>(kMavCompIdAutopilot1)};
  TelemetryReader reader(autopilot.system_id);
  EXPECT_FALSE(reader.Complete());
  SystemTime time;
  time.time_boot_ms = 3000;
  reader.Read(AsFrame(MakeOutgoing(time), autopilot));
  EXPECT_FALSE(reader.Complete());
  EXPECT_LT(reader.sample().OldestS(), 0.0);  // nothing else received: never
  // Another component's or system's frames are not the vehicle's telemetry.
  EXPECT_FALSE(reader.Read(AsFrame(MakeOutgoing(time), Address{1, 191})));
  EXPECT_FALSE(reader.Read(AsFrame(MakeOutgoing(time), Address{2, 1})));
  // A SYS_STATUS without a measurement (0 V) does not count as a reading.
  SysStatus unmeasured;
  unmeasured.current_battery = -1;
  reader.Read(AsFrame(MakeOutgoing(unmeasured), autopilot));
  EXPECT_LT(reader.sample().power_s, 0.0);
}

}  // namespace
}  // namespace uascma::mavlink
