#pragma once
// The raw MAVLink items of a mission file (include/uascma/planning/mission_file.h), shared by the units of the
// mission-file reader and writer: mission_plan_read.h (QGroundControl .plan), mission_wpl_read.h (QGC WPL 110
// .waypoints, the home and the DO_JUMP loops), mission_builder.h (flying the items) and mission_write.cc (export).
// Reading is two steps: the format readers collect the raw MAVLink items (command, frame, seven parameters), then
// BuildMission flies them in order, item by item, as a multicopter's mission executor would, and writes the waypoints
// in the local frame.
#include <array>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "uascma/common/bounds.h"
#include "uascma/planning/map_projection.h"
#include "uascma/planning/mission_file.h"

namespace uascma::planning::mission_detail {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = 3.14159265358979323846;
// m: a take-off item's position farther than this from where the vehicle stands is reported (it climbs where it
// stands). Our estimate: well above GNSS-level differences between a planned home and a take-off point.
constexpr double kTakeoffPositionTolerance = 1.0;
// m: moves shorter than this are no moves (FlightPlan::Through skips them too); heights within it of the ground
// count as on the ground.
constexpr double kSamePlace = 1e-6;

// Plausibility bounds of a mission's numbers (common/bounds.h), the scenario's bounds for the same
// quantities (sim/scenario_bounds.h): a height above home up to 1000 m (mission.cruise_altitude_m), a hover,
// delay or loiter of at most an hour (mission.drop_hover_s: four times the packs' ~15 min hover endurance), a
// speed of 0.1 to 30 m/s (limits.cruise_speed_mps). A value outside is an InputError naming the item.
constexpr Bounds kMissionHeightBounds{0.0, 1000.0, "m above home"};
constexpr Bounds kMissionHoverBounds{0.0, 3600.0, "s"};
constexpr Bounds kMissionSpeedBounds{0.1, 30.0, "m/s"};

// One MAVLink mission item as the files hold it: params = param1 … param4, latitude (x), longitude (y), altitude (z);
// NaN where the file has null.
struct RawItem {
  std::string name;  // "item 3" / "line 5 (index 4)", for messages
  int number = 0;    // the item's position in the mission, from 1
  int jump_id = -1;  // what a DO_JUMP's param1 names it by: QGroundControl's doJumpId, a .waypoints file's index
  int command = 0;
  int frame = 0;
  std::array<double, 7> params{};
  // QGroundControl's terrain-calculated item (AltitudeMode 3) whose AMSL altitude was never computed
  // (params[6] = null): its "Altitude" above the terrain.
  std::optional<double> altitude_above_terrain;
};

struct RawMission {
  GeoPoint home;
  std::optional<double> home_amsl;
  bool home_unset = false;  // ArduPilot's home of (0, 0): not yet known when the file was written
  std::vector<RawItem> items;
  std::vector<std::string> warnings;
  std::optional<double> planned_speed;
  std::optional<int> firmware_type, vehicle_type;
  MissionFirmware firmware = MissionFirmware::kUnknown;  // set by the format reader (mission_file.h)
  std::string firmware_basis;
  std::vector<std::array<double, 3>> rally;  // latitude, longitude (degrees), altitude (m, relative)
  struct Zone {
    bool inclusion = true;
    std::vector<GeoPoint> polygon;  // empty for a circle
    GeoPoint centre;                // of a circle
    double radius = 0.0;            // m, of a circle
    std::string name;
  };
  std::vector<Zone> fence;
};

}  // namespace uascma::planning::mission_detail
