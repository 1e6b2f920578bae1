#pragma once
// What the emergency-landing units share (landing_path.h, land_asap.h, land_pract.h): the path-time formula
// (landing_path.cc), the reach margin and the request check (emergency_landing.cc). Internal to src/planning/.
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "uascma/planning/emergency_landing.h"
#include "uascma/prognostics/reach_margin.h"

namespace uascma::planning::landing_internal {

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

// RM = 1 − flight_time / eod (−∞ when eod ≤ 0): prognostics::CalcReachMargin without a safety margin (the sites are
// ranked by it; the executor judges the plan it flies with t_sf, sim/act.cc).
inline double ReachMargin(double flight_time, double eod) { return prognostics::CalcReachMargin(eod, flight_time, 0.0); }

// The time of a path from start_W through waypoints_W: each leg's horizontal and vertical trapezoid moves.
double PathTime(const Eigen::Vector3d& start_W, const std::vector<Eigen::Vector3d>& waypoints_W,
                const PlanLimits& limits);

// InputError naming `source` when a request has a non-finite field.
void RequireFinite(const LandingRequest& request, const char* source);

}  // namespace uascma::planning::landing_internal
