#include "uascma/sim/outcome.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/frames.h"
#include "uascma/models/battery_cell.h"
#include "uascma/models/battery_pack.h"

namespace uascma::sim {

const char* OutcomeName(Outcome outcome) {
  switch (outcome) {
    case Outcome::kInProgress:
      return "in_progress";
    case Outcome::kCompleted:
      return "completed";
    case Outcome::kEmergencyLanding:
      return "emergency_landing";
    case Outcome::kTerminated:
      return "terminated";
    case Outcome::kFailedBattery:
      return "failed_battery";
    case Outcome::kFailedControl:
      return "failed_control";
    case Outcome::kFailedCollision:
      return "failed_collision";
    case Outcome::kTimeout:
      return "timeout";
    case Outcome::kGrounded:
      return "grounded";
    case Outcome::kLandedOffSite:
      return "landed_off_site";
  }
  return "unknown";
}

bool IsFailure(Outcome outcome) {
  return outcome == Outcome::kFailedBattery || outcome == Outcome::kFailedControl ||
         outcome == Outcome::kFailedCollision || outcome == Outcome::kTimeout;
}

decision::CmaTerminal TerminalStateOf(Outcome outcome) {
  UASCMA_CHECK(outcome != Outcome::kInProgress, "a finished flight");
  // Grounded is a landing where the vehicle stands (LandASAP/LandPract chosen before take-off, §5.5.3): C.
  // A gentle touchdown off the site ends the flight safely on the ground: C as well.
  if (outcome == Outcome::kCompleted || outcome == Outcome::kEmergencyLanding || outcome == Outcome::kGrounded ||
      outcome == Outcome::kLandedOffSite) {
    return decision::CmaTerminal::kC;
  }
  if (outcome == Outcome::kTerminated) return decision::CmaTerminal::kT;
  return decision::CmaTerminal::kFL;
}

bool OutcomeThresholds::IsValid(std::string* error) const {
  const struct {
    const char* name;
    double value;
  } positive[] = {{"max_tilt", max_tilt},
                  {"max_cross_track_error", max_cross_track_error},
                  {"max_body_rate", max_body_rate},
                  {"touchdown_speed", touchdown_speed},
                  {"airborne_height", airborne_height},
                  {"landing_radius", landing_radius},
                  {"landing_window_s", landing_window_s},
                  {"landing_height", landing_height},
                  {"settled_height", settled_height},
                  {"settled_speed", settled_speed},
                  {"time_limit_factor", time_limit_factor}};
  for (const auto& f : positive) {
    if (!(f.value > 0.0 && std::isfinite(f.value))) {
      if (error) *error = fmt::format("{}: expected a positive number, got {}", f.name, f.value);
      return false;
    }
  }
  if (!(max_tilt <= std::numbers::pi)) {
    if (error) *error = fmt::format("max_tilt: expected at most pi rad (180 deg), got {}", max_tilt);
    return false;
  }
  for (const auto& [name, value] :
       {std::pair{"building_margin", building_margin}, std::pair{"time_limit_margin_s", time_limit_margin_s}}) {
    if (!(value >= 0.0 && std::isfinite(value))) {
      if (error) *error = fmt::format("{}: expected a number >= 0, got {}", name, value);
      return false;
    }
  }
  return true;
}

OutcomeClassifier::OutcomeClassifier(const OutcomeThresholds& thresholds)
    : thresholds_(thresholds), cos_max_tilt_(std::cos(std::min(thresholds.max_tilt, std::numbers::pi))) {}

OutcomeDecision ClassifyOutcome(const OutcomeThresholds& thresholds, const OutcomeInputs& inputs,
                                const planning::CityMap& map) {
  return OutcomeClassifier(thresholds).Classify(inputs, map);
}

OutcomeDecision OutcomeClassifier::Classify(const OutcomeInputs& in, const planning::CityMap& map) const {
  const OutcomeThresholds& limits = thresholds_;
  OutcomeDecision out;
  if (in.min_cell_voltage_v <= models::kCutoffVoltage) {
    out.outcome = Outcome::kFailedBattery;
    out.reason = fmt::format("cell {} reached {:.3f} V", models::CellLabel(in.min_cell_branch, in.min_cell_index),
                             in.min_cell_voltage_v);
    return out;
  }
  if (in.cos_tilt < cos_max_tilt_ || in.body_rate > limits.max_body_rate ||
      in.cross_track_error > limits.max_cross_track_error) {
    out.outcome = Outcome::kFailedControl;
    out.reason = fmt::format("tilt {:.0f} deg, body rate {:.1f} rad/s, cross-track error {:.1f} m",
                             std::acos(std::clamp(in.cos_tilt, -1.0, 1.0)) * kDegreesPerRadian, in.body_rate,
                             in.cross_track_error);
    return out;
  }
  const double altitude = -in.p_WB_W.z();
  const double above_end = altitude - (-in.plan_end_W.z());
  // The horizontal distance to the end point, computed only where it is read: the landing zone is checked in the
  // plan's last seconds, near the end's height (pure comparisons: the order of the conjuncts does not matter).
  auto distance_to_end = [&] { return (in.p_WB_W.head<2>() - in.plan_end_W.head<2>()).norm(); };
  const double radius = in.landing_radius > 0.0 ? in.landing_radius : limits.landing_radius;
  const bool landing = in.plan_time_remaining_s < limits.landing_window_s && above_end < limits.landing_height &&
                       distance_to_end() < radius;
  auto landed = [&](const char* how) {
    out.outcome = in.on_original_plan ? Outcome::kCompleted : Outcome::kEmergencyLanding;
    out.reason = in.on_original_plan ? fmt::format("{} at the destination of the original plan", how)
                                     : fmt::format("{} at the emergency site {}", how, in.emergency_site);
  };
  // Every path returns `out` itself (no other object), so that it is built in the caller's slot (NRVO), not moved
  // there at every step.
  if (in.airborne && landing && in.plan_time_remaining_s <= 0.0 && above_end < limits.settled_height &&
      in.v_WB_W.norm() < limits.settled_speed) {
    landed("landed");
    return out;
  }
  // Contact with a surface: a roof (inside a building prism, only possible below the tallest roof) or the ground.
  const bool gentle = in.v_WB_W.z() <= limits.touchdown_speed;  // NED: +z is down
  if (altitude < map.max_building_height() + limits.building_margin) {
    const int building = map.BuildingContaining(in.p_WB_W);
    if (building != planning::kNoBuilding) {
      if (in.airborne && landing && gentle) {
        landed("touched down on the roof");
        return out;
      }
      out.outcome = Outcome::kFailedCollision;
      out.reason = fmt::format("struck building {} at {:.1f} m, {:.1f} m/s down", map.building(building).id, altitude,
                               in.v_WB_W.z());
      return out;
    }
  }
  if (in.airborne && altitude <= 0.0) {
    if (landing && gentle) {
      landed("touched down");
      return out;
    }
    const double across = in.v_WB_W.head<2>().norm();
    if (gentle && across <= limits.touchdown_speed) {
      out.outcome = Outcome::kLandedOffSite;
      out.reason = fmt::format(
          "touched down on open ground at {:.1f} m/s down, {:.1f} m/s across, {:.1f} m from the "
          "landing point (radius {:.2f} m)",
          in.v_WB_W.z(), across, distance_to_end(), radius);
      return out;
    }
    out.outcome = Outcome::kFailedCollision;
    out.reason =
        fmt::format("ground contact at {:.1f} m/s, {:.1f} m from the landing point", in.v_WB_W.z(), distance_to_end());
    return out;
  }
  if (in.time_s >= in.time_limit_s) {
    out.outcome = Outcome::kTimeout;
    out.reason = fmt::format("still flying after {:.0f} s", in.time_s);
  }
  return out;
}

}  // namespace uascma::sim
