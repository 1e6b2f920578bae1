// Mission files in (QGroundControl .plan, QGC WPL 110 .waypoints): the contract is in
// include/uascma/planning/mission_file.h. Reading is two steps (mission_items.h): the format readers
// (mission_plan_read.cc, mission_wpl_read.cc) collect the raw MAVLink items, then BuildMission (mission_builder.cc)
// flies them; the writers are in mission_write.h. Here: the entry points, the geofence and the command names.
#include "uascma/planning/mission_file.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "mission_builder.h"
#include "mission_items.h"
#include "mission_plan_read.h"
#include "mission_wpl_read.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"

namespace uascma::planning {
namespace {

using mission_detail::kSamePlace;

std::string LowerExtension(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

}  // namespace

std::string MavCommandName(int command) {
  static const std::map<int, const char*> names = {
      {16, "NAV_WAYPOINT"},
      {17, "NAV_LOITER_UNLIM"},
      {18, "NAV_LOITER_TURNS"},
      {19, "NAV_LOITER_TIME"},
      {20, "NAV_RETURN_TO_LAUNCH"},
      {21, "NAV_LAND"},
      {22, "NAV_TAKEOFF"},
      {23, "NAV_LAND_LOCAL"},
      {24, "NAV_TAKEOFF_LOCAL"},
      {25, "NAV_FOLLOW"},
      {30, "NAV_CONTINUE_AND_CHANGE_ALT"},
      {31, "NAV_LOITER_TO_ALT"},
      {32, "DO_FOLLOW"},
      {34, "DO_ORBIT"},
      {80, "NAV_ROI"},
      {82, "NAV_SPLINE_WAYPOINT"},
      {84, "NAV_VTOL_TAKEOFF"},
      {85, "NAV_VTOL_LAND"},
      {92, "NAV_GUIDED_ENABLE"},
      {93, "NAV_DELAY"},
      {94, "NAV_PAYLOAD_PLACE"},
      {112, "CONDITION_DELAY"},
      {113, "CONDITION_CHANGE_ALT"},
      {114, "CONDITION_DISTANCE"},
      {115, "CONDITION_YAW"},
      {176, "DO_SET_MODE"},
      {177, "DO_JUMP"},
      {178, "DO_CHANGE_SPEED"},
      {179, "DO_SET_HOME"},
      {180, "DO_SET_PARAMETER"},
      {181, "DO_SET_RELAY"},
      {182, "DO_REPEAT_RELAY"},
      {183, "DO_SET_SERVO"},
      {184, "DO_REPEAT_SERVO"},
      {185, "DO_FLIGHTTERMINATION"},
      {186, "DO_CHANGE_ALTITUDE"},
      {189, "DO_LAND_START"},
      {190, "DO_RALLY_LAND"},
      {191, "DO_GO_AROUND"},
      {192, "DO_REPOSITION"},
      {193, "DO_PAUSE_CONTINUE"},
      {195, "DO_SET_ROI_LOCATION"},
      {197, "DO_SET_ROI_NONE"},
      {200, "DO_CONTROL_VIDEO"},
      {201, "DO_SET_ROI"},
      {202, "DO_DIGICAM_CONFIGURE"},
      {203, "DO_DIGICAM_CONTROL"},
      {204, "DO_MOUNT_CONFIGURE"},
      {205, "DO_MOUNT_CONTROL"},
      {206, "DO_SET_CAM_TRIGG_DIST"},
      {207, "DO_FENCE_ENABLE"},
      {208, "DO_PARACHUTE"},
      {211, "DO_GRIPPER"},
      {214, "DO_SET_CAM_TRIGG_INTERVAL"},
      {218, "DO_AUX_FUNCTION"},
      {224, "DO_SET_MISSION_CURRENT"},
      {601, "DO_JUMP_TAG"},
      {31000, "WAYPOINT_USER_1"},
      {530, "SET_CAMERA_MODE"},
      {531, "SET_CAMERA_ZOOM"},
      {532, "SET_CAMERA_FOCUS"},
      {1000, "DO_GIMBAL_MANAGER_PITCHYAW"},
      {2000, "IMAGE_START_CAPTURE"},
      {2001, "IMAGE_STOP_CAPTURE"},
      {2500, "VIDEO_START_CAPTURE"},
      {2501, "VIDEO_STOP_CAPTURE"},
      {5000, "NAV_FENCE_RETURN_POINT"},
      {5001, "NAV_FENCE_POLYGON_VERTEX_INCLUSION"},
      {5002, "NAV_FENCE_POLYGON_VERTEX_EXCLUSION"},
      {5003, "NAV_FENCE_CIRCLE_INCLUSION"},
      {5004, "NAV_FENCE_CIRCLE_EXCLUSION"},
      {5100, "NAV_RALLY_POINT"},
  };
  const auto it = names.find(command);
  return it != names.end() ? fmt::format("{} ({})", it->second, command) : fmt::format("command {}", command);
}

MissionFormat DetectMissionFormat(const std::filesystem::path& path) {
  const std::string extension = LowerExtension(path.extension().string());
  if (extension == ".plan") return MissionFormat::kQgcPlan;
  if (extension == ".waypoints" || extension == ".wpl" || extension == ".txt") return MissionFormat::kQgcWpl;
  throw InputError(path.string(), "extension", ".plan (QGroundControl JSON) or .waypoints / .wpl / .txt (QGC WPL 110)");
}

bool MissionImportOptions::IsValid(std::string* error) const {
  if (!(loiter_turn_speed > 0.0 && std::isfinite(loiter_turn_speed))) {
    if (error) *error = fmt::format("loiter_turn_speed: expected a positive speed (m/s), got {}", loiter_turn_speed);
    return false;
  }
  if (!(max_distance_from_origin > 0.0)) {
    if (error)
      *error =
          fmt::format("max_distance_from_origin: expected a positive distance (m), got {}", max_distance_from_origin);
    return false;
  }
  return true;
}

std::vector<Eigen::Vector2d> Mission::RouteNE() const {
  std::vector<Eigen::Vector2d> route{home_W.head<2>()};
  for (const Waypoint& waypoint : waypoints) {
    if ((waypoint.p_W.head<2>() - route.back()).norm() > kSamePlace) route.push_back(waypoint.p_W.head<2>());
  }
  return route;
}

std::string_view MissionFirmwareName(MissionFirmware firmware) {
  switch (firmware) {
    case MissionFirmware::kArduPilot:
      return "ArduPilot";
    case MissionFirmware::kPx4:
      return "PX4";
    case MissionFirmware::kUnknown:
      break;
  }
  return "no known firmware";
}

std::string Mission::FirmwareNote() const {
  switch (firmware) {
    case MissionFirmware::kArduPilot:
      return fmt::format("{}: altitudes as ArduPilot reads them ({}): altitude 0 holds the current altitude", source,
                         firmware_basis);
    case MissionFirmware::kPx4:
      return fmt::format("{}: altitudes as PX4 reads them ({}): as written, altitude 0 above home is its ground",
                         source, firmware_basis);
    case MissionFirmware::kUnknown:
      break;
  }
  return fmt::format("{}: altitudes as ArduPilot and PX4 both read them ({}: neither firmware named); an altitude 0 "
                     "in the air, which they read differently, is refused",
                     source, firmware_basis);
}

Mission ParseMission(std::string_view text, const std::string& source, MissionFormat format,
                     const MissionImportOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("mission import options: " + error);
  using namespace mission_detail;
  RawMission raw = format == MissionFormat::kQgcPlan ? ReadQgcPlan(text, source) : ReadQgcWpl(text, source);
  ResolveUnsetHome(raw, source);
  raw.items = UnrollJumps(raw.items, source, &raw.warnings);
  Mission mission = BuildMission(raw, source, options);
  mission.format = format;
  return mission;
}

Mission LoadMissionFile(const std::filesystem::path& path, const MissionImportOptions& options) {
  const MissionFormat format = DetectMissionFormat(path);
  return ParseMission(ReadFile(path), path.string(), format, options);
}

Mission MissionFromItems(std::span<const MissionItem> items, const GeoPoint& home, const std::string& source,
                         MissionFirmware firmware, const std::string& firmware_basis,
                         const MissionImportOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("mission import options: " + error);
  using namespace mission_detail;
  RawMission raw;
  raw.home = home;
  raw.firmware = firmware;
  raw.firmware_basis = firmware_basis;
  for (std::size_t seq = 0; seq < items.size(); ++seq) {
    RawItem item;
    item.number = static_cast<int>(seq) + 1;
    item.jump_id = static_cast<int>(seq);  // DO_JUMP's param1: the target's sequence number (MAV_CMD_DO_JUMP)
    item.name = fmt::format("item {} (seq {})", item.number, seq);
    item.command = items[seq].command;
    item.frame = items[seq].frame;
    item.params = items[seq].params;
    raw.items.push_back(std::move(item));
  }
  raw.items = UnrollJumps(raw.items, source, &raw.warnings);
  return BuildMission(raw, source, options);
}

std::vector<ItemArrival> MissionItemArrivals(const Mission& mission, const PlanLimits& limits) {
  std::vector<ItemArrival> arrivals;
  const std::vector<Waypoint>& waypoints = mission.waypoints;
  for (std::size_t k = 0; k < waypoints.size(); ++k) {
    if (waypoints[k].item_number <= 0) continue;
    if (k + 1 < waypoints.size() && waypoints[k + 1].item_number == waypoints[k].item_number) continue;
    // The plan through the waypoints up to this one ends with its hold: the arrival is that much earlier.
    const std::vector<Waypoint> prefix(waypoints.begin(), waypoints.begin() + static_cast<std::ptrdiff_t>(k) + 1);
    const double end_s = FlightPlan::Through(mission.home_W, prefix, limits).duration();
    arrivals.push_back({end_s - waypoints[k].hover_after_s, waypoints[k].item_number});
  }
  return arrivals;
}

FlightPlan MakeMissionPlan(const Mission& mission, const PlanLimits& limits) {
  return FlightPlan::Through(mission.home_W, mission.waypoints, limits);
}

bool Geofence::Zone::Contains(const Eigen::Vector2d& p_NE) const {
  if (polygon_NE.empty()) return (p_NE - centre_NE).norm() <= radius;
  // Even-odd crossing test.
  bool inside = false;
  for (std::size_t i = 0, j = polygon_NE.size() - 1; i < polygon_NE.size(); j = i++) {
    const Eigen::Vector2d& a = polygon_NE[i];
    const Eigen::Vector2d& b = polygon_NE[j];
    if ((a.y() > p_NE.y()) != (b.y() > p_NE.y()) &&
        p_NE.x() < (b.x() - a.x()) * (p_NE.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      inside = !inside;
    }
  }
  return inside;
}

bool Geofence::Allows(const Eigen::Vector2d& p_NE) const {
  bool any_inclusion = false, in_inclusion = false;
  for (const Zone& zone : zones) {
    if (zone.inclusion) {
      any_inclusion = true;
      in_inclusion = in_inclusion || zone.Contains(p_NE);
    } else if (zone.Contains(p_NE)) {
      return false;
    }
  }
  return !any_inclusion || in_inclusion;
}

bool Geofence::AllowsPath(std::span<const Eigen::Vector2d> path_NE, double step) const {
  if (zones.empty()) return true;
  for (std::size_t i = 0; i < path_NE.size(); ++i) {
    if (!Allows(path_NE[i])) return false;
    if (i + 1 == path_NE.size()) break;
    const Eigen::Vector2d delta = path_NE[i + 1] - path_NE[i];
    const int samples = static_cast<int>(std::ceil(delta.norm() / step));
    for (int k = 1; k < samples; ++k) {
      if (!Allows(path_NE[i] + delta * (static_cast<double>(k) / samples))) return false;
    }
  }
  return true;
}

CityMap WithMissionSafety(const CityMap& map, const Mission& mission) {
  if (mission.rally_points.empty() && mission.geofence.empty()) return map;
  std::vector<LandingSite> sites;
  for (const LandingSite& site : map.sites()) {
    if (mission.geofence.Allows(site.p_W.head<2>())) sites.push_back(site);
  }
  for (std::size_t i = 0; i < mission.rally_points.size(); ++i) {
    LandingSite site;
    site.id = fmt::format("rally {}", i);
    const Eigen::Vector2d p_NE = mission.rally_points[i].p_W.head<2>();
    site.p_W = Eigen::Vector3d(p_NE.x(), p_NE.y(), -map.SurfaceAltitudeAt(p_NE));
    site.radius = kRallyPointSiteRadius;
    site.risk = 0.0;
    sites.push_back(std::move(site));
  }
  return CityMap(map.buildings(), std::move(sites));
}

}  // namespace uascma::planning
