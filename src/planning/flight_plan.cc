#include "uascma/planning/flight_plan.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "uascma/common/error.h"

namespace uascma::planning {
namespace {

// Speed and acceleration limits along a direction with horizontal part h and vertical part v (|d| = 1):
// the largest along-path value whose horizontal and vertical components both respect their limits.
double AlongPathLimit(double horizontal_fraction, double vertical_fraction, double horizontal_limit,
                      double vertical_limit) {
  double limit = std::numeric_limits<double>::infinity();
  if (horizontal_fraction > 1e-12) limit = std::min(limit, horizontal_limit / horizontal_fraction);
  if (vertical_fraction > 1e-12) limit = std::min(limit, vertical_limit / vertical_fraction);
  return limit;
}

// Distance covered at time tau into a trapezoid segment (rest to rest).
void Trapezoid(const PlanSegment& s, double length, double tau, double* distance, double* speed, double* accel) {
  const double ta = s.accel_time;
  const double coast = s.duration - 2.0 * ta;
  if (tau < ta) {
    *distance = 0.5 * s.accel * tau * tau;
    *speed = s.accel * tau;
    *accel = s.accel;
  } else if (tau < ta + coast) {
    *distance = 0.5 * s.accel * ta * ta + s.peak_speed * (tau - ta);
    *speed = s.peak_speed;
    *accel = 0.0;
  } else {
    const double left = std::max(s.duration - tau, 0.0);
    *distance = length - 0.5 * s.accel * left * left;
    *speed = s.accel * left;
    *accel = -s.accel;
  }
}

}  // namespace

TrapezoidProfile CalcTrapezoid(double length, double max_speed, double accel) {
  TrapezoidProfile profile;
  if (length >= max_speed * max_speed / accel) {  // reaches the speed limit: trapezoid
    profile.peak_speed = max_speed;
    profile.accel_time = max_speed / accel;
    profile.duration = 2.0 * profile.accel_time + (length - max_speed * max_speed / accel) / max_speed;
  } else {  // too short: triangle
    profile.peak_speed = std::sqrt(length * accel);
    profile.accel_time = profile.peak_speed / accel;
    profile.duration = 2.0 * profile.accel_time;
  }
  return profile;
}

bool PlanLimits::IsValid(std::string* error) const {
  const struct {
    const char* name;
    double value;
  } fields[] = {{"cruise_speed", cruise_speed},
                {"vertical_speed", vertical_speed},
                {"horizontal_accel", horizontal_accel},
                {"vertical_accel", vertical_accel}};
  for (const auto& f : fields) {
    if (!(std::isfinite(f.value) && f.value > 0.0)) {
      if (error) *error = fmt::format("{}: expected a positive number, got {}", f.name, f.value);
      return false;
    }
  }
  return true;
}

bool DeliveryMission::IsValid(std::string* error) const {
  if (!(cruise_altitude > 0.0 && std::isfinite(cruise_altitude))) {
    if (error) *error = fmt::format("cruise_altitude: expected > 0 m, got {}", cruise_altitude);
    return false;
  }
  if (!(drop_hover_s >= 0.0 && std::isfinite(drop_hover_s))) {
    if (error) *error = fmt::format("drop_hover_s: expected >= 0 s, got {}", drop_hover_s);
    return false;
  }
  if (!home_NE.allFinite() || !destination_NE.allFinite()) {
    if (error) *error = "home/destination: expected finite coordinates";
    return false;
  }
  return true;
}

FlightPlan FlightPlan::Through(const Eigen::Vector3d& start_W, const std::vector<Waypoint>& waypoints,
                               const PlanLimits& limits) {
  std::string error;
  if (!limits.IsValid(&error)) throw InputError("flight plan limits: " + error);
  FlightPlan plan;
  Eigen::Vector3d from = start_W;
  double time = 0.0;
  for (std::size_t i = 0; i < waypoints.size(); ++i) {
    const Waypoint& waypoint = waypoints[i];
    if (!waypoint.p_W.allFinite())
      throw InputError("flight plan", fmt::format("waypoint {}", i), "finite coordinates (m)");
    if (!(waypoint.hover_after_s >= 0.0 && std::isfinite(waypoint.hover_after_s))) {
      throw InputError("flight plan", fmt::format("waypoint {} hover", i),
                       fmt::format("a finite time >= 0 s, got {}", waypoint.hover_after_s));
    }
    if (!(waypoint.max_speed >= 0.0 && std::isfinite(waypoint.max_speed))) {
      throw InputError("flight plan", fmt::format("waypoint {} speed", i),
                       fmt::format("a finite speed >= 0 m/s (0: the cruise speed), got {}", waypoint.max_speed));
    }
    const double cruise_speed = waypoint.max_speed > 0.0 ? waypoint.max_speed : limits.cruise_speed;
    const Eigen::Vector3d delta = waypoint.p_W - from;
    const double length = delta.norm();
    if (length > 1e-9) {
      const double horizontal = delta.head<2>().norm() / length;
      const double vertical = std::abs(delta.z()) / length;
      PlanSegment segment;
      segment.kind = PlanSegment::Kind::kMove;
      segment.label = waypoint.label;
      segment.start_W = from;
      segment.end_W = waypoint.p_W;
      segment.start_time = time;
      const double speed_limit = AlongPathLimit(horizontal, vertical, cruise_speed, limits.vertical_speed);
      segment.accel = AlongPathLimit(horizontal, vertical, limits.horizontal_accel, limits.vertical_accel);
      segment.cruise_speed = cruise_speed;
      const TrapezoidProfile profile = CalcTrapezoid(length, speed_limit, segment.accel);
      segment.peak_speed = profile.peak_speed;
      segment.accel_time = profile.accel_time;
      segment.duration = profile.duration;
      time += segment.duration;
      plan.Append(segment);
    }
    if (waypoint.hover_after_s > 0.0) {
      PlanSegment hover;
      hover.kind = PlanSegment::Kind::kHover;
      hover.label = waypoint.label.empty() ? "hover" : waypoint.label + " hover";
      hover.start_W = hover.end_W = waypoint.p_W;
      hover.start_time = time;
      hover.duration = waypoint.hover_after_s;
      time += hover.duration;
      plan.Append(hover);
    }
    from = waypoint.p_W;
  }
  return plan;
}

void FlightPlan::Append(const PlanSegment& segment) {
  const Eigen::Vector3d delta = segment.end_W - segment.start_W;
  const double length = delta.norm();
  segments_.push_back(segment);
  length_.push_back(length);
  direction_W_.push_back(segment.kind == PlanSegment::Kind::kHover || length == 0.0 ? Eigen::Vector3d::Zero()
                                                                                    : Eigen::Vector3d(delta / length));
}

PlanReference FlightPlan::At(double time) const {
  PlanCursor none{.segment = -1};  // the search from scratch
  return At(time, none);
}

PlanReference FlightPlan::At(double time, PlanCursor& cursor) const {
  PlanReference reference;
  if (segments_.empty()) return reference;
  const int count = static_cast<int>(segments_.size());
  if (time >= duration()) {
    reference.p_W = segments_.back().end_W;
    reference.segment = count - 1;
    cursor.segment = count - 1;
    return reference;
  }
  time = std::max(time, 0.0);
  // The last segment that starts at or before `time`: from the cursor forward when the cursor is at or before it,
  // else by a binary search (segments are few, a delivery plan has 6, but long plans stay cheap too).
  int index = cursor.segment;
  if (index >= 0 && index < count && segments_[index].start_time <= time) {
    while (index + 1 < count && segments_[index + 1].start_time <= time) ++index;
  } else {
    const auto it = std::upper_bound(segments_.begin(), segments_.end(), time,
                                     [](double t, const PlanSegment& s) { return t < s.start_time; });
    index = static_cast<int>(it - segments_.begin()) - 1;
  }
  cursor.segment = index;
  const PlanSegment& segment = segments_[index];
  reference.segment = index;
  if (segment.kind == PlanSegment::Kind::kHover) {
    reference.p_W = segment.end_W;
    return reference;
  }
  const Eigen::Vector3d& direction = direction_W_[index];
  double distance, speed, accel;
  if (segment.kind == PlanSegment::Kind::kBrake) {
    // s(τ) = v₀τ − ½aτ², v(τ) = v₀ − aτ over τ ∈ [0, v₀/a].
    const double tau = std::min(time - segment.start_time, segment.duration);
    distance = segment.peak_speed * tau - 0.5 * segment.accel * tau * tau;
    speed = segment.peak_speed - segment.accel * tau;
    accel = -segment.accel;
  } else {
    Trapezoid(segment, length_[index], time - segment.start_time, &distance, &speed, &accel);
  }
  reference.p_W = segment.start_W + distance * direction;
  reference.v_W = speed * direction;
  reference.a_W = accel * direction;
  return reference;
}

Eigen::Vector3d BrakingStop(const Eigen::Vector3d& start_W, const Eigen::Vector3d& velocity_W, double accel) {
  return start_W + velocity_W * (velocity_W.norm() / (2.0 * accel));
}

FlightPlan FlightPlan::AfterBraking(const Eigen::Vector3d& start_W, const Eigen::Vector3d& velocity_W, double accel,
                                    const FlightPlan& then) {
  if (!(accel > 0.0 && std::isfinite(accel))) throw InputError("braking", "accel", "a positive acceleration (m/s²)");
  if (!start_W.allFinite() || !velocity_W.allFinite()) throw InputError("braking", "start", "finite values");
  FlightPlan plan;
  const double speed = velocity_W.norm();
  if (speed > 0.0) {
    PlanSegment brake;
    brake.kind = PlanSegment::Kind::kBrake;
    brake.label = "brake";
    brake.start_W = start_W;
    brake.end_W = BrakingStop(start_W, velocity_W, accel);
    brake.duration = speed / accel;
    brake.accel = accel;
    brake.peak_speed = speed;
    brake.cruise_speed = speed;
    plan.Append(brake);
  }
  const double offset = plan.duration();
  for (PlanSegment segment : then.segments()) {
    segment.start_time += offset;
    plan.Append(segment);
  }
  return plan;
}

double FlightPlan::Length() const {
  double length = 0.0;
  for (const PlanSegment& s : segments_) length += (s.end_W - s.start_W).norm();
  return length;
}

Eigen::Vector3d FlightPlan::PointAtDistance(double distance) const {
  for (const PlanSegment& s : segments_) {
    const double length = (s.end_W - s.start_W).norm();
    if (distance <= length && length > 0.0) return s.start_W + (distance / length) * (s.end_W - s.start_W);
    distance -= length;
  }
  return end_W();
}

FlightPlan MakeDeliveryPlan(const DeliveryMission& mission, const PlanLimits& limits) {
  std::string error;
  if (!mission.IsValid(&error)) throw InputError("delivery mission: " + error);
  const double z = -mission.cruise_altitude;  // NED: up is −z
  const Eigen::Vector3d home(mission.home_NE.x(), mission.home_NE.y(), 0.0);
  const Eigen::Vector3d home_aloft(home.x(), home.y(), z);
  const Eigen::Vector3d drop(mission.destination_NE.x(), mission.destination_NE.y(), z);
  return FlightPlan::Through(home,
                             {{home_aloft, 0.0, "takeoff"},
                              {drop, mission.drop_hover_s, "cruise out"},
                              {home_aloft, 0.0, "return"},
                              {home, 0.0, "land"}},
                             limits);
}

}  // namespace uascma::planning
