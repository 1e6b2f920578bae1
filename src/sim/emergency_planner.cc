// The map's emergency planners for the simulator: LandPract from a database built before flight, LandASAP online
// (planning/land_pract.h, planning/land_asap.h, §5.3.2.2), behind sim::EmergencyPlanner.
#include "uascma/sim/emergency_planner.h"

#include <memory>
#include <vector>

#include "uascma/planning/land_asap.h"
#include "uascma/planning/land_pract.h"
#include "uascma/planning/landing_path.h"

namespace uascma::sim {

namespace {

// A mission's geofence (planning/mission_file.h): an emergency path that leaves it is no plan
// (docs/modelling-choices.md#unavailable-actions then substitutes).
bool LeavesFence(const planning::Geofence* fence, const planning::FlightPlan& plan) {
  if (!fence) return false;
  std::vector<Eigen::Vector2d> path_NE{plan.start_W().head<2>()};
  for (const auto& segment : plan.segments()) path_NE.push_back(segment.end_W.head<2>());
  return !fence->AllowsPath(path_NE);
}

PointPlanner MakePointPlanner(std::shared_ptr<const planning::CityMap> map,
                              std::shared_ptr<const planning::LandingPathPlanner> planner,
                              std::shared_ptr<const planning::Geofence> fence) {
  return [map, planner, fence](const EmergencyRequest& r, const Eigen::Vector3d& target_W) {
    EmergencyPlan plan;
    const auto& sites = map->sites();
    const int nearest = NearestLandingSite(*map, target_W);
    const planning::LandingPath path = planner->PlanToSite(r.p_WB_W, nearest);
    if (!path.feasible()) {
      plan.message = "no path to site " + sites[nearest].id;
      return plan;
    }
    plan.plan = path.ToFlightPlan(planner->params().limits);
    if (LeavesFence(fence.get(), plan.plan)) {
      plan.message = "the path to site " + sites[nearest].id + " leaves the mission's geofence";
      return plan;
    }
    plan.status = planning::LandingStatus::kOk;
    plan.site = sites[nearest].id;
    plan.site_radius = sites[nearest].radius;
    return plan;
  };
}

}  // namespace

int NearestLandingSite(const planning::CityMap& map, const Eigen::Vector3d& p_W) {
  const auto& sites = map.sites();
  int nearest = -1;
  for (int k = 0; k < static_cast<int>(sites.size()); ++k) {
    if (nearest < 0 || (sites[k].p_W - p_W).norm() < (sites[nearest].p_W - p_W).norm()) nearest = k;
  }
  return nearest;
}

MapEmergencyPlanner MakeMapEmergencyPlanner(const Scenario& scenario, const planning::FlightPlan& nominal_plan,
                                            const models::DragTable& drag, const models::PropulsionParams& propulsion) {
  if (!scenario.map || scenario.map->sites().empty()) return {};
  planning::LandingPathParams path;
  path.limits = scenario.limits;
  // The hulls built with the map (Scenario::map_obstacles: at the default margin, as `path` has it) or, for a
  // scenario made without them, now.
  auto obstacles = scenario.map_obstacles
                       ? scenario.map_obstacles
                       : planning::LandingPathPlanner::InflateBuildings(*scenario.map, path.lateral_margin);
  auto planner = std::make_shared<const planning::LandingPathPlanner>(*scenario.map, path, std::move(obstacles));
  auto practical =
      std::make_shared<const planning::LandPractDatabase>(planning::LandPractDatabase::Build(*planner, nominal_plan));
  planning::LandAsapParams asap;
  asap.footprint.mass = scenario.body.mass;
  asap.footprint.drag_slope = planning::CruiseDragSlope(drag, scenario.limits.cruise_speed, scenario.body.mass);
  // A hovering vehicle's footprint of eqs. 5.10-5.11 is a point; LandASAP then plans as if it were cruising
  // (our choice: in the dissertation the action is taken in flight).
  asap.min_footprint_speed = scenario.limits.cruise_speed;
  const double rotor_max = propulsion.max_thrust;
  auto map = scenario.map;  // keeps the map alive as long as the planners
  MapEmergencyPlanner out;
  for (const auto& checkpoint : practical->checkpoints()) out.checkpoints_W.push_back(checkpoint.p_W);
  // A mission's geofence (planning/mission_file.h): an emergency path that leaves it is no plan
  // (docs/modelling-choices.md#unavailable-actions then substitutes); its forbidden sites were already dropped from the
  // map (WithMissionSafety).
  std::shared_ptr<const planning::Geofence> fence;
  if (scenario.route && !scenario.route->geofence.empty()) {
    fence = std::make_shared<const planning::Geofence>(scenario.route->geofence);
  }
  out.planner = [map, planner, practical, asap, rotor_max, fence](const EmergencyRequest& r) {
    const planning::LandingRequest request{r.p_WB_W, r.v_WB_W, r.yaw, r.eod_s, r.original_plan_elapsed_s};
    planning::LandingResult result;
    const bool land_asap = r.action == decision::CmaAction::kLandAsap;
    if (land_asap) {
      planning::LandAsapParams params = asap;
      // After the failure rule only four rotors fly (§4.4.1).
      params.footprint.available_thrust = (r.failed_motor != 0 ? 4.0 : 6.0) * rotor_max;
      result = planning::PlanLandAsap(*planner, params, request);
    } else {
      result = practical->Plan(request);
    }
    EmergencyPlan plan;
    plan.status = result.status;
    plan.message = result.message;
    if (!result.ok()) return plan;
    if (LeavesFence(fence.get(), result.plan)) {
      plan.status = planning::LandingStatus::kNoFeasibleTrajectory;
      plan.message = "the path to site " + result.site_id + " leaves the mission's geofence";
      return plan;
    }
    plan.plan = std::move(result.plan);
    plan.site = result.site_id;
    if (result.site >= 0) plan.site_radius = map->sites()[result.site].radius;
    plan.reach_margin = result.reach_margin;
    if (land_asap) {
      for (const Eigen::Vector2d& p_H : result.footprint.region.Boundary(72)) {
        plan.footprint_NE.push_back(result.frame.ToWorld(p_H).head<2>());
      }
    }
    return plan;
  };
  out.to_point = MakePointPlanner(map, planner, fence);
  return out;
}

}  // namespace uascma::sim
