// Flying a mission's raw items (mission_items.h): the waypoints in the local frame, as a multicopter's mission
// executor would fly the items in order, item by item.
#include "mission_builder.h"

#include <algorithm>
#include <cmath>
#include <string_view>
#include <utility>

#include <fmt/format.h>

#include "map_import_detail.h"
#include "mission_items.h"
#include "uascma/common/error.h"

namespace uascma::planning::mission_detail {

// Commands that move the vehicle in a way uascma does not fly, with the reason a refusal gives. Every other command
// outside the MAVLink navigation range (MAV_CMD 16-99: NAV_*) and the navigation-like user commands does not move
// the vehicle (camera, gimbal, servo, relay, gripper, parachute, auxiliary functions, region of interest, yaw,
// markers, …): it is skipped with a warning, whatever its number.
std::optional<std::string> RefusalReason(int command) {
  switch (command) {
    case 17:
      return "it loiters until the operator intervenes (the mission never ends)";
    case 113:
      return "it climbs or descends at a rate and holds the mission until then (not modelled)";
    case 176:
      return "it changes the flight mode (the mission may stop)";
    case 179:
      return "it moves the home that RETURN_TO_LAUNCH flies to (not modelled)";
    case 185:
      return "it terminates the flight";
    case 186:
      return "it changes the altitude outside a mission item (not modelled)";
    case 190:
      return "it lands at a rally point chosen by the autopilot";
    case 191:
      return "it aborts a landing (not modelled)";
    case 192:
      return "it repositions the vehicle outside the mission (not modelled)";
    case 193:
      return "it pauses the mission until the operator continues it";
    case 224:
      return "it jumps to another item (not modelled)";
    case 601:
      return "it jumps to a tag (not modelled)";
    default:
      break;
  }
  // The geofence and rally items (MAV_CMD 5000–5004, 5100) belong to the FENCE and RALLY lists, not to the mission:
  // ArduPilot and PX4 answer them MAV_MISSION_UNSUPPORTED in a mission upload (AP_Mission's conversion from
  // MAVLink, libraries/AP_Mission/AP_Mission.cpp; MavlinkMissionManager::parse_mavlink_mission_item, PX4).
  if (command >= 5000 && command <= 5004) {
    return "it is a geofence item, not a mission item (the file holds a geofence: the autopilot refuses it in a "
           "mission, MAV_MISSION_UNSUPPORTED)";
  }
  if (command == 5100) {
    return "it is a rally point, not a mission item (the autopilot refuses it in a mission, "
           "MAV_MISSION_UNSUPPORTED)";
  }
  if ((command >= 16 && command <= 99) || (command >= 31000 && command <= 31004)) {
    return "a navigation command that uascma does not fly";
  }
  return std::nullopt;
}
bool IsNavigation(int command) { return (command >= 16 && command <= 99) || (command >= 31000 && command <= 31004); }

namespace {

// --- flying the items ---------------------------------------------------------------------------------------------
class MissionBuilder {
 public:
  MissionBuilder(const RawMission& raw, const std::string& source, const MissionImportOptions& options)
      : raw_(raw), source_(source), options_(options), projection_(options.origin.value_or(raw.home)) {
    mission_.source = source;
    mission_.home = raw.home;
    mission_.home_amsl = raw.home_amsl;
    mission_.origin = projection_.origin();
    mission_.planned_speed = raw.planned_speed;
    mission_.warnings = raw.warnings;
    mission_.items = static_cast<int>(raw.items.size());
    mission_.home_W = Eigen::Vector3d::Zero();
    mission_.home_W.head<2>() = Local(raw.home, "home");
    position_ = mission_.home_W;
    mission_.firmware_type = raw.firmware_type;
    mission_.vehicle_type = raw.vehicle_type;
    mission_.firmware = raw.firmware;
    mission_.firmware_basis = raw.firmware_basis;
    for (std::size_t i = 0; i < raw.rally.size(); ++i) {
      RallyPoint rally;
      rally.position = {raw.rally[i][0], raw.rally[i][1]};
      rally.altitude = raw.rally[i][2];
      const Eigen::Vector2d p_NE = Local(rally.position, fmt::format("rallyPoints.points[{}]", i));
      rally.p_W = Eigen::Vector3d(p_NE.x(), p_NE.y(), 0.0);
      mission_.rally_points.push_back(rally);
    }
    for (const RawMission::Zone& raw_zone : raw.fence) {
      Geofence::Zone zone;
      zone.inclusion = raw_zone.inclusion;
      zone.name = raw_zone.name;
      if (raw_zone.polygon.empty()) {
        zone.centre_NE = Local(raw_zone.centre, raw_zone.name + ".circle.center");
        zone.radius = raw_zone.radius;
      } else {
        for (const GeoPoint& vertex : raw_zone.polygon) zone.polygon_NE.push_back(Local(vertex, raw_zone.name));
      }
      mission_.geofence.zones.push_back(std::move(zone));
    }
    if (!mission_.geofence.Allows(mission_.home_W.head<2>())) {
      Warn("home: outside the geofence (the emergency planners keep to it; the mission is flown as written)");
    }
    if (options_.map && options_.map->IsInsideBuilding(mission_.home_W + Eigen::Vector3d(0, 0, -0.1))) {
      throw InputError(
          source_, "home",
          fmt::format(
              "a planned home on open ground; ({:.1f}, {:.1f}) m is inside building {}", mission_.home_W.x(),
              mission_.home_W.y(),
              options_.map->building(options_.map->BuildingContaining(mission_.home_W + Eigen::Vector3d(0, 0, -0.1)))
                  .id));
    }
  }

  Mission Build() && {
    for (std::size_t i = 0; i < raw_.items.size(); ++i) {
      if (ended_) {
        std::string names;
        for (std::size_t j = i; j < raw_.items.size(); ++j) {
          names +=
              fmt::format("{}{} {}", j == i ? "" : ", ", raw_.items[j].number, MavCommandName(raw_.items[j].command));
        }
        Warn(fmt::format("items after the landing are never flown: {}", names));
        break;
      }
      Fly(raw_.items[i]);
    }
    if (mission_.waypoints.empty()) {
      throw InputError(source_, "mission", "at least one item that moves the vehicle (take-off, waypoint, land)");
    }
    if (Airborne()) {
      if (!options_.land_at_end) {
        throw InputError(source_, "mission", "a mission that ends landed (NAV_LAND or NAV_RETURN_TO_LAUNCH)");
      }
      Warn(
          fmt::format("the mission ends in the air at {:.1f} m, where {} would hold until the operator or a "
                      "failsafe acts: landing vertically there (mission.land_at_end)",
                      -position_.z(),
                      raw_.firmware == MissionFirmware::kUnknown ? std::string_view("the autopilot")
                                                                 : MissionFirmwareName(raw_.firmware)));
      Push(TouchdownBelow(position_.head<2>()), "land");
    }
    return std::move(mission_);
  }

 private:
  bool Airborne() const {
    return position_.z() < -kSamePlace + (options_.map ? -options_.map->SurfaceAltitudeAt(position_.head<2>()) : 0.0);
  }

  void Warn(const std::string& message) { mission_.warnings.push_back(fmt::format("{}: {}", source_, message)); }

  // What the mission's firmware does with a mission whose first move is not a take-off, started on the ground.
  // PX4 inserts a vertical take-off to the item's altitude (Mission::do_need_vertical_takeoff, "force takeoff if
  // landed"; at least MIS_TAKEOFF_ALT). ArduCopter refuses to start AUTO on the ground ("Auto: Missing Takeoff
  // Cmd", ModeAuto::init): the operator takes off in another mode and starts the mission in the air.
  std::string_view NoTakeoffMeaning() const {
    switch (raw_.firmware) {
      case MissionFirmware::kPx4:
        return "PX4 takes off vertically to the item's altitude first";
      case MissionFirmware::kArduPilot:
        return "ArduCopter does not start AUTO on the ground without a NAV_TAKEOFF: flown as taken off by hand "
               "and the mission started there";
      case MissionFirmware::kUnknown:
        break;
    }
    return "as PX4 takes off, and as an ArduCopter taken off by hand";
  }

  Eigen::Vector2d Local(const GeoPoint& point, const std::string& field) const {
    detail::CheckGeoPoint(point, source_, field);
    const Eigen::Vector2d p_NE = projection_.ToLocal(point);
    if (!(p_NE.allFinite() && p_NE.norm() <= options_.max_distance_from_origin)) {
      throw InputError(
          source_, field,
          fmt::format("a point within {:.0f} km of the local origin ({:.6f}, {:.6f}); it is {:.1f} km away",
                      options_.max_distance_from_origin / 1000.0, projection_.origin().lat_deg,
                      projection_.origin().lon_deg, p_NE.norm() / 1000.0));
    }
    return p_NE;
  }

  // The item's horizontal position; latitude = longitude = 0 (or null) means "where the vehicle is" for the
  // commands that allow it (MAVLink: a zero position is the current one for LAND, loiters and delays).
  Eigen::Vector2d Horizontal(const RawItem& item, bool zero_is_here) const {
    const double lat = item.params[4], lon = item.params[5];
    if (std::isnan(lat) && std::isnan(lon)) return position_.head<2>();
    if (zero_is_here && lat == 0.0 && lon == 0.0) return position_.head<2>();
    return Local({lat, lon}, item.name + " latitude/longitude");
  }

  // The item's height above home (m) from its altitude and frame.
  double Height(const RawItem& item) {
    if (item.altitude_above_terrain) {
      // QGroundControl's "calculated above terrain" without its terrain data: flown at "Altitude" above the map's
      // ground (flat, z = 0: the height above home's ground level).
      if (!terrain_warned_) {
        Warn(
            fmt::format("{}: terrain-calculated altitude (AltitudeMode 3) with params[6] null: flown at its "
                        "\"Altitude\" {:.1f} m over the map's ground (flat)",
                        item.name, *item.altitude_above_terrain));
        terrain_warned_ = true;
      }
      return *item.altitude_above_terrain;
    }
    const double altitude = item.params[6];
    if (std::isnan(altitude)) {
      throw InputError(source_, item.name + " altitude",
                       "a number of metres in params[6], got null (a terrain-calculated item needs AltitudeMode 3 and "
                       "its \"Altitude\")");
    }
    if (!std::isfinite(altitude)) throw InputError(source_, item.name + " altitude", "a finite number of metres");
    switch (item.frame) {
      case kMavFrameGlobalRelativeAlt:
      case kMavFrameGlobalRelativeAltInt:
        return altitude;
      case kMavFrameGlobal:
      case kMavFrameGlobalInt:
        if (!raw_.home_amsl) {
          throw InputError(source_, item.name + " frame",
                           fmt::format("a relative altitude (frame 3): frame {} gives the altitude above mean sea "
                                       "level, and the file gives no home altitude to refer it to",
                                       item.frame));
        }
        return altitude - *raw_.home_amsl;
      case kMavFrameGlobalTerrainAlt:
      case kMavFrameGlobalTerrainAltInt:
        if (!terrain_warned_) {
          Warn(fmt::format("{} frame {} (above terrain): read as above home, the map's ground being flat", item.name,
                           item.frame));
          terrain_warned_ = true;
        }
        return altitude;
      default:
        throw InputError(source_, item.name + " frame",
                         fmt::format("a global frame (0, 3, 5, 6, 10 or 11) for {}, got {}",
                                     MavCommandName(item.command), item.frame));
    }
  }

  // The height above home (m) a waypoint or a loiter flies to: its altitude as the mission's firmware reads it
  // (mission_file.h, MissionFirmware; docs/maps-and-missions-firmware.md).
  double TargetHeight(const RawItem& item) {
    if (raw_.firmware == MissionFirmware::kPx4) return Px4Height(item);
    // AP_Mission stores the altitude in whole centimetres (metres × 100, truncated toward 0; libraries/AP_Mission/
    // AP_Mission.cpp): an altitude under 1 cm is ArduPilot's altitude 0.
    const double altitude = item.params[6];
    const bool zero = !item.altitude_above_terrain && std::isfinite(altitude) && std::abs(altitude) < 0.01;
    if (!zero) return Height(item);
    if (raw_.firmware == MissionFirmware::kUnknown) {
      throw InputError(
          source_, item.name + " altitude",
          fmt::format("an altitude other than 0, or a file that names its firmware: ArduPilot reads altitude 0 as "
                      "\"hold the current altitude\", PX4 as altitude 0 of frame {}, and the file names neither ({}; "
                      "set mission.firmwareType to 3 for ArduPilot or 12 for PX4)",
                      item.frame, raw_.firmware_basis));
    }
    // ArduCopter's ModeAuto::loc_from_cmd (ArduCopter/mode_auto.cpp): altitude 0 takes the altitude of the previous
    // destination (where the vehicle is), in the item's frame, whatever that frame.
    if (!Airborne()) {
      throw InputError(source_, item.name + " altitude",
                       "a height above the ground: ArduPilot reads altitude 0 as \"hold the current altitude\", and "
                       "the vehicle is on the ground here (no NAV_TAKEOFF before it)");
    }
    Warn(fmt::format("{}: altitude 0: ArduPilot holds the current altitude, {:.1f} m above home", item.name,
                     -position_.z()));
    return -position_.z();
  }

  // PX4 (MavlinkMissionManager::parse_mavlink_mission_item, src/modules/mavlink/mavlink_mission.cpp): the altitude as
  // written, in frames 0/3/5/6; other frames are refused at upload.
  double Px4Height(const RawItem& item) {
    if (item.frame == kMavFrameGlobalTerrainAlt || item.frame == kMavFrameGlobalTerrainAltInt) {
      throw InputError(source_, item.name + " frame",
                       fmt::format("a frame PX4 accepts (0, 3, 5 or 6); PX4 refuses frame {} (above terrain) when the "
                                   "mission is uploaded (MAV_MISSION_UNSUPPORTED_FRAME)",
                                   item.frame));
    }
    const double height = Height(item);
    if (std::abs(height) <= kSamePlace && Airborne()) {
      Warn(fmt::format("{}: altitude 0 m above home: PX4 flies it down to home's ground level", item.name));
    }
    return height;
  }

  double TouchdownHeight(const Eigen::Vector2d& p_NE) const {
    return options_.map ? options_.map->SurfaceAltitudeAt(p_NE) : 0.0;
  }
  Eigen::Vector3d TouchdownBelow(const Eigen::Vector2d& p_NE) const {
    return Eigen::Vector3d(p_NE.x(), p_NE.y(), -TouchdownHeight(p_NE));
  }

  void Push(const Eigen::Vector3d& p_W, const std::string& label) {
    Waypoint waypoint;
    waypoint.p_W = p_W;
    waypoint.label = label;
    waypoint.max_speed = speed_;
    waypoint.item_number = item_number_;
    mission_.waypoints.push_back(std::move(waypoint));
    position_ = p_W;
  }

  void CheckClear(const Eigen::Vector3d& p_W, const RawItem& item) const {
    if (options_.map && options_.map->IsInsideBuilding(p_W)) {
      throw InputError(source_, item.name,
                       fmt::format("a {} clear of the buildings; ({:.1f}, {:.1f}) m at {:.1f} m is inside one",
                                   MavCommandName(item.command), p_W.x(), p_W.y(), -p_W.z()));
    }
  }

  // The straight leg from where the vehicle is to `target` must not meet a building (except `ignore_building`,
  // the roof it lands on).
  void CheckLeg(const Eigen::Vector3d& target, const RawItem& item, int ignore_building = kNoBuilding) const {
    if (!options_.map) return;
    const SegmentHit hit = options_.map->FirstHit(position_, target, ignore_building);
    if (hit.hit) {
      throw InputError(
          source_, item.name,
          fmt::format("a leg clear of the buildings; the leg of {} to ({:.1f}, {:.1f}) m at {:.1f} m meets "
                      "building {} at ({:.1f}, {:.1f}) m, {:.1f} m up",
                      MavCommandName(item.command), target.x(), target.y(), -target.z(),
                      options_.map->building(hit.building).id, hit.p_W.x(), hit.p_W.y(), -hit.p_W.z()));
    }
  }

  // A straight move to `target`; from the ground without a take-off, a vertical climb first (reported).
  void MoveTo(const Eigen::Vector3d& target, const RawItem& item, const std::string& label) {
    if (target.z() > kSamePlace) {
      throw InputError(source_, item.name + " altitude", fmt::format("a height ≥ 0 m above home, got {}", -target.z()));
    }
    if (-target.z() > kMissionHeightBounds.high) {
      throw InputError(source_, item.name + " altitude", OutsideBoundsMessage(kMissionHeightBounds, -target.z()));
    }
    CheckClear(target, item);
    if (!Airborne() && target.z() < position_.z() - kSamePlace && item.command != kMavCmdNavTakeoff) {
      Warn(fmt::format("{}: no NAV_TAKEOFF before it: climbing vertically to {:.1f} m first ({})", item.name,
                       -target.z(), NoTakeoffMeaning()));
      if ((target.head<2>() - position_.head<2>()).norm() > kSamePlace) {
        const Eigen::Vector3d climb(position_.x(), position_.y(), target.z());
        CheckLeg(climb, item);
        Push(climb, "takeoff");
      }
    }
    CheckLeg(target, item);
    Push(target, label);
  }

  void Hover(double seconds, const RawItem& item, const std::string& label) {
    RequireWithin(seconds, kMissionHoverBounds, source_, item.name + " param1");
    if (seconds == 0.0) return;
    if (mission_.waypoints.empty() || (mission_.waypoints.back().p_W - position_).norm() > kSamePlace) {
      Push(position_, label);
    }
    mission_.waypoints.back().hover_after_s += seconds;
  }

  // A loiter's altitude: 0 with no position keeps the current one (except PX4's: as written, TargetHeight).
  Eigen::Vector3d LoiterPoint(const RawItem& item) {
    const Eigen::Vector2d p_NE = Horizontal(item, true);
    const bool here = raw_.firmware != MissionFirmware::kPx4 && item.params[6] == 0.0 &&
                      (p_NE - position_.head<2>()).norm() <= kSamePlace;
    const double z = here ? position_.z() : -TargetHeight(item);
    return Eigen::Vector3d(p_NE.x(), p_NE.y(), z);
  }

  // The height above home (m) at which the firmware flies a NAV_RETURN_TO_LAUNCH home from where the vehicle is,
  // with its default parameters (docs/maps-and-missions-firmware.md). ArduCopter (ModeRTL's return target,
  // ArduCopter/mode_rtl.cpp): at least RTL_ALT = 15 m, lowered near home to the cone of slope RTL_CONE_SLOPE = 3
  // but at least 2.5 m (RTL_ABS_MIN_CLIMB) above the current height, never below it. PX4 (RTL::computeReturnAltitude,
  // src/modules/navigator/rtl.cpp): RTL_RETURN_ALT = 60 m; within NAV_ACC_RAD = 10 m of home twice the distance;
  // never below the current height. (Its cone of half-angle RTL_CONE_ANG applies within RTL_MIN_DIST, which by
  // default equals NAV_ACC_RAD: beyond the acceptance radius the return altitude is RTL_RETURN_ALT.) A file naming
  // neither firmware keeps the current height (the two differ).
  double ReturnHeight() const {
    const double current = -position_.z();
    const double distance = (mission_.home_W.head<2>() - position_.head<2>()).norm();
    switch (raw_.firmware) {
      case MissionFirmware::kArduPilot: {
        constexpr double kRtlAlt = 15.0, kRtlAltMin = 2.0, kConeSlope = 3.0, kAbsMinClimb = 2.5;
        const double target = std::max({current, kRtlAlt, kRtlAltMin});
        return std::max(current, std::min(target, std::max(distance * kConeSlope, current + kAbsMinClimb)));
      }
      case MissionFirmware::kPx4: {
        constexpr double kReturnAlt = 60.0, kAcceptanceRadius = 10.0;
        return std::max(distance <= kAcceptanceRadius ? 2.0 * distance : kReturnAlt, current);
      }
      case MissionFirmware::kUnknown:
        break;
    }
    return current;
  }

  // NAV_RETURN_TO_LAUNCH climbs where the vehicle is to the firmware's return height first (warned).
  void ClimbToReturnHeight(const RawItem& item) {
    if (!Airborne()) return;
    const double height = ReturnHeight();
    if (height <= -position_.z() + kSamePlace) return;
    Warn(
        fmt::format("{}: {} climbs to its return height, {:.1f} m above home, before flying home (its default "
                    "return parameters)",
                    item.name, MissionFirmwareName(raw_.firmware), height));
    MoveTo(Eigen::Vector3d(position_.x(), position_.y(), -height), item, "return climb");
  }

  // Move at the current altitude to above `p_NE`, then descend to the touchdown there.
  void LandAt(const Eigen::Vector2d& p_NE, const RawItem& item, const std::string& label) {
    if (!Airborne()) {
      Warn(fmt::format("{}: {} while on the ground: nothing to fly", item.name, MavCommandName(item.command)));
      ended_ = true;
      return;
    }
    const Eigen::Vector3d above(p_NE.x(), p_NE.y(), position_.z());
    if ((above - position_).norm() > kSamePlace) MoveTo(above, item, label + " approach");
    const Eigen::Vector3d touchdown = TouchdownBelow(p_NE);
    if (options_.map) {  // the descent may end on a roof: that building is where it lands, not an obstacle
      CheckLeg(touchdown, item, options_.map->BuildingContaining(touchdown + Eigen::Vector3d(0, 0, 0.01)));
    }
    Push(touchdown, label);
    ended_ = true;
  }

  // Frames with a global position, or MAV_FRAME_MISSION (no position).
  void CheckFrame(const RawItem& item) const {
    switch (item.frame) {
      case kMavFrameGlobal:
      case kMavFrameMission:
      case kMavFrameGlobalRelativeAlt:
      case kMavFrameGlobalInt:
      case kMavFrameGlobalRelativeAltInt:
      case kMavFrameGlobalTerrainAlt:
      case kMavFrameGlobalTerrainAltInt:
        return;
      default:
        throw InputError(source_, item.name + " frame",
                         fmt::format("a global frame (0, 3, 5, 6, 10 or 11) or 2 (no position); frame {} (local "
                                     "coordinates) is not modelled",
                                     item.frame));
    }
  }

  // NAV_LOITER_TURNS: a hover at the centre for as long as the turns would take at loiter_turn_speed.
  void FlyLoiterTurns(const RawItem& item, const std::string& label) {
    const Eigen::Vector3d p_W = LoiterPoint(item);
    if ((p_W - position_).norm() > kSamePlace) MoveTo(p_W, item, label);
    const double turns = item.params[0], radius = std::abs(item.params[2]);
    if (!(turns >= 0.0 && std::isfinite(turns)) || !std::isfinite(radius)) {
      throw InputError(source_, item.name, "param1 turns ≥ 0 and a finite param3 radius (m)");
    }
    const double seconds = turns * 2.0 * kPi * radius / options_.loiter_turn_speed;
    Warn(
        fmt::format("{}: NAV_LOITER_TURNS ({} turns of {} m) flown as a hover of {:.1f} s at the centre (the "
                    "circle is not modelled)",
                    item.name, turns, radius, seconds));
    Hover(seconds, item, label);
  }

  // NAV_TAKEOFF: a vertical climb where the vehicle stands.
  void FlyTakeoff(const RawItem& item) {
    const double height = raw_.firmware == MissionFirmware::kPx4 ? Px4Height(item) : Height(item);
    if (!(height > 0.0))
      throw InputError(source_, item.name + " altitude", fmt::format("a height > 0 m, got {}", height));
    const double lat = item.params[4], lon = item.params[5];
    if (std::isfinite(lat) && std::isfinite(lon) && !(lat == 0.0 && lon == 0.0)) {
      const double off = (Local({lat, lon}, item.name) - position_.head<2>()).norm();
      if (off > kTakeoffPositionTolerance) {
        Warn(fmt::format("{}: the take-off position is {:.1f} m away: the vehicle climbs where it stands", item.name,
                         off));
      }
    }
    if (Airborne())
      Warn(fmt::format("{}: NAV_TAKEOFF in the air: climbing or descending to {:.1f} m", item.name, height));
    MoveTo(Eigen::Vector3d(position_.x(), position_.y(), -height), item, "takeoff");
  }

  // DO_CHANGE_SPEED of ground or air speed (types 0, 1): the speed of the moves after it.
  void ChangeSpeed(const RawItem& item) {
    const double type = item.params[0], speed = item.params[1];
    if (type == 0.0 || type == 1.0) {
      if (speed > 0.0) {  // −1 (or 0): no change
        RequireWithin(speed, kMissionSpeedBounds, source_, item.name + " param2");
        speed_ = speed;
      }
    } else {
      Warn(fmt::format("{}: DO_CHANGE_SPEED of type {} (climb or descent speed) is not modelled", item.name, type));
    }
  }

  void Fly(const RawItem& item) {
    const std::string number = std::to_string(item.number);
    item_number_ = item.number;
    if (item.command != kMavCmdDoChangeSpeed && (item.command == kMavCmdNavRoi || !RefusalReason(item.command))) {
      Warn(fmt::format("{}: {} does not move the vehicle: skipped", item.name, MavCommandName(item.command)));
      return;
    }
    CheckFrame(item);
    switch (item.command) {
      case kMavCmdNavSplineWaypoint:
        Warn(fmt::format("{}: NAV_SPLINE_WAYPOINT flown as a NAV_WAYPOINT (straight legs, not the spline)", item.name));
        [[fallthrough]];
      case kMavCmdNavWaypoint: {
        const Eigen::Vector2d p_NE = Horizontal(item, true);
        MoveTo(Eigen::Vector3d(p_NE.x(), p_NE.y(), -TargetHeight(item)), item, "waypoint " + number);
        const double hold = std::isnan(item.params[0]) ? 0.0 : item.params[0];
        Hover(hold, item, "waypoint " + number);
        return;
      }
      case kMavCmdNavLoiterTime: {
        const Eigen::Vector3d p_W = LoiterPoint(item);
        if ((p_W - position_).norm() > kSamePlace) MoveTo(p_W, item, "loiter " + number);
        Hover(item.params[0], item, "loiter " + number);
        return;
      }
      case kMavCmdNavLoiterTurns:
        FlyLoiterTurns(item, "loiter " + number);
        return;
      case kMavCmdNavLoiterToAlt: {
        const Eigen::Vector2d p_NE = Horizontal(item, true);
        MoveTo(Eigen::Vector3d(p_NE.x(), p_NE.y(), -TargetHeight(item)), item, "loiter " + number);
        return;
      }
      case kMavCmdNavDelay: {
        if (item.params[0] < 0.0) {
          throw InputError(source_, item.name + " param1",
                           "a delay ≥ 0 s (a delay until a time of day, param1 = −1, is not modelled)");
        }
        Hover(item.params[0], item, "delay " + number);
        return;
      }
      case kMavCmdNavTakeoff:
        FlyTakeoff(item);
        return;
      case kMavCmdNavLand:
        LandAt(Horizontal(item, true), item, "land");
        return;
      case kMavCmdNavReturnToLaunch:
        ClimbToReturnHeight(item);
        LandAt(mission_.home_W.head<2>(), item, "return");
        return;
      case kMavCmdDoChangeSpeed:
        ChangeSpeed(item);
        return;
      default:
        break;
    }
    const std::optional<std::string> refused = RefusalReason(item.command);
    UASCMA_CHECK(refused.has_value(), "commands that do not move the vehicle are skipped before");
    throw InputError(
        source_, item.name,
        fmt::format("a command that uascma flies (NAV_WAYPOINT, NAV_SPLINE_WAYPOINT, NAV_TAKEOFF, NAV_LAND, "
                    "NAV_RETURN_TO_LAUNCH, NAV_LOITER_TIME, NAV_LOITER_TURNS, NAV_LOITER_TO_ALT, NAV_DELAY, "
                    "DO_CHANGE_SPEED, a finite DO_JUMP, or one that does not move the vehicle); {} is "
                    "refused: {}",
                    MavCommandName(item.command), *refused));
  }

  const RawMission& raw_;
  const std::string& source_;
  const MissionImportOptions& options_;
  LocalProjection projection_;
  Mission mission_;
  Eigen::Vector3d position_ = Eigen::Vector3d::Zero();
  double speed_ = 0.0;  // m/s, DO_CHANGE_SPEED (0: the plan's cruise speed)
  int item_number_ = 0;  // the item being flown (Waypoint::item_number)
  bool ended_ = false;
  bool terrain_warned_ = false;
};

}  // namespace

Mission BuildMission(const RawMission& raw, const std::string& source, const MissionImportOptions& options) {
  return MissionBuilder(raw, source, options).Build();
}

}  // namespace uascma::planning::mission_detail
