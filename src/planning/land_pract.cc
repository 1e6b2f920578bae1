// LandPract (§5.3.2.2, Fig. 5.6, planning/land_pract.h): the database of pre-planned paths from the
// nominal plan's checkpoints, and its look-up.
#include "uascma/planning/land_pract.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "landing_internal.h"
#include "uascma/common/error.h"

namespace uascma::planning {
using namespace landing_internal;

namespace {

// m: checkpoints closer than this are the same place (an out-and-back route passes each point twice); far below
// the checkpoint spacing, far above the round-off of FlightPlan::PointAtDistance.
constexpr double kCheckpointCoincidence = 1e-3;

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

// --- parameters ---------------------------------------------------------------------------------------------------
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
    return fail(
        fmt::format("trajectories_per_checkpoint: expected an integer ≥ 1, got {}", trajectories_per_checkpoint));
  }
  return true;
}

// --- LandPract -----------------------------------------------------------------------------------------------------
std::optional<CheckpointInBuilding> FirstCheckpointInBuilding(const CityMap& map, const FlightPlan& nominal_plan,
                                                              const LandPractParams& params) {
  const double length = nominal_plan.Length();
  for (int k = 1; k <= params.checkpoint_count; ++k) {
    const Eigen::Vector3d p_W = nominal_plan.PointAtDistance(length * k / (params.checkpoint_count + 1));
    if (map.IsInsideBuilding(p_W)) return CheckpointInBuilding{k - 1, p_W};
  }
  return std::nullopt;
}

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
  if (const auto inside = FirstCheckpointInBuilding(map, nominal_plan, params)) {
    throw InputError("LandPract", "nominal_plan",
                     fmt::format("a plan clear of the buildings; checkpoint {} at ({:.1f}, {:.1f}, {:.1f}) m is inside "
                                 "one",
                                 inside->checkpoint, inside->p_W.x(), inside->p_W.y(), inside->p_W.z()));
  }
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
      case LandingStatus::kStartInsideBuilding:
        result.message = "the vehicle's position is inside a building";
        break;
      case LandingStatus::kNoFeasibleTrajectory:
        result.message = "the checkpoint is out of reach below the ceiling";
        break;
      default:
        result.message = checkpoints_.empty() ? "the database is empty"
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
