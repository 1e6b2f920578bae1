// The emergency path planner (planning/landing_path.h: THE TRAJECTORY MODEL): the climb-over and the
// visibility-graph detour to a site, their verification, and the multi-site search.
#include "uascma/planning/landing_path.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "landing_internal.h"
#include "uascma/common/error.h"

namespace uascma::planning {
using namespace landing_internal;

namespace {

double Altitude(const Eigen::Vector3d& p_W) { return -p_W.z(); }
double HorizontalDistance(const Eigen::Vector3d& a_W, const Eigen::Vector3d& b_W) {
  return (b_W.head<2>() - a_W.head<2>()).norm();
}

double HorizontalMoveTime(double length, const PlanLimits& limits) {
  return TrapezoidMoveTime(length, limits.cruise_speed, limits.horizontal_accel);
}
double VerticalMoveTime(double height, const PlanLimits& limits) {
  return TrapezoidMoveTime(std::abs(height), limits.vertical_speed, limits.vertical_accel);
}

double HorizontalLength(const Eigen::Vector3d& start_W, const std::vector<Eigen::Vector3d>& waypoints_W) {
  double length = 0.0;
  Eigen::Vector3d from = start_W;
  for (const Eigen::Vector3d& to : waypoints_W) {
    length += HorizontalDistance(from, to);
    from = to;
  }
  return length;
}

// Appends `point` unless it repeats the last point (start_W when empty) within kMinMoveLength.
void AppendPoint(const Eigen::Vector3d& start_W, const Eigen::Vector3d& point, std::vector<Eigen::Vector3d>* points) {
  const Eigen::Vector3d& last = points->empty() ? start_W : points->back();
  if ((point - last).norm() > kMinMoveLength) points->push_back(point);
}

// Ends the path exactly at the target: the last point is replaced by it when they are within kMinMoveLength.
void EndAt(const Eigen::Vector3d& start_W, const Eigen::Vector3d& target_W, std::vector<Eigen::Vector3d>* points) {
  if (!points->empty() && (points->back() - target_W).norm() <= kMinMoveLength) points->pop_back();
  AppendPoint(start_W, target_W, points);
}

// Site order: faster first, then the lower risk, then the lower index.
bool FasterSite(const SitePlan& a, const SitePlan& b, const CityMap& map) {
  if (a.path.flight_time != b.path.flight_time) return a.path.flight_time < b.path.flight_time;
  const double risk_a = map.site(a.site).risk, risk_b = map.site(b.site).risk;
  if (risk_a != risk_b) return risk_a < risk_b;
  return a.site < b.site;
}

}  // namespace

namespace landing_internal {

// The time of a path of pure moves (horizontal or vertical, as every LandingPath is), summed move by move as
// FlightPlan::Through does.
double PathTime(const Eigen::Vector3d& start_W, const std::vector<Eigen::Vector3d>& waypoints_W,
                const PlanLimits& limits) {
  double time = 0.0;
  Eigen::Vector3d from = start_W;
  for (const Eigen::Vector3d& to : waypoints_W) {
    const double horizontal = HorizontalDistance(from, to), vertical = std::abs(to.z() - from.z());
    UASCMA_CHECK(horizontal <= kMinMoveLength || vertical <= kMinMoveLength,
                 "a landing path has only horizontal and vertical moves");
    time += horizontal > vertical ? HorizontalMoveTime(horizontal, limits) : VerticalMoveTime(vertical, limits);
    from = to;
  }
  return time;
}

}  // namespace landing_internal

// --- parameters --------------------------------------------------------------------------------------------------
bool LandingPathParams::IsValid(std::string* error) const {
  const auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (!(std::isfinite(lateral_margin) && lateral_margin >= 0.0)) {
    return fail(fmt::format("lateral_margin: expected a finite number ≥ 0 m, got {}", lateral_margin));
  }
  if (!(std::isfinite(vertical_clearance) && vertical_clearance > 0.0)) {
    return fail(fmt::format("vertical_clearance: expected a finite number > 0 m, got {}", vertical_clearance));
  }
  if (!(max_transit_altitude > 0.0)) {
    return fail(fmt::format("max_transit_altitude: expected > 0 m (or infinity), got {}", max_transit_altitude));
  }
  if (!(std::isfinite(geometry_tolerance) && geometry_tolerance > 0.0 && geometry_tolerance < 1e-2)) {
    return fail(fmt::format("geometry_tolerance: expected a number in (0, 0.01) m, got {}", geometry_tolerance));
  }
  std::string limits_error;
  if (!limits.IsValid(&limits_error)) return fail("limits." + limits_error);
  return true;
}

const char* LandingPathKindName(LandingPathKind kind) {
  switch (kind) {
    case LandingPathKind::kNone:
      return "none";
    case LandingPathKind::kClimbOver:
      return "climb-over";
    case LandingPathKind::kDetour:
      return "detour";
    case LandingPathKind::kViaCheckpoint:
      return "via checkpoint";
  }
  return "?";
}

FlightPlan LandingPath::ToFlightPlan(const PlanLimits& limits) const {
  std::vector<Waypoint> waypoints;
  waypoints.reserve(waypoints_W.size());
  Eigen::Vector3d from = start_W;
  for (const Eigen::Vector3d& to : waypoints_W) {
    Waypoint waypoint;
    waypoint.p_W = to;
    if (HorizontalDistance(from, to) > kMinMoveLength) {
      waypoint.label = kind == LandingPathKind::kDetour ? "emergency detour" : "emergency transit";
    } else {
      waypoint.label = to.z() < from.z() ? "emergency climb" : "emergency descent";
    }
    waypoints.push_back(std::move(waypoint));
    from = to;
  }
  return FlightPlan::Through(start_W, waypoints, limits);
}

// --- one site ----------------------------------------------------------------------------------------------------
LandingPathPlanner::LandingPathPlanner(const CityMap& map, const LandingPathParams& params)
    : LandingPathPlanner(map, params, nullptr) {}

LandingPathPlanner::LandingPathPlanner(const CityMap& map, const LandingPathParams& params,
                                       std::shared_ptr<const ObstacleSet> obstacles)
    : map_(&map), params_(params), obstacles_(std::move(obstacles)) {
  std::string error;
  if (!params.IsValid(&error)) {
    const auto colon = error.find(':');
    throw InputError("landing path params", error.substr(0, colon), error.substr(std::min(colon + 2, error.size())));
  }
  if (!obstacles_) obstacles_ = InflateBuildings(map, params.lateral_margin);
  UASCMA_CHECK(obstacles_->size() == static_cast<int>(map.buildings().size()),
               "shared obstacles are one per building of this map");
}

std::shared_ptr<const ObstacleSet> LandingPathPlanner::InflateBuildings(const CityMap& map, double lateral_margin) {
  std::vector<ConvexObstacle> hulls;
  std::vector<double> heights;
  hulls.reserve(map.buildings().size());
  std::vector<Eigen::Vector2d> corners;
  for (const Building& building : map.buildings()) {
    corners.clear();
    for (const Ring& ring : building.rings) corners.insert(corners.end(), ring.begin(), ring.end());
    hulls.push_back(MakeInflatedHull(corners, lateral_margin));
    hulls.back().building = static_cast<int>(hulls.size()) - 1;
    heights.push_back(building.height);
  }
  return std::make_shared<const ObstacleSet>(std::move(hulls), std::move(heights));
}

double LandingPathPlanner::LowerBoundTime(const Eigen::Vector3d& start_W, const Eigen::Vector3d& target_W) const {
  return HorizontalMoveTime(HorizontalDistance(start_W, target_W), params_.limits) +
         VerticalMoveTime(Altitude(start_W) - Altitude(target_W), params_.limits);
}

double LandingPathPlanner::TransitAltitude(const Eigen::Vector3d& start_W, const Eigen::Vector3d& target_W) const {
  const Eigen::Vector2d route[2] = {start_W.head<2>(), target_W.head<2>()};
  // The ground counts as a building of height 0: the transit is never lower than the clearance.
  const double tallest = map_->TallestBuildingUnder(route, params_.lateral_margin).height;
  return std::max({Altitude(start_W), Altitude(target_W), tallest + params_.vertical_clearance});
}

double LandingPathPlanner::ClimbOverTime(const Eigen::Vector3d& start_W, const Eigen::Vector3d& target_W,
                                         double transit_altitude) const {
  return VerticalMoveTime(transit_altitude - Altitude(start_W), params_.limits) +
         HorizontalMoveTime(HorizontalDistance(start_W, target_W), params_.limits) +
         VerticalMoveTime(transit_altitude - Altitude(target_W), params_.limits);
}

LandingPath LandingPathPlanner::ClimbOver(const Eigen::Vector3d& start_W, const Eigen::Vector3d& target_W,
                                          int target_building) const {
  LandingPath path;
  path.start_W = start_W;
  path.target_building = target_building;
  const double transit = TransitAltitude(start_W, target_W);
  path.transit_altitude = transit;
  if (transit > params_.max_transit_altitude && transit > Altitude(start_W)) return path;  // above the ceiling
  AppendPoint(start_W, Eigen::Vector3d(start_W.x(), start_W.y(), -transit), &path.waypoints_W);
  AppendPoint(start_W, Eigen::Vector3d(target_W.x(), target_W.y(), -transit), &path.waypoints_W);
  EndAt(start_W, target_W, &path.waypoints_W);
  path.kind = LandingPathKind::kClimbOver;
  path.flight_time = PathTime(start_W, path.waypoints_W, params_.limits);
  path.horizontal_length = HorizontalLength(start_W, path.waypoints_W);
  return path;
}

LandingPath LandingPathPlanner::Detour(const Eigen::Vector3d& start_W, const Eigen::Vector3d& target_W,
                                       int target_building, double time_budget, DetourResult* searched) const {
  LandingPath path;
  path.start_W = start_W;
  path.target_building = target_building;
  const double altitude = Altitude(start_W);
  path.transit_altitude = altitude;
  // Only downwards to the target, and never lower than the clearance above the ground (as the climb-over).
  if (!params_.allow_detour || Altitude(target_W) > altitude || altitude < params_.vertical_clearance) return path;
  const double descent_time = VerticalMoveTime(altitude - Altitude(target_W), params_.limits);
  const double horizontal_budget = time_budget - descent_time;
  if (!(horizontal_budget > 0.0)) return path;

  // The buildings that reach within the clearance of this altitude are in the way: height > altitude − clearance.
  DetourProblem problem;
  problem.start_NE = start_W.head<2>();
  problem.goal_NE = target_W.head<2>();
  problem.min_height = altitude - params_.vertical_clearance;
  problem.max_speed = params_.limits.cruise_speed;
  problem.accel = params_.limits.horizontal_accel;
  problem.time_budget = horizontal_budget;
  problem.tolerance = params_.geometry_tolerance;
  DetourResult detour = ShortestDetour(*obstacles_, problem);
  if (detour.found()) {
    for (std::size_t i = 1; i < detour.points_NE.size(); ++i) {
      AppendPoint(start_W, Eigen::Vector3d(detour.points_NE[i].x(), detour.points_NE[i].y(), -altitude),
                  &path.waypoints_W);
    }
    EndAt(start_W, target_W, &path.waypoints_W);
    path.kind = LandingPathKind::kDetour;
    path.flight_time = PathTime(start_W, path.waypoints_W, params_.limits);
    path.horizontal_length = HorizontalLength(start_W, path.waypoints_W);
  }
  if (searched != nullptr) *searched = std::move(detour);
  return path;
}

bool LandingPathPlanner::Verify(const LandingPath& path) const {
  if (!path.feasible()) return false;
  Eigen::Vector3d from = path.start_W;
  for (std::size_t i = 0; i < path.waypoints_W.size(); ++i) {
    const bool last = i + 1 == path.waypoints_W.size();
    if (map_->SegmentCollides(from, path.waypoints_W[i], last ? path.target_building : kNoBuilding)) return false;
    from = path.waypoints_W[i];
  }
  return true;
}

LandingPath LandingPathPlanner::PlanToPoint(const Eigen::Vector3d& start_W, const Eigen::Vector3d& target_W,
                                            int target_building, double time_budget, SiteSearchResult* counters) const {
  if (map_->IsInsideBuilding(start_W)) {
    LandingPath none;
    none.start_W = start_W;
    none.target_building = target_building;
    return none;
  }
  LandingPath climb = ClimbOver(start_W, target_W, target_building);
  LandingPath detour;
  // A detour can only help when the climb-over climbs (otherwise it flies the straight line, the lower bound).
  if (params_.allow_detour && (!climb.feasible() || climb.transit_altitude > Altitude(start_W))) {
    const double limit = std::min(time_budget, climb.flight_time);
    if (LowerBoundTime(start_W, target_W) < limit) {
      if (counters != nullptr) ++counters->detour_searches;
      detour = Detour(start_W, target_W, target_building, limit);
    }
  }
  const bool detour_first = detour.feasible() && detour.flight_time < climb.flight_time;
  LandingPath& first = detour_first ? detour : climb;
  LandingPath& second = detour_first ? climb : detour;
  if (Verify(first)) return std::move(first);
  if (first.feasible() && counters != nullptr) ++counters->verification_failures;
  if (Verify(second)) return std::move(second);
  if (second.feasible() && counters != nullptr) ++counters->verification_failures;
  LandingPath none;
  none.start_W = start_W;
  none.target_building = target_building;
  return none;
}

LandingPath LandingPathPlanner::PlanToSite(const Eigen::Vector3d& start_W, int site, double time_budget) const {
  const LandingSite& landing = map_->site(site);
  return PlanToPoint(start_W, landing.p_W, landing.building, time_budget);
}

SiteSearchResult LandingPathPlanner::PlanToSites(const Eigen::Vector3d& start_W, std::span<const int> sites,
                                                 const SiteSearchOptions& options) const {
  SiteSearchResult result;
  result.candidates = static_cast<int>(sites.size());
  const int keep = std::max(options.keep, 1);
  // Best first: the sites in the order of their lower bound (then risk, then index).
  struct Candidate {
    double lower_bound;
    double risk;
    int site;
  };
  std::vector<Candidate> order;
  order.reserve(sites.size());
  for (int site : sites) {
    const LandingSite& landing = map_->site(site);
    order.push_back({LowerBoundTime(start_W, landing.p_W), landing.risk, site});
  }
  std::sort(order.begin(), order.end(), [](const Candidate& a, const Candidate& b) {
    if (a.lower_bound != b.lower_bound) return a.lower_bound < b.lower_bound;
    if (a.risk != b.risk) return a.risk < b.risk;
    return a.site < b.site;
  });

  std::vector<SitePlan>& kept = result.plans;
  // The time a site must not exceed to be kept: the keep-th fastest + the tie window (and the flight budget).
  const auto threshold = [&] {
    const double kth =
        static_cast<int>(kept.size()) >= keep ? kept[keep - 1].path.flight_time + options.tie_window : kInfinity;
    return std::min(kth, options.max_flight_time);
  };
  for (const Candidate& candidate : order) {
    const double limit = threshold();
    if (!options.plan_all && candidate.lower_bound > limit) break;  // no later site can be kept
    ++result.planned;
    // Budget a hair above the threshold: a site exactly at it still ties.
    const double budget = options.plan_all ? kInfinity : limit + 1e-12 * (1.0 + std::abs(limit));
    const LandingSite& landing = map_->site(candidate.site);
    SitePlan plan;
    plan.site = candidate.site;
    plan.lower_bound = candidate.lower_bound;
    plan.path = PlanToPoint(start_W, landing.p_W, landing.building, budget, &result);
    if (!plan.path.feasible()) {
      ++result.infeasible;
      continue;
    }
    if (plan.path.flight_time > options.max_flight_time) continue;
    const auto at = std::upper_bound(kept.begin(), kept.end(), plan,
                                     [&](const SitePlan& a, const SitePlan& b) { return FasterSite(a, b, *map_); });
    kept.insert(at, std::move(plan));
    if (!options.plan_all) {
      const double now = threshold();
      while (static_cast<int>(kept.size()) > keep && kept.back().path.flight_time > now) kept.pop_back();
    }
  }
  return result;
}

}  // namespace uascma::planning
