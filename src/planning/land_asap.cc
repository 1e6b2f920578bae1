// LandASAP (§5.3.2.2, planning/land_asap.h): the reachable footprint's candidate sites, planned exactly.
#include "uascma/planning/land_asap.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "landing_internal.h"
#include "uascma/common/error.h"

namespace uascma::planning {
using namespace landing_internal;

// --- parameters ---------------------------------------------------------------------------------------------------
bool LandAsapParams::IsValid(std::string* error) const {
  if (!(std::isfinite(min_footprint_speed) && min_footprint_speed >= 0.0)) {
    if (error)
      *error = fmt::format("min_footprint_speed: expected a finite number ≥ 0 m/s, got {}", min_footprint_speed);
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

// --- LandASAP ------------------------------------------------------------------------------------------------------
namespace {
// Of the plans (fastest first), the one to the least risky site among those within `tie_window` (s) of the fastest.
std::size_t LeastRiskyWithinTie(const CityMap& map, const std::vector<SitePlan>& plans, double tie_window) {
  const double fastest = plans.front().path.flight_time;
  std::size_t chosen = 0;
  for (std::size_t i = 1; i < plans.size() && plans[i].path.flight_time <= fastest + tie_window; ++i) {
    if (map.site(plans[i].site).risk < map.site(plans[chosen].site).risk) chosen = i;
  }
  return chosen;
}
}  // namespace

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
  const double radius =
      std::abs(region.center_x) + std::max(region.semi_axis_x, region.semi_axis_y) + params.footprint_tolerance;
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
    result.message = fmt::format(
        "none of the {} sites in the footprint has a feasible path ({} infeasible, {} refused "
        "by the collision check)",
        result.candidates, search.infeasible, search.verification_failures);
    return result;
  }
  const SitePlan& best = search.plans[LeastRiskyWithinTie(map, search.plans, options.tie_window)];
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

}  // namespace uascma::planning
