#pragma once
// LandASAP (§5.3.2.2: "determines a list of available emergency landing sites within its approximate
// footprint … plans a minimum time trajectory to reachable emergency landing sites and selects the solution
// with maximum RM"). The footprint comes from CalcFootprint with the current horizontal speed, heading (course
// over ground, or yaw when hovering) and EOD (a hovering vehicle's footprint is a point: see
// LandAsapParams::min_footprint_speed); candidates are the sites of CityMap::SitesWithinRadius over the
// footprint's circumscribed circle that FootprintRegion::Contains. RM = 1 − t_flight / t_EOD
// (docs/modelling-choices.md#margins; t_flight = the plan's duration), so the largest RM is the shortest flight;
// RMs within kReachMarginTie of the largest count as equal and the lowest risk among them wins (then the
// shorter flight, then the lower site index).
//
// Thread safety: PlanLandAsap is a const query of the planner (landing_path.h) and may run on many threads.
#include "uascma/planning/emergency_landing.h"
#include "uascma/planning/footprint.h"
#include "uascma/planning/landing_path.h"

namespace uascma::planning {

struct LandAsapParams {
  // The vehicle of the footprint (mass, available thrust, max tilt, drag slope); initial_speed and eod are
  // replaced by the request's horizontal speed and EOD. After a motor failure put models::CalcControlAuthority's
  // values here (footprint.h).
  FootprintParams footprint;
  double footprint_tolerance = 0.0;  // m, FootprintRegion::Contains
  // m/s: the footprint's initial speed is max(the horizontal speed, this). 0 follows §5.3.1 (the current speed).
  // Beware: the footprint scales with the initial speed (eqs. 5.10–5.11 end the manoeuvre at ±v_init), and a
  // hovering vehicle's footprint is a point, so with 0 LandASAP finds no site during take-off, landing and the drop
  // hover. Raise it (e.g. to PlanLimits::cruise_speed) to give a hovering vehicle a cruising vehicle's reach.
  double min_footprint_speed = 0.0;
  bool plan_all_candidates = false;  // plan every candidate (Fig. 5.28) instead of stopping at the lower bound
  bool IsValid(std::string* error) const;
};

// LandASAP from the request (header comment). InputError on invalid params or a non-finite request.
LandingResult PlanLandAsap(const LandingPathPlanner& planner, const LandAsapParams& params,
                           const LandingRequest& request);

}  // namespace uascma::planning
