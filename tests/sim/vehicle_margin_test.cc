// The vehicle-level motor margin (sim/vehicle_margin.h) against its closed forms, the quadcopter's reach against an
// independent EOD propagation (a plan the quadcopter can finish at its forecast load, one it cannot), and the
// `cma-vehicle` policy's model (decision/cma_vehicle_mdp.h) and registration.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "test_scenarios.h"
#include "uascma/decision/cma_abstraction.h"
#include "uascma/decision/cma_vehicle_mdp.h"
#include "uascma/prognostics/eod.h"
#include "uascma/prognostics/motor_rul.h"
#include "uascma/sim/flight.h"
#include "uascma/sim/initial_state.h"
#include "uascma/sim/policy.h"
#include "uascma/sim/speed_cap.h"
#include "uascma/sim/vehicle_margin.h"
#include "uascma/sim/vehicle_policy.h"

namespace uascma::sim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMarginTolerance = 1e-12;  // dimensionless: the closed forms are evaluated in the same order
constexpr double kSecondsTolerance = 1e-9;  // s

TEST(VehicleMarginTest, EachCaseOfTheClosedForm) {
  QuadcopterReach quad;
  quad.time_remaining_s = 300.0;
  quad.eod_s = 400.0;
  const double t_sf = 10.0;
  // No fault: eq. 5.14 with t_RUL = +inf gives 1.
  EXPECT_EQ(CalcVehicleMotorMargin(200.0, kInf, false, 0.3, quad, t_sf), 1.0);
  // The motor outlives the plan: eq. 5.14's value, 1 - 200 / 500.
  EXPECT_NEAR(CalcVehicleMotorMargin(200.0, 500.0, false, 0.3, quad, t_sf), 1.0 - 200.0 / 500.0, kMarginTolerance);
  // The jam comes within the plan: the quadcopter's reach, 1 - (300 + 10) / 400 (eq. 5.14 alone would give
  // 1 - 200 / 50 = -3, MM0).
  EXPECT_NEAR(CalcVehicleMotorMargin(200.0, 50.0, false, 0.3, quad, t_sf), 1.0 - 310.0 / 400.0, kMarginTolerance);
  quad.eod_s = 305.0;  // the quadcopter would cut out 5 s into its margin
  EXPECT_NEAR(CalcVehicleMotorMargin(200.0, 50.0, false, 0.3, quad, t_sf), 1.0 - 310.0 / 305.0, kMarginTolerance);
  EXPECT_EQ(decision::ClassifyMotorMargin(CalcVehicleMotorMargin(200.0, 50.0, false, 0.3, quad, t_sf)),
            decision::MotorMargin::kMM0);
  // Seized and not isolated: -inf whatever the quadcopter could do.
  EXPECT_EQ(CalcVehicleMotorMargin(200.0, 0.0, false, 0.3, quad, t_sf), -kInf);
  // Isolated: the vehicle is the quadcopter; its margin is the epoch's reach margin.
  EXPECT_EQ(CalcVehicleMotorMargin(200.0, 0.0, true, 0.3, quad, t_sf), 0.3);
  EXPECT_EQ(CalcVehicleMotorMargin(200.0, 0.0, true, -0.2, quad, t_sf), -0.2);
  EXPECT_TRUE(MotorJamsWithinPlan(200.0, 50.0, false));
  EXPECT_FALSE(MotorJamsWithinPlan(200.0, 250.0, false));
  EXPECT_FALSE(MotorJamsWithinPlan(200.0, 50.0, true));
}

// A delivery flown from its first epoch on the ground (ShortJam's plan without its fault).
struct Delivery {
  Delivery(double safety_margin_s, bool capped, double distance_scale = 1.0)
      : model(Make(safety_margin_s, capped, distance_scale)) {
    state = MakeInitialState(model, 5);
  }
  static Scenario Make(double safety_margin_s, bool capped, double distance_scale) {
    Scenario scenario = testing_scenarios::ShortJam();
    scenario.mission.destination_NE *= distance_scale;
    scenario.fault.enabled = false;
    scenario.options.safety_margin_s = safety_margin_s;
    scenario.options.cap_speed_after_isolation = capped;
    return scenario;
  }
  // The EOD propagated to the cut-off (CalcPackEod, not the bounded propagation the margin uses) at `current_a`.
  double FullEod(double current_a) const {
    return prognostics::CalcPackEod(model.pack(), state.power.pack, current_a).eod_s;
  }
  FlightModel model;
  FlightState state;
};

TEST(VehicleMarginTest, AQuadcopterThatCanFinishAndOneThatCannotAtItsForecastLoad) {
  // Uncapped: the quadcopter flies the plan's own speeds, so its time is the plan's rest.
  const Delivery can(0.0, false);
  const double plan_s = can.model.nominal_plan().duration();
  const QuadcopterReach reach = CalcQuadcopterReach(can.model, can.state, can.state.power.pack);
  EXPECT_NEAR(reach.time_remaining_s, plan_s, kSecondsTolerance);
  // Its forecast current: the four-rotor profile's energy over the rest, at the bus voltage, plus the hotel load.
  const LoadProfile four(can.model.nominal_plan(), can.model.steady_load(), 4);
  const double expected_a =
      four.RemainingEnergyJ(0.0) / (plan_s * can.state.power.bus_voltage_v) + can.model.options().hotel_current_a;
  EXPECT_NEAR(reach.current_a, expected_a, 1e-9 * expected_a);  // A
  // Four rotors share the thrust: more power than six (eq. 2.10's P ∝ T^1.5 per rotor, sqrt(6/4) in hover).
  const LoadProfile six(can.model.nominal_plan(), can.model.steady_load(), 6);
  EXPECT_GT(four.RemainingEnergyJ(0.0), six.RemainingEnergyJ(0.0));
  const double eod_s = can.FullEod(reach.current_a);
  ASSERT_GT(eod_s, plan_s) << "a short delivery a healthy pack can fly on four rotors";
  // Can finish: the margin is the closed form 1 - t_quad / t_EOD,quad, or a lower bound above 0 when the bounded
  // propagation stopped at t_quad (it never crosses before then).
  const double can_margin = CalcVehicleMotorMargin(plan_s, 1.0, false, 1.0, reach, 0.0);
  EXPECT_GE(can_margin, 0.0);
  if (!reach.eod_is_lower_bound) {
    EXPECT_NEAR(can_margin, 1.0 - plan_s / eod_s, 1e-9);
  }
  // Cannot finish: the same delivery taken far enough that its plan outlasts the quadcopter's EOD at t_sf = 5 s.
  const double t_sf = 5.0;
  const Delivery cannot(t_sf, false, 1.5 * eod_s / plan_s);
  const double long_plan_s = cannot.model.nominal_plan().duration();
  const QuadcopterReach short_reach = CalcQuadcopterReach(cannot.model, cannot.state, cannot.state.power.pack);
  EXPECT_NEAR(short_reach.time_remaining_s, long_plan_s, kSecondsTolerance);
  const double long_eod_s = cannot.FullEod(short_reach.current_a);
  ASSERT_LT(long_eod_s, long_plan_s + t_sf) << "a delivery the quadcopter cannot finish";
  ASSERT_FALSE(short_reach.eod_is_lower_bound);
  EXPECT_NEAR(short_reach.eod_s, long_eod_s, 1e-6);  // s: the bounded propagation reaches the same crossing
  const double cannot_margin = CalcVehicleMotorMargin(long_plan_s, 1.0, false, 1.0, short_reach, t_sf);
  EXPECT_NEAR(cannot_margin, 1.0 - (long_plan_s + t_sf) / long_eod_s, 1e-9);
  EXPECT_LT(cannot_margin, 0.0);
  // Through the epoch's inputs: a RUL longer than the plan leaves eq. 5.14's MM1, a short one asks the quadcopter.
  DecisionInputs inputs;
  inputs.flight_time_remaining_s = long_plan_s;
  EXPECT_NEAR(
      ObserveVehicleMotorMargin(cannot.model, cannot.state, inputs, 2.0 * long_plan_s, false, cannot.state.power.pack),
      0.5, kMarginTolerance);
  EXPECT_NEAR(ObserveVehicleMotorMargin(cannot.model, cannot.state, inputs, 20.0, false, cannot.state.power.pack),
              cannot_margin, kMarginTolerance);
}

TEST(VehicleMarginTest, TheCappedQuadcopterFliesTheRestAtItsCap) {
  const Delivery capped(0.0, true);
  const FlightModel& model = capped.model;
  const double cap_mps = CalcAuthorityAirspeed(model, capped.state, 4);
  ASSERT_GT(cap_mps, 0.0);
  const planning::FlightPlan rest =
      ReplanAtCappedSpeed(model.nominal_plan(), 0.0, capped.state.vehicle.body.p_WB_W, model.scenario().limits,
                          model.wind().MeanWind_W().head<2>(), cap_mps);
  const QuadcopterReach reach = CalcQuadcopterReach(model, capped.state, capped.state.power.pack);
  EXPECT_NEAR(reach.time_remaining_s, rest.duration(), kSecondsTolerance);
  EXPECT_GE(reach.time_remaining_s, model.nominal_plan().duration() - kSecondsTolerance);  // never faster
  // Four rotors hold less than six: the cap of six is at least the cap of four.
  EXPECT_GE(CalcAuthorityAirspeed(model, capped.state, 6), cap_mps);
}

TEST(VehicleMarginTest, TheVehicleModelDiffersFromTheDdnOnlyInTable55sJfRows) {
  const decision::FiniteMdp ddn = decision::BuildCmaMdp(decision::CmaWeights{});
  const decision::FiniteMdp vehicle = decision::BuildCmaVehicleMdp(decision::CmaWeights{});
  ASSERT_EQ(ddn.num_states(), vehicle.num_states());
  // A row as (successor, probability) pairs, compared bit for bit.
  auto row = [](const decision::FiniteMdp& mdp, int s, int a) {
    const std::int64_t c = mdp.FindChoice(s, a);
    const auto next = mdp.choice_next_states(c);
    const auto p = mdp.choice_probabilities(c);
    return std::make_pair(std::vector<decision::StateIndex>(next.begin(), next.end()),
                          std::vector<double>(p.begin(), p.end()));
  };
  int differing_rows = 0;
  for (int fs = 0; fs < 3; ++fs) {
    for (int mh = 0; mh < 3; ++mh) {
      for (int mm = 0; mm < 2; ++mm) {
        for (int bh = 0; bh < 3; ++bh) {
          for (int rm = 0; rm < 2; ++rm) {
            const decision::CmaState state{
                static_cast<decision::FlightStatus>(fs), static_cast<decision::MotorHealth>(mh),
                static_cast<decision::MotorMargin>(mm), static_cast<decision::BatteryHealth>(bh),
                static_cast<decision::ReachMargin>(rm)};
            const int s = decision::CmaStateIndex(state);
            for (int a = 0; a < decision::kCmaNumActions; ++a) {
              ASSERT_EQ(ddn.IsAvailable(s, a), vehicle.IsAvailable(s, a));
              if (!ddn.IsAvailable(s, a)) continue;
              const bool same = row(ddn, s, a) == row(vehicle, s, a);
              differing_rows += same ? 0 : 1;
              if (state.mh != decision::MotorHealth::kJF) {
                EXPECT_TRUE(same) << decision::CmaStateLabel(state) << " action " << a;
              }
            }
          }
        }
      }
    }
  }
  EXPECT_GT(differing_rows, 0);
  // The policy: a jammed hexacopter that the quadcopter can carry home flies on in the safe quadrant.
  const decision::Policy policy = decision::SolveCmaVehiclePolicy();
  for (auto bh : {decision::BatteryHealth::kG, decision::BatteryHealth::kM, decision::BatteryHealth::kP}) {
    const decision::CmaState safe{decision::FlightStatus::kN, decision::MotorHealth::kJF, decision::MotorMargin::kMM1,
                                  bh, decision::ReachMargin::kRM1};
    EXPECT_EQ(policy.action[decision::CmaStateIndex(safe)], static_cast<int>(decision::CmaAction::kNoOp))
        << decision::CmaStateLabel(safe);
  }
}

TEST(VehicleMarginTest, ThePolicyReadsTheVehicleMarginAndIsStoredAndRebuiltWhole) {
  const PolicyDefinition definition = ResolvePolicy("cma-vehicle", "--policy");
  EXPECT_EQ(definition.kind, "cma-vehicle");
  EXPECT_EQ(definition.name, "cma-vehicle");
  EXPECT_NE(definition.hash, SolvedCmaPolicyDefinition().hash);
  const PolicyDefinition stored =
      MakeStoredPolicy(definition.name, definition.kind, definition.source, PolicyActionsJson(definition), "test");
  EXPECT_EQ(stored.hash, definition.hash);
  EXPECT_EQ(stored.actions, definition.actions);
  // A spalled motor whose RUL is shorter than the plan: eq. 5.14's MM0 (cma lands), a quadcopter that can finish
  // (MM1 for cma-vehicle: NoOp in the safe quadrant).
  DecisionInputs inputs;
  inputs.state = {decision::FlightStatus::kN, decision::MotorHealth::kSF, decision::MotorMargin::kMM0,
                  decision::BatteryHealth::kG, decision::ReachMargin::kRM1};
  inputs.vehicle_motor_margin = 0.2;
  EXPECT_EQ(VehicleCmaState(inputs).mm, decision::MotorMargin::kMM1);
  auto vehicle = MakeDecisionPolicy(definition);
  auto cma = MakePolicy("cma", "test");
  EXPECT_NE(cma->Decide(inputs), decision::CmaAction::kNoOp);
  EXPECT_EQ(vehicle->Decide(inputs), decision::CmaAction::kNoOp);
  inputs.vehicle_motor_margin = -0.1;  // the quadcopter could not finish: the vehicle-level MM0
  EXPECT_EQ(vehicle->Decide(inputs), cma->Decide(inputs));
}

}  // namespace
}  // namespace uascma::sim
