#pragma once
// The emergency landing plans the simulator asks for when the CMA picks LandPract or LandASAP (the planning layer's
// planners, §5.3.2.2): what the simulator knows at that moment (EmergencyRequest), a plan or why there is none
// (EmergencyPlan), and the planners over a scenario's map (MakeMapEmergencyPlanner). The kernel (sim/flight.h) holds
// the map's planner in its model; the executor (sim/act.h Act) calls one.
#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

#include "uascma/decision/cma_mdp.h"
#include "uascma/models/drag.h"
#include "uascma/models/propulsion.h"
#include "uascma/planning/city_map.h"
#include "uascma/planning/emergency_landing.h"
#include "uascma/planning/flight_plan.h"
#include "uascma/sim/scenario.h"

namespace uascma::sim {

// What the simulator knows when the policy picks an emergency action.
struct EmergencyRequest {
  decision::CmaAction action = decision::CmaAction::kLandPract;
  double time_s = 0.0;
  Eigen::Vector3d p_WB_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_WB_W = Eigen::Vector3d::Zero();
  double yaw = 0.0;      // rad
  int failed_motor = 0;  // the rotor the allocation has switched off (0: none): fewer rotors, less reach
  double eod_s = 0.0;
  double original_plan_elapsed_s = 0.0;  // how far along the nominal plan the vehicle is
};
// A plan, or why there is none (the planner's status and one-line message).
struct EmergencyPlan {
  planning::LandingStatus status = planning::LandingStatus::kNoFeasibleTrajectory;
  std::string message;  // why no plan; empty when ok()
  planning::FlightPlan plan;
  std::string site;          // a label of the landing site
  double site_radius = 0.0;  // m, the site's clear touchdown radius (0: unknown, OutcomeThresholds::landing_radius)
  double reach_margin = 0.0;
  std::vector<Eigen::Vector2d> footprint_NE;  // LandASAP: the footprint's boundary in W (north, east), m
  bool ok() const { return status == planning::LandingStatus::kOk; }
};
using EmergencyPlanner = std::function<EmergencyPlan(const EmergencyRequest&)>;

// The emergency planners over the scenario's map: LandPract from a database built before flight on the nominal
// plan (5 checkpoints), LandASAP online inside the footprint. Empty (no planner) when the map has no sites.
// `to_point` plans the path to a point another agent chose (an external CMA's landing site, sent as a MAVLink
// DO_REPOSITION): the map's path planner from the request's position to the map site nearest that point
// (planning::LandingPathPlanner::PlanToSite), the site's label and radius with it.
using PointPlanner = std::function<EmergencyPlan(const EmergencyRequest&, const Eigen::Vector3d& target_W)>;
struct MapEmergencyPlanner {
  EmergencyPlanner planner;
  PointPlanner to_point;
  std::vector<Eigen::Vector3d> checkpoints_W;  // LandPract's checkpoints on the nominal plan
};
// The index of the map's landing site nearest `p_W` (3-D distance); −1 when the map has none.
int NearestLandingSite(const planning::CityMap& map, const Eigen::Vector3d& p_W);
MapEmergencyPlanner MakeMapEmergencyPlanner(const Scenario& scenario, const planning::FlightPlan& nominal_plan,
                                            const models::DragTable& drag, const models::PropulsionParams& propulsion);

}  // namespace uascma::sim
