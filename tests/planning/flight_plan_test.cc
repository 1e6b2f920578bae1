#include <gtest/gtest.h>

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

}  // namespace
}  // namespace uascma::planning
