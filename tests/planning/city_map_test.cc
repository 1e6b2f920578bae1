// The city map's geometry and queries: closed-form cases, the exact 2.5-D kernels against an independent
// computation with Boost.Geometry, and every indexed query against a linear scan over all buildings or sites.
#include <gtest/gtest.h>

// Boost.Geometry is the independent reference. Boost 1.74 includes a deprecated header of its own and GCC 12 sees
// a maybe-uninitialized variable in its rescaling policy: both are Boost's, silenced for its headers only.
#define BOOST_ALLOW_DEPRECATED_HEADERS
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <boost/geometry.hpp>
#include <boost/geometry/geometries/linestring.hpp>
#include <boost/geometry/geometries/multi_linestring.hpp>
#include <boost/geometry/geometries/point_xy.hpp>
#include <boost/geometry/geometries/polygon.hpp>
#pragma GCC diagnostic pop

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include "uascma/common/error.h"
#include "uascma/common/random.h"
#include "uascma/planning/city_map.h"
#include "uascma/planning/map_geometry.h"
#include "uascma/planning/procedural_city.h"

namespace uascma::planning {
namespace {

namespace bg = boost::geometry;
using BoostPoint = bg::model::d2::point_xy<double>;
using BoostPolygon = bg::model::polygon<BoostPoint>;
using BoostLine = bg::model::linestring<BoostPoint>;
using BoostLines = bg::model::multi_linestring<BoostLine>;

constexpr double kLengthTolerance = 1e-9;     // m, closed-form positions
constexpr double kParameterTolerance = 1e-9;  // segment parameter t (dimensionless), independent computations
constexpr double kBoundaryBand = 1e-7;        // m: random points this close to an edge are left out of the
                                              // point-in-polygon comparison (the boundary may go either way)

Ring Square(double x0, double y0, double side) {
  return {{x0, y0}, {x0 + side, y0}, {x0 + side, y0 + side}, {x0, y0 + side}};
}

// A U-shaped (concave) outline: 30 m × 30 m with a 10 m × 20 m notch open to the north (+x).
//   x 0..30, y 0..30; notch x 10..30, y 10..20.
Ring UShape() { return {{0, 0}, {30, 0}, {30, 10}, {10, 10}, {10, 20}, {30, 20}, {30, 30}, {0, 30}}; }

// A random star-shaped polygon around `centre`: vertices at sorted angles with radii in [r_min, r_max]; simple and,
// with enough spread in the radii, concave.
Ring RandomStar(RandomStream& random, const Eigen::Vector2d& centre, int vertices, double r_min, double r_max) {
  Ring ring;
  for (int k = 0; k < vertices; ++k) {
    const double angle = 2.0 * std::numbers::pi * (k + random.Uniform(0.1, 0.9)) / vertices;
    const double r = random.Uniform(r_min, r_max);
    ring.emplace_back(centre + r * Eigen::Vector2d(std::cos(angle), std::sin(angle)));
  }
  return ring;
}

BoostPolygon ToBoost(const std::vector<Ring>& rings) {
  BoostPolygon polygon;
  for (const auto& p : rings[0]) bg::append(polygon.outer(), BoostPoint(p.x(), p.y()));
  for (std::size_t r = 1; r < rings.size(); ++r) {
    polygon.inners().emplace_back();
    for (const auto& p : rings[r]) bg::append(polygon.inners().back(), BoostPoint(p.x(), p.y()));
  }
  bg::correct(polygon);  // orientation and closure as Boost wants them
  return polygon;
}

double DistanceToEdges(const std::vector<Edge2>& edges, const Eigen::Vector2d& p) {
  double d = std::numeric_limits<double>::infinity();
  for (const auto& e : edges) d = std::min(d, PointSegmentDistance(p, e.a_NE, e.b_NE));
  return d;
}

// The independent reference for a segment and a prism: the part below the roof from the altitude profile, then
// the pieces of its horizontal projection inside the polygon from Boost.Geometry's intersection.
std::optional<double> ReferenceFirstEntry(const BoostPolygon& polygon, double height, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b) {
  const double altitude_a = -a.z(), altitude_b = -b.z();
  double t0 = 0.0, t1 = 1.0;
  if (altitude_a > height && altitude_b > height) return std::nullopt;
  if (altitude_a > height) t0 = (altitude_a - height) / (altitude_a - altitude_b);
  if (altitude_b > height) t1 = (altitude_a - height) / (altitude_a - altitude_b);
  const Eigen::Vector2d p0 = a.head<2>() + t0 * (b - a).head<2>(), p1 = a.head<2>() + t1 * (b - a).head<2>();
  if ((p1 - p0).norm() < 1e-12) {
    return bg::covered_by(BoostPoint(p0.x(), p0.y()), polygon) ? std::optional<double>(t0) : std::nullopt;
  }
  BoostLine line{BoostPoint(p0.x(), p0.y()), BoostPoint(p1.x(), p1.y())};
  BoostLines inside;
  bg::intersection(line, polygon, inside);
  double first = std::numeric_limits<double>::infinity();
  const Eigen::Vector2d direction = p1 - p0;
  for (const auto& piece : inside) {
    for (const auto& q : piece) {
      const double s = (Eigen::Vector2d(q.x(), q.y()) - p0).dot(direction) / direction.squaredNorm();
      first = std::min(first, s);
    }
  }
  if (!std::isfinite(first)) return std::nullopt;
  return t0 + first * (t1 - t0);
}

// --- kernels: closed forms ---------------------------------------------------------------------------------

TEST(MapGeometryTest, ConcaveOutlineContainsTheArmsButNotTheNotch) {
  const auto edges = EdgesOfRings({UShape()});
  EXPECT_TRUE(OutlineContains(edges, {5, 15}));    // the base of the U
  EXPECT_TRUE(OutlineContains(edges, {25, 5}));    // west arm
  EXPECT_TRUE(OutlineContains(edges, {25, 25}));   // east arm
  EXPECT_FALSE(OutlineContains(edges, {25, 15}));  // in the notch
  EXPECT_FALSE(OutlineContains(edges, {15, 15}));  // in the notch, near its bottom
  EXPECT_FALSE(OutlineContains(edges, {35, 15}));  // beyond the arms
  EXPECT_FALSE(OutlineContains(edges, {-1, 15}));
  // A ray along y = 10 passes through a vertex of the notch: the half-open rule counts it once.
  EXPECT_TRUE(OutlineContains(edges, {5, 10}));
  EXPECT_NEAR(TwiceSignedArea(UShape()), 2.0 * (900 - 200), kLengthTolerance);
}

TEST(MapGeometryTest, HoleIsOutsideByTheEvenOddRule) {
  const auto edges = EdgesOfRings({Square(0, 0, 30), Square(10, 10, 10)});
  EXPECT_TRUE(OutlineContains(edges, {5, 5}));
  EXPECT_FALSE(OutlineContains(edges, {15, 15}));  // the courtyard
  EXPECT_TRUE(OutlineContains(edges, {25, 15}));
  // A segment that starts and ends in the courtyard never meets the building...
  EXPECT_FALSE(SegmentMeetsOutline(edges, {12, 12}, {18, 18}));
  // ...and one that leaves it meets the courtyard wall at x = 20.
  const auto s = FirstEntryIntoOutline(edges, {15, 15}, {25, 15});
  ASSERT_TRUE(s.has_value());
  EXPECT_NEAR(*s, 0.5, kParameterTolerance);
}

TEST(MapGeometryTest, SegmentAgainstAPrismInClosedForm) {
  // A 10 m square, 20 m tall, x 0..10, y 0..10: roof at z = −20.
  const auto edges = EdgesOfRings({Square(0, 0, 10)});
  // Level flight at 15 m altitude from x = −10 to x = 20 along y = 5: enters the west wall at x = 0, t = 1/3.
  auto t = FirstEntryIntoPrism(edges, 20.0, {-10, 5, -15}, {20, 5, -15});
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, 1.0 / 3.0, kParameterTolerance);
  // The same flight at 25 m clears the roof; grazing it at exactly 20 m touches (closed prism).
  EXPECT_FALSE(FirstEntryIntoPrism(edges, 20.0, {-10, 5, -25}, {20, 5, -25}).has_value());
  EXPECT_TRUE(FirstEntryIntoPrism(edges, 20.0, {-10, 5, -20}, {20, 5, -20}).has_value());
  // A descent from (−10, 5, −30) to (10, 5, −10) crosses the roof height at t = 1/2, over x = 0: the first contact
  // is the roof edge, t = 1/2.
  t = FirstEntryIntoPrism(edges, 20.0, {-10, 5, -30}, {10, 5, -10});
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, 0.5, kParameterTolerance);
  // A vertical descent onto the roof centre meets the roof at t = (30 − 20) / 30.
  t = FirstEntryIntoPrism(edges, 20.0, {5, 5, -30}, {5, 5, 0});
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, 1.0 / 3.0, kParameterTolerance);
  // Climbing away from the roof at the side: below the roof only near the start, and outside the outline there.
  EXPECT_FALSE(FirstEntryIntoPrism(edges, 20.0, {-1, 5, -19}, {-1, 5, -40}).has_value());
  // Running along the wall (collinear with an edge) touches it.
  EXPECT_TRUE(FirstEntryIntoPrism(edges, 20.0, {0, -5, -5}, {0, 20, -5}).has_value());
}

TEST(MapGeometryTest, SegmentOutlineDistanceInClosedForm) {
  const auto edges = EdgesOfRings({Square(0, 0, 10)});
  EXPECT_NEAR(SegmentOutlineDistance(edges, {-5, 13}, {15, 13}), 3.0, kLengthTolerance);  // parallel, 3 m east
  EXPECT_NEAR(SegmentOutlineDistance(edges, {13, 14}, {20, 20}), 5.0, kLengthTolerance);  // corner (10, 10)
  EXPECT_NEAR(SegmentOutlineDistance(edges, {-5, 5}, {15, 5}), 0.0, kLengthTolerance);    // crosses
}

// --- kernels against Boost.Geometry ------------------------------------------------------------------------

TEST(MapGeometryTest, PointInConcavePolygonsAgreesWithBoostGeometry) {
  RandomStream random(11);
  int inside = 0, outside = 0;
  for (int polygon_index = 0; polygon_index < 40; ++polygon_index) {
    std::vector<Ring> rings = {RandomStar(random, {0, 0}, 12, 8.0, 30.0)};
    if (polygon_index % 2 == 1) rings.push_back(RandomStar(random, {0, 0}, 7, 1.0, 4.0));  // a courtyard
    const auto edges = EdgesOfRings(rings);
    const BoostPolygon reference = ToBoost(rings);
    ASSERT_TRUE(bg::is_valid(reference));
    for (int k = 0; k < 500; ++k) {
      const Eigen::Vector2d p(random.Uniform(-32, 32), random.Uniform(-32, 32));
      if (DistanceToEdges(edges, p) < kBoundaryBand) continue;
      const bool expected = bg::within(BoostPoint(p.x(), p.y()), reference);
      EXPECT_EQ(OutlineContains(edges, p), expected) << "polygon " << polygon_index << " point " << p.transpose();
      (expected ? inside : outside)++;
    }
  }
  EXPECT_GT(inside, 2000);  // both answers are exercised
  EXPECT_GT(outside, 2000);
}

TEST(MapGeometryTest, SegmentPrismFirstEntryAgreesWithBoostGeometry) {
  RandomStream random(12);
  int hits = 0, misses = 0;
  for (int polygon_index = 0; polygon_index < 40; ++polygon_index) {
    std::vector<Ring> rings = {RandomStar(random, {0, 0}, 10, 6.0, 25.0)};
    if (polygon_index % 3 == 0) rings.push_back(RandomStar(random, {0, 0}, 6, 1.0, 4.0));
    const double height = random.Uniform(5.0, 60.0);
    const auto edges = EdgesOfRings(rings);
    const BoostPolygon reference = ToBoost(rings);
    for (int k = 0; k < 250; ++k) {
      const Eigen::Vector3d a(random.Uniform(-40, 40), random.Uniform(-40, 40), -random.Uniform(0, 2 * height));
      const Eigen::Vector3d b(random.Uniform(-40, 40), random.Uniform(-40, 40), -random.Uniform(0, 2 * height));
      const auto t = FirstEntryIntoPrism(edges, height, a, b);
      const auto expected = ReferenceFirstEntry(reference, height, a, b);
      ASSERT_EQ(t.has_value(), expected.has_value()) << "polygon " << polygon_index << " segment " << k;
      if (t) {
        EXPECT_NEAR(*t, *expected, kParameterTolerance) << "polygon " << polygon_index << " segment " << k;
        ++hits;
      } else {
        ++misses;
      }
    }
  }
  EXPECT_GT(hits, 1500);
  EXPECT_GT(misses, 1500);
}

TEST(MapGeometryTest, DenseSamplingNeverFindsAContactTheExactTestMisses) {
  // A third, cruder computation: points every 1 cm along the segment. Any sampled point inside the prism means
  // the exact test must report a contact no later than that point.
  RandomStream random(13);
  const std::vector<Ring> rings = {UShape()};
  const auto edges = EdgesOfRings(rings);
  constexpr double kHeight = 30.0;
  for (int k = 0; k < 300; ++k) {
    const Eigen::Vector3d a(random.Uniform(-10, 40), random.Uniform(-10, 40), -random.Uniform(0, 60));
    const Eigen::Vector3d b(random.Uniform(-10, 40), random.Uniform(-10, 40), -random.Uniform(0, 60));
    const auto t = FirstEntryIntoPrism(edges, kHeight, a, b);
    const int samples = static_cast<int>((b - a).norm() / 0.01) + 1;
    for (int s = 0; s <= samples; ++s) {
      const double u = static_cast<double>(s) / samples;
      const Eigen::Vector3d p = a + u * (b - a);
      if (p.z() >= -kHeight && OutlineContains(edges, p.head<2>())) {
        ASSERT_TRUE(t.has_value()) << "segment " << k;
        EXPECT_LE(*t, u + kParameterTolerance);
        break;
      }
    }
  }
}

// --- the map: closed forms ---------------------------------------------------------------------------------

CityMap TwoBuildingMap() {
  // Building 0: 20 m square, 30 m tall at x 0..20, y 0..20. Building 1: the U shape shifted to x 50..80, 50 m tall.
  Building low{"low", {Square(0, 0, 20)}, 30.0};
  Ring u = UShape();
  for (auto& p : u) p += Eigen::Vector2d(50, 0);
  Building tall{"tall", {u}, 50.0};
  LandingSite roof;
  roof.id = "roof of low";
  roof.p_W = {10, 10, -30.0};
  roof.risk = 0.2;
  roof.radius = 5.0;
  LandingSite ground;
  ground.id = "in the notch";
  ground.p_W = {75, 15, 0.0};  // in the U's notch, on the ground
  ground.risk = 0.1;
  ground.radius = 3.0;
  return CityMap({low, tall}, {roof, ground});
}

TEST(CityMapTest, PointQueriesAndRooftopAssignment) {
  const CityMap map = TwoBuildingMap();
  EXPECT_EQ(map.BuildingContaining({10, 10, -29}), 0);
  EXPECT_EQ(map.BuildingContaining({10, 10, -31}), kNoBuilding);  // above the roof
  EXPECT_EQ(map.BuildingContaining({55, 15, -49}), 1);            // base of the U
  EXPECT_EQ(map.BuildingContaining({75, 15, -1}), kNoBuilding);   // in the notch
  EXPECT_NEAR(map.SurfaceAltitudeAt({10, 10}), 30.0, kLengthTolerance);
  EXPECT_NEAR(map.SurfaceAltitudeAt({75, 15}), 0.0, kLengthTolerance);
  EXPECT_NEAR(map.max_building_height(), 50.0, kLengthTolerance);
  EXPECT_EQ(map.tallest_building(), 1);
  EXPECT_EQ(map.site(0).building, 0);  // on the roof of "low"
  EXPECT_TRUE(map.site(0).on_rooftop());
  EXPECT_EQ(map.site(1).building, kNoBuilding);
}

TEST(CityMapTest, ApproachOntoItsOwnRoofIsFreeWhenThatBuildingIsIgnored) {
  const CityMap map = TwoBuildingMap();
  const LandingSite& roof = map.site(0);
  const Eigen::Vector3d above = roof.p_W + Eigen::Vector3d(0, 0, -15);  // 15 m above the pad
  EXPECT_TRUE(map.SegmentCollides(above, roof.p_W));                    // touches the roof …
  EXPECT_FALSE(map.SegmentCollides(above, roof.p_W, roof.building));    // … which is its own
  // A low pass into the U's notch and out again, at 10 m: clear inside the notch, hitting the far wall beyond.
  EXPECT_FALSE(map.SegmentCollides({85, 15, -10}, {65, 15, -10}));
  const SegmentHit hit = map.FirstHit({85, 15, -10}, {55, 15, -10});
  ASSERT_TRUE(hit.hit);
  EXPECT_EQ(hit.building, 1);
  EXPECT_NEAR(hit.p_W.x(), 60.0, kLengthTolerance);  // the notch's bottom wall at x = 50 + 10
  EXPECT_NEAR(hit.fraction, 25.0 / 30.0, kParameterTolerance);
  // Flying over both at 51 m: nothing.
  EXPECT_FALSE(map.SegmentCollides({-10, 10, -51}, {90, 10, -51}));
  EXPECT_FALSE(map.FirstHit({-10, 10, -51}, {90, 10, -51}).hit);
}

TEST(CityMapTest, TallestBuildingUnderARouteAndTheCruiseAltitude) {
  const CityMap map = TwoBuildingMap();
  const std::vector<Eigen::Vector2d> over_low = {{-10, 10}, {30, 10}};
  EXPECT_NEAR(map.TallestBuildingUnder(over_low).height, 30.0, kLengthTolerance);
  EXPECT_EQ(map.TallestBuildingUnder(over_low).building, 0);
  EXPECT_NEAR(map.CruiseAltitude(over_low), 30.0 + kCruiseClearanceAboveBuildings, kLengthTolerance);
  // Along y = 40, 10 m east of the U (y 0..30) and 20 m east of "low": nothing under it, the U within 10 m.
  const std::vector<Eigen::Vector2d> beside = {{-10, 40}, {100, 40}};
  EXPECT_EQ(map.TallestBuildingUnder(beside).building, kNoBuilding);
  EXPECT_NEAR(map.TallestBuildingUnder(beside).height, 0.0, kLengthTolerance);
  EXPECT_EQ(map.TallestBuildingUnder(beside, 9.9).building, kNoBuilding);
  EXPECT_EQ(map.TallestBuildingUnder(beside, 10.0).building, 1);
  // A polyline: over "low", then north into the U's notch (not over the U), then out.
  const std::vector<Eigen::Vector2d> dogleg = {{10, -10}, {10, 10}, {75, 15}};
  EXPECT_EQ(map.TallestBuildingUnder(dogleg).building, 1);  // its second leg crosses the U's west arm
  const std::vector<Eigen::Vector2d> into_notch = {{75, 15}, {95, 15}};
  EXPECT_EQ(map.TallestBuildingUnder(into_notch).building, kNoBuilding);
}

TEST(CityMapTest, InvalidBuildingsAndSitesAreInputErrors) {
  EXPECT_THROW(CityMap({Building{"flat", {Square(0, 0, 10)}, 0.0}}, {}), InputError);
  EXPECT_THROW(CityMap({Building{"line", {Ring{Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1)}}, 10.0}}, {}), InputError);
  LandingSite buried;
  buried.id = "buried";
  buried.p_W = {5, 5, -3.0};  // 3 m altitude inside a 10 m building
  buried.risk = 0.5;
  buried.radius = 2.0;
  try {
    CityMap({Building{"b1", {Square(0, 0, 10)}, 10.0}}, {buried});
    FAIL() << "a site inside a building must be rejected";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("buried"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("b1"), std::string::npos) << e.what();
  }
  LandingSite risky = buried;
  risky.p_W = {50, 50, 0};
  risky.risk = 1.5;
  EXPECT_THROW(CityMap({}, {risky}), InputError);
}

// --- the map's indexes against a linear scan ----------------------------------------------------------------

struct BruteHit {
  std::optional<double> t;
  int building = kNoBuilding;
};

// Every building's edges, computed from its rings (not taken from the map's own flattened copy).
std::vector<std::vector<Edge2>> AllEdges(const CityMap& map) {
  std::vector<std::vector<Edge2>> edges;
  for (const Building& building : map.buildings()) edges.push_back(EdgesOfRings(building.rings));
  return edges;
}

BruteHit BruteFirstHit(const CityMap& map, const std::vector<std::vector<Edge2>>& edges, const Eigen::Vector3d& a,
                       const Eigen::Vector3d& b, int ignore) {
  BruteHit best;
  for (int k = 0; k < static_cast<int>(map.buildings().size()); ++k) {
    if (k == ignore) continue;
    const auto t = FirstEntryIntoPrism(edges[k], map.building(k).height, a, b);
    if (t && (!best.t || *t < *best.t)) best = {t, k};
  }
  return best;
}

void ExpectIndexAgreesWithLinearScan(const CityMap& map, std::uint64_t seed) {
  RandomStream random(seed);
  const auto edges = AllEdges(map);
  const Eigen::AlignedBox2d& bounds = map.bounds();
  auto random_point = [&](double max_altitude) {
    return Eigen::Vector3d(random.Uniform(bounds.min().x() - 20, bounds.max().x() + 20),
                           random.Uniform(bounds.min().y() - 20, bounds.max().y() + 20),
                           -random.Uniform(0.0, max_altitude));
  };
  int hits = 0, misses = 0, roof_hits = 0;
  for (int k = 0; k < 400; ++k) {
    const Eigen::Vector3d a = random_point(60.0);
    // Mostly short hops (the simulator's steps), some long legs (a planner's candidate paths).
    const double reach = k % 4 == 0 ? 400.0 : 40.0;
    const Eigen::Vector3d b =
        a + Eigen::Vector3d(random.Uniform(-reach, reach), random.Uniform(-reach, reach), random.Uniform(-20.0, 20.0));
    const int ignore = k % 5 == 0 ? static_cast<int>(random.UniformIndex(map.buildings().size())) : kNoBuilding;
    const BruteHit expected = BruteFirstHit(map, edges, a, b, ignore);
    EXPECT_EQ(map.SegmentCollides(a, b, ignore), expected.t.has_value()) << "segment " << k;
    const SegmentHit hit = map.FirstHit(a, b, ignore);
    ASSERT_EQ(hit.hit, expected.t.has_value()) << "segment " << k;
    if (hit.hit) {
      EXPECT_NEAR(hit.fraction, *expected.t, kParameterTolerance) << "segment " << k;
      ++hits;
    } else {
      ++misses;
    }
    // Points: the prism that contains the segment's start, if any; also at exactly some building's roof height
    // (a prism is closed: its roof is in it; BuildingContaining skips a cell whose roofs are all below the point).
    auto brute_containing = [&](const Eigen::Vector3d& p) {
      for (int b_index = 0; b_index < static_cast<int>(map.buildings().size()); ++b_index) {
        const Building& building = map.building(b_index);
        if (p.z() >= -building.height && OutlineContains(edges[b_index], p.head<2>())) return b_index;
      }
      return kNoBuilding;
    };
    EXPECT_EQ(map.BuildingContaining(a), brute_containing(a)) << "point " << k;
    const Eigen::Vector3d at_a_roof(a.x(), a.y(), -map.building(random.UniformIndex(map.buildings().size())).height);
    EXPECT_EQ(map.BuildingContaining(at_a_roof), brute_containing(at_a_roof)) << "point at a roof's height " << k;
    if (k < static_cast<int>(map.buildings().size())) {  // on building k's own roof, at its box's centre
      const Eigen::Vector2d centre = map.building_box(k).center();
      const Eigen::Vector3d on_roof(centre.x(), centre.y(), -map.building(k).height);
      const int expected = brute_containing(on_roof);
      EXPECT_EQ(map.BuildingContaining(on_roof), expected) << "on the roof of building " << k;
      roof_hits += expected != kNoBuilding;
    }
    // Routes: the tallest building within 0 m and 15 m of the horizontal leg.
    const std::vector<Eigen::Vector2d> route = {a.head<2>(), b.head<2>()};
    for (double half_width : {0.0, 15.0}) {
      double tallest = 0.0;
      for (int b_index = 0; b_index < static_cast<int>(map.buildings().size()); ++b_index) {
        if (SegmentOutlineDistance(edges[b_index], route[0], route[1]) <= half_width) {
          tallest = std::max(tallest, map.building(b_index).height);
        }
      }
      EXPECT_NEAR(map.TallestBuildingUnder(route, half_width).height, tallest, kLengthTolerance) << "route " << k;
    }
  }
  EXPECT_GT(hits, 40);
  EXPECT_GT(misses, 40);
  EXPECT_GT(roof_hits, 0);
}

TEST(CityMapTest, IndexedQueriesAgreeWithALinearScan) { ExpectIndexAgreesWithLinearScan(MakeProceduralCity(), 21); }

TEST(CityMapTest, AnswersDoNotDependOnTheCellSize) {
  // Tiny cells (buildings span many cells, exercising deduplication) and huge ones (one cell holds everything).
  for (double cell : {3.0, 2000.0}) {
    CityMapOptions options;
    options.building_cell_size = cell;
    options.site_cell_size = cell;
    ProceduralCityParams params;
    params.blocks_north = 5;
    params.blocks_east = 2;
    ExpectIndexAgreesWithLinearScan(MakeProceduralCity(params, options), 22);
  }
}

TEST(CityMapTest, SitesWithinRadiusAndBuildingsInBoxAgreeWithALinearScan) {
  const CityMap map = MakeProceduralCity();
  RandomStream random(23);
  std::vector<int> found;
  for (int k = 0; k < 300; ++k) {
    const Eigen::Vector2d centre(random.Uniform(-100, 1100), random.Uniform(-100, 950));
    const double radius = random.Uniform(0.0, 400.0);
    map.SitesWithinRadius(centre, radius, &found);
    std::vector<int> expected;
    for (int s = 0; s < static_cast<int>(map.sites().size()); ++s) {
      if ((map.site(s).p_W.head<2>() - centre).norm() <= radius) expected.push_back(s);
    }
    EXPECT_EQ(found, expected) << "query " << k;
    const Eigen::AlignedBox2d box(centre, centre + Eigen::Vector2d(radius, 0.5 * radius));
    std::vector<int> in_box;
    for (int b = 0; b < static_cast<int>(map.buildings().size()); ++b) {
      if (map.building_box(b).intersects(box)) in_box.push_back(b);
    }
    EXPECT_EQ(map.BuildingsInBox(box), in_box) << "query " << k;
  }
}

}  // namespace
}  // namespace uascma::planning
