#include "uascma/planning/emergency_landing.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "uascma/common/error.h"

namespace uascma::planning {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// m: checkpoints closer than this are the same place (an out-and-back route passes each point twice); far below
// the checkpoint spacing, far above the round-off of FlightPlan::PointAtDistance.
constexpr double kCheckpointCoincidence = 1e-3;

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

double ReachMargin(double flight_time, double eod) { return eod > 0.0 ? 1.0 - flight_time / eod : -kInfinity; }

void RequireFinite(const LandingRequest& request, const char* source) {
  if (!request.p_WB_W.allFinite()) throw InputError(source, "p_WB_W", "finite coordinates (m)");
  if (!request.v_WB_W.allFinite()) throw InputError(source, "v_WB_W", "a finite velocity (m/s)");
  if (!std::isfinite(request.yaw)) throw InputError(source, "yaw", fmt::format("a finite angle (rad), got {}", request.yaw));
  if (std::isnan(request.eod)) throw InputError(source, "eod", "a number of seconds, got NaN");
}

// The time into a trapezoid move (rest to rest) at which it has covered `distance` m of its `length` m.
double TimeAtDistanceInMove(const PlanSegment& segment, double length, double distance) {
  const double accel_distance = 0.5 * segment.accel * segment.accel_time * segment.accel_time;
  if (distance <= accel_distance) return std::sqrt(2.0 * distance / segment.accel);
  if (distance <= length - accel_distance) return segment.accel_time + (distance - accel_distance) / segment.peak_speed;
  return segment.duration - std::sqrt(2.0 * std::max(length - distance, 0.0) / segment.accel);
}

// When the plan passes arc length `distance` (s), consistent with FlightPlan::PointAtDistance.
double PlanTimeAtDistance(const FlightPlan& plan, double distance) {
  for (const PlanSegment& segment : plan.segments()) {
    const double length = (segment.end_W - segment.start_W).norm();
    if (distance <= length && length > 0.0) {
      return segment.start_time + TimeAtDistanceInMove(segment, length, distance);
    }
    distance -= length;
  }
  return plan.duration();
}

}  // namespace

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

bool LandAsapParams::IsValid(std::string* error) const {
  if (!(std::isfinite(min_footprint_speed) && min_footprint_speed >= 0.0)) {
    if (error) *error = fmt::format("min_footprint_speed: expected a finite number ≥ 0 m/s, got {}", min_footprint_speed);
    return false;
  }
  if (!(std::isfinite(footprint_tolerance) && footprint_tolerance >= 0.0)) {
    if (error) *error = fmt::format("footprint_tolerance: expected a finite number ≥ 0 m, got {}", footprint_tolerance);
    return false;
  }
  FootprintParams vehicle = footprint;  // speed and EOD come from the request: check the rest
  vehicle.initial_speed = 0.0;
  vehicle.eod = 0.0;
  std::string footprint_error;
  if (!vehicle.IsValid(&footprint_error)) {
    if (error) *error = "footprint." + footprint_error;
    return false;
  }
  return true;
}

bool LandPractParams::IsValid(std::string* error) const {
  const auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (!(checkpoint_count >= 1 && checkpoint_count <= 10'000)) {
    return fail(fmt::format("checkpoint_count: expected an integer in [1, 10000], got {}", checkpoint_count));
  }
  if (!(std::isfinite(site_search_radius) && site_search_radius >= 0.0)) {
    return fail(fmt::format("site_search_radius: expected a finite number ≥ 0 m, got {}", site_search_radius));
  }
  if (!(max_flight_time > 0.0)) {
    return fail(fmt::format("max_flight_time: expected > 0 s (or infinity), got {}", max_flight_time));
  }
  if (!(trajectories_per_checkpoint >= 1)) {
    return fail(fmt::format("trajectories_per_checkpoint: expected an integer ≥ 1, got {}", trajectories_per_checkpoint));
  }
  return true;
}

const char* LandingPathKindName(LandingPathKind kind) {
  switch (kind) {
    case LandingPathKind::kNone: return "none";
    case LandingPathKind::kClimbOver: return "climb-over";
    case LandingPathKind::kDetour: return "detour";
    case LandingPathKind::kViaCheckpoint: return "via checkpoint";
  }
  return "?";
}

const char* LandingStatusName(LandingStatus status) {
  switch (status) {
    case LandingStatus::kOk: return "ok";
    case LandingStatus::kNoSiteInFootprint: return "no site in footprint";
    case LandingStatus::kNoStoredTrajectory: return "no stored trajectory";
    case LandingStatus::kNoFeasibleTrajectory: return "no feasible trajectory";
    case LandingStatus::kStartInsideBuilding: return "start inside a building";
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

std::string LandingResult::BriefReport() const {
  if (!ok()) return fmt::format("{}: {}", LandingStatusName(status), message);
  std::string report = fmt::format("site '{}' (risk {:.3f}) by {} in {:.2f} s, RM {:.4f}; {} candidates, {} planned, {} "
                                   "detour searches", site_id, site_risk, LandingPathKindName(path.kind), flight_time,
                                   reach_margin, candidates, planned, detour_searches);
  if (checkpoint >= 0) {
    report += fmt::format("; checkpoint {} ({:.2f} s to it + {:.2f} s stored)", checkpoint, time_to_checkpoint,
                          stored_flight_time);
  }
  return report;
}

// --- one site ----------------------------------------------------------------------------------------------------
LandingPathPlanner::LandingPathPlanner(const CityMap& map, const LandingPathParams& params)
    : map_(&map), params_(params) {
  std::string error;
  if (!params.IsValid(&error)) {
    const auto colon = error.find(':');
    throw InputError("landing path params", error.substr(0, colon), error.substr(std::min(colon + 2, error.size())));
  }
  std::vector<ConvexObstacle> hulls;
  std::vector<double> heights;
  hulls.reserve(map.buildings().size());
  std::vector<Eigen::Vector2d> corners;
  for (const Building& building : map.buildings()) {
    corners.clear();
    for (const Ring& ring : building.rings) corners.insert(corners.end(), ring.begin(), ring.end());
    hulls.push_back(MakeInflatedHull(corners, params.lateral_margin));
    hulls.back().building = static_cast<int>(hulls.size()) - 1;
    heights.push_back(building.height);
  }
  obstacles_ = ObstacleSet(std::move(hulls), std::move(heights));
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
  DetourResult detour = ShortestDetour(obstacles_, problem);
  if (detour.found()) {
    for (std::size_t i = 1; i < detour.points_NE.size(); ++i) {
      AppendPoint(start_W, Eigen::Vector3d(detour.points_NE[i].x(), detour.points_NE[i].y(), -altitude), &path.waypoints_W);
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
    const double kth = static_cast<int>(kept.size()) >= keep ? kept[keep - 1].path.flight_time + options.tie_window
                                                             : kInfinity;
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

// --- LandASAP ------------------------------------------------------------------------------------------------------
LandingResult PlanLandAsap(const LandingPathPlanner& planner, const LandAsapParams& params,
                           const LandingRequest& request) {
  std::string error;
  if (!params.IsValid(&error)) {
    const auto colon = error.find(':');
    throw InputError("LandASAP params", error.substr(0, colon), error.substr(std::min(colon + 2, error.size())));
  }
  RequireFinite(request, "LandASAP request");
  const CityMap& map = planner.map();
  LandingResult result;
  result.frame = HeadingFrame::FromState(request.p_WB_W, request.v_WB_W, request.yaw);
  if (map.IsInsideBuilding(request.p_WB_W)) {
    result.status = LandingStatus::kStartInsideBuilding;
    result.message = "the vehicle's position is inside a building";
    return result;
  }
  if (!(request.eod > 0.0)) {
    result.status = LandingStatus::kNoSiteInFootprint;
    result.message = fmt::format("EOD {} s: the footprint is empty", request.eod);
    return result;
  }

  // The footprint (§5.3.1) from the current horizontal speed and EOD, placed by the heading frame.
  FootprintParams footprint_params = params.footprint;
  footprint_params.initial_speed = std::max(request.v_WB_W.head<2>().norm(), params.min_footprint_speed);
  footprint_params.eod = request.eod;
  result.footprint = CalcFootprint(footprint_params);
  if (!result.footprint.ok()) {
    result.status = LandingStatus::kNoSiteInFootprint;
    result.message = "footprint: " + result.footprint.message;
    return result;
  }
  // Candidates: the map's site index over the ellipse's circumscribed circle about the vehicle, then the ellipse.
  const FootprintRegion& region = result.footprint.region;
  const double radius = std::abs(region.center_x) + std::max(region.semi_axis_x, region.semi_axis_y) +
                        params.footprint_tolerance;
  std::vector<int> candidates;
  map.SitesWithinRadius(request.p_WB_W.head<2>(), radius, &candidates);
  std::erase_if(candidates, [&](int site) {
    return !result.footprint.Contains(result.frame, map.site(site).p_W, params.footprint_tolerance);
  });
  result.candidates = static_cast<int>(candidates.size());
  if (candidates.empty()) {
    result.status = LandingStatus::kNoSiteInFootprint;
    result.message = fmt::format("no landing site in the footprint ({})", result.footprint.BriefReport());
    return result;
  }

  // Largest RM = shortest flight; RMs within kReachMarginTie ⇔ times within kReachMarginTie · t_EOD.
  SiteSearchOptions options;
  options.keep = 1;
  options.tie_window = kReachMarginTie * request.eod;
  options.plan_all = params.plan_all_candidates;
  SiteSearchResult search = planner.PlanToSites(request.p_WB_W, candidates, options);
  result.planned = search.planned;
  result.detour_searches = search.detour_searches;
  if (search.plans.empty()) {
    result.status = LandingStatus::kNoFeasibleTrajectory;
    result.message = fmt::format("none of the {} sites in the footprint has a feasible path ({} infeasible, {} refused "
                                 "by the collision check)", result.candidates, search.infeasible,
                                 search.verification_failures);
    return result;
  }
  const double fastest = search.plans.front().path.flight_time;
  std::size_t chosen = 0;
  for (std::size_t i = 1; i < search.plans.size() && search.plans[i].path.flight_time <= fastest + options.tie_window; ++i) {
    if (map.site(search.plans[i].site).risk < map.site(search.plans[chosen].site).risk) chosen = i;
  }
  const SitePlan& best = search.plans[chosen];
  result.status = LandingStatus::kOk;
  result.site = best.site;
  result.site_id = map.site(best.site).id;
  result.site_risk = map.site(best.site).risk;
  result.path = best.path;
  result.plan = best.path.ToFlightPlan(planner.params().limits);
  result.flight_time = result.plan.duration();
  result.reach_margin = ReachMargin(result.flight_time, request.eod);
  result.candidate_plans = std::move(search.plans);
  return result;
}

// --- LandPract -----------------------------------------------------------------------------------------------------
LandPractDatabase LandPractDatabase::Build(const LandingPathPlanner& planner, const FlightPlan& nominal_plan,
                                           const LandPractParams& params) {
  std::string error;
  if (!params.IsValid(&error)) {
    const auto colon = error.find(':');
    throw InputError("LandPract params", error.substr(0, colon), error.substr(std::min(colon + 2, error.size())));
  }
  const double length = nominal_plan.Length();
  if (!(length > 0.0)) throw InputError("LandPract", "nominal_plan", "a plan with a positive length");
  const CityMap& map = planner.map();
  LandPractDatabase database;
  database.params_ = params;
  database.planner_.push_back(planner);
  SiteSearchOptions options;
  options.keep = params.trajectories_per_checkpoint;
  options.max_flight_time = params.max_flight_time;
  std::vector<int> candidates;
  for (int k = 1; k <= params.checkpoint_count; ++k) {
    // Checkpoints divide the plan's length equally (§5.3.2.2): arc lengths k L / (N + 1).
    Checkpoint checkpoint;
    checkpoint.route_distance = length * k / (params.checkpoint_count + 1);
    checkpoint.p_W = nominal_plan.PointAtDistance(checkpoint.route_distance);
    checkpoint.plan_time = PlanTimeAtDistance(nominal_plan, checkpoint.route_distance);
    if (map.IsInsideBuilding(checkpoint.p_W)) {
      throw InputError("LandPract", "nominal_plan",
                       fmt::format("a plan clear of the buildings; checkpoint {} at ({:.1f}, {:.1f}, {:.1f}) m is inside "
                                   "one", k - 1, checkpoint.p_W.x(), checkpoint.p_W.y(), checkpoint.p_W.z()));
    }
    map.SitesWithinRadius(checkpoint.p_W.head<2>(), params.site_search_radius, &candidates);
    SiteSearchResult search = planner.PlanToSites(checkpoint.p_W, candidates, options);
    std::vector<StoredTrajectory> stored;
    for (SitePlan& plan : search.plans) {
      if (static_cast<int>(stored.size()) == params.trajectories_per_checkpoint) break;
      stored.push_back({plan.site, map.site(plan.site).risk, plan.path.flight_time, std::move(plan.path)});
    }
    database.checkpoints_.push_back(checkpoint);
    database.trajectories_.push_back(std::move(stored));
  }
  return database;
}

int LandPractDatabase::NearestCheckpoint(const Eigen::Vector3d& p_W, double plan_elapsed) const {
  int nearest = -1;
  double nearest_distance = kInfinity;
  for (int k = 0; k < static_cast<int>(checkpoints_.size()); ++k) {
    const double distance = (checkpoints_[k].p_W - p_W).norm();
    if (distance < nearest_distance) {
      nearest = k;
      nearest_distance = distance;
    }
  }
  if (nearest < 0 || std::isnan(plan_elapsed)) return nearest;
  // Checkpoints at the same place: the one the nominal plan passes closest in time to the vehicle's progress.
  int chosen = nearest;
  for (int k = 0; k < static_cast<int>(checkpoints_.size()); ++k) {
    if (k == nearest || (checkpoints_[k].p_W - checkpoints_[nearest].p_W).norm() > kCheckpointCoincidence) continue;
    if (std::abs(checkpoints_[k].plan_time - plan_elapsed) < std::abs(checkpoints_[chosen].plan_time - plan_elapsed)) {
      chosen = k;
    }
  }
  return chosen;
}

LandPractChoice LandPractDatabase::Lookup(const LandingRequest& request) const {
  RequireFinite(request, "LandPract request");
  LandPractChoice choice;
  if (checkpoints_.empty()) return choice;
  const LandingPathPlanner& planner = planner_.front();
  if (planner.map().IsInsideBuilding(request.p_WB_W)) {
    choice.status = LandingStatus::kStartInsideBuilding;
    return choice;
  }
  choice.checkpoint = NearestCheckpoint(request.p_WB_W, request.plan_elapsed);
  const std::vector<StoredTrajectory>& stored = trajectories_[choice.checkpoint];
  if (stored.empty()) return choice;  // kNoStoredTrajectory
  // The climb-over to the checkpoint, closed form after one map query.
  const Eigen::Vector3d& checkpoint = checkpoints_[choice.checkpoint].p_W;
  choice.transit_altitude = planner.TransitAltitude(request.p_WB_W, checkpoint);
  if (choice.transit_altitude > planner.params().max_transit_altitude &&
      choice.transit_altitude > -request.p_WB_W.z()) {
    choice.status = LandingStatus::kNoFeasibleTrajectory;
    return choice;
  }
  choice.time_to_checkpoint = planner.ClimbOverTime(request.p_WB_W, checkpoint, choice.transit_altitude);
  // The stored paths are sorted by time, and the time to the checkpoint is common: the first has the largest RM;
  // those within the RM tie go to the lower risk.
  const double window = request.eod > 0.0 ? kReachMarginTie * request.eod : 0.0;
  int best = 0;
  choice.scanned = 1;
  for (int j = 1; j < static_cast<int>(stored.size()) && stored[j].flight_time <= stored[0].flight_time + window; ++j) {
    ++choice.scanned;
    if (stored[j].risk < stored[best].risk) best = j;
  }
  choice.status = LandingStatus::kOk;
  choice.entry = best;
  choice.site = stored[best].site;
  choice.flight_time = choice.time_to_checkpoint + stored[best].flight_time;
  choice.reach_margin = ReachMargin(choice.flight_time, request.eod);
  return choice;
}

LandingResult LandPractDatabase::Plan(const LandingRequest& request) const {
  LandingResult result;
  const LandPractChoice choice = Lookup(request);
  result.status = choice.status;
  result.checkpoint = choice.checkpoint;
  if (choice.checkpoint >= 0) result.candidates = static_cast<int>(trajectories_[choice.checkpoint].size());
  result.planned = choice.scanned;
  if (!result.ok()) {
    switch (result.status) {
      case LandingStatus::kStartInsideBuilding: result.message = "the vehicle's position is inside a building"; break;
      case LandingStatus::kNoFeasibleTrajectory: result.message = "the checkpoint is out of reach below the ceiling"; break;
      default: result.message = checkpoints_.empty() ? "the database is empty"
                                                      : fmt::format("checkpoint {} has no stored path", choice.checkpoint);
    }
    return result;
  }
  const LandingPathPlanner& planner = planner_.front();
  const StoredTrajectory& stored = trajectories_[choice.checkpoint][choice.entry];
  const LandingPath leg = planner.ClimbOver(request.p_WB_W, checkpoints_[choice.checkpoint].p_W);
  LandingPath& path = result.path;
  path.kind = LandingPathKind::kViaCheckpoint;
  path.start_W = request.p_WB_W;
  path.waypoints_W = leg.waypoints_W;
  path.waypoints_W.insert(path.waypoints_W.end(), stored.path.waypoints_W.begin(), stored.path.waypoints_W.end());
  path.target_building = stored.path.target_building;
  path.transit_altitude = std::max(leg.transit_altitude, stored.path.transit_altitude);
  path.horizontal_length = leg.horizontal_length + stored.path.horizontal_length;
  path.flight_time = PathTime(path.start_W, path.waypoints_W, planner.params().limits);
  if (!planner.Verify(path)) {
    result.status = LandingStatus::kNoFeasibleTrajectory;
    result.message = "the path through the checkpoint failed the collision check";
    return result;
  }
  result.site = stored.site;
  result.site_id = planner.map().site(stored.site).id;
  result.site_risk = stored.risk;
  result.plan = path.ToFlightPlan(planner.params().limits);
  result.flight_time = result.plan.duration();
  result.reach_margin = ReachMargin(result.flight_time, request.eod);
  result.time_to_checkpoint = choice.time_to_checkpoint;
  result.stored_flight_time = stored.flight_time;
  return result;
}

}  // namespace uascma::planning
