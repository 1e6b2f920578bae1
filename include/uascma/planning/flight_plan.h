#pragma once
// Flight plans: straight segments flown with trapezoidal velocity profiles (rest to rest at every
// waypoint) and hovers, as the dissertation's flight planner generates them (§4.3.3, §5.4: "a trapezoidal
// velocity profile with limits on velocity and accelerations"). Positions are in the world frame W (NED,
// metres, z down, ground at z = 0); times in seconds from the plan's start.
//
// The package-delivery plan (§4.3.3, Fig. 4.6; docs/defaults.md#guidance-and-control): take off
// vertically to the cruise altitude, cruise to the destination, hover for the drop, cruise back, land
// vertically at home.
#include <Eigen/Core>

#include <algorithm>
#include <string>
#include <vector>

namespace uascma::planning {

struct PlanLimits {
  double cruise_speed = 5.0;      // m/s horizontal; Table 4.4 samples 1–9 m/s
  double vertical_speed = 2.0;    // m/s climb and descent; our estimate for a small hexacopter
  double horizontal_accel = 2.0;  // m/s², docs/defaults.md#guidance-and-control (estimate within the tested envelope)
  double vertical_accel = 1.0;    // m/s², docs/defaults.md#guidance-and-control
  bool IsValid(std::string* error) const;
};

// Where the plan should be at one instant: position, velocity, acceleration in W.
struct PlanReference {
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d a_W = Eigen::Vector3d::Zero();
  int segment = 0;
};

struct PlanSegment {
  // kBrake: a straight deceleration from `peak_speed` to rest at `accel` (an emergency plan that starts while the
  // vehicle moves, FlightPlan::AfterBraking).
  enum class Kind { kMove, kHover, kBrake };
  Kind kind = Kind::kMove;
  std::string label;  // "takeoff", "cruise out", "drop", …
  Eigen::Vector3d start_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d end_W = Eigen::Vector3d::Zero();
  double start_time = 0.0;  // s
  double duration = 0.0;    // s
  // Trapezoid along the segment: accelerate for accel_time at `accel`, coast at peak_speed, brake.
  double accel = 0.0;         // m/s²
  double peak_speed = 0.0;    // m/s
  double accel_time = 0.0;    // s
  double cruise_speed = 0.0;  // m/s: the horizontal speed limit the move was planned with (0 for a hover)
  bool operator==(const PlanSegment&) const = default;
};

// A straight rest-to-rest move of `length` m under a speed limit `max_speed` (m/s) and an acceleration
// limit `accel` (m/s²): a trapezoid when the length allows reaching the limit, else a triangle.
struct TrapezoidProfile {
  double duration = 0.0;    // s
  double peak_speed = 0.0;  // m/s
  double accel_time = 0.0;  // s, time to reach the peak (and to brake from it)
};
TrapezoidProfile CalcTrapezoid(double length, double max_speed, double accel);

struct Waypoint {
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();
  double hover_after_s = 0.0;  // hover this long on arrival
  std::string label;
  // m/s: the horizontal speed limit of the move to this waypoint (a mission's DO_CHANGE_SPEED); 0: the plan's
  // PlanLimits::cruise_speed.
  double max_speed = 0.0;
  // The mission item (numbered from 1, as the mission file or upload orders them) whose flying placed this
  // waypoint; 0 for a plan not made from a mission (mission_file.h).
  int item_number = 0;
};

// Where a flight last was on its plan (FlightPlan::At with a cursor): a cache, not part of the flight's behaviour,
// so any two cursors compare equal.
struct PlanCursor {
  int segment = 0;
  bool operator==(const PlanCursor&) const { return true; }
};

class FlightPlan {
 public:
  FlightPlan() = default;
  // Straight moves from `start_W` through the waypoints, each rest to rest with the trapezoidal profile of §5.4
  // (CalcTrapezoid), and the hovers. Throws InputError on invalid limits, a non-finite waypoint, a negative hover
  // or a negative speed limit.
  static FlightPlan Through(const Eigen::Vector3d& start_W, const std::vector<Waypoint>& waypoints,
                            const PlanLimits& limits);

  // A braking move from `start_W` at the horizontal velocity `velocity_W` to rest at `accel` (m/s²) along it, then
  // `then` (which should start where the braking stops, BrakingStop). An emergency plan chosen while the vehicle
  // cruises begins so, instead of commanding rest at once (which asks for more tilt than the vehicle has at
  // Table 4.4's higher cruise speeds). InputError on a non-positive accel or non-finite inputs.
  static FlightPlan AfterBraking(const Eigen::Vector3d& start_W, const Eigen::Vector3d& velocity_W, double accel,
                                 const FlightPlan& then);
  PlanReference At(double time) const;  // clamps to the start and end of the plan
  // The same reference, its segment found from `cursor` (the last segment found) forward, when the query times of
  // a flight only move forward (the simulator's 200 Hz loop): the plan is shared read-only by a campaign's
  // threads, the cursor is the flight's. Any cursor gives At(time)'s result (an out-of-date one only costs the
  // search At makes). Sets the cursor to the segment found.
  PlanReference At(double time, PlanCursor& cursor) const;
  double duration() const { return segments_.empty() ? 0.0 : segments_.back().start_time + segments_.back().duration; }
  // s from `time` to the end of the whole plan (every remaining move and hover); 0 after the end.
  double TimeRemaining(double time) const { return std::max(duration() - time, 0.0); }
  double Length() const;  // m, path length
  bool empty() const { return segments_.empty(); }
  const std::vector<PlanSegment>& segments() const { return segments_; }
  Eigen::Vector3d start_W() const { return segments_.empty() ? Eigen::Vector3d::Zero() : segments_.front().start_W; }
  Eigen::Vector3d end_W() const { return segments_.empty() ? Eigen::Vector3d::Zero() : segments_.back().end_W; }
  // The point at arc length `distance` from the start (for checkpoints), m.
  Eigen::Vector3d PointAtDistance(double distance) const;
  bool operator==(const FlightPlan&) const = default;

 private:
  void Append(const PlanSegment& segment);
  std::vector<PlanSegment> segments_;
  // Per segment, derived once for At() (called at 200 Hz): the unit direction (0 for a hover) and length.
  std::vector<Eigen::Vector3d> direction_W_;
  std::vector<double> length_;
};

// Where a vehicle at `start_W` moving at `velocity_W` comes to rest decelerating at `accel` (m/s²) along its
// velocity: start + v |v| / (2 accel).
Eigen::Vector3d BrakingStop(const Eigen::Vector3d& start_W, const Eigen::Vector3d& velocity_W, double accel);

struct DeliveryMission {
  Eigen::Vector2d home_NE = Eigen::Vector2d::Zero();         // m
  Eigen::Vector2d destination_NE = Eigen::Vector2d(600, 0);  // m
  double cruise_altitude = 30.0;  // m above ground; docs/defaults.md#guidance-and-control: 10 m above the tallest
                                  // building
  double drop_hover_s = 30.0;     // docs/defaults.md#guidance-and-control
  bool IsValid(std::string* error) const;
};

FlightPlan MakeDeliveryPlan(const DeliveryMission& mission, const PlanLimits& limits);

}  // namespace uascma::planning
