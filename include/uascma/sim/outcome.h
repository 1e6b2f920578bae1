#pragma once
// How a flight ends (decisions items 10-11): the outcome enum and its classification as a pure function of
// one GNC step's observable quantities, with every threshold a named option.
//
// The classification runs after every 5 ms step, in this order (the first that holds ends the flight):
//   1. battery:   a cell of a switched-on branch at or below the 3.3 V cut-off (§3.3.2.1)  -> kFailedBattery
//   2. control:   tilt above max_tilt or distance to the reference above max_tracking_error -> kFailedControl
//   3. landed:    airborne once, in the landing zone of the executing plan (within landing_radius of its end
//                 point horizontally, in its last landing_window_s, within landing_height above the end),
//                 the plan's time used up, settled (within settled_height, slower than settled_speed)
//                 -> kCompleted (original plan) or kEmergencyLanding (an emergency plan)
//   4. building:  below the tallest roof + building_margin and outside the landing zone, inside a building
//                 prism -> kFailedCollision
//   5. ground:    airborne once and at or below the ground, faster than touchdown_speed or outside the
//                 landing zone -> kFailedCollision
//   6. time:      the time limit (time_limit_factor x the original plan's duration + time_limit_margin_s)
//                 -> kTimeout
// Every bound is ours (the dissertation gives none); decisions item 11 names the kinds.
#include <Eigen/Core>

#include <string>
#include <string_view>

#include "uascma/decision/cma_mdp.h"
#include "uascma/planning/city_map.h"

namespace uascma::sim {

enum class Outcome {
  kInProgress,
  kCompleted,          // landed at the end of the original plan
  kEmergencyLanding,   // landed at the end of an emergency plan
  kTerminated,         // Terminate: parachute and motors cut
  kFailedBattery,      // a cell reached the 3.3 V cut-off
  kFailedControl,      // attitude or tracking error beyond the bounds
  kFailedCollision,    // struck the ground (or a building) outside a landing
  kTimeout,            // still flying at the time limit (counted as a failure)
};
const char* OutcomeName(Outcome outcome);
bool IsFailure(Outcome outcome);
// The terminal CMA state a flight ended in (decisions items 10–11): C for a landing, T for Terminate, FL for a
// failure. The outcome must not be kInProgress.
decision::CmaTerminal TerminalStateOf(Outcome outcome);

struct OutcomeThresholds {
  double max_tilt = 1.2;             // rad (~69°): beyond it the flight is out of control (our bound)
  double max_tracking_error = 15.0;  // m from the reference: out of control (our bound)
  double touchdown_speed = 1.5;      // m/s: faster ground contact is a crash (our bound)
  double airborne_height = 0.5;      // m above the ground: the vehicle has taken off (our bound)
  double landing_radius = 2.0;       // m, horizontal distance to the plan's end point (our bound)
  double landing_window_s = 5.0;     // s: the plan's last seconds count as the landing (our bound)
  double landing_height = 0.5;       // m above the end point: inside the landing zone (our bound)
  double settled_height = 0.3;       // m above the end point: touched down (our bound)
  double settled_speed = 0.5;        // m/s: at rest after touchdown (our bound)
  double building_margin = 0.5;      // m above the tallest roof: no building can be struck (our bound)
  double time_limit_factor = 2.5;    // the flight times out at this x the original plan's duration …
  double time_limit_margin_s = 60.0; // … + this (s)
  bool IsValid(std::string* error) const;
};

// What the classification sees after one step. Frames: W is NED (common/frames.h).
struct OutcomeInputs {
  double time_s = 0.0;                 // at the end of the step
  Eigen::Vector3d p_WB_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_WB_W = Eigen::Vector3d::Zero();
  double cos_tilt = 1.0;               // R_WB(2, 2): cosine of the angle between z_B and z_W
  double tracking_error = 0.0;         // m, |p_WB_W − p_ref_W|
  double min_cell_voltage_v = 4.2;     // over the switched-on branches
  int min_cell_branch = 0;             // 0, 1: the branch and cell of that voltage (models::CellLabel)
  int min_cell_index = 0;
  bool airborne = false;               // has been above airborne_height
  double plan_time_remaining_s = 0.0;  // of the executing plan
  Eigen::Vector3d plan_end_W = Eigen::Vector3d::Zero();
  bool on_original_plan = true;
  std::string_view emergency_site;     // the executing emergency plan's site, for the reason
  double time_limit_s = 0.0;
};

struct OutcomeDecision {
  Outcome outcome = Outcome::kInProgress;
  std::string reason;  // one line; empty while in progress
};

// The pure classification above, with what the thresholds imply computed once (the simulator classifies every
// step). `map` gives the buildings (an empty map: open ground).
class OutcomeClassifier {
 public:
  explicit OutcomeClassifier(const OutcomeThresholds& thresholds);
  OutcomeDecision Classify(const OutcomeInputs& inputs, const planning::CityMap& map) const;
  const OutcomeThresholds& thresholds() const { return thresholds_; }

 private:
  OutcomeThresholds thresholds_;
  double cos_max_tilt_;  // tilt > max_tilt ⇔ cos(tilt) < cos(max_tilt) for tilts in [0, π]
};

OutcomeDecision ClassifyOutcome(const OutcomeThresholds& thresholds, const OutcomeInputs& inputs,
                                const planning::CityMap& map);

}  // namespace uascma::sim
