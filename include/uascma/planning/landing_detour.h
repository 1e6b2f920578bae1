#pragma once
// The constant-altitude detour of the emergency-landing planners (include/uascma/planning/landing_path.h):
// the minimum-time path in the horizontal plane around polygonal obstacles, found on their visibility graph.
//
// OBSTACLES. At a given altitude a building whose roof is not far enough below the vehicle is an obstacle in the
// horizontal plane. Each is modelled by a convex polygon: the convex hull of its outline (every ring: a
// courtyard or a notch is filled in), grown by the lateral margin. The exact grown hull (Minkowski sum with a
// disc) has circular corners; we circumscribe each corner arc by straight pieces (one piece per ≤ 90° of turn:
// a mitre for the 90° corners of a rectangle, whose tip lies √2 · margin from the corner). So the polygon
// contains every point within the margin of the outline, and no point farther than √2 · margin from it.
//
// PATH MODEL. The vehicle flies straight segments between stops, rest to rest, with the trapezoidal velocity
// profile of include/uascma/planning/flight_plan.h (speed limit v, acceleration limit α). A segment of length L
// takes
//   f(L) = L / v + v / α          when L ≥ v² / α   (trapezoid)
//   f(L) = 2 √(L / α)             otherwise          (triangle)                                   (TrapezoidMoveTime)
// and a path takes Σ f(L_i). f is increasing, concave and f(0) = 0, hence subadditive: f(L1) + f(L2) ≥
// f(L1 + L2), with equality only when one length is 0 — every stop costs time.
//
// WHAT IS EXACT. Among paths that avoid the obstacle interiors, the SHORTEST one turns only at obstacle vertices
// and its segments are edges of the visibility graph (vertices: the obstacle corners, start and goal; edges: the
// segments between them that do not cross an obstacle's interior) — the classical result for polygonal
// obstacles (Lozano-Pérez & Wesley 1979; de Berg et al., Computational Geometry, ch. 15). We search that graph
// with the edge cost f(L) instead of L: the result is the exact minimum-time path among the paths that stop
// only at obstacle corners, a set that contains the shortest path, so it is never slower than the shortest
// path flown with the same stops. LIMIT: because every stop costs time, the minimum-time path over ALL
// polygonal paths may turn at a point in free space: two tangent lines grazing two corners can meet above the
// gap between them, and one stop there can beat two stops at the corners (s = (−100, −10), corners (±1, 0),
// g = (100, −10), v = 5 m/s, α = 2 m/s²: 45.2 s against 46.8 s). The shortfall of our path against the
// unrestricted optimum is at most v/α per segment of the shortest path (f(L) ≤ L/v + v/α and L/v ≤ f(L)).
//
// SEARCH. Dijkstra's algorithm with the potential h(v) = f(|v − g|) (A* on the visibility graph, not on a grid):
// by the triangle inequality and subadditivity h(u) ≤ f(|u − v|) + h(v), so h is consistent and the search
// returns the same optimum as plain Dijkstra while settling fewer vertices. The graph is lazy: a vertex's edges
// are tested when it is settled, and an edge is tested only when it could lead to a path cheaper than the best
// known one and than the caller's time budget. With a budget T, every vertex of a path of time < T lies in
// the ellipse |p − s| + |p − g| ≤ f⁻¹(T) (subadditivity again: a path of length Λ takes at least f(Λ)), so
// only the vertices inside that ellipse are graph vertices, and only the obstacles that meet it matter
// (the caller passes those; see LandingPathPlanner::Detour).
//
// Frames and units: points p_NE in the horizontal (north, east) plane of the world frame W, metres; times in s.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <limits>
#include <span>
#include <vector>

#include "uascma/planning/map_grid.h"

namespace uascma::planning {

// f(L) of the header: the time (s) to fly a straight segment of `length` m from rest to rest with speed limit
// `max_speed` (m/s) and acceleration limit `accel` (m/s²), as FlightPlan::Through times each move. 0 for a
// length ≤ kMinMoveLength (FlightPlan::Through skips such moves).
double TrapezoidMoveTime(double length, double max_speed, double accel);
// The inverse: the longest segment (m) that takes at most `time` s (+infinity for an infinite time, 0 for ≤ 0).
double TrapezoidMoveLength(double time, double max_speed, double accel);
// Moves at most this long (m) are skipped by FlightPlan::Through (flight_plan.cc: "length > 1e-9").
inline constexpr double kMinMoveLength = 1e-9;

// A convex polygon obstacle in the horizontal plane, counter-clockwise in (north, east) (turning from north
// towards east), with its edges' outward unit normals: the interior is {p : normals[i]·p < offsets[i] ∀ i}.
struct ConvexObstacle {
  std::vector<Eigen::Vector2d> vertices_NE;  // m, n ≥ 3, counter-clockwise
  std::vector<Eigen::Vector2d> normals;      // edge i = vertices i → i+1 (mod n): outward unit normal
  std::vector<double> offsets;               // m, normals[i] · vertices_NE[i]
  Eigen::AlignedBox2d box;                   // m, bounding box of the vertices
  int building = -1;                         // the building it models (CityMap index), −1 for none

  // True when p lies deeper than `tolerance` (m, ≥ 0) inside every edge: strictly inside, boundary excluded.
  bool StrictlyContains(const Eigen::Vector2d& p_NE, double tolerance) const;
  // True when the closed segment a → b passes through the polygon shrunk by `tolerance` (m): a segment that only
  // touches the boundary (at a vertex, or sliding along an edge) does not cross. Cyrus–Beck clipping, O(n).
  bool SegmentCrossesInterior(const Eigen::Vector2d& a_NE, const Eigen::Vector2d& b_NE, double tolerance) const;
};

// The convex hull of `points` (Andrew's monotone chain; collinear points dropped) grown by `margin` (m, ≥ 0) with
// circumscribed corner pieces, one per ≤ 90° of turn (header comment). Fewer than three non-collinear points:
// their bounding box, grown the same way (grown by at least 1e-6 m when margin is 0 so it has an interior).
ConvexObstacle MakeInflatedHull(std::span<const Eigen::Vector2d> points, double margin);

// Convex obstacles indexed by a uniform grid over their boxes (include/uascma/planning/map_grid.h), each with a
// height: at a flight level only the obstacles taller than a threshold are ACTIVE (height > min_height), so one
// set serves every altitude. Immutable; queries are const.
class ObstacleSet {
 public:
  ObstacleSet() = default;
  // `heights` (m): one per obstacle, or empty for "always active" (height +infinity).
  explicit ObstacleSet(std::vector<ConvexObstacle> obstacles, std::vector<double> heights = {});

  int size() const { return static_cast<int>(obstacles_.size()); }
  const ConvexObstacle& obstacle(int k) const { return obstacles_[k]; }
  double height(int k) const { return heights_[k]; }

  // True when no active obstacle's interior (shrunk by `tolerance`, m) meets the segment a → b.
  bool SegmentIsFree(const Eigen::Vector2d& a_NE, const Eigen::Vector2d& b_NE, double min_height,
                     double tolerance) const;
  // An active obstacle other than `skip` that strictly contains p (ConvexObstacle::StrictlyContains), or −1.
  int StrictlyContaining(const Eigen::Vector2d& p_NE, double min_height, double tolerance, int skip = -1) const;
  // The active obstacles whose boxes meet `box`, in increasing order.
  std::vector<int> ActiveInBox(const Eigen::AlignedBox2d& box, double min_height) const;
  // The box of all obstacles (empty without any).
  const Eigen::AlignedBox2d& bounds() const { return bounds_; }

 private:
  std::vector<ConvexObstacle> obstacles_;
  std::vector<double> heights_;
  Eigen::AlignedBox2d bounds_;
  UniformGrid grid_;
};

struct DetourProblem {
  Eigen::Vector2d start_NE = Eigen::Vector2d::Zero();  // m
  Eigen::Vector2d goal_NE = Eigen::Vector2d::Zero();   // m
  double min_height = 0.0;                             // m: the obstacles taller than this are in the way (ObstacleSet)
  double max_speed = 5.0;                              // m/s, PlanLimits::cruise_speed
  double accel = 2.0;                                  // m/s², PlanLimits::horizontal_accel
  // s: only paths that take less than this are searched; +infinity searches them all.
  double time_budget = std::numeric_limits<double>::infinity();
  // m: the strict-interior tolerance of ConvexObstacle (numerical slack of the touching tests).
  double tolerance = 1e-6;
};

enum class DetourStatus {
  kFound,
  kStartBlocked,  // start or goal strictly inside an active obstacle (within the margin of a building)
  kNotFound,      // no path within the budget (or none at all)
};

struct DetourResult {
  DetourStatus status = DetourStatus::kNotFound;
  std::vector<Eigen::Vector2d> points_NE;                 // the path: start, the obstacle corners it turns at, goal
  double time = std::numeric_limits<double>::infinity();  // s, Σ f(L_i)
  double length = 0.0;                                    // m, Σ L_i
  int graph_vertices = 0;    // the vertices inside the budget ellipse (start and goal included)
  int settled = 0;           // vertices settled by the search
  int visibility_tests = 0;  // segment tests
  bool found() const { return status == DetourStatus::kFound; }
};

// The minimum-time path from start to goal around the active obstacles (header comment). Pure. Graph vertices: the
// corners, inside the budget ellipse, of the active obstacles whose boxes meet the ellipse's box, except corners
// strictly inside another active obstacle (unreachable). Cost O(S · V) segment tests for S settled and V graph
// vertices, each visiting the obstacles of the grid cells along the segment; the budget and the potential prune
// most of them.
DetourResult ShortestDetour(const ObstacleSet& obstacles, const DetourProblem& problem);

}  // namespace uascma::planning
