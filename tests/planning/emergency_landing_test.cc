// The emergency-landing planners (dissertation §5.3.2.2): the move-time model against FlightPlan, the grown hulls
// and the segment test against closed forms, the visibility-graph detour against an independent all-pairs search,
// climb-over against detour on hand-built maps, and LandASAP / LandPract on procedural cities: every plan starts at
// the vehicle, ends on the chosen site and is collision-free when sampled densely (IsInsideBuilding, and the
// lateral/vertical clearances checked building by building); the choice is the brute-force maximum RM.
#include "uascma/planning/emergency_landing.h"
#include "uascma/planning/land_asap.h"
#include "uascma/planning/land_pract.h"
#include "uascma/planning/landing_path.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <numbers>
#include <vector>

#include "uascma/common/error.h"
#include "uascma/common/random.h"
#include "uascma/planning/landing_detour.h"
#include "uascma/planning/map_geometry.h"
#include "uascma/planning/map_import.h"
#include "uascma/planning/procedural_city.h"
#include "../support/data_paths.h"

namespace uascma::planning {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Tolerances, each named for what it covers.
constexpr double kTimeRoundOff = 1e-9;    // s: the same times summed in a different order
constexpr double kLengthRoundOff = 1e-9;  // m: closed-form positions
constexpr double kGeometrySlack = 1e-6;   // m: the strict-interior tolerance of the planner
constexpr double kSampleSpacing = 0.05;   // s between samples of a plan (0.25 m at 5 m/s)
constexpr double kMarginSlack = 1e-4;     // m: a detour may graze a grown hull within the geometry slack

Ring Rectangle(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }

Building MakeBuilding(const std::string& id, Ring ring, double height) {
  Building building;
  building.id = id;
  building.rings = {std::move(ring)};
  building.height = height;
  return building;
}

LandingSite MakeSite(const std::string& id, const Eigen::Vector3d& p_W, double risk, double radius = 3.0) {
  LandingSite site;
  site.id = id;
  site.p_W = p_W;
  site.risk = risk;
  site.radius = radius;
  return site;
}

double Move(double length, double speed, double accel) { return TrapezoidMoveTime(length, speed, accel); }

// Samples the plan every kSampleSpacing s and checks it never enters a building, except the site's own roof on
// the final descent in the site's column; and that wherever it flies level, every building whose outline is within
// the lateral margin is at least the vertical clearance below it.
void ExpectCollisionFree(const CityMap& map, const FlightPlan& plan, int site, const LandingPathParams& params) {
  const LandingSite& landing = map.site(site);
  const int samples = static_cast<int>(std::ceil(plan.duration() / kSampleSpacing));
  for (int i = 0; i <= samples; ++i) {
    const PlanReference reference = plan.At(plan.duration() * i / std::max(samples, 1));
    const Eigen::Vector3d& p = reference.p_W;
    const int inside = map.BuildingContaining(p);
    if (inside != kNoBuilding) {
      const bool on_own_roof_column =
          inside == landing.building && (p.head<2>() - landing.p_W.head<2>()).norm() < kGeometrySlack;
      ASSERT_TRUE(on_own_roof_column) << "inside building " << map.building(inside).id
                                      << " at t = " << plan.duration() * i / samples << " s, p = " << p.transpose();
    }
    // Level flight: the clearances, building by building (independent of the grids and hulls).
    if (std::abs(reference.v_W.z()) < 1e-12 && reference.v_W.head<2>().norm() > 1e-9) {
      for (int k = 0; k < static_cast<int>(map.buildings().size()); ++k) {
        const auto edges = map.edges(k);
        double distance = kInf;
        for (const Edge2& e : edges) distance = std::min(distance, PointSegmentDistance(p.head<2>(), e.a_NE, e.b_NE));
        if (OutlineContains(edges, p.head<2>())) distance = 0.0;
        if (distance < params.lateral_margin - kMarginSlack) {
          ASSERT_LE(map.building(k).height + params.vertical_clearance, -p.z() + kGeometrySlack)
              << "building " << map.building(k).id << " within the margin at " << p.transpose();
        }
      }
    }
  }
}

void ExpectEndsAtSite(const CityMap& map, const FlightPlan& plan, const Eigen::Vector3d& start_W, int site) {
  EXPECT_LT((plan.start_W() - start_W).norm(), kLengthRoundOff);
  EXPECT_LT((plan.end_W() - map.site(site).p_W).norm(), kLengthRoundOff);
  EXPECT_LT((plan.At(plan.duration()).p_W - map.site(site).p_W).norm(), kLengthRoundOff);
}

// --- move times ---------------------------------------------------------------------------------------------------
TEST(LandingMoveTimeTest, MatchesFlightPlanAndInverts) {
  const PlanLimits limits;
  for (double length : {0.5, 3.0, 12.5, 12.6, 80.0, 900.0}) {
    const FlightPlan horizontal = FlightPlan::Through(Eigen::Vector3d(0, 0, -30),
                                                      {Waypoint{Eigen::Vector3d(length, 0, -30), 0.0, "move"}}, limits);
    EXPECT_NEAR(Move(length, limits.cruise_speed, limits.horizontal_accel), horizontal.duration(), kTimeRoundOff);
    const FlightPlan vertical =
        FlightPlan::Through(Eigen::Vector3d(0, 0, -length), {Waypoint{Eigen::Vector3d(0, 0, 0), 0.0, "move"}}, limits);
    EXPECT_NEAR(Move(length, limits.vertical_speed, limits.vertical_accel), vertical.duration(), kTimeRoundOff);
    const double time = Move(length, limits.cruise_speed, limits.horizontal_accel);
    EXPECT_NEAR(TrapezoidMoveLength(time, limits.cruise_speed, limits.horizontal_accel), length, 1e-9 * length);
  }
  EXPECT_LT(Move(0.0, 5.0, 2.0), kTimeRoundOff);
  // Subadditive: one stop more always costs time.
  EXPECT_GT(Move(30.0, 5.0, 2.0) + Move(50.0, 5.0, 2.0), Move(80.0, 5.0, 2.0) + 1.0);
}

// --- grown hulls and the segment test ------------------------------------------------------------------------------
TEST(LandingDetourGeometryTest, GrownRectangleHasMitredCorners) {
  const std::vector<Eigen::Vector2d> corners = {{0, 0}, {20, 0}, {20, 10}, {0, 10}};
  const ConvexObstacle grown = MakeInflatedHull(corners, 5.0);
  ASSERT_EQ(grown.vertices_NE.size(), 4u);  // one mitre per 90° corner: the rectangle grown by 5 m
  const Eigen::AlignedBox2d expected(Eigen::Vector2d(-5, -5), Eigen::Vector2d(25, 15));
  for (const auto& v : grown.vertices_NE) {
    const bool at_corner = (v - expected.corner(Eigen::AlignedBox2d::BottomLeft)).norm() < kLengthRoundOff ||
                           (v - expected.corner(Eigen::AlignedBox2d::BottomRight)).norm() < kLengthRoundOff ||
                           (v - expected.corner(Eigen::AlignedBox2d::TopLeft)).norm() < kLengthRoundOff ||
                           (v - expected.corner(Eigen::AlignedBox2d::TopRight)).norm() < kLengthRoundOff;
    EXPECT_TRUE(at_corner) << v.transpose();
  }
}

TEST(LandingDetourGeometryTest, GrownHullHoldsTheMarginAndNoMore) {
  // A concave U and a sharp triangle: every point within the margin of the outline is in the grown hull (not
  // strictly outside), and every vertex of the grown hull is within √2 · margin of the hull of the outline.
  const double margin = 4.0;
  const std::vector<std::vector<Eigen::Vector2d>> shapes = {
      {{0, 0}, {30, 0}, {30, 10}, {10, 10}, {10, 20}, {30, 20}, {30, 30}, {0, 30}}, {{0, 0}, {60, 5}, {0, 8}}};
  RandomStream random(5);
  for (const auto& shape : shapes) {
    const ConvexObstacle grown = MakeInflatedHull(shape, margin);
    const ConvexObstacle hull = MakeInflatedHull(shape, 0.0);
    EXPECT_GE(grown.vertices_NE.size(), hull.vertices_NE.size());
    for (int i = 0; i < 2000; ++i) {
      // A point on the outline pushed out by up to the margin.
      const std::size_t k = random.UniformIndex(shape.size());
      const Eigen::Vector2d on_edge = shape[k] + random.Uniform() * (shape[(k + 1) % shape.size()] - shape[k]);
      const double angle = random.Uniform(0.0, 2.0 * std::numbers::pi);
      const Eigen::Vector2d p =
          on_edge + random.Uniform(0.0, margin) * Eigen::Vector2d(std::cos(angle), std::sin(angle));
      bool outside_an_edge = false;  // strictly outside the grown hull
      for (std::size_t e = 0; e < grown.normals.size(); ++e) {
        if (grown.normals[e].dot(p) > grown.offsets[e] + kGeometrySlack) outside_an_edge = true;
      }
      EXPECT_FALSE(outside_an_edge) << p.transpose();
    }
    for (const auto& v : grown.vertices_NE) {
      double distance = kInf;
      for (std::size_t e = 0; e < hull.vertices_NE.size(); ++e) {
        distance = std::min(distance, PointSegmentDistance(v, hull.vertices_NE[e],
                                                           hull.vertices_NE[(e + 1) % hull.vertices_NE.size()]));
      }
      EXPECT_LE(distance, std::numbers::sqrt2 * margin + kLengthRoundOff);
      EXPECT_GE(distance, margin - kLengthRoundOff);
    }
  }
}

TEST(LandingDetourGeometryTest, SegmentTestClosedFormCases) {
  const ConvexObstacle square = MakeInflatedHull(std::vector<Eigen::Vector2d>{{0, 0}, {10, 0}, {10, 10}, {0, 10}}, 0.0);
  const double tol = kGeometrySlack;
  EXPECT_TRUE(square.SegmentCrossesInterior({-5, 5}, {15, 5}, tol));       // through the middle
  EXPECT_TRUE(square.SegmentCrossesInterior({5, 5}, {5, 50}, tol));        // from inside
  EXPECT_TRUE(square.SegmentCrossesInterior({0, 0}, {10, 10}, tol));       // the diagonal, corner to corner
  EXPECT_TRUE(square.SegmentCrossesInterior({-1, 1.5}, {1.5, -1}, tol));   // cuts a corner
  EXPECT_FALSE(square.SegmentCrossesInterior({-1, 0.5}, {0.5, -1}, tol));  // misses the corner
  EXPECT_FALSE(square.SegmentCrossesInterior({-5, 0}, {15, 0}, tol));      // slides along an edge
  EXPECT_FALSE(square.SegmentCrossesInterior({-5, 5}, {5, -5}, tol));      // touches the corner (0, 0)
  EXPECT_FALSE(square.SegmentCrossesInterior({-5, 11}, {15, 11}, tol));    // passes by
  EXPECT_FALSE(square.SegmentCrossesInterior({10, 10}, {20, 20}, tol));    // leaves a corner outwards
  EXPECT_TRUE(square.StrictlyContains({5, 5}, tol));
  EXPECT_FALSE(square.StrictlyContains({10, 5}, tol));
}

// --- the detour search ---------------------------------------------------------------------------------------------
TEST(LandingDetourSearchTest, GoesAroundASquareByItsCorners) {
  // A 20 m square centred on the origin between s = (−50, 0) and g = (50, 0): the fastest corner path turns at two
  // adjacent corners, (−10, ±10) and (10, ±10); both sides take the same time.
  std::vector<ConvexObstacle> obstacles = {
      MakeInflatedHull(std::vector<Eigen::Vector2d>{{-10, -10}, {10, -10}, {10, 10}, {-10, 10}}, 0.0)};
  const ObstacleSet set(std::move(obstacles));
  DetourProblem problem;
  problem.start_NE = {-50, 0};
  problem.goal_NE = {50, 0};
  const DetourResult result = ShortestDetour(set, problem);
  ASSERT_TRUE(result.found());
  ASSERT_EQ(result.points_NE.size(), 4u);
  const double side = std::hypot(40.0, 10.0);
  const double expected = 2.0 * Move(side, 5.0, 2.0) + Move(20.0, 5.0, 2.0);
  EXPECT_NEAR(result.time, expected, kTimeRoundOff);
  EXPECT_NEAR(std::abs(result.points_NE[1].y()), 10.0, kLengthRoundOff);
  EXPECT_NEAR(result.length, 2.0 * side + 20.0, kLengthRoundOff);
  // A budget below the optimum finds nothing; just above it finds the same path.
  problem.time_budget = expected - 1e-6;
  EXPECT_EQ(ShortestDetour(set, problem).status, DetourStatus::kNotFound);
  problem.time_budget = expected + 1e-6;
  EXPECT_NEAR(ShortestDetour(set, problem).time, expected, kTimeRoundOff);
  // Start inside the obstacle: a clear status.
  problem.start_NE = {0, 0};
  EXPECT_EQ(ShortestDetour(set, problem).status, DetourStatus::kStartBlocked);
}

// The reference: every pair of vertices tested, then Floyd–Warshall on the complete visibility graph.
double AllPairsReference(const ObstacleSet& set, const DetourProblem& problem) {
  std::vector<Eigen::Vector2d> nodes = {problem.start_NE, problem.goal_NE};
  for (int k = 0; k < set.size(); ++k) {
    for (const auto& v : set.obstacle(k).vertices_NE) nodes.push_back(v);
  }
  const int n = static_cast<int>(nodes.size());
  std::vector<double> d(n * n, kInf);
  for (int i = 0; i < n; ++i) {
    d[i * n + i] = 0.0;
    for (int j = i + 1; j < n; ++j) {
      bool free = true;
      for (int k = 0; k < set.size() && free; ++k) {
        free = !set.obstacle(k).SegmentCrossesInterior(nodes[i], nodes[j], problem.tolerance);
      }
      if (free) d[i * n + j] = d[j * n + i] = Move((nodes[i] - nodes[j]).norm(), problem.max_speed, problem.accel);
    }
  }
  for (int k = 0; k < n; ++k) {
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) d[i * n + j] = std::min(d[i * n + j], d[i * n + k] + d[k * n + j]);
    }
  }
  return d[0 * n + 1];
}

TEST(LandingDetourSearchTest, MatchesAllPairsReferenceOnRandomFields) {
  RandomStream random(2025);
  int compared = 0;
  for (int trial = 0; trial < 60; ++trial) {
    std::vector<ConvexObstacle> obstacles;
    const int count = 3 + static_cast<int>(random.UniformIndex(6));
    for (int k = 0; k < count; ++k) {
      const Eigen::Vector2d centre(random.Uniform(-80, 80), random.Uniform(-80, 80));
      std::vector<Eigen::Vector2d> points;
      for (int j = 0; j < 6; ++j)
        points.push_back(centre + Eigen::Vector2d(random.Uniform(-20, 20), random.Uniform(-20, 20)));
      obstacles.push_back(MakeInflatedHull(points, random.Uniform(0.0, 5.0)));
    }
    const ObstacleSet set(std::move(obstacles));
    DetourProblem problem;
    problem.start_NE = {-120, random.Uniform(-60, 60)};
    problem.goal_NE = {120, random.Uniform(-60, 60)};
    const DetourResult result = ShortestDetour(set, problem);
    const double reference = AllPairsReference(set, problem);
    if (result.status == DetourStatus::kStartBlocked) continue;
    ++compared;
    if (!std::isfinite(reference)) {
      EXPECT_FALSE(result.found());
      continue;
    }
    ASSERT_TRUE(result.found()) << "trial " << trial;
    EXPECT_NEAR(result.time, reference, kTimeRoundOff) << "trial " << trial;
    // The path itself is free and its time adds up.
    double time = 0.0;
    for (std::size_t i = 1; i < result.points_NE.size(); ++i) {
      EXPECT_TRUE(set.SegmentIsFree(result.points_NE[i - 1], result.points_NE[i], -kInf, problem.tolerance));
      time += Move((result.points_NE[i] - result.points_NE[i - 1]).norm(), problem.max_speed, problem.accel);
    }
    EXPECT_NEAR(time, result.time, kTimeRoundOff);
  }
  EXPECT_GT(compared, 40);
}

// --- one site: climb-over against detour
// ------------------------------------------------------------------------------
TEST(LandingPathTest, ClimbOverClosedForm) {
  // A 40 m block between the vehicle (30 m up) and a ground site 200 m north.
  const CityMap map({MakeBuilding("block", Rectangle(90, -30, 110, 30), 40.0)},
                    {MakeSite("park", Eigen::Vector3d(200, 0, 0), 0.2)});
  LandingPathParams params;
  params.allow_detour = false;
  const LandingPathPlanner planner(map, params);
  const Eigen::Vector3d start(0, 0, -30);
  const LandingPath path = planner.PlanToSite(start, 0);
  ASSERT_EQ(path.kind, LandingPathKind::kClimbOver);
  EXPECT_NEAR(path.transit_altitude, 50.0, kLengthRoundOff);  // 40 m + 10 m clearance
  const PlanLimits& l = params.limits;
  const double expected = Move(20.0, l.vertical_speed, l.vertical_accel) +
                          Move(200.0, l.cruise_speed, l.horizontal_accel) +
                          Move(50.0, l.vertical_speed, l.vertical_accel);
  EXPECT_NEAR(path.flight_time, expected, kTimeRoundOff);
  ASSERT_EQ(path.waypoints_W.size(), 3u);
  EXPECT_LT((path.waypoints_W[0] - Eigen::Vector3d(0, 0, -50)).norm(), kLengthRoundOff);
  EXPECT_LT((path.waypoints_W[1] - Eigen::Vector3d(200, 0, -50)).norm(), kLengthRoundOff);
  const FlightPlan plan = path.ToFlightPlan(params.limits);
  EXPECT_NEAR(plan.duration(), path.flight_time, kTimeRoundOff);
  ExpectEndsAtSite(map, plan, start, 0);
  ExpectCollisionFree(map, plan, 0, params);
  // The lower bound holds and the margin matters: a building 4 m beside the line (within 5 m) still counts.
  EXPECT_LE(planner.LowerBoundTime(start, map.site(0).p_W), path.flight_time);
  const CityMap beside({MakeBuilding("beside", Rectangle(90, 4, 110, 30), 40.0)}, {});
  EXPECT_NEAR(LandingPathPlanner(beside, params).TransitAltitude(start, Eigen::Vector3d(200, 0, 0)), 50.0,
              kLengthRoundOff);
  const CityMap away({MakeBuilding("away", Rectangle(90, 6, 110, 30), 40.0)}, {});
  EXPECT_NEAR(LandingPathPlanner(away, params).TransitAltitude(start, Eigen::Vector3d(200, 0, 0)), 30.0,
              kLengthRoundOff);
}

TEST(LandingPathTest, DetourBeatsClimbAroundATallTower) {
  // A 150 m tower, 30 m square, on the straight line; the vehicle at 30 m would climb 130 m.
  const CityMap map({MakeBuilding("tower", Rectangle(85, -15, 115, 15), 150.0)},
                    {MakeSite("park", Eigen::Vector3d(200, 0, 0), 0.2)});
  const LandingPathParams params;
  const LandingPathPlanner planner(map, params);
  const Eigen::Vector3d start(0, 0, -30);
  const LandingPath climb = planner.ClimbOver(start, map.site(0).p_W, map.site(0).building);
  const LandingPath path = planner.PlanToSite(start, 0);
  ASSERT_EQ(path.kind, LandingPathKind::kDetour);
  EXPECT_LT(path.flight_time, climb.flight_time);
  EXPECT_NEAR(path.transit_altitude, 30.0, kLengthRoundOff);
  // It turns at two mitred corners of the tower grown by 5 m: (85 − 5, ±(15 + 5)) and (115 + 5, ±(15 + 5)).
  ASSERT_EQ(path.waypoints_W.size(), 4u);
  EXPECT_NEAR(std::abs(path.waypoints_W[0].y()), 20.0, kLengthRoundOff);
  EXPECT_NEAR(path.waypoints_W[0].x(), 80.0, kLengthRoundOff);
  const PlanLimits& l = params.limits;
  const double side = std::hypot(80.0, 20.0);
  EXPECT_NEAR(path.flight_time,
              2.0 * Move(side, l.cruise_speed, l.horizontal_accel) + Move(40.0, l.cruise_speed, l.horizontal_accel) +
                  Move(30.0, l.vertical_speed, l.vertical_accel),
              kTimeRoundOff);
  const FlightPlan plan = path.ToFlightPlan(params.limits);
  EXPECT_NEAR(plan.duration(), path.flight_time, kTimeRoundOff);
  ExpectEndsAtSite(map, plan, start, 0);
  ExpectCollisionFree(map, plan, 0, params);
}

TEST(LandingPathTest, SharedObstaclesPlanExactlyAsBuiltOnes) {
  // A planner over hulls inflated once and shared (a campaign's planners, sim/emergency_planner.cc) plans
  // bit for bit as one that inflates its own; hulls of another margin or map are refused.
  const CityMap map({MakeBuilding("tower", Rectangle(85, -15, 115, 15), 150.0),
                     MakeBuilding("block", Rectangle(130, 30, 160, 60), 40.0)},
                    {MakeSite("park", Eigen::Vector3d(200, 0, 0), 0.2)});
  const LandingPathParams params;
  const auto shared = LandingPathPlanner::InflateBuildings(map, params.lateral_margin);
  const LandingPathPlanner own(map, params);
  const LandingPathPlanner reused(map, params, shared);
  ASSERT_EQ(reused.obstacles().size(), own.obstacles().size());
  for (int k = 0; k < own.obstacles().size(); ++k) {
    EXPECT_EQ(reused.obstacles().obstacle(k).vertices_NE, own.obstacles().obstacle(k).vertices_NE);
  }
  const Eigen::Vector3d start(0, 0, -30);
  const LandingPath a = own.PlanToSite(start, 0), b = reused.PlanToSite(start, 0);
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_EQ(a.flight_time, b.flight_time);  // exact: the same hulls, the same arithmetic
  EXPECT_EQ(a.waypoints_W, b.waypoints_W);
  const CityMap one_building({MakeBuilding("tower", Rectangle(85, -15, 115, 15), 150.0)}, {});
  EXPECT_DEATH_IF_SUPPORTED(LandingPathPlanner(one_building, params, shared), "one per building");
}

TEST(LandingPathTest, ClimbBeatsDetourOverAWideLowBlock) {
  // A 25 m block 600 m wide: at 30 m it is an obstacle (25 + 10 > 30); climbing 5 m beats going around it.
  const CityMap map({MakeBuilding("block", Rectangle(90, -300, 110, 300), 25.0)},
                    {MakeSite("park", Eigen::Vector3d(200, 0, 0), 0.2)});
  const LandingPathParams params;
  const LandingPathPlanner planner(map, params);
  const Eigen::Vector3d start(0, 0, -30);
  const LandingPath path = planner.PlanToSite(start, 0);
  ASSERT_EQ(path.kind, LandingPathKind::kClimbOver);
  EXPECT_NEAR(path.transit_altitude, 35.0, kLengthRoundOff);
  const LandingPath detour = planner.Detour(start, map.site(0).p_W, kNoBuilding, kInf);
  ASSERT_TRUE(detour.feasible());  // it exists, round the end of the block, but is slower
  EXPECT_GT(detour.flight_time, path.flight_time);
  EXPECT_GT(detour.horizontal_length, 600.0);
  ExpectCollisionFree(map, path.ToFlightPlan(params.limits), 0, params);
  ExpectCollisionFree(map, detour.ToFlightPlan(params.limits), 0, params);
}

TEST(LandingPathTest, DescendsOntoItsOwnRoofAndRespectsTheCeiling) {
  const CityMap map({MakeBuilding("host", Rectangle(100, -10, 120, 10), 30.0),
                     MakeBuilding("wall", Rectangle(50, -40, 60, 40), 60.0)},
                    {MakeSite("roof", Eigen::Vector3d(110, 0, -30), 0.3)});
  ASSERT_EQ(map.site(0).building, 0);
  LandingPathParams params;
  const LandingPathPlanner planner(map, params);
  const Eigen::Vector3d start(0, 0, -45);
  const LandingPath path = planner.PlanToSite(start, 0);
  ASSERT_TRUE(path.feasible());
  EXPECT_TRUE(planner.Verify(path));
  const FlightPlan plan = path.ToFlightPlan(params.limits);
  ExpectEndsAtSite(map, plan, start, 0);
  ExpectCollisionFree(map, plan, 0, params);
  // Over the wall or round it, the path ends with the descent in the site's column.
  EXPECT_LT((path.waypoints_W[path.waypoints_W.size() - 2].head<2>() - Eigen::Vector2d(110, 0)).norm(),
            kLengthRoundOff);
  // A ceiling below the needed transit and no detour: no path.
  params.max_transit_altitude = 55.0;
  params.allow_detour = false;
  EXPECT_FALSE(LandingPathPlanner(map, params).PlanToSite(start, 0).feasible());
}

// --- LandASAP -------------------------------------------------------------------------------------------------------
ProceduralCityParams SmallCity(std::uint64_t seed) {
  ProceduralCityParams params;
  params.seed = seed;
  params.blocks_north = 6;
  params.blocks_east = 3;
  return params;
}

Eigen::Vector3d RandomFreePoint(const CityMap& map, RandomStream& random, double min_altitude, double max_altitude) {
  while (true) {
    const Eigen::Vector3d p(random.Uniform(map.bounds().min().x(), map.bounds().max().x()),
                            random.Uniform(map.bounds().min().y(), map.bounds().max().y()),
                            -random.Uniform(min_altitude, max_altitude));
    if (!map.IsInsideBuilding(p)) return p;
  }
}

// The brute force: every site of the map, in the footprint or not decided independently, planned without budget.
struct BruteForceChoice {
  int site = -1;
  double reach_margin = -kInf;
  int candidates = 0;
};
BruteForceChoice BruteForce(const LandingPathPlanner& planner, const LandAsapParams& params,
                            const LandingRequest& request) {
  const CityMap& map = planner.map();
  FootprintParams footprint_params = params.footprint;
  footprint_params.initial_speed = std::max(request.v_WB_W.head<2>().norm(), params.min_footprint_speed);
  footprint_params.eod = request.eod;
  const FootprintResult footprint = CalcFootprint(footprint_params);
  const HeadingFrame frame = HeadingFrame::FromState(request.p_WB_W, request.v_WB_W, request.yaw);
  std::vector<std::pair<double, int>> margins;  // (RM, site)
  BruteForceChoice choice;
  for (int s = 0; s < static_cast<int>(map.sites().size()); ++s) {
    if (!footprint.Contains(frame, map.site(s).p_W)) continue;
    ++choice.candidates;
    const LandingPath path = planner.PlanToSite(request.p_WB_W, s);
    if (path.feasible()) margins.emplace_back(1.0 - path.flight_time / request.eod, s);
  }
  if (margins.empty()) return choice;
  double best = -kInf;
  for (const auto& [rm, s] : margins) best = std::max(best, rm);
  for (const auto& [rm, s] : margins) {
    if (rm < best - kReachMarginTie) continue;
    if (choice.site < 0 || map.site(s).risk < map.site(choice.site).risk ||
        (map.site(s).risk == map.site(choice.site).risk && rm > choice.reach_margin)) {
      choice.site = s;
      choice.reach_margin = rm;
    }
  }
  return choice;
}

TEST(LandAsapTest, PicksTheBruteForceMaximumRmInsideTheFootprint) {
  const CityMap map = MakeProceduralCity(SmallCity(11));
  const LandingPathParams path_params;
  const LandingPathPlanner planner(map, path_params);
  LandAsapParams params;
  RandomStream random(77);
  int detours = 0, ok = 0;
  for (int trial = 0; trial < 16; ++trial) {
    LandingRequest request;
    request.p_WB_W = RandomFreePoint(map, random, 20.0, 70.0);
    const double speed = random.Uniform(0.0, 8.0), course = random.Uniform(-std::numbers::pi, std::numbers::pi);
    request.v_WB_W = Eigen::Vector3d(speed * std::cos(course), speed * std::sin(course), 0.0);
    request.eod = random.Uniform(20.0, 60.0);
    const LandingResult result = PlanLandAsap(planner, params, request);
    const BruteForceChoice reference = BruteForce(planner, params, request);
    EXPECT_EQ(result.candidates, reference.candidates) << "trial " << trial;
    if (reference.site < 0) {
      EXPECT_FALSE(result.ok());
      continue;
    }
    ASSERT_TRUE(result.ok()) << result.BriefReport();
    ++ok;
    EXPECT_EQ(result.site, reference.site) << "trial " << trial << ": " << result.BriefReport();
    EXPECT_NEAR(result.reach_margin, reference.reach_margin, kTimeRoundOff / request.eod);
    EXPECT_NEAR(result.reach_margin, 1.0 - result.plan.duration() / request.eod, kTimeRoundOff);
    EXPECT_TRUE(result.footprint.Contains(result.frame, map.site(result.site).p_W));
    ExpectEndsAtSite(map, result.plan, request.p_WB_W, result.site);
    ExpectCollisionFree(map, result.plan, result.site, path_params);
    EXPECT_LE(result.planned, result.candidates);
    detours += result.path.kind == LandingPathKind::kDetour;
  }
  EXPECT_GT(ok, 10);
}

TEST(LandAsapTest, PlanningEveryCandidateGivesTheSameChoiceAndNeverLeavesTheFootprint) {
  const CityMap map = MakeProceduralCity(SmallCity(12));
  const LandingPathParams path_params;
  const LandingPathPlanner planner(map, path_params);
  LandAsapParams pruned, all;
  all.plan_all_candidates = true;
  RandomStream random(78);
  int outside = 0, detours = 0;
  for (int trial = 0; trial < 8; ++trial) {
    LandingRequest request;
    request.p_WB_W = RandomFreePoint(map, random, 25.0, 60.0);
    request.v_WB_W = Eigen::Vector3d(random.Uniform(-6, 6), random.Uniform(-6, 6), 0.0);
    request.eod = 30.0;
    const LandingResult a = PlanLandAsap(planner, pruned, request);
    const LandingResult b = PlanLandAsap(planner, all, request);
    ASSERT_EQ(a.status, b.status);
    if (!a.ok()) continue;
    EXPECT_EQ(a.site, b.site);
    EXPECT_NEAR(a.flight_time, b.flight_time, kTimeRoundOff);
    EXPECT_EQ(b.planned, b.candidates);
    EXPECT_EQ(static_cast<int>(b.candidate_plans.size()), b.candidates);
    for (const SitePlan& plan : b.candidate_plans) {
      EXPECT_TRUE(b.footprint.Contains(b.frame, map.site(plan.site).p_W));
      EXPECT_LE(plan.lower_bound, plan.path.flight_time + kTimeRoundOff);
      EXPECT_GE(plan.path.flight_time, b.flight_time - kReachMarginTie * request.eod - kTimeRoundOff);
      detours += plan.path.kind == LandingPathKind::kDetour;
    }
    outside += static_cast<int>(map.sites().size()) - b.candidates;
  }
  EXPECT_GT(outside, 0);  // the footprint (EOD 30 s) leaves sites out: the filter was exercised
  EXPECT_GT(detours, 0);  // and some candidates are reached faster round the buildings than over them
}

TEST(LandAsapTest, EqualMarginsGoToTheLowerRisk) {
  // No buildings; sites 100 m north and south of a vehicle flying east: the same time (every plan starts at rest).
  // Then a 0.01 m longer flight is no longer a tie (2 ms ≫ 1e-9 · EOD).
  const CityMap tie(
      {}, {MakeSite("ahead", Eigen::Vector3d(100, 0, 0), 0.5), MakeSite("behind", Eigen::Vector3d(-100, 0, 0), 0.2)});
  const LandingPathPlanner planner(tie);
  LandingRequest request;
  request.p_WB_W = Eigen::Vector3d(0, 0, -30);
  request.v_WB_W = Eigen::Vector3d(0, 5, 0);
  request.eod = 120.0;
  LandingResult result = PlanLandAsap(planner, {}, request);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result.site_id, "behind");
  const CityMap no_tie({}, {MakeSite("ahead", Eigen::Vector3d(100, 0, 0), 0.5),
                            MakeSite("behind", Eigen::Vector3d(-100.01, 0, 0), 0.2)});
  const LandingPathPlanner planner2(no_tie);
  result = PlanLandAsap(planner2, {}, request);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result.site_id, "ahead");
}

TEST(LandAsapTest, ClearStatusesWithoutSitesOrInsideABuilding) {
  const CityMap empty({MakeBuilding("b", Rectangle(0, 0, 20, 20), 30.0)}, {});
  const LandingPathPlanner planner(empty);
  LandingRequest request;
  request.p_WB_W = Eigen::Vector3d(-20, -20, -40);
  request.v_WB_W = Eigen::Vector3d(5, 0, 0);
  request.eod = 100.0;
  EXPECT_EQ(PlanLandAsap(planner, {}, request).status, LandingStatus::kNoSiteInFootprint);
  request.p_WB_W = Eigen::Vector3d(10, 10, -10);
  EXPECT_EQ(PlanLandAsap(planner, {}, request).status, LandingStatus::kStartInsideBuilding);
  // A site far outside a short footprint; and EOD 0.
  const CityMap far({}, {MakeSite("far", Eigen::Vector3d(5000, 0, 0), 0.1)});
  const LandingPathPlanner planner_far(far);
  request.p_WB_W = Eigen::Vector3d(0, 0, -30);
  request.eod = 10.0;
  const LandingResult result = PlanLandAsap(planner_far, {}, request);
  EXPECT_EQ(result.status, LandingStatus::kNoSiteInFootprint);
  EXPECT_FALSE(result.message.empty());
  request.eod = 0.0;
  EXPECT_EQ(PlanLandAsap(planner_far, {}, request).status, LandingStatus::kNoSiteInFootprint);
  // A ceiling under every needed transit: candidates, but no feasible path.
  const CityMap walled({MakeBuilding("wall", Rectangle(40, -500, 50, 500), 80.0)},
                       {MakeSite("beyond", Eigen::Vector3d(100, 0, 0), 0.1)});
  LandingPathParams capped;
  capped.max_transit_altitude = 60.0;
  capped.allow_detour = false;
  const LandingPathPlanner planner_capped(walled, capped);
  request.eod = 100.0;
  EXPECT_EQ(PlanLandAsap(planner_capped, {}, request).status, LandingStatus::kNoFeasibleTrajectory);
  // Bad input.
  request.p_WB_W.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(PlanLandAsap(planner_capped, {}, request), InputError);
  LandingPathParams bad;
  bad.vertical_clearance = 0.0;
  EXPECT_THROW(LandingPathPlanner(walled, bad), InputError);
}

TEST(LandAsapTest, HoveringFootprintIsAPointUnlessASpeedFloorIsSet) {
  const CityMap map({}, {MakeSite("near", Eigen::Vector3d(50, 0, 0), 0.2)});
  const LandingPathPlanner planner(map);
  LandingRequest request;
  request.p_WB_W = Eigen::Vector3d(0, 0, -30);
  request.eod = 60.0;
  LandAsapParams params;
  EXPECT_EQ(PlanLandAsap(planner, params, request).status, LandingStatus::kNoSiteInFootprint);
  params.min_footprint_speed = 5.0;
  const LandingResult result = PlanLandAsap(planner, params, request);
  ASSERT_TRUE(result.ok()) << result.BriefReport();
  EXPECT_EQ(result.site_id, "near");
}

std::uint64_t Bits(double x) { return std::bit_cast<std::uint64_t>(x); }

TEST(LandAsapTest, Reproducible) {
  const CityMap map = MakeProceduralCity(SmallCity(13));
  const LandingPathPlanner first(map), second(map);
  RandomStream random(79);
  for (int trial = 0; trial < 5; ++trial) {
    LandingRequest request;
    request.p_WB_W = RandomFreePoint(map, random, 25.0, 60.0);
    request.v_WB_W = Eigen::Vector3d(3, -2, 0);
    request.eod = 40.0;
    const LandingResult a = PlanLandAsap(first, {}, request), b = PlanLandAsap(second, {}, request);
    ASSERT_EQ(a.status, b.status);
    EXPECT_EQ(a.site, b.site);
    EXPECT_EQ(Bits(a.flight_time), Bits(b.flight_time));
    EXPECT_EQ(a.path.waypoints_W.size(), b.path.waypoints_W.size());
  }
}

// --- LandPract ------------------------------------------------------------------------------------------------------
struct PractFixture {
  CityMap map = MakeProceduralCity(SmallCity(21));
  LandingPathParams path_params;
  FlightPlan nominal;
  LandPractDatabase database;
  PractFixture() {
    // Home and destination at street/avenue intersections (x = i · 79.3 m, y = j · 210.5 m), cruise 10 m above the
    // tallest building under the route (docs/defaults.md#guidance-and-control).
    DeliveryMission mission;
    mission.home_NE = Eigen::Vector2d(0.0, 0.0);
    mission.destination_NE = Eigen::Vector2d(5 * 79.3, 2 * 210.5);
    const Eigen::Vector2d route[2] = {mission.home_NE, mission.destination_NE};
    mission.cruise_altitude = map.CruiseAltitude(route, kCruiseClearanceAboveBuildings, path_params.lateral_margin);
    nominal = MakeDeliveryPlan(mission, path_params.limits);
    database = LandPractDatabase::Build(LandingPathPlanner(map, path_params), nominal);
  }
};

TEST(LandPractTest, CheckpointsDivideTheRouteEqually) {
  const PractFixture f;
  ASSERT_EQ(f.database.checkpoints().size(), 5u);
  const double spacing = f.nominal.Length() / 6.0;
  for (int k = 0; k < 5; ++k) {
    const Checkpoint& c = f.database.checkpoints()[k];
    EXPECT_NEAR(c.route_distance, (k + 1) * spacing, kLengthRoundOff);
    EXPECT_LT((c.p_W - f.nominal.PointAtDistance(c.route_distance)).norm(), kLengthRoundOff);
    EXPECT_LT((f.nominal.At(c.plan_time).p_W - c.p_W).norm(), 1e-6);  // the plan passes it at plan_time
  }
  // Out and back: checkpoints 1 and 3 (0-based) are the same place, 3 on the return leg.
  EXPECT_LT((f.database.checkpoints()[1].p_W - f.database.checkpoints()[3].p_W).norm(), 1e-6);
  EXPECT_GT(f.database.checkpoints()[3].plan_time, f.database.checkpoints()[2].plan_time);
}

TEST(LandPractTest, StoredPathsAreSortedFreeAndEndOnTheirSites) {
  const PractFixture f;
  int stored = 0;
  for (int k = 0; k < 5; ++k) {
    const auto paths = f.database.trajectories(k);
    EXPECT_LE(static_cast<int>(paths.size()), f.database.params().trajectories_per_checkpoint);
    for (std::size_t i = 0; i < paths.size(); ++i) {
      ++stored;
      if (i > 0) {
        EXPECT_LE(paths[i - 1].flight_time, paths[i].flight_time);
      }
      EXPECT_NEAR(paths[i].flight_time, paths[i].path.flight_time, kTimeRoundOff);
      const FlightPlan plan = paths[i].path.ToFlightPlan(f.path_params.limits);
      EXPECT_NEAR(plan.duration(), paths[i].flight_time, kTimeRoundOff);
      ExpectEndsAtSite(f.map, plan, f.database.checkpoints()[k].p_W, paths[i].site);
      ExpectCollisionFree(f.map, plan, paths[i].site, f.path_params);
    }
  }
  EXPECT_GT(stored, 50);
  // The stored sites are the fastest: no site within the radius is faster than the last stored one.
  const LandingPathPlanner planner(f.map, f.path_params);
  const Checkpoint& c = f.database.checkpoints()[2];
  const auto paths = f.database.trajectories(2);
  ASSERT_FALSE(paths.empty());
  for (int s : f.map.SitesWithinRadius(c.p_W.head<2>(), f.database.params().site_search_radius)) {
    const bool kept = std::any_of(paths.begin(), paths.end(), [&](const StoredTrajectory& t) { return t.site == s; });
    if (!kept) {
      EXPECT_GE(planner.PlanToSite(c.p_W, s).flight_time, paths.back().flight_time - kTimeRoundOff);
    }
  }
}

TEST(LandPractTest, NearestCheckpointAndCoincidingOnesByProgress) {
  const PractFixture f;
  const auto& checkpoints = f.database.checkpoints();
  const Eigen::Vector3d nudge(2.0, -1.0, 0.5);
  EXPECT_EQ(f.database.NearestCheckpoint(checkpoints[0].p_W + nudge, std::nan("")), 0);
  EXPECT_EQ(f.database.NearestCheckpoint(checkpoints[2].p_W + nudge, std::nan("")), 2);
  // Checkpoints 1 and 3 coincide: the vehicle's time along the nominal plan decides.
  EXPECT_EQ(f.database.NearestCheckpoint(checkpoints[1].p_W + nudge, checkpoints[1].plan_time + 3.0), 1);
  EXPECT_EQ(f.database.NearestCheckpoint(checkpoints[3].p_W + nudge, checkpoints[3].plan_time - 3.0), 3);
  EXPECT_EQ(f.database.NearestCheckpoint(checkpoints[3].p_W + nudge, std::nan("")), 1);
}

TEST(LandPractTest, LookupIsTheMaximumRmOfTheCheckpointAndPlanMatchesIt) {
  const PractFixture f;
  const LandingPathPlanner planner(f.map, f.path_params);
  RandomStream random(99);
  int checked = 0;
  for (int trial = 0; trial < 30; ++trial) {
    // Somewhere along the nominal plan, pushed off it a little.
    const double distance = random.Uniform(0.0, f.nominal.Length());
    Eigen::Vector3d p = f.nominal.PointAtDistance(distance) +
                        Eigen::Vector3d(random.Uniform(-15, 15), random.Uniform(-15, 15), random.Uniform(-3, 3));
    p.z() = std::min(p.z(), -1.0);
    if (f.map.IsInsideBuilding(p)) continue;
    LandingRequest request;
    request.p_WB_W = p;
    request.eod = random.Uniform(30.0, 200.0);
    const LandPractChoice choice = f.database.Lookup(request);
    ASSERT_EQ(choice.status, LandingStatus::kOk);
    // Reference: the nearest checkpoint by a linear scan, the leg by the FlightPlan of the climb-over.
    int nearest = 0;
    for (int k = 1; k < 5; ++k) {
      if ((f.database.checkpoints()[k].p_W - p).norm() < (f.database.checkpoints()[nearest].p_W - p).norm() - 1e-3)
        nearest = k;
    }
    EXPECT_LT((f.database.checkpoints()[choice.checkpoint].p_W - f.database.checkpoints()[nearest].p_W).norm(), 1e-3);
    const LandingPath leg = planner.ClimbOver(p, f.database.checkpoints()[choice.checkpoint].p_W);
    const double leg_time = leg.ToFlightPlan(f.path_params.limits).duration();
    EXPECT_NEAR(choice.time_to_checkpoint, leg_time, kTimeRoundOff);
    const auto paths = f.database.trajectories(choice.checkpoint);
    double best_rm = -kInf;
    for (const auto& t : paths) best_rm = std::max(best_rm, 1.0 - (leg_time + t.flight_time) / request.eod);
    EXPECT_NEAR(choice.reach_margin, best_rm, kTimeRoundOff);
    for (const auto& t : paths) {
      const double rm = 1.0 - (leg_time + t.flight_time) / request.eod;
      if (rm >= best_rm - kReachMarginTie) {
        EXPECT_LE(f.map.site(choice.site).risk, t.risk);
      }
    }
    // The plan: vehicle → checkpoint → stored path, the same time as the look-up, collision-free, on the site.
    const LandingResult result = f.database.Plan(request);
    ASSERT_TRUE(result.ok()) << result.BriefReport();
    EXPECT_EQ(result.site, choice.site);
    EXPECT_EQ(result.checkpoint, choice.checkpoint);
    EXPECT_NEAR(result.flight_time, choice.flight_time, kTimeRoundOff);
    EXPECT_NEAR(result.reach_margin, choice.reach_margin, kTimeRoundOff);
    ExpectEndsAtSite(f.map, result.plan, p, result.site);
    ExpectCollisionFree(f.map, result.plan, result.site, f.path_params);
    ++checked;
  }
  EXPECT_GT(checked, 20);
}

TEST(LandPractTest, EmptyDatabaseAndNoSitesGiveClearStatuses) {
  const LandPractDatabase empty;
  LandingRequest request;
  request.eod = 60.0;
  EXPECT_EQ(empty.Lookup(request).status, LandingStatus::kNoStoredTrajectory);
  EXPECT_EQ(empty.Plan(request).status, LandingStatus::kNoStoredTrajectory);
  const CityMap no_sites({MakeBuilding("b", Rectangle(100, 100, 120, 120), 30.0)}, {});
  const FlightPlan nominal = MakeDeliveryPlan(DeliveryMission{}, PlanLimits{});
  const LandPractDatabase database = LandPractDatabase::Build(LandingPathPlanner(no_sites), nominal);
  request.p_WB_W = Eigen::Vector3d(300, 0, -30);
  const LandingResult result = database.Plan(request);
  EXPECT_EQ(result.status, LandingStatus::kNoStoredTrajectory);
  EXPECT_FALSE(result.message.empty());
  LandPractParams bad;
  bad.checkpoint_count = 0;
  EXPECT_THROW(LandPractDatabase::Build(LandingPathPlanner(no_sites), nominal, bad), InputError);
}

// --- real geometry ------------------------------------------------------------------------------------------------
TEST(LandAsapTest, CollisionFreeOverRealUpperEastSideBuildings) {
  const auto file =
      ::uascma::testing_support::OsmDataDir() / "upper-east-side-buildings.geojson";
  MapImportOptions options;
  options.skip_missing_height = true;
  const std::vector<std::filesystem::path> files = {file};
  const CityMap imported = ImportCityMap(files, {}, options).map;
  // Rooftop sites at the centre of the bounding box of every 7th building, where that point is on its roof.
  std::vector<LandingSite> sites;
  for (int k = 0; k < static_cast<int>(imported.buildings().size()); k += 7) {
    const Eigen::Vector2d centre = imported.building_box(k).center();
    if (!OutlineContains(imported.edges(k), centre)) continue;
    const double height = imported.building(k).height;
    if (imported.SurfaceAltitudeAt(centre) > height) continue;  // under a taller overlapping part
    sites.push_back(MakeSite(imported.building(k).id, Eigen::Vector3d(centre.x(), centre.y(), -height), 0.3));
  }
  const CityMap map(imported.buildings(), sites);
  const LandingPathParams path_params;
  const LandingPathPlanner planner(map, path_params);
  RandomStream random(4);
  int ok = 0;
  for (int trial = 0; trial < 12; ++trial) {
    LandingRequest request;
    request.p_WB_W = RandomFreePoint(map, random, 20.0, 60.0);
    request.v_WB_W = Eigen::Vector3d(random.Uniform(-5, 5), random.Uniform(-5, 5), 0.0);
    request.eod = 60.0;
    const LandingResult result = PlanLandAsap(planner, {}, request);
    if (!result.ok()) continue;
    ++ok;
    ExpectEndsAtSite(map, result.plan, request.p_WB_W, result.site);
    ExpectCollisionFree(map, result.plan, result.site, path_params);
  }
  EXPECT_GT(ok, 6);
}

}  // namespace
}  // namespace uascma::planning
