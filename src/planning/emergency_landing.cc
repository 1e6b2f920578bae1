// What LandASAP and LandPract share (planning/emergency_landing.h): the status names, the one-line report of a
// landing result and the check of a request.
#include "uascma/planning/emergency_landing.h"

#include <cmath>
#include <string>

#include <fmt/format.h>

#include "landing_internal.h"
#include "uascma/common/error.h"

namespace uascma::planning {

const char* LandingStatusName(LandingStatus status) {
  switch (status) {
    case LandingStatus::kOk:
      return "ok";
    case LandingStatus::kNoSiteInFootprint:
      return "no site in footprint";
    case LandingStatus::kNoStoredTrajectory:
      return "no stored trajectory";
    case LandingStatus::kNoFeasibleTrajectory:
      return "no feasible trajectory";
    case LandingStatus::kStartInsideBuilding:
      return "start inside a building";
  }
  return "?";
}

std::string LandingResult::BriefReport() const {
  if (!ok()) return fmt::format("{}: {}", LandingStatusName(status), message);
  std::string report = fmt::format(
      "site '{}' (risk {:.3f}) by {} in {:.2f} s, RM {:.4f}; {} candidates, {} planned, {} "
      "detour searches",
      site_id, site_risk, LandingPathKindName(path.kind), flight_time, reach_margin, candidates, planned,
      detour_searches);
  if (checkpoint >= 0) {
    report += fmt::format("; checkpoint {} ({:.2f} s to it + {:.2f} s stored)", checkpoint, time_to_checkpoint,
                          stored_flight_time);
  }
  return report;
}

namespace landing_internal {

void RequireFinite(const LandingRequest& request, const char* source) {
  if (!request.p_WB_W.allFinite()) throw InputError(source, "p_WB_W", "finite coordinates (m)");
  if (!request.v_WB_W.allFinite()) throw InputError(source, "v_WB_W", "a finite velocity (m/s)");
  if (!std::isfinite(request.yaw))
    throw InputError(source, "yaw", fmt::format("a finite angle (rad), got {}", request.yaw));
  if (std::isnan(request.eod)) throw InputError(source, "eod", "a number of seconds, got NaN");
}

}  // namespace landing_internal

}  // namespace uascma::planning
