#pragma once
// Mission files out (mission_write.cc): a FlightPlan as a QGroundControl plan (`.plan`, JSON) or as the QGC WPL 110
// text of Mission Planner (`.waypoints`), the formats mission_file.h reads; and the MAVLink mission items a vehicle
// would hold for it. Each move of the plan becomes one item in the relative-altitude frame; reading a written file
// back with ParseMission (and the same origin) gives the plan's waypoints again within the projection's round-off.
#include <Eigen/Core>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "uascma/planning/flight_plan.h"
#include "uascma/planning/map_projection.h"
#include "uascma/planning/mission_file.h"

namespace uascma::planning {

struct QgcPlanExportOptions {
  GeoPoint origin;         // of W (the map's or the mission's origin)
  double home_amsl = 0.0;  // m above mean sea level of W's ground (0 when unknown)
  // The planned home in W (on the ground); default: the plan's start with z = 0.
  std::optional<Eigen::Vector3d> home_W;
  // m/s, written as the mission's "cruiseSpeed" and "hoverSpeed" (pass the PlanLimits' cruise speed: the moves
  // planned at another speed get a DO_CHANGE_SPEED)
  double cruise_speed = 5.0;
  int firmware_type = kMavAutopilotGeneric;  // mission.firmwareType (pass Mission::firmware_type when known)
  int vehicle_type = kMavTypeHexarotor;      // mission.vehicleType
  bool IsValid(std::string* error) const;
};

// A FlightPlan as a QGroundControl plan (JSON text). Each move becomes one item in the relative-altitude frame
// (3): a first vertical climb from the ground → NAV_TAKEOFF; a last vertical descent → NAV_LAND (param7 = the
// touchdown height above home); every other move → NAV_WAYPOINT, whose param1 holds the hover that follows it.
// A horizontal move planned at a speed other than the one in force (QgcPlanExportOptions::cruise_speed at first) is
// preceded by a DO_CHANGE_SPEED (ground speed). A plan that starts in the air (an emergency plan) begins with a
// NAV_WAYPOINT at its start. Reading the text back
// with ParseMission (and the same origin) gives the plan's waypoints again within the projection's round-off.
std::string QgcPlanJson(const FlightPlan& plan, const QgcPlanExportOptions& options);
// The same items as MissionItem (what a vehicle holds and a ground station downloads; MissionFromItems reads them
// back).
std::vector<MissionItem> PlanMissionItems(const FlightPlan& plan, const QgcPlanExportOptions& options);
// Writes QgcPlanJson to `path` atomically (WriteFileAtomically).
void WriteQgcPlan(const std::filesystem::path& path, const FlightPlan& plan, const QgcPlanExportOptions& options);
// The same items as QgcPlanJson in the QGC WPL 110 text of Mission Planner (.waypoints): the home line (index 0,
// frame 0, altitude home_amsl), then one tab-separated line per item; latitude and longitude with 9 decimals
// (0.1 mm), heights with 4. Reading it back with ParseMission gives the plan's waypoints within 1 cm.
std::string QgcWplText(const FlightPlan& plan, const QgcPlanExportOptions& options);
// Writes the plan as a .plan or a .waypoints file by the extension (DetectMissionFormat), atomically.
void WriteMissionFile(const std::filesystem::path& path, const FlightPlan& plan, const QgcPlanExportOptions& options);

}  // namespace uascma::planning
