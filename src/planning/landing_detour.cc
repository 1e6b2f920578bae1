#include "uascma/planning/landing_detour.h"

#include "uascma/planning/flight_plan.h"
#include "uascma/planning/map_geometry.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <queue>
#include <utility>

#include "uascma/common/error.h"

namespace uascma::planning {
namespace {

// The convex hull of the points, counter-clockwise, collinear and repeated points dropped (Andrew's monotone
// chain: sort, then build the lower and upper chains keeping only left turns).
std::vector<Eigen::Vector2d> ConvexHull(std::span<const Eigen::Vector2d> points) {
  std::vector<Eigen::Vector2d> sorted(points.begin(), points.end());
  std::sort(sorted.begin(), sorted.end(), [](const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
    return p.x() < q.x() || (p.x() == q.x() && p.y() < q.y());
  });
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
  if (sorted.size() < 3) return sorted;
  std::vector<Eigen::Vector2d> hull(2 * sorted.size());
  std::size_t k = 0;
  for (const auto& p : sorted) {  // lower chain
    while (k >= 2 && Cross2d(hull[k - 1] - hull[k - 2], p - hull[k - 2]) <= 0.0) --k;
    hull[k++] = p;
  }
  const std::size_t lower = k + 1;
  for (auto it = sorted.rbegin() + 1; it != sorted.rend(); ++it) {  // upper chain
    while (k >= lower && Cross2d(hull[k - 1] - hull[k - 2], *it - hull[k - 2]) <= 0.0) --k;
    hull[k++] = *it;
  }
  hull.resize(k - 1);  // the last point repeats the first
  return hull;
}

// Fills normals, offsets and box of a convex counter-clockwise polygon, dropping vertices that repeat their
// predecessor (within 1e-9 m), whose edge would have no direction.
ConvexObstacle FinishPolygon(std::vector<Eigen::Vector2d> vertices) {
  ConvexObstacle obstacle;
  for (const auto& v : vertices) {
    if (obstacle.vertices_NE.empty() || (v - obstacle.vertices_NE.back()).norm() > 1e-9)
      obstacle.vertices_NE.push_back(v);
  }
  while (obstacle.vertices_NE.size() > 1 &&
         (obstacle.vertices_NE.back() - obstacle.vertices_NE.front()).norm() <= 1e-9) {
    obstacle.vertices_NE.pop_back();
  }
  const std::size_t n = obstacle.vertices_NE.size();
  obstacle.normals.resize(n);
  obstacle.offsets.resize(n);
  obstacle.box.setEmpty();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& a = obstacle.vertices_NE[i];
    const Eigen::Vector2d edge = obstacle.vertices_NE[(i + 1) % n] - a;
    // Counter-clockwise in (x, y): the interior is on the left of each edge, the outward normal on its right.
    obstacle.normals[i] = Eigen::Vector2d(edge.y(), -edge.x()).normalized();
    obstacle.offsets[i] = obstacle.normals[i].dot(a);
    obstacle.box.extend(a);
  }
  return obstacle;
}

}  // namespace

double TrapezoidMoveTime(double length, double max_speed, double accel) {
  if (!(length > kMinMoveLength)) return 0.0;
  // The profile FlightPlan::Through uses, so that the two agree to the last bits.
  return CalcTrapezoid(length, max_speed, accel).duration;
}

double TrapezoidMoveLength(double time, double max_speed, double accel) {
  if (!(time > 0.0)) return 0.0;
  if (std::isinf(time)) return time;
  // Trapezoid: t = 2 v/α + (L − v²/α)/v  ⇔  L = v t − v²/α, valid from t = 2 v/α. Triangle: t = 2 √(L/α).
  if (time >= 2.0 * max_speed / accel) return max_speed * time - max_speed * max_speed / accel;
  return 0.25 * accel * time * time;
}

bool ConvexObstacle::StrictlyContains(const Eigen::Vector2d& p_NE, double tolerance) const {
  for (std::size_t i = 0; i < normals.size(); ++i) {
    if (normals[i].dot(p_NE) >= offsets[i] - tolerance) return false;
  }
  return !normals.empty();
}

bool ConvexObstacle::SegmentCrossesInterior(const Eigen::Vector2d& a_NE, const Eigen::Vector2d& b_NE,
                                            double tolerance) const {
  // Cyrus–Beck: p(t) = a + t (b − a), t ∈ [0, 1], is inside the shrunk polygon when n_i·p(t) < offset_i − tol
  // for every edge i; each edge bounds t from one side. A non-empty open interval means a crossing.
  const Eigen::Vector2d d = b_NE - a_NE;
  double t_enter = 0.0, t_exit = 1.0;
  for (std::size_t i = 0; i < normals.size(); ++i) {
    const double room = offsets[i] - tolerance - normals[i].dot(a_NE);  // n·(a + t d) < offset − tol ⇔ t·den < room
    const double den = normals[i].dot(d);
    if (den == 0.0) {
      if (room <= 0.0) return false;  // parallel to the edge and not inside it
      continue;
    }
    const double t = room / den;
    if (den > 0.0) {
      t_exit = std::min(t_exit, t);
    } else {
      t_enter = std::max(t_enter, t);
    }
    if (t_enter >= t_exit) return false;
  }
  return !normals.empty() && t_enter < t_exit;
}

ConvexObstacle MakeInflatedHull(std::span<const Eigen::Vector2d> points, double margin) {
  const std::vector<Eigen::Vector2d> hull = ConvexHull(points);
  if (hull.size() < 3) {
    // A point or a segment: its bounding box, grown (the 90° mitres of a box grown by g are the box grown by g).
    Eigen::AlignedBox2d box;
    for (const auto& p : points) box.extend(p);
    const double grow = std::max(margin, 1e-6);
    const Eigen::Vector2d lo = box.min().array() - grow, hi = box.max().array() + grow;
    return FinishPolygon({lo, {hi.x(), lo.y()}, hi, {lo.x(), hi.y()}});
  }
  if (margin == 0.0) return FinishPolygon(hull);
  // Grow each corner c: the outward normals of its two edges turn by φ ∈ (0, π) counter-clockwise; the exact
  // growth is the arc of radius r = margin from angle θ_in to θ_in + φ. We circumscribe it with m = ⌈φ / 90°⌉
  // tangent pieces: consecutive tangent lines (at θ_in + j φ/m) meet at angle θ_in + (j + ½) φ/m, at distance
  // r / cos(φ/(2m)) from c.
  const std::size_t n = hull.size();
  std::vector<Eigen::Vector2d> grown;
  grown.reserve(2 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& c = hull[i];
    const Eigen::Vector2d e_in = c - hull[(i + n - 1) % n], e_out = hull[(i + 1) % n] - c;
    const Eigen::Vector2d n_in = Eigen::Vector2d(e_in.y(), -e_in.x()).normalized();
    const Eigen::Vector2d n_out = Eigen::Vector2d(e_out.y(), -e_out.x()).normalized();
    const double theta_in = std::atan2(n_in.y(), n_in.x());
    const double phi = std::atan2(Cross2d(n_in, n_out), n_in.dot(n_out));  // (0, π) on a convex ccw hull
    const int pieces = std::max(1, static_cast<int>(std::ceil(phi / (0.5 * std::numbers::pi) - 1e-12)));
    const double step = phi / pieces;
    const double reach = margin / std::cos(0.5 * step);
    for (int j = 0; j < pieces; ++j) {
      const double angle = theta_in + (j + 0.5) * step;
      grown.emplace_back(c + reach * Eigen::Vector2d(std::cos(angle), std::sin(angle)));
    }
  }
  return FinishPolygon(std::move(grown));
}

ObstacleSet::ObstacleSet(std::vector<ConvexObstacle> obstacles, std::vector<double> heights)
    : obstacles_(std::move(obstacles)), heights_(std::move(heights)) {
  if (heights_.empty()) heights_.assign(obstacles_.size(), std::numeric_limits<double>::infinity());
  UASCMA_CHECK(heights_.size() == obstacles_.size(), "one height per obstacle");
  std::vector<Eigen::AlignedBox2d> boxes;
  boxes.reserve(obstacles_.size());
  for (const ConvexObstacle& o : obstacles_) {
    boxes.push_back(o.box);
    bounds_.extend(o.box);
  }
  if (obstacles_.empty()) return;
  // About two obstacles per cell, as the city map's own grids (city_map.h).
  grid_ = UniformGrid(boxes, UniformGrid::SuggestCellSize(bounds_, obstacles_.size(), 2.0, 10.0, 500.0));
}

bool ObstacleSet::SegmentIsFree(const Eigen::Vector2d& a_NE, const Eigen::Vector2d& b_NE, double min_height,
                                double tolerance) const {
  const Eigen::AlignedBox2d box(a_NE.cwiseMin(b_NE), a_NE.cwiseMax(b_NE));
  // An obstacle listed in several cells along the segment is tested again: the test is cheap and idempotent.
  return grid_.VisitNearSegment(a_NE, b_NE, 0.0, [&](int k) {
    return !(heights_[k] > min_height && obstacles_[k].box.intersects(box) &&
             obstacles_[k].SegmentCrossesInterior(a_NE, b_NE, tolerance));
  });
}

int ObstacleSet::StrictlyContaining(const Eigen::Vector2d& p_NE, double min_height, double tolerance, int skip) const {
  int found = -1;
  grid_.VisitBox(Eigen::AlignedBox2d(p_NE, p_NE), [&](int k) {
    if (k != skip && heights_[k] > min_height && obstacles_[k].box.contains(p_NE) &&
        obstacles_[k].StrictlyContains(p_NE, tolerance)) {
      found = k;
      return false;
    }
    return true;
  });
  return found;
}

std::vector<int> ObstacleSet::ActiveInBox(const Eigen::AlignedBox2d& box, double min_height) const {
  std::vector<int> active;
  grid_.VisitBox(box, [&](int k) {
    if (heights_[k] > min_height && obstacles_[k].box.intersects(box)) active.push_back(k);
    return true;
  });
  std::sort(active.begin(), active.end());
  active.erase(std::unique(active.begin(), active.end()), active.end());
  return active;
}

namespace {

// The bounding box of the budget ellipse |p − s| + |p − g| ≤ max_length (all obstacles' box without a budget).
Eigen::AlignedBox2d BudgetEllipseBox(const ObstacleSet& obstacles, const Eigen::Vector2d& s, const Eigen::Vector2d& g,
                                     double max_length) {
  Eigen::AlignedBox2d ellipse_box = obstacles.bounds();
  if (std::isfinite(max_length)) {
    const double major = 0.5 * max_length, focal = 0.5 * (g - s).norm();
    const double minor = std::sqrt(std::max(major * major - focal * focal, 0.0));
    const Eigen::Vector2d axis = focal > 0.0 ? Eigen::Vector2d((g - s).normalized()) : Eigen::Vector2d(1.0, 0.0);
    const Eigen::Vector2d half(std::sqrt(major * major * axis.x() * axis.x() + minor * minor * axis.y() * axis.y()),
                               std::sqrt(major * major * axis.y() * axis.y() + minor * minor * axis.x() * axis.x()));
    const Eigen::Vector2d centre = 0.5 * (s + g);
    ellipse_box = Eigen::AlignedBox2d(centre - half, centre + half);
  }
  return ellipse_box;
}

// Graph vertices: start, goal, and the corners inside the ellipse that are not strictly inside another active
// obstacle (such a corner cannot be reached without crossing that obstacle).
std::vector<Eigen::Vector2d> DetourGraphNodes(const ObstacleSet& obstacles, const Eigen::AlignedBox2d& ellipse_box,
                                              const Eigen::Vector2d& s, const Eigen::Vector2d& g, double max_length,
                                              double min_height, double tol) {
  std::vector<Eigen::Vector2d> nodes = {s, g};
  for (int k : obstacles.ActiveInBox(ellipse_box, min_height)) {
    for (const Eigen::Vector2d& v : obstacles.obstacle(k).vertices_NE) {
      if ((v - s).norm() + (v - g).norm() > max_length) continue;
      if (obstacles.StrictlyContaining(v, min_height, tol, k) >= 0) continue;
      nodes.push_back(v);
    }
  }
  return nodes;
}

// The path to `goal` by the parents of the search, start first, and its length.
void SetPathFromParents(const std::vector<Eigen::Vector2d>& nodes, const std::vector<int>& parent, int goal,
                        DetourResult* result) {
  for (int v = goal; v != -1; v = parent[v]) result->points_NE.push_back(nodes[v]);
  std::reverse(result->points_NE.begin(), result->points_NE.end());
  for (std::size_t i = 1; i < result->points_NE.size(); ++i) {
    result->length += (result->points_NE[i] - result->points_NE[i - 1]).norm();
  }
}

}  // namespace

DetourResult ShortestDetour(const ObstacleSet& obstacles, const DetourProblem& problem) {
  DetourResult result;
  const double tol = problem.tolerance;
  const double min_height = problem.min_height;
  const Eigen::Vector2d& s = problem.start_NE;
  const Eigen::Vector2d& g = problem.goal_NE;
  const auto move_time = [&](double length) { return TrapezoidMoveTime(length, problem.max_speed, problem.accel); };
  const auto visible = [&](const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
    ++result.visibility_tests;
    return obstacles.SegmentIsFree(p, q, min_height, tol);
  };

  if (obstacles.StrictlyContaining(s, min_height, tol) >= 0 || obstacles.StrictlyContaining(g, min_height, tol) >= 0) {
    result.status = DetourStatus::kStartBlocked;
    return result;
  }
  const double budget = problem.time_budget;
  const double direct_time = move_time((g - s).norm());
  if (!(direct_time < budget)) return result;  // nothing can beat the straight line (subadditivity)
  if (visible(s, g)) {
    result.status = DetourStatus::kFound;
    result.points_NE = {s, g};
    result.time = direct_time;
    result.length = (g - s).norm();
    result.graph_vertices = 2;
    return result;
  }

  // The budget ellipse |p − s| + |p − g| ≤ Λ: the graph's vertices lie inside it.
  const double max_length = TrapezoidMoveLength(budget, problem.max_speed, problem.accel);
  const std::vector<Eigen::Vector2d> nodes =
      DetourGraphNodes(obstacles, BudgetEllipseBox(obstacles, s, g, max_length), s, g, max_length, min_height, tol);
  const int count = static_cast<int>(nodes.size());
  result.graph_vertices = count;
  constexpr int kStart = 0, kGoal = 1;
  std::vector<double> potential(count), cost(count, std::numeric_limits<double>::infinity());
  std::vector<int> parent(count, -1);
  std::vector<char> settled(count, 0);
  for (int i = 0; i < count; ++i) potential[i] = move_time((nodes[i] - g).norm());

  // Dijkstra with the consistent potential (A* on the visibility graph), edges tested lazily: an edge is tested
  // only when it would improve its end and could still lead to a path faster than the goal's and the budget.
  using Entry = std::pair<double, int>;  // (cost + potential, vertex)
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  cost[kStart] = 0.0;
  open.emplace(potential[kStart], kStart);
  while (!open.empty()) {
    const auto [key, u] = open.top();
    open.pop();
    if (settled[u]) continue;
    if (!(key < std::min(budget, cost[kGoal]))) break;  // nothing left can beat the goal's cost or the budget
    settled[u] = 1;
    ++result.settled;
    if (u == kGoal) break;
    for (int v = 0; v < count; ++v) {
      if (settled[v]) continue;
      const double through = cost[u] + move_time((nodes[v] - nodes[u]).norm());
      if (!(through < cost[v]) || !(through + potential[v] < std::min(budget, cost[kGoal]))) continue;
      if (!visible(nodes[u], nodes[v])) continue;
      cost[v] = through;
      parent[v] = u;
      open.emplace(through + potential[v], v);
    }
  }
  if (!(cost[kGoal] < budget)) return result;

  result.status = DetourStatus::kFound;
  result.time = cost[kGoal];
  SetPathFromParents(nodes, parent, kGoal, &result);
  return result;
}

}  // namespace uascma::planning
