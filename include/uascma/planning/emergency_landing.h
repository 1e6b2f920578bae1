#pragma once
// The emergency-landing planners of the contingency manager: LandASAP and LandPract (dissertation §5.3.2.2,
// "Action Definition"; Fig. 5.6), on the city map of include/uascma/planning/city_map.h, with the footprint of
// §5.3.1 (include/uascma/planning/footprint.h). Frames: the world frame W (NED, metres, z down, the ground at
// z = 0; an altitude a is the point z = −a). Times in seconds.
//
// What both actions share, declared here: the request (what the simulator knows when the contingency manager picks
// one), the result and its status, and the tie rule of the reach margin. The path they fly is LandingPath
// (landing_path.h); LandASAP is PlanLandAsap (land_asap.h), LandPract is LandPractDatabase (land_pract.h).
#include <Eigen/Core>

#include <limits>
#include <string>
#include <vector>

#include "uascma/planning/flight_plan.h"
#include "uascma/planning/footprint.h"
#include "uascma/planning/landing_path.h"

namespace uascma::planning {

// RMs closer than this are equal and the lower risk wins (§5.3.2.2 picks the maximum RM; the tie rule is ours).
inline constexpr double kReachMarginTie = 1e-9;

// What the simulator knows when the contingency manager picks LandASAP or LandPract (sim::EmergencyRequest).
struct LandingRequest {
  Eigen::Vector3d p_WB_W = Eigen::Vector3d::Zero();  // m, the vehicle's position
  Eigen::Vector3d v_WB_W = Eigen::Vector3d::Zero();  // m/s, its velocity
  double yaw = 0.0;                                  // rad, the heading when hovering (HeadingFrame::FromState)
  double eod = 0.0;                                  // s, t_EOD of the battery prognosis
  // s since the start of the nominal plan (LandPract tells coinciding checkpoints apart); NaN when unknown.
  double plan_elapsed = std::numeric_limits<double>::quiet_NaN();
};

enum class LandingStatus {
  kOk,
  kNoSiteInFootprint,     // LandASAP: no site in the footprint (or EOD ≤ 0, or the footprint is a point)
  kNoStoredTrajectory,    // LandPract: the chosen checkpoint has no stored path
  kNoFeasibleTrajectory,  // candidates exist but no path to any (ceiling, blocked)
  kStartInsideBuilding,   // the vehicle's position is inside a building prism
};
const char* LandingStatusName(LandingStatus status);

struct LandingResult {
  LandingStatus status = LandingStatus::kNoFeasibleTrajectory;
  std::string message;  // one line; empty when kOk
  int site = -1;        // CityMap site index
  std::string site_id;  // LandingSite::id
  double site_risk = 0.0;
  LandingPath path;                                                // start → site (LandPract: through the checkpoint)
  FlightPlan plan;                                                 // path.ToFlightPlan(limits)
  double flight_time = std::numeric_limits<double>::infinity();    // s, plan.duration()
  double reach_margin = -std::numeric_limits<double>::infinity();  // RM = 1 − flight_time / eod (−∞ if eod ≤ 0)
  int candidates = 0;  // LandASAP: sites in the footprint; LandPract: stored paths of the checkpoint
  int planned = 0;     // LandASAP: candidates planned exactly; LandPract: stored paths scanned
  int detour_searches = 0;
  // LandASAP only.
  FootprintResult footprint;
  HeadingFrame frame;
  std::vector<SitePlan> candidate_plans;  // the planned candidates, fastest first (all with plan_all_candidates)
  // LandPract only.
  int checkpoint = -1;
  double time_to_checkpoint = 0.0;  // s
  double stored_flight_time = 0.0;  // s

  bool ok() const { return status == LandingStatus::kOk; }
  std::string BriefReport() const;  // one line
};

}  // namespace uascma::planning
