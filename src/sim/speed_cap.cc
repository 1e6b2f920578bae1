#include "uascma/sim/speed_cap.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "uascma/common/frames.h"

namespace uascma::sim {
namespace {

constexpr double kUncappedAirspeed = std::numeric_limits<double>::infinity();
constexpr double kMaxSearchAirspeed = 60.0;  // m/s: beyond the drag table's use (Table 4.4 cruises at 1-9 m/s)
// m: a move shorter than this horizontally is vertical (take-off, landing): its horizontal speed is not capped.
constexpr double kVerticalMove = 0.5;

// Level flight's tilt at an airspeed: the fixed point of tan φ = D(V, −φ) / (m g). The drag's incidence is −φ, the
// rigid body's asin(v_air · z_B / |v_air|) for a thrust tilted into the air flow (models/rigid_body.cc).
double LevelTilt(const models::RigidBodyParams& body, const models::DragTable& drag, double airspeed) {
  const double weight = body.mass * kGravity;
  double tilt = 0.0;
  for (int i = 0; i < 100; ++i) {
    const double next = std::atan(drag.Drag(airspeed, -tilt) / weight);
    const bool converged = std::abs(next - tilt) < 1e-12;
    tilt = next;
    if (converged) break;
  }
  return tilt;
}

}  // namespace

double CalcMaxLevelAirspeed(const models::RigidBodyParams& body, const models::DragTable& drag, double max_tilt) {
  if (LevelTilt(body, drag, kMaxSearchAirspeed) <= max_tilt) return kUncappedAirspeed;
  double low = 0.0, high = kMaxSearchAirspeed;
  while (high - low > 1e-6) {
    const double mid = 0.5 * (low + high);
    (LevelTilt(body, drag, mid) <= max_tilt ? low : high) = mid;
  }
  return low;
}

double CalcGroundSpeedCap(const Eigen::Vector2d& direction_NE, const Eigen::Vector2d& wind_NE, double max_airspeed) {
  // |s ê − w|² = s² − 2 s (ê·w) + |w|² ≤ V²  ⇔  s ≤ ê·w + √((ê·w)² − |w|² + V²).
  const double along = direction_NE.dot(wind_NE);
  const double discriminant = along * along - wind_NE.squaredNorm() + max_airspeed * max_airspeed;
  if (discriminant < 0.0) return 0.0;
  return std::max(0.0, along + std::sqrt(discriminant));
}

planning::FlightPlan ReplanAtCappedSpeed(const planning::FlightPlan& plan, double t_plan,
                                         const Eigen::Vector3d& start_W, const planning::PlanLimits& limits,
                                         const Eigen::Vector2d& wind_NE, double max_airspeed) {
  const auto& segments = plan.segments();
  if (segments.empty() || t_plan >= plan.duration()) return {};
  const int first = plan.At(t_plan).segment;
  std::vector<planning::Waypoint> waypoints;
  Eigen::Vector3d from_W = start_W;
  for (int i = first; i < static_cast<int>(segments.size()); ++i) {
    const planning::PlanSegment& segment = segments[static_cast<std::size_t>(i)];
    if (segment.kind == planning::PlanSegment::Kind::kHover) {
      const double hover = i == first ? segment.start_time + segment.duration - t_plan : segment.duration;
      if (waypoints.empty()) {
        waypoints.push_back({segment.end_W, 0.0, segment.label, 0.0});
        from_W = segment.end_W;
      }
      waypoints.back().hover_after_s += std::max(hover, 0.0);
      continue;
    }
    if (segment.kind == planning::PlanSegment::Kind::kBrake) continue;  // the vehicle is brought to rest anyway
    const Eigen::Vector2d horizontal = (segment.end_W - from_W).head<2>();
    double speed = segment.cruise_speed > 0.0 ? segment.cruise_speed : limits.cruise_speed;
    if (horizontal.norm() > kVerticalMove) {
      speed = std::min(speed, CalcGroundSpeedCap(horizontal.normalized(), wind_NE, max_airspeed));
    }
    // A cap of 0 (a wind the vehicle cannot fly against at all) keeps a crawl rather than an impossible plan.
    waypoints.push_back({segment.end_W, 0.0, segment.label, std::max(speed, 0.1)});
    from_W = segment.end_W;
  }
  if (waypoints.empty()) return {};
  return planning::FlightPlan::Through(start_W, waypoints, limits);
}

}  // namespace uascma::sim
