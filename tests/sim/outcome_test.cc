// The outcome classification (sim/outcome.h) at hand-built points, one rule at a time, and the scenario's one
// validator (Scenario::IsValid) naming the part and field.
#include <gtest/gtest.h>

#include "uascma/planning/city_map.h"
#include "uascma/sim/outcome.h"
#include "uascma/sim/scenario.h"

namespace uascma::sim {
namespace {

// Flying level at 20 m, on plan, healthy: nothing ends.
OutcomeInputs Cruising() {
  OutcomeInputs in;
  in.time_s = 100.0;
  in.p_WB_W = Eigen::Vector3d(50, 0, -20);
  in.v_WB_W = Eigen::Vector3d(5, 0, 0);
  in.cos_tilt = std::cos(0.1);
  in.cross_track_error = 1.0;
  in.min_cell_voltage_v = 3.8;
  in.airborne = true;
  in.plan_time_remaining_s = 60.0;
  in.plan_end_W = Eigen::Vector3d(300, 0, 0);
  in.time_limit_s = 1000.0;
  return in;
}

// One 10 m × 10 m building, 15 m tall, centred at (100, 0).
planning::CityMap OneBuilding() {
  planning::Building building;
  building.id = "block";
  building.rings = {{{95, -5}, {105, -5}, {105, 5}, {95, 5}}};
  building.height = 15.0;
  return planning::CityMap({building}, {});
}

TEST(OutcomeTest, EachRuleAtItsThreshold) {
  const OutcomeThresholds limits;
  const planning::CityMap open;
  EXPECT_EQ(ClassifyOutcome(limits, Cruising(), open).outcome, Outcome::kInProgress);

  OutcomeInputs in = Cruising();
  in.min_cell_voltage_v = 3.3;  // the cut-off itself (§3.3.2.1)
  EXPECT_EQ(ClassifyOutcome(limits, in, open).outcome, Outcome::kFailedBattery);
  in.min_cell_voltage_v = 3.3001;
  EXPECT_EQ(ClassifyOutcome(limits, in, open).outcome, Outcome::kInProgress);

  in = Cruising();
  in.cos_tilt = std::cos(limits.max_tilt + 1e-6);
  EXPECT_EQ(ClassifyOutcome(limits, in, open).outcome, Outcome::kFailedControl);
  in.cos_tilt = std::cos(limits.max_tilt - 1e-6);
  EXPECT_EQ(ClassifyOutcome(limits, in, open).outcome, Outcome::kInProgress);
  in.cross_track_error = limits.max_cross_track_error + 1e-9;
  EXPECT_EQ(ClassifyOutcome(limits, in, open).outcome, Outcome::kFailedControl);
  in = Cruising();
  in.body_rate = limits.max_body_rate + 1e-9;
  EXPECT_EQ(ClassifyOutcome(limits, in, open).outcome, Outcome::kFailedControl);

  in = Cruising();
  in.time_s = in.time_limit_s;
  EXPECT_EQ(ClassifyOutcome(limits, in, open).outcome, Outcome::kTimeout);
}

TEST(OutcomeTest, LandingAtThePlansEndCompletesOrIsAnEmergencyLanding) {
  const OutcomeThresholds limits;
  const planning::CityMap open;
  OutcomeInputs in = Cruising();
  in.p_WB_W = Eigen::Vector3d(301.0, 0.5, -0.1);  // 1.1 m from the end point, 0.1 m up
  in.v_WB_W = Eigen::Vector3d(0.1, 0, 0.2);
  in.plan_time_remaining_s = 0.0;
  EXPECT_EQ(ClassifyOutcome(limits, in, open).outcome, Outcome::kCompleted);
  in.on_original_plan = false;
  in.emergency_site = "roof 7";
  const OutcomeDecision emergency = ClassifyOutcome(limits, in, open);
  EXPECT_EQ(emergency.outcome, Outcome::kEmergencyLanding);
  EXPECT_NE(emergency.reason.find("roof 7"), std::string::npos);
  in.v_WB_W = Eigen::Vector3d(0.6, 0, 0);  // still moving: not settled, and above ground: nothing yet
  EXPECT_EQ(ClassifyOutcome(limits, in, open).outcome, Outcome::kInProgress);
  in.airborne = false;  // never took off: a vehicle at rest on its destination has not completed anything
  in.v_WB_W.setZero();
  EXPECT_EQ(ClassifyOutcome(limits, in, open).outcome, Outcome::kInProgress);
}

TEST(OutcomeTest, GroundContactOutsideTheLandingZoneOrTooFastIsACollision) {
  const OutcomeThresholds limits;
  const planning::CityMap open;
  OutcomeInputs in = Cruising();
  in.p_WB_W = Eigen::Vector3d(200, 0, 0.01);  // on the ground, 100 m short of the end point
  EXPECT_EQ(ClassifyOutcome(limits, in, open).outcome, Outcome::kFailedCollision);
  in.p_WB_W = Eigen::Vector3d(300, 0, 0.0);
  in.plan_time_remaining_s = 1.0;
  in.v_WB_W = Eigen::Vector3d(0, 0, limits.touchdown_speed + 0.1);  // NED: +z is down
  EXPECT_EQ(ClassifyOutcome(limits, in, open).outcome, Outcome::kFailedCollision);
  in.v_WB_W = Eigen::Vector3d(0, 0, limits.touchdown_speed - 0.1);  // gentle, in the landing zone: a touchdown
  EXPECT_EQ(ClassifyOutcome(limits, in, open).outcome, Outcome::kCompleted);
}

// docs/modelling-choices.md#outcomes-refined: a touchdown on a rooftop site is a landing like one on the ground; off
// the site or too fast, a crash.
TEST(OutcomeTest, ARooftopTouchdownIsALandingOnTheSiteAndACollisionOffIt) {
  const OutcomeThresholds limits;
  const planning::CityMap map = OneBuilding();
  OutcomeInputs in = Cruising();
  in.on_original_plan = false;
  in.emergency_site = "roof of block";
  in.plan_end_W = Eigen::Vector3d(100, 0, -15.0);  // the site on the 15 m roof
  in.landing_radius = 3.0;                         // the site's radius (m)
  in.plan_time_remaining_s = 0.5;
  in.p_WB_W = Eigen::Vector3d(101.0, 1.0, -14.99);  // just inside the prism, 1.4 m from the site's centre
  in.v_WB_W = Eigen::Vector3d(0, 0, 0.4);
  EXPECT_EQ(ClassifyOutcome(limits, in, map).outcome, Outcome::kEmergencyLanding);
  in.v_WB_W.z() = limits.touchdown_speed + 0.1;  // too fast
  EXPECT_EQ(ClassifyOutcome(limits, in, map).outcome, Outcome::kFailedCollision);
  in.v_WB_W.z() = 0.4;
  in.landing_radius = 1.0;  // a smaller site: 1.4 m is off it
  EXPECT_EQ(ClassifyOutcome(limits, in, map).outcome, Outcome::kFailedCollision);
}

// A gust on the final descent puts the vehicle down gently on open ground 4.5 m from the pad, outside
// the 3.46 m landing radius: landed off-site, safe, neither completed nor failed. A building that is not the site,
// or a touchdown too fast down or across, stays a failure.
TEST(OutcomeTest, AGentleTouchdownOnOpenGroundOffTheSiteIsLandedOffSite) {
  const OutcomeThresholds limits;
  OutcomeInputs in = Cruising();
  in.plan_end_W = Eigen::Vector3d(300, 0, 0);
  in.plan_time_remaining_s = 0.0;
  in.p_WB_W = Eigen::Vector3d(304.5, 0, 0.0);  // 4.5 m from the end point, on the ground
  in.v_WB_W = Eigen::Vector3d(0.05, 0, 0.1);   // 0.1 m/s down (the measured case)
  const planning::CityMap open;
  const OutcomeDecision off = ClassifyOutcome(limits, in, open);
  EXPECT_EQ(off.outcome, Outcome::kLandedOffSite);
  EXPECT_NE(off.reason.find("4.5 m"), std::string::npos);
  EXPECT_FALSE(IsFailure(Outcome::kLandedOffSite));
  EXPECT_STREQ(OutcomeName(Outcome::kLandedOffSite), "landed_off_site");
  EXPECT_EQ(TerminalStateOf(Outcome::kLandedOffSite), decision::CmaTerminal::kC);
  in.v_WB_W = Eigen::Vector3d(limits.touchdown_speed + 0.1, 0, 0.1);  // skidding in across the ground
  EXPECT_EQ(ClassifyOutcome(limits, in, open).outcome, Outcome::kFailedCollision);
  in.v_WB_W = Eigen::Vector3d(0, 0, limits.touchdown_speed + 0.1);  // too fast down
  EXPECT_EQ(ClassifyOutcome(limits, in, open).outcome, Outcome::kFailedCollision);
  // Gently onto the roof of a building that is not the landing site: a collision.
  const planning::CityMap map = OneBuilding();
  in.v_WB_W = Eigen::Vector3d(0, 0, 0.1);
  in.p_WB_W = Eigen::Vector3d(100, 0, -14.99);
  EXPECT_EQ(ClassifyOutcome(limits, in, map).outcome, Outcome::kFailedCollision);
}

TEST(OutcomeTest, GroundedIsSafeAndNotCompletedAndEndsInC) {
  EXPECT_FALSE(IsFailure(Outcome::kGrounded));
  EXPECT_STREQ(OutcomeName(Outcome::kGrounded), "grounded");
  EXPECT_EQ(TerminalStateOf(Outcome::kGrounded), decision::CmaTerminal::kC);
}

TEST(OutcomeTest, InsideABuildingBelowItsRoofIsACollision) {
  const OutcomeThresholds limits;
  const planning::CityMap map = OneBuilding();
  OutcomeInputs in = Cruising();
  in.p_WB_W = Eigen::Vector3d(100, 0, -14.0);  // 1 m below the roof
  const OutcomeDecision hit = ClassifyOutcome(limits, in, map);
  EXPECT_EQ(hit.outcome, Outcome::kFailedCollision);
  EXPECT_NE(hit.reason.find("block"), std::string::npos);
  in.p_WB_W = Eigen::Vector3d(100, 0, -16.0);  // 1 m above it
  EXPECT_EQ(ClassifyOutcome(limits, in, map).outcome, Outcome::kInProgress);
}

TEST(OutcomeTest, ThresholdsAreValidated) {
  OutcomeThresholds limits;
  std::string error;
  EXPECT_TRUE(limits.IsValid(&error));
  limits.landing_radius = 0.0;
  EXPECT_FALSE(limits.IsValid(&error));
  EXPECT_NE(error.find("landing_radius"), std::string::npos);
}

TEST(ScenarioValidationTest, NamesThePartAndTheField) {
  std::string error;
  EXPECT_TRUE(Scenario{}.IsValid(&error)) << error;
  const auto expect_invalid = [](const Scenario& scenario, const std::string& part, const std::string& field) {
    std::string message;
    EXPECT_FALSE(scenario.IsValid(&message));
    // "part: field: …" from a part's validator, "part.key: expected from … to …" from a plausibility bound.
    EXPECT_TRUE(message.rfind(part + ": ", 0) == 0 || message.rfind(part + ".", 0) == 0) << message;
    EXPECT_NE(message.find(field), std::string::npos) << message;
  };
  Scenario s;
  s.fault.enabled = true;
  s.fault.motor = 7;
  expect_invalid(s, "fault", "motor");
  s = Scenario{};
  s.battery.initial_cell_voltage_v[1][2] = 4.5;  // above the OCV table's 4.20 V (docs/defaults.md#battery)
  expect_invalid(s, "battery", "initial_cell_voltage_v");
  s = Scenario{};
  s.options.outcome.max_cross_track_error = -1.0;
  expect_invalid(s, "options", "max_cross_track_error");
  s = Scenario{};
  s.lqr.dt = 0.01;  // not the 200 Hz GNC step
  expect_invalid(s, "lqr", "dt");
  s = Scenario{};
  s.map = std::make_shared<const planning::CityMap>(OneBuilding());
  s.mission.home_NE = Eigen::Vector2d(100, 0);  // inside the building
  expect_invalid(s, "mission", "home_ne_m");
}

}  // namespace
}  // namespace uascma::sim
