#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "uascma/common/error.h"
#include "uascma/planning/flight_plan.h"

namespace uascma::planning {
namespace {

constexpr double kTimeTolerance = 1e-9;      // s
constexpr double kPositionTolerance = 1e-9;  // m

TEST(FlightPlanTest, DeliveryPlanDurationMatchesTheTrapezoidClosedForm) {
  DeliveryMission mission;  // 600 m north, 30 m altitude, 30 s drop
  const PlanLimits limits;  // 5 m/s, 2 m/s vertical, 2 m/s² and 1 m/s²
  const FlightPlan plan = MakeDeliveryPlan(mission, limits);
  // Climb 30 m: t = 2·v/a + (d − v²/a)/v = 2·2 + (30 − 4)/2 = 17 s; cruise 600 m: 2·2.5 + (600 − 12.5)/5
  // = 122.5 s; drop 30 s; back 122.5 s; land 17 s.
  EXPECT_NEAR(plan.duration(), 17 + 122.5 + 30 + 122.5 + 17, kTimeTolerance);
  EXPECT_EQ(plan.segments().size(), 5u);
  EXPECT_NEAR(plan.Length(), 30 + 600 + 600 + 30, kPositionTolerance);
  EXPECT_NEAR(plan.TimeRemaining(100.0), plan.duration() - 100.0, kTimeTolerance);
  EXPECT_NEAR(plan.TimeRemaining(1e6), 0.0, kTimeTolerance);
}

TEST(FlightPlanTest, ShortSegmentsUseATriangleProfile) {
  PlanLimits limits;
  const FlightPlan plan = FlightPlan::Through(Eigen::Vector3d::Zero(), {{Eigen::Vector3d(4, 0, 0), 0, "hop"}}, limits);
  // 4 m < v²/a = 12.5 m: peak √(d a) = √8, duration 2√(d/a) = 2√2 s.
  EXPECT_NEAR(plan.duration(), 2.0 * std::sqrt(2.0), kTimeTolerance);
  EXPECT_NEAR(plan.segments()[0].peak_speed, std::sqrt(8.0), 1e-12);
}

TEST(FlightPlanTest, VelocityIsTheDerivativeOfPositionAndLimitsHold) {
  const FlightPlan plan = MakeDeliveryPlan({}, {});
  constexpr double kStep = 1e-5;  // s, central difference
  for (double t = 0.01; t < plan.duration(); t += 0.37) {
    const PlanReference r = plan.At(t);
    const Eigen::Vector3d numeric = (plan.At(t + kStep).p_W - plan.At(t - kStep).p_W) / (2 * kStep);
    EXPECT_NEAR((numeric - r.v_W).norm(), 0.0, 1e-5) << "t = " << t;
    EXPECT_LE(r.v_W.head<2>().norm(), 5.0 + 1e-12);
    EXPECT_LE(std::abs(r.v_W.z()), 2.0 + 1e-12);
    EXPECT_LE(r.a_W.head<2>().norm(), 2.0 + 1e-12);
    EXPECT_LE(std::abs(r.a_W.z()), 1.0 + 1e-12);
  }
}

TEST(FlightPlanTest, StartsAndEndsAtHomeOnTheGroundAndHoversAtTheDrop) {
  DeliveryMission mission;
  mission.destination_NE = Eigen::Vector2d(300, 400);
  const FlightPlan plan = MakeDeliveryPlan(mission, {});
  EXPECT_NEAR(plan.At(0).p_W.norm(), 0.0, kPositionTolerance);
  EXPECT_NEAR(plan.At(plan.duration() + 5).p_W.norm(), 0.0, kPositionTolerance);
  const PlanSegment& drop = plan.segments()[2];
  ASSERT_EQ(drop.kind, PlanSegment::Kind::kHover);
  const PlanReference mid = plan.At(drop.start_time + 15.0);
  EXPECT_NEAR((mid.p_W - Eigen::Vector3d(300, 400, -30)).norm(), 0.0, kPositionTolerance);
  EXPECT_NEAR(mid.v_W.norm(), 0.0, 1e-12);
  EXPECT_NEAR((plan.PointAtDistance(30 + 250) - Eigen::Vector3d(150, 200, -30)).norm(), 0.0, 1e-9);
}

TEST(FlightPlanTest, InvalidLimitsAreInputErrors) {
  PlanLimits limits;
  limits.cruise_speed = 0.0;
  EXPECT_THROW(MakeDeliveryPlan({}, limits), InputError);
  DeliveryMission mission;
  mission.cruise_altitude = -3;
  EXPECT_THROW(MakeDeliveryPlan(mission, {}), InputError);
}

// The delivery plan is what the simulator and the campaigns fly: it must stay the same plan, bit for bit, for the
// same inputs (a campaign replays runs from their seeds). Rebuilt here segment by segment from CalcTrapezoid: the
// climb and the landing at the vertical limits, the cruises at the horizontal ones, the drop hover between.
TEST(FlightPlanTest, DeliveryPlanIsBitForBitTheTrapezoidsOfItsFourMoves) {
  const struct {
    Eigen::Vector2d home, destination;
    double altitude, hover, speed;
  } cases[] = {
      {{0, 0}, {600, 0}, 30, 30, 5}, {{-120, 40}, {380, 260}, 41.5, 0, 8.7}, {{10, 10}, {13, 11}, 12, 12.5, 1}};
  for (const auto& c : cases) {
    DeliveryMission mission;
    mission.home_NE = c.home;
    mission.destination_NE = c.destination;
    mission.cruise_altitude = c.altitude;
    mission.drop_hover_s = c.hover;
    PlanLimits limits;
    limits.cruise_speed = c.speed;
    const FlightPlan plan = MakeDeliveryPlan(mission, limits);
    const double cruise = (c.destination - c.home).norm();
    struct Expected {
      PlanSegment::Kind kind;
      double length, speed, accel, hover;
    };
    std::vector<Expected> expected = {
        {PlanSegment::Kind::kMove, c.altitude, limits.vertical_speed, limits.vertical_accel, 0},
        {PlanSegment::Kind::kMove, cruise, limits.cruise_speed, limits.horizontal_accel, 0}};
    if (c.hover > 0) expected.push_back({PlanSegment::Kind::kHover, 0, 0, 0, c.hover});
    expected.push_back({PlanSegment::Kind::kMove, cruise, limits.cruise_speed, limits.horizontal_accel, 0});
    expected.push_back({PlanSegment::Kind::kMove, c.altitude, limits.vertical_speed, limits.vertical_accel, 0});
    ASSERT_EQ(plan.segments().size(), expected.size());
    double time = 0.0;
    for (std::size_t i = 0; i < expected.size(); ++i) {
      const PlanSegment& s = plan.segments()[i];
      SCOPED_TRACE(s.label);
      ASSERT_EQ(s.kind, expected[i].kind);
      EXPECT_EQ(s.start_time, time);  // exact: bitwise identity is the requirement
      if (s.kind == PlanSegment::Kind::kHover) {
        EXPECT_EQ(s.duration, expected[i].hover);
      } else {
        const TrapezoidProfile profile = CalcTrapezoid(expected[i].length, expected[i].speed, expected[i].accel);
        EXPECT_EQ(s.duration, profile.duration);
        EXPECT_EQ(s.peak_speed, profile.peak_speed);
        EXPECT_EQ(s.accel_time, profile.accel_time);
        EXPECT_EQ(s.accel, expected[i].accel);
      }
      time += s.duration;
    }
  }
}

TEST(FlightPlanTest, MultiWaypointPlansFlyEveryLegRestToRestAndCountAllThatRemains) {
  const PlanLimits limits;  // 5 m/s, 2 m/s², vertical 2 m/s, 1 m/s²
  const std::vector<Waypoint> waypoints = {
      {Eigen::Vector3d(0, 0, -20), 0, "takeoff"},
      {Eigen::Vector3d(200, 0, -20), 15, "a"},
      {Eigen::Vector3d(200, 150, -20), 0, "b", 3.0},  // DO_CHANGE_SPEED: 3 m/s on this leg
      {Eigen::Vector3d(0, 150, -20), 0, "c"},
      {Eigen::Vector3d(0, 150, 0), 0, "land"}};
  const FlightPlan plan = FlightPlan::Through(Eigen::Vector3d::Zero(), waypoints, limits);
  ASSERT_EQ(plan.segments().size(), 6u);
  // Each leg is its own trapezoid: climb 20 m → 2·2 + (20 − 4)/2 = 12 s; 200 m at 5 m/s → 5 + (200 − 12.5)/5
  // = 42.5 s; hover 15 s; 150 m at 3 m/s → 2·1.5 + (150 − 4.5)/3 = 51.5 s; 200 m → 42.5 s; land 12 s.
  const double durations[] = {12, 42.5, 15, 51.5, 42.5, 12};
  double total = 0.0;
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(plan.segments()[i].duration, durations[i], kTimeTolerance) << plan.segments()[i].label;
    total += durations[i];
  }
  EXPECT_NEAR(plan.duration(), total, kTimeTolerance);
  EXPECT_NEAR(plan.segments()[3].peak_speed, 3.0, 1e-12);
  // At rest at every waypoint: the velocity vanishes at each segment boundary.
  for (const PlanSegment& s : plan.segments()) {
    EXPECT_NEAR(plan.At(s.start_time).v_W.norm(), 0.0, 1e-12) << s.label;
  }
  // Time remaining from inside the third leg: the rest of it, the last two legs.
  const double t = 12 + 42.5 + 15 + 20.0;
  EXPECT_NEAR(plan.TimeRemaining(t), (51.5 - 20.0) + 42.5 + 12, kTimeTolerance);
  EXPECT_NEAR(plan.Length(), 20 + 200 + 150 + 200 + 20, kPositionTolerance);
  EXPECT_NEAR((plan.PointAtDistance(20 + 200 + 75) - Eigen::Vector3d(200, 75, -20)).norm(), 0.0, 1e-9);
  // A negative hover or speed, or a non-finite waypoint, is an input error.
  EXPECT_THROW(FlightPlan::Through(Eigen::Vector3d::Zero(), {{Eigen::Vector3d(1, 0, 0), -1, "x"}}, limits), InputError);
  EXPECT_THROW(FlightPlan::Through(Eigen::Vector3d::Zero(), {{Eigen::Vector3d(1, 0, 0), 0, "x", -2}}, limits),
               InputError);
  EXPECT_THROW(FlightPlan::Through(Eigen::Vector3d::Zero(), {{Eigen::Vector3d(NAN, 0, 0), 0, "x"}}, limits),
               InputError);
}

// The 200 Hz loop's cursor gives At(time)'s reference bit for bit: forward at the GNC step, after a jump
// back (a new plan), from a cursor of another plan, and from an out-of-range one.
TEST(FlightPlanTest, CursorGivesAtsReferenceExactly) {
  const FlightPlan plan =
      FlightPlan::AfterBraking({1, 2, -30}, {4, -3, 0}, 2.0, MakeDeliveryPlan({{0, 0}, {400, 300}, 30.0, 20.0}, {}));
  auto expect_same = [&](double t, PlanCursor& cursor) {
    const PlanReference a = plan.At(t);
    const PlanReference b = plan.At(t, cursor);
    EXPECT_EQ(a.segment, b.segment) << t;
    EXPECT_EQ(cursor.segment, a.segment) << t;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(a.p_W[k], b.p_W[k]) << t;
      EXPECT_EQ(a.v_W[k], b.v_W[k]) << t;
      EXPECT_EQ(a.a_W[k], b.a_W[k]) << t;
    }
  };
  PlanCursor cursor;
  for (int step = -10; step * 0.005 < plan.duration() + 1.0; ++step) expect_same(step * 0.005, cursor);
  for (double t : {3.0, 0.0, plan.duration() - 1e-9, 1.0, -1.0, plan.duration(), 50.0}) expect_same(t, cursor);
  for (int stale : {-7, 0, 3, 99}) {
    for (double t : {0.0, 2.5, 60.0, plan.duration() * 0.5, plan.duration() + 3.0}) {
      cursor.segment = stale;
      expect_same(t, cursor);
    }
  }
  EXPECT_EQ(PlanCursor{.segment = 1}, PlanCursor{.segment = 4});  // a cache: not part of a state's value
}

}  // namespace
}  // namespace uascma::planning
