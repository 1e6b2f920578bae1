#pragma once
// Mission files of ground control stations, read (the writers are in mission_write.h):
//  - QGroundControl plans (`.plan`, JSON: {"fileType": "Plan", "mission": {"plannedHomePosition": [lat, lon, alt],
//    "items": [...]}, "geoFence": …, "rallyPoints": …}), whose "SimpleItem" entries carry one MAVLink mission item
//    each ("command", "frame", "params": [param1 … param4, latitude, longitude, altitude]);
//  - the plain-text "QGC WPL 110" format of Mission Planner and ArduPilot (`.waypoints`): a header line
//    "QGC WPL 110", then one item per line, fields separated by tabs (or spaces):
//      index  current  frame  command  param1  param2  param3  param4  latitude  longitude  altitude  autocontinue
//    where the item of index 0 is the home position (absolute altitude, frame 0), whatever its command: Mission
//    Planner reads that line's position as the home and ArduPilot answers item 0 with its own home, so another
//    command written there (a NAV_TAKEOFF) is not flown (warned).
// Sources: QGroundControl developer guide "Plan File Format"; mavlink.io "File Formats" (plain-text mission
// format); the MAVLink common message set (MAV_CMD and MAV_FRAME numbers). Facts only, no code from them.
//
// What is modelled. A mission becomes a list of Waypoint for FlightPlan::Through (flight_plan.h: straight
// rest-to-rest moves with the trapezoidal profile of §5.4, hovers at waypoints), starting on the ground at the
// planned home:
//   16 NAV_WAYPOINT          move to the point; param1 = hold time (s) → a hover
//   19 NAV_LOITER_TIME       move to the point (latitude = longitude = 0: stay), hover param1 s (the loiter
//                            radius is not flown: a multicopter loiters at the point)
//   18 NAV_LOITER_TURNS      move to the point, hover for the time of param1 turns of the param3 radius at
//                            MissionImportOptions::loiter_turn_speed (warned: the circle itself is not flown)
//   31 NAV_LOITER_TO_ALT     move to the point at its altitude
//   93 NAV_DELAY             hover param1 s where the vehicle is (param1 = −1, a time of day, is an error)
//   22 NAV_TAKEOFF           climb vertically to the item's altitude (a copter takes off where it stands; a
//                            different take-off position is warned about)
//   21 NAV_LAND              move at the current altitude to above the point (0, 0: where it is), then descend
//                            to the touchdown height: the roof under it when a map is given, else the ground
//   20 NAV_RETURN_TO_LAUNCH  move at the current altitude to above home, descend to the ground at home
//   178 DO_CHANGE_SPEED      param1 = 0 or 1 (air or ground speed), param2 > 0: the horizontal speed limit of the
//                            moves that follow (Waypoint::max_speed); climb/descent speed changes are warned about
//   82 NAV_SPLINE_WAYPOINT   flown as NAV_WAYPOINT, straight legs (warned: the spline is not modelled)
//   177 DO_JUMP              unrolled: param1 names the target (QGroundControl's doJumpId; a .waypoints file's
//                            index), param2 the number of jumps; the items are flown as the autopilot would fly
//                            them (warned); a negative param2 (forever) is an InputError naming the item
// QGroundControl ComplexItems (survey, corridor scan) are flown from the SimpleItems QGroundControl stored in them
// (TransectStyleComplexItem.Items; warned); one that stores none (a structure scan) is an InputError naming it.
// Every command that does not move the vehicle — whatever its number: camera, gimbal, servo, relay, gripper,
// parachute, auxiliary function, region of interest, yaw, markers, CONDITION_DELAY/DISTANCE — is skipped and named
// in Mission::warnings. Refused (InputError naming the item, the command and why): the navigation commands
// (MAV_CMD 16–99, 31000–31004) not listed above (NAV_LOITER_UNLIM never ends, local frames, VTOL, follow, payload
// place, guided), and the commands that move the vehicle outside the mission's items (CONDITION_CHANGE_ALT,
// DO_SET_MODE, DO_SET_HOME, DO_FLIGHTTERMINATION, DO_CHANGE_ALTITUDE, DO_RALLY_LAND, DO_GO_AROUND, DO_REPOSITION,
// DO_PAUSE_CONTINUE, DO_SET_MISSION_CURRENT, DO_JUMP_TAG), and the geofence and rally items (MAV_CMD 5000–5004,
// 5100), which the autopilots refuse in a mission (a geofence saved as a mission file). A .plan whose
// mission.vehicleType is not a rotorcraft (a plane, a VTOL, a rover, a boat) is refused naming that member: its
// firmware flies or drives it otherwise. Items after a LAND or RTL are never flown
// and are named in a warning. A mission that ends in the air lands vertically where it ends (warned: the autopilot
// would hold there until the operator or a failsafe acts), unless MissionImportOptions::land_at_end is false (then
// it is an InputError: the simulator's flight must end landed). A vehicle that leaves the ground without a
// NAV_TAKEOFF climbs vertically to its first item's altitude (warned: PX4 inserts that take-off; ArduCopter refuses
// AUTO on the ground without one, so the operator takes off by hand and starts the mission in the air).
//
// Home. ArduPilot writes a home of (0, 0) when it was not yet known: the home is then the first item with a
// position (warned), its altitude unknown.
//
// Rally points and the geofence of a .plan ("rallyPoints": {"points": [[lat, lon, alt], …]}; "geoFence":
// {"polygons": [{"inclusion": bool, "polygon": [[lat, lon], …]}], "circles": [{"inclusion": bool, "circle":
// {"center": [lat, lon], "radius": m}}]}) are kept in Mission (rally_points, geofence). WithMissionSafety adds the
// rally points to a map's landing sites (the operator's own safe landing sites, for LandPract and LandASAP) and
// drops the sites the geofence forbids; Geofence::AllowsPath is what the emergency planners check their paths
// against.
//
// Altitude frames (MAV_FRAME): 3/6 GLOBAL_RELATIVE_ALT(_INT), altitude above home; 0/5 GLOBAL(_INT), altitude
// above mean sea level, allowed when the file gives the home's altitude (plannedHomePosition's third value; the
// home line of a .waypoints file), then height above home = altitude − home altitude; 10/11 GLOBAL_TERRAIN_ALT
// (_INT), read as above home (warned: the map's ground is flat, z = 0 everywhere; refused for PX4, which refuses
// them); 2 MISSION for items without a position. An altitude of 0 means what the file's firmware makes of it
// (MissionFirmware below: ArduPilot holds the current altitude, PX4 flies to 0). Local frames are an InputError.
// QGroundControl's terrain-calculated items (AltitudeMode 3) whose computed altitude is missing (params[6] = null) fly
// at their "Altitude" over the map's ground (warned); any other null altitude is an InputError that says so.
//
// Local frame. Latitude/longitude go to W (x north, y east, z down, ground at z = 0 at home's level) through the
// map importer's transverse Mercator projection (map_projection.h, LocalProjection; PROJ): centred on
// MissionImportOptions::origin (pass the imported map's origin, ImportSummary::origin, so that the mission and
// the buildings share a frame), else on the planned home. Points farther than max_distance_from_origin are an
// InputError, as for maps.
#include <Eigen/Core>

#include <array>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "uascma/planning/city_map.h"
#include "uascma/planning/flight_plan.h"
#include "uascma/planning/map_projection.h"

namespace uascma::planning {

enum class MissionFormat { kQgcPlan, kQgcWpl };
// By extension: .plan → kQgcPlan; .waypoints, .wpl, .txt → kQgcWpl. InputError otherwise.
MissionFormat DetectMissionFormat(const std::filesystem::path& path);

// MAVLink command numbers that the importer and exporter use (MAV_CMD, common message set).
enum MavCommand : int {
  kMavCmdNavWaypoint = 16,
  kMavCmdNavLoiterUnlimited = 17,
  kMavCmdNavLoiterTurns = 18,
  kMavCmdNavLoiterTime = 19,
  kMavCmdNavReturnToLaunch = 20,
  kMavCmdNavLand = 21,
  kMavCmdNavTakeoff = 22,
  kMavCmdNavLoiterToAlt = 31,
  kMavCmdNavDelay = 93,
  kMavCmdDoChangeSpeed = 178,
};
// MAV_AUTOPILOT and MAV_TYPE of an exported plan when the mission gives none: generic autopilot, hexarotor (the
// dissertation's vehicle).
inline constexpr int kMavAutopilotGeneric = 0;
inline constexpr int kMavTypeHexarotor = 13;
// MAV_FRAME numbers.
enum MavFrame : int {
  kMavFrameGlobal = 0,
  kMavFrameMission = 2,
  kMavFrameGlobalRelativeAlt = 3,
  kMavFrameGlobalInt = 5,
  kMavFrameGlobalRelativeAltInt = 6,
  kMavFrameGlobalTerrainAlt = 10,
  kMavFrameGlobalTerrainAltInt = 11,
};
// "NAV_WAYPOINT", "DO_JUMP", …; "command N" for a number we do not know.
std::string MavCommandName(int command);

// MAV_AUTOPILOT numbers of the two autopilots whose mission semantics the importer follows.
inline constexpr int kMavAutopilotArduPilotMega = 3;
inline constexpr int kMavAutopilotPx4 = 12;
// The autopilot a mission file is flown as (docs/maps-and-missions-firmware.md). The two read an item's altitude
// differently:
//  - ArduPilot (ArduCopter's ModeAuto::loc_from_cmd, ArduCopter/mode_auto.cpp; AP_Mission stores the altitude in
//    whole centimetres): an altitude of 0 (|altitude| < 1 cm) on a waypoint, spline waypoint or loiter means "hold
//    the current altitude", in every frame (relative, absolute, above terrain); frames 0/3/10 and their _INT twins.
//  - PX4 (MavlinkMissionManager::parse_mavlink_mission_item, src/modules/mavlink/mavlink_mission.cpp): the altitude
//    is taken as written, above home (frames 3/6) or above mean sea level (0/5); altitude 0 above home is home's
//    ground level. The terrain frames 10/11 are refused at upload (MAV_MISSION_UNSUPPORTED_FRAME).
//  - kUnknown (a .plan of another or no firmwareType): the altitudes both read alike are flown; an altitude 0 in
//    the air, which they read differently, is an InputError naming the item.
// A .waypoints file is Mission Planner's format for ArduPilot; a .plan names its firmware in mission.firmwareType.
enum class MissionFirmware { kArduPilot, kPx4, kUnknown };
std::string_view MissionFirmwareName(MissionFirmware firmware);  // "ArduPilot", "PX4", "no known firmware"

struct MissionImportOptions {
  std::optional<GeoPoint> origin;  // the local frame's origin; default: the planned home
  // The map the mission flies over (not owned; null: flat open ground). With it, LAND touches down on the roof under
  // its point (CityMap::SurfaceAltitudeAt), and a home inside a building, a waypoint inside one or a straight leg
  // through one is an InputError naming the item and the building.
  const CityMap* map = nullptr;
  bool land_at_end = true;  // a mission ending in the air lands vertically there (warned), else InputError
  // m/s: the speed at which LOITER_TURNS circles are timed. Our estimate: PlanLimits' default cruise speed.
  double loiter_turn_speed = 5.0;
  double max_distance_from_origin = 50'000.0;  // m, as MapImportOptions (the flat-projection limit)
  bool IsValid(std::string* error) const;
};

// The geofence of a .plan in the local frame W: the vehicle stays inside at least one inclusion zone (when there is
// any) and outside every exclusion zone (QGroundControl's and PX4's reading of several zones).
struct Geofence {
  struct Zone {
    bool inclusion = true;
    std::vector<Eigen::Vector2d> polygon_NE;  // m; empty for a circle
    Eigen::Vector2d centre_NE = Eigen::Vector2d::Zero();
    double radius = 0.0;  // m, a circle's
    std::string name;     // "geoFence.polygons[0]"
    bool Contains(const Eigen::Vector2d& p_NE) const;
  };
  std::vector<Zone> zones;
  bool empty() const { return zones.empty(); }
  bool Allows(const Eigen::Vector2d& p_NE) const;
  // Every point of the horizontal polyline allowed (checked every `step` m along it and at its vertices).
  bool AllowsPath(std::span<const Eigen::Vector2d> path_NE, double step = 1.0) const;
};

struct RallyPoint {
  GeoPoint position;
  double altitude = 0.0;                          // m above home, as the file gives it
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();  // on the ground below it (z = 0)
};

struct Mission {
  std::string source;  // the file
  MissionFormat format = MissionFormat::kQgcPlan;
  GeoPoint home;                                     // the planned home, WGS84
  std::optional<double> home_amsl;                   // m above mean sea level, when the file gives it
  GeoPoint origin;                                   // the local frame's origin
  Eigen::Vector3d home_W = Eigen::Vector3d::Zero();  // home in W, on the ground (z = 0)
  std::vector<Waypoint> waypoints;                   // W, flown from home_W in order (FlightPlan::Through)
  std::vector<std::string> warnings;                 // one line each: the items read but not modelled, and our choices
  std::optional<double> planned_speed;  // m/s: the .plan's "hoverSpeed" (multicopter default speed), if any
  int items = 0;                        // mission items read (not counting the home; DO_JUMPs unrolled)
  std::optional<int> firmware_type;     // the .plan's mission.firmwareType (MAV_AUTOPILOT), kept for export
  std::optional<int> vehicle_type;      // the .plan's mission.vehicleType (MAV_TYPE)
  // The autopilot whose altitude meaning was applied, and why ("mission.firmwareType 3", "a .waypoints file").
  MissionFirmware firmware = MissionFirmware::kUnknown;
  std::string firmware_basis;
  std::vector<RallyPoint> rally_points;
  Geofence geofence;

  // The horizontal route home → waypoints (for CityMap::CruiseAltitude and the like), m.
  std::vector<Eigen::Vector2d> RouteNE() const;
  // One line naming the firmware applied and its basis: "flown as ArduPilot flies it (a .waypoints file): …".
  std::string FirmwareNote() const;
};

// Parses a mission file's text; `source` names it in messages. InputError on malformed or unsupported input.
Mission ParseMission(std::string_view text, const std::string& source, MissionFormat format,
                     const MissionImportOptions& options = {});
// Reads the file (format by extension, DetectMissionFormat).
Mission LoadMissionFile(const std::filesystem::path& path, const MissionImportOptions& options = {});

// The mission's plan: FlightPlan::Through(mission.home_W, mission.waypoints, limits).
FlightPlan MakeMissionPlan(const Mission& mission, const PlanLimits& limits);

// One MAVLink mission item as a vehicle holds it (MISSION_ITEM_INT of the common message set, in degrees and metres):
// params = param1 … param4, latitude (x · 1e-7), longitude (y · 1e-7), altitude (z, m in the item's frame).
struct MissionItem {
  int command = 0;
  int frame = 0;
  std::array<double, 7> params{};
};

// A mission uploaded to a vehicle (the MAVLink mission protocol), flown by the same reader as a mission file: the
// items are read as a file's items (DO_JUMPs unrolled, then BuildMission; every rule above holds, the map's
// buildings checked), numbered from 1 in upload order (seq + 1), from `home` (where the vehicle stands, on the
// ground). The mission protocol names no firmware: `firmware` and `firmware_basis` say whose altitude reading applies
// (kUnknown: an altitude 0 in the air is refused). `source` names the mission in messages ("the uploaded mission").
// InputError naming the item, as for a file.
Mission MissionFromItems(std::span<const MissionItem> items, const GeoPoint& home, const std::string& source,
                         MissionFirmware firmware, const std::string& firmware_basis,
                         const MissionImportOptions& options = {});

// m: the touchdown radius of a rally point's landing site: the landing radius a touchdown is judged by
// (sim/outcome.h kHoverTrackingErrorBound, 3.46 m); its risk is 0, the operator's own safe site (ours).
inline constexpr double kRallyPointSiteRadius = 3.46;
// The map with the mission's rally points added to its landing sites ("rally N", on the roof or ground under
// the point) and the sites outside its geofence removed; the map itself when the mission has neither.
CityMap WithMissionSafety(const CityMap& map, const Mission& mission);

// Where a mission's flight reaches its items: for each run of waypoints placed by one item (Waypoint::item_number),
// the plan time (s from the plan's start, FlightPlan::Through from home_W at `limits`) at which the vehicle arrives
// at the run's last waypoint, before the hold there; in flying order (an item repeated by DO_JUMP once per pass).
struct ItemArrival {
  double time_s = 0.0;
  int item_number = 0;  // from 1
};
std::vector<ItemArrival> MissionItemArrivals(const Mission& mission, const PlanLimits& limits);

}  // namespace uascma::planning
