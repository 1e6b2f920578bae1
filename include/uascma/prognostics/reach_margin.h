#pragma once
// The reach margin (§5.3.2.1, eq. 5.13; docs/modelling-choices.md#margins): the one formula the CMA state's RM
// (sim/epoch.cc), the emergency planners' RM (planning/emergency_landing.h) and the executor's check of an emergency
// plan (sim/act.cc) share, so that a plan's margin when it is accepted and the state's margin once it executes are
// the same number from the same EOD.
//
//   RM = 1 − (t_flight + t_sf) / t_EOD
//
// t_flight (s): the time the plan still needs to reach the ground; t_sf (s): the safety margin (Table 4.4; 0 where
// none is asked, as the planners' own ranking of sites); t_EOD (s): the pack's end of discharge at the plan's load.
// RM ≥ 0 ⇔ t_flight + t_sf ≤ t_EOD. With t_flight + t_sf ≤ 0, RM = 1; with t_EOD ≤ 0 (and t_flight + t_sf > 0),
// RM = −∞.
#include <limits>

namespace uascma::prognostics {

inline double CalcReachMargin(double eod_s, double flight_time_s, double safety_margin_s) {
  const double needed_s = flight_time_s + safety_margin_s;
  if (needed_s <= 0.0) return 1.0;
  if (eod_s <= 0.0) return -std::numeric_limits<double>::infinity();
  return 1.0 - needed_s / eod_s;
}

}  // namespace uascma::prognostics
