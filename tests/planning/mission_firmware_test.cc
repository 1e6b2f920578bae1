// The firmware a mission file is flown as (include/uascma/planning/mission_file.h, MissionFirmware): ArduPilot's
// altitude 0 holds the current altitude in every frame, PX4 flies an altitude as written and refuses the terrain
// frames, a file that names neither is refused where the two differ; and QGroundControl's earlier SimpleItem
// layouts read as the current one.
#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/planning/mission_file.h"

namespace uascma::planning {
namespace {

constexpr double kExactHeight = 1e-9;  // m: heights are differences of the files' decimal numbers
constexpr double kHomeLat = 40.77, kHomeLon = -73.96, kHomeAmsl = 10.0;

// One MAVLink item: command, frame, altitude (m), at a point `north_step` × 0.001° north of home.
struct Item {
  int command;
  int frame;
  double altitude;
  int north_step = 0;
};

std::string PlanText(const std::vector<Item>& items, const std::string& firmware_member) {
  std::string json_items;
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Item& item = items[i];
    json_items += fmt::format(
        "{}{{\"type\": \"SimpleItem\", \"command\": {}, \"frame\": {}, \"autoContinue\": true, \"doJumpId\": {}, "
        "\"params\": [0, 0, 0, null, {:.6f}, {:.6f}, {}]}}",
        i == 0 ? "" : ", ", item.command, item.frame, i + 1, kHomeLat + 0.001 * item.north_step, kHomeLon,
        item.altitude);
  }
  return fmt::format(
      "{{\"fileType\": \"Plan\", \"version\": 1, \"groundStation\": \"QGroundControl\", \"mission\": {{{}"
      "\"plannedHomePosition\": [{}, {}, {}], \"items\": [{}]}}}}",
      firmware_member, kHomeLat, kHomeLon, kHomeAmsl, json_items);
}

std::string WaypointsText(const std::vector<Item>& items) {
  std::string text = fmt::format("QGC WPL 110\n0\t1\t0\t16\t0\t0\t0\t0\t{}\t{}\t{}\t1\n", kHomeLat, kHomeLon, kHomeAmsl);
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Item& item = items[i];
    text += fmt::format("{}\t0\t{}\t{}\t0\t0\t0\t0\t{:.6f}\t{:.6f}\t{}\t1\r\n", i + 1, item.frame, item.command,
                        kHomeLat + 0.001 * item.north_step, kHomeLon, item.altitude);
  }
  return text;
}

Mission Plan(const std::vector<Item>& items, int firmware_type) {
  return ParseMission(PlanText(items, fmt::format("\"firmwareType\": {}, ", firmware_type)), "m.plan",
                      MissionFormat::kQgcPlan);
}

std::string ErrorOf(const std::string& text, MissionFormat format) {
  try {
    ParseMission(text, format == MissionFormat::kQgcPlan ? "m.plan" : "m.waypoints", format);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

bool AnyWarningContains(const Mission& mission, const std::string& text) {
  for (const std::string& warning : mission.warnings) {
    if (warning.find(text) != std::string::npos) return true;
  }
  return false;
}

// Take-off to 20 m, a waypoint at altitude 0 (relative), one at 30 m, return to launch.
const std::vector<Item> kAltitudeZeroMission = {{kMavCmdNavTakeoff, kMavFrameGlobalRelativeAlt, 20.0},
                                                {kMavCmdNavWaypoint, kMavFrameGlobalRelativeAlt, 0.0, 1},
                                                {kMavCmdNavWaypoint, kMavFrameGlobalRelativeAlt, 30.0, 2},
                                                {kMavCmdNavReturnToLaunch, kMavFrameMission, 0.0}};

TEST(MissionFirmwareTest, ArduPilotHoldsTheCurrentAltitudeForAltitudeZeroInBothFormats) {
  const Mission waypoints = ParseMission(WaypointsText(kAltitudeZeroMission), "m.waypoints", MissionFormat::kQgcWpl);
  const Mission plan = Plan(kAltitudeZeroMission, kMavAutopilotArduPilotMega);
  for (const Mission* mission : {&waypoints, &plan}) {
    SCOPED_TRACE(mission->source);
    EXPECT_EQ(mission->firmware, MissionFirmware::kArduPilot);
    ASSERT_GE(mission->waypoints.size(), 3u);
    EXPECT_NEAR(-mission->waypoints[0].p_W.z(), 20.0, kExactHeight);  // take-off
    EXPECT_NEAR(-mission->waypoints[1].p_W.z(), 20.0, kExactHeight);  // altitude 0: the 20 m held
    EXPECT_NEAR(-mission->waypoints[2].p_W.z(), 30.0, kExactHeight);
    EXPECT_NEAR(mission->waypoints.back().p_W.z(), 0.0, kExactHeight);  // landed at home
    EXPECT_TRUE(AnyWarningContains(*mission, "ArduPilot holds the current altitude, 20.0 m")) << mission->source;
    EXPECT_NE(mission->FirmwareNote().find("ArduPilot"), std::string::npos);
  }
  EXPECT_NE(waypoints.FirmwareNote().find("a .waypoints file"), std::string::npos) << waypoints.FirmwareNote();
  EXPECT_NE(plan.FirmwareNote().find("mission.firmwareType 3"), std::string::npos) << plan.FirmwareNote();
}

TEST(MissionFirmwareTest, ArduPilotAltitudeZeroHoldsInTheAbsoluteAndTerrainFramesToo) {
  for (const int frame : {kMavFrameGlobal, kMavFrameGlobalInt, kMavFrameGlobalTerrainAlt,
                          kMavFrameGlobalTerrainAltInt, kMavFrameGlobalRelativeAltInt}) {
    SCOPED_TRACE(frame);
    const Mission mission = Plan({{kMavCmdNavTakeoff, kMavFrameGlobalRelativeAlt, 15.0},
                                  {kMavCmdNavWaypoint, frame, 0.0, 1},
                                  {kMavCmdNavLoiterTime, frame, 0.0, 2},
                                  {kMavCmdNavReturnToLaunch, kMavFrameMission, 0.0}},
                                 kMavAutopilotArduPilotMega);
    ASSERT_GE(mission.waypoints.size(), 3u);
    EXPECT_NEAR(-mission.waypoints[1].p_W.z(), 15.0, kExactHeight);
    EXPECT_NEAR(-mission.waypoints[2].p_W.z(), 15.0, kExactHeight);  // the loiter at a position, altitude 0
  }
}

TEST(MissionFirmwareTest, ArduPilotKeepsTheAltitudeInWholeCentimetres) {
  // 0.4 cm is stored as 0 cm: held; 2 cm is 2 cm above home.
  const Mission below = Plan({{kMavCmdNavTakeoff, kMavFrameGlobalRelativeAlt, 12.0},
                              {kMavCmdNavWaypoint, kMavFrameGlobalRelativeAlt, 0.004, 1},
                              {kMavCmdNavReturnToLaunch, kMavFrameMission, 0.0}},
                             kMavAutopilotArduPilotMega);
  EXPECT_NEAR(-below.waypoints[1].p_W.z(), 12.0, kExactHeight);
  const Mission above = Plan({{kMavCmdNavTakeoff, kMavFrameGlobalRelativeAlt, 12.0},
                              {kMavCmdNavWaypoint, kMavFrameGlobalRelativeAlt, 0.02, 1},
                              {kMavCmdNavReturnToLaunch, kMavFrameMission, 0.0}},
                             kMavAutopilotArduPilotMega);
  EXPECT_NEAR(-above.waypoints[1].p_W.z(), 0.02, kExactHeight);
}

TEST(MissionFirmwareTest, ArduPilotAltitudeZeroOnTheGroundIsRefusedNamingTheItem) {
  const std::string error = ErrorOf(WaypointsText({{kMavCmdNavWaypoint, kMavFrameGlobalRelativeAlt, 0.0, 1},
                                                   {kMavCmdNavLand, kMavFrameGlobalRelativeAlt, 0.0, 1}}),
                                    MissionFormat::kQgcWpl);
  EXPECT_NE(error.find("line 3 (item 1) altitude"), std::string::npos) << error;
  EXPECT_NE(error.find("on the ground"), std::string::npos) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;  // one line
}

TEST(MissionFirmwareTest, Px4FliesAltitudeZeroAsWrittenAndSaysSo) {
  const Mission mission = Plan(kAltitudeZeroMission, kMavAutopilotPx4);
  EXPECT_EQ(mission.firmware, MissionFirmware::kPx4);
  ASSERT_GE(mission.waypoints.size(), 3u);
  EXPECT_NEAR(-mission.waypoints[1].p_W.z(), 0.0, kExactHeight);  // home's ground level
  EXPECT_TRUE(AnyWarningContains(mission, "PX4 flies it down to home's ground level"));
  EXPECT_NE(mission.FirmwareNote().find("PX4"), std::string::npos);
  // Absolute frame: 10 m above mean sea level over a home at 10 m is the ground too, 25 m is 15 m up.
  const Mission amsl = Plan({{kMavCmdNavTakeoff, kMavFrameGlobalRelativeAlt, 20.0},
                             {kMavCmdNavWaypoint, kMavFrameGlobal, 25.0, 1},
                             {kMavCmdNavReturnToLaunch, kMavFrameMission, 0.0}},
                            kMavAutopilotPx4);
  EXPECT_NEAR(-amsl.waypoints[1].p_W.z(), 15.0, kExactHeight);
}

TEST(MissionFirmwareTest, Px4RefusesTheTerrainFramesAsItsUploadDoes) {
  for (const int frame : {kMavFrameGlobalTerrainAlt, kMavFrameGlobalTerrainAltInt}) {
    const std::string error = ErrorOf(PlanText({{kMavCmdNavTakeoff, kMavFrameGlobalRelativeAlt, 20.0},
                                                {kMavCmdNavWaypoint, frame, 30.0, 1},
                                                {kMavCmdNavReturnToLaunch, kMavFrameMission, 0.0}},
                                               "\"firmwareType\": 12, "),
                                      MissionFormat::kQgcPlan);
    EXPECT_NE(error.find("mission.items[1] (item 2) frame"), std::string::npos) << error;
    EXPECT_NE(error.find(fmt::format("PX4 refuses frame {}", frame)), std::string::npos) << error;
  }
  // ArduPilot flies the same file (the terrain read as flat ground, warned).
  EXPECT_NO_THROW(Plan({{kMavCmdNavTakeoff, kMavFrameGlobalRelativeAlt, 20.0},
                        {kMavCmdNavWaypoint, kMavFrameGlobalTerrainAlt, 30.0, 1},
                        {kMavCmdNavReturnToLaunch, kMavFrameMission, 0.0}},
                       kMavAutopilotArduPilotMega));
}

TEST(MissionFirmwareTest, AFileNamingNeitherFirmwareIsRefusedOnlyWhereTheyDiffer) {
  for (const std::string& member : {std::string("\"firmwareType\": 0, "), std::string()}) {
    SCOPED_TRACE(member);
    const std::string error = ErrorOf(PlanText(kAltitudeZeroMission, member), MissionFormat::kQgcPlan);
    EXPECT_NE(error.find("mission.items[1] (item 2) altitude"), std::string::npos) << error;
    EXPECT_NE(error.find("firmwareType"), std::string::npos) << error;
    // Without an altitude 0 it flies: both read the other altitudes alike.
    std::vector<Item> nonzero = kAltitudeZeroMission;
    nonzero[1].altitude = 20.0;
    const Mission mission =
        ParseMission(PlanText(nonzero, member), "m.plan", MissionFormat::kQgcPlan);
    EXPECT_EQ(mission.firmware, MissionFirmware::kUnknown);
    EXPECT_NEAR(-mission.waypoints[1].p_W.z(), 20.0, kExactHeight);
    EXPECT_NE(mission.FirmwareNote().find("neither firmware named"), std::string::npos) << mission.FirmwareNote();
  }
}

// QGroundControl's earlier layouts: "params" of 4 plus "coordinate", and "param1"…"param4" plus "coordinate" with
// the type "missionItem". Both read as the current 7-number layout of the same items.
TEST(MissionFirmwareTest, QgcEarlierSimpleItemLayoutsReadAsTheCurrentOne) {
  const std::string current = PlanText(kAltitudeZeroMission, "\"firmwareType\": 3, ");
  std::string v2_items, v1_items;
  for (std::size_t i = 0; i < kAltitudeZeroMission.size(); ++i) {
    const Item& item = kAltitudeZeroMission[i];
    const std::string coordinate =
        fmt::format("[{:.6f}, {:.6f}, {}]", kHomeLat + 0.001 * item.north_step, kHomeLon, item.altitude);
    v2_items += fmt::format(
        "{}{{\"type\": \"SimpleItem\", \"command\": {}, \"frame\": {}, \"autoContinue\": true, \"doJumpId\": {}, "
        "\"params\": [0, 0, 0, null], \"coordinate\": {}}}",
        i == 0 ? "" : ", ", item.command, item.frame, i + 1, coordinate);
    v1_items += fmt::format(
        "{}{{\"type\": \"missionItem\", \"id\": {}, \"command\": {}, \"frame\": {}, \"autoContinue\": true, "
        "\"param1\": 0, \"param2\": 0, \"param3\": 0, \"param4\": null, \"coordinate\": {}}}",
        i == 0 ? "" : ", ", i + 1, item.command, item.frame, coordinate);
  }
  const auto plan_with = [](const std::string& items) {
    return fmt::format(
        "{{\"fileType\": \"Plan\", \"version\": 1, \"mission\": {{\"firmwareType\": 3, \"plannedHomePosition\": "
        "[{}, {}, {}], \"items\": [{}]}}}}",
        kHomeLat, kHomeLon, kHomeAmsl, items);
  };
  const Mission reference = ParseMission(current, "m.plan", MissionFormat::kQgcPlan);
  for (const std::string& items : {v2_items, v1_items}) {
    const Mission mission = ParseMission(plan_with(items), "m.plan", MissionFormat::kQgcPlan);
    ASSERT_EQ(mission.waypoints.size(), reference.waypoints.size());
    for (std::size_t w = 0; w < mission.waypoints.size(); ++w) {
      EXPECT_EQ(mission.waypoints[w].p_W, reference.waypoints[w].p_W) << w;  // the same numbers, the same bits
    }
  }
  // The first layout's home: a mission item holding its coordinate.
  const std::string home_item = fmt::format(
      "{{\"fileType\": \"Plan\", \"mission\": {{\"firmwareType\": 3, \"plannedHomePosition\": {{\"command\": 16, "
      "\"frame\": 0, \"coordinate\": [{}, {}, {}]}}, \"items\": [{}]}}}}",
      kHomeLat, kHomeLon, kHomeAmsl, v1_items);
  const Mission first = ParseMission(home_item, "m.plan", MissionFormat::kQgcPlan);
  ASSERT_EQ(first.waypoints.size(), reference.waypoints.size());
  for (std::size_t w = 0; w < first.waypoints.size(); ++w) EXPECT_EQ(first.waypoints[w].p_W, reference.waypoints[w].p_W);
  ASSERT_TRUE(first.home_amsl.has_value());
  EXPECT_EQ(*first.home_amsl, kHomeAmsl);
  // A coordinate without its altitude is refused naming the item (QGroundControl requires the altitude too).
  std::string broken = v2_items;
  broken.replace(broken.find(", 20]"), 5, "]");
  const std::string error = ErrorOf(plan_with(broken), MissionFormat::kQgcPlan);
  EXPECT_NE(error.find("mission.items[0].coordinate"), std::string::npos) << error;
}

// Index 0 of a .waypoints file is the home slot whatever its command: Mission Planner reads the line's position as
// the home and ArduPilot answers item 0 with its own home, so a NAV_TAKEOFF written there is never flown.
TEST(MissionFirmwareTest, ATakeoffInTheHomeSlotIsTheHomeAndIsNotFlown) {
  const std::string text =
      "QGC WPL 110\n"
      "0\t0\t3\t22\t0\t0\t0\t0\t40.770000\t-73.960000\t10.000000\t1\n"
      "1\t0\t3\t16\t0\t0\t0\t0\t40.770000\t-73.960000\t20.000000\t1\n"
      "2\t0\t3\t16\t0\t0\t0\t0\t40.771000\t-73.960000\t20.000000\t1\n"
      "3\t0\t3\t21\t0\t0\t0\t0\t40.771000\t-73.960000\t0.000000\t1\n";
  const Mission mission = ParseMission(text, "m.waypoints", MissionFormat::kQgcWpl);
  EXPECT_EQ(mission.home.lat_deg, 40.77);
  EXPECT_EQ(mission.home.lon_deg, -73.96);
  EXPECT_FALSE(mission.home_amsl.has_value());  // frame 3: the home's altitude above sea level is not given
  EXPECT_TRUE(AnyWarningContains(mission, "line 2 (home): NAV_TAKEOFF (22) in the home slot (index 0) is not flown"));
  // No take-off is flown to 10 m: the first move is the climb to item 1's 20 m above home, then north, then land.
  ASSERT_EQ(mission.waypoints.size(), 3u);
  EXPECT_NEAR(-mission.waypoints[0].p_W.z(), 20.0, kExactHeight);
  EXPECT_NEAR(mission.waypoints[0].p_W.head<2>().norm(), 0.0, kExactHeight);
  EXPECT_NEAR(-mission.waypoints[1].p_W.z(), 20.0, kExactHeight);
  EXPECT_GT(mission.waypoints[1].p_W.x(), 100.0);  // 0.001° of latitude ≈ 111 m north
  EXPECT_NEAR(mission.waypoints.back().p_W.z(), 0.0, kExactHeight);
  EXPECT_TRUE(AnyWarningContains(mission, "ArduCopter does not start AUTO on the ground without a NAV_TAKEOFF"));
}

// A Mission Planner geofence saved as QGC WPL 110 (NAV_FENCE_* items): the autopilots refuse those items in a
// mission upload; uascma refuses the file naming the first such item, on one line.
TEST(MissionFirmwareTest, AGeofenceFileIsRefusedNamingItsFirstVertex) {
  std::string text =
      fmt::format("QGC WPL 110\n0\t1\t0\t16\t0\t0\t0\t0\t{}\t{}\t{}\t1\n", kHomeLat, kHomeLon, kHomeAmsl);
  for (int i = 1; i <= 3; ++i) {
    text += fmt::format("{}\t0\t3\t5001\t3\t0\t0\t0\t{:.6f}\t{:.6f}\t0\t1\n", i, kHomeLat + 0.001 * (i % 2),
                        kHomeLon + 0.001 * (i / 2));
  }
  const std::string error = ErrorOf(text, MissionFormat::kQgcWpl);
  EXPECT_NE(error.find("line 3 (item 1)"), std::string::npos) << error;
  EXPECT_NE(error.find("NAV_FENCE_POLYGON_VERTEX_INCLUSION (5001)"), std::string::npos) << error;
  EXPECT_NE(error.find("geofence item"), std::string::npos) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  // A rally point in a mission likewise.
  const std::string rally = ErrorOf(
      PlanText({{kMavCmdNavTakeoff, kMavFrameGlobalRelativeAlt, 20.0}, {5100, kMavFrameGlobalRelativeAlt, 20.0, 1}},
               "\"firmwareType\": 3, "),
      MissionFormat::kQgcPlan);
  EXPECT_NE(rally.find("mission.items[1] (item 2)"), std::string::npos) << rally;
  EXPECT_NE(rally.find("NAV_RALLY_POINT (5100)"), std::string::npos) << rally;
}

// A plan for another vehicle than a rotorcraft (QGroundControl's vehicleType: a rover, a boat, a plane) is refused
// naming mission.vehicleType: its firmware drives or flies it otherwise (a rover ignores the altitudes).
TEST(MissionFirmwareTest, APlanForAnotherKindOfVehicleIsRefusedNamingItsType) {
  const auto plan_for = [](int vehicle_type) {
    return PlanText(kAltitudeZeroMission, fmt::format("\"firmwareType\": 3, \"vehicleType\": {}, ", vehicle_type));
  };
  for (const int vehicle_type : {1, 10, 11, 12, 20}) {
    SCOPED_TRACE(vehicle_type);
    const std::string error = ErrorOf(plan_for(vehicle_type), MissionFormat::kQgcPlan);
    EXPECT_NE(error.find("mission.vehicleType"), std::string::npos) << error;
    EXPECT_NE(error.find(fmt::format("got {} (", vehicle_type)), std::string::npos) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  }
  EXPECT_NE(ErrorOf(plan_for(10), MissionFormat::kQgcPlan).find("ground rover"), std::string::npos);
  for (const int vehicle_type : {0, 2, 3, 4, 13, 14, 15, 29, 35}) {
    SCOPED_TRACE(vehicle_type);
    EXPECT_EQ(ParseMission(plan_for(vehicle_type), "m.plan", MissionFormat::kQgcPlan).vehicle_type, vehicle_type);
  }
}

// A .plan that holds the plain-text format (QGroundControl refuses it: it loads a .plan as JSON) is refused on one
// line that says what it holds.
TEST(MissionFirmwareTest, PlainTextUnderAPlanNameIsRefusedSayingWhatItHolds) {
  const std::string error = ErrorOf(WaypointsText(kAltitudeZeroMission), MissionFormat::kQgcPlan);
  EXPECT_NE(error.find("m.plan: line 1"), std::string::npos) << error;
  EXPECT_NE(error.find("QGC WPL"), std::string::npos) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
}

// NAV_RETURN_TO_LAUNCH climbs first to the firmware's return height (default parameters), in closed form:
// ArduCopter max(h, min(max(h, 15 m), max(3 d, h + 2.5 m))), PX4 60 m beyond 10 m of home and 2 d within it, both
// never below the current height h (d: the horizontal distance to home); a file naming neither keeps h.
TEST(MissionFirmwareTest, ReturnToLaunchClimbsToTheFirmwaresReturnHeight) {
  struct Case {
    int firmware_type;
    double height;                           // m above home at the last waypoint
    double north_steps;                      // its distance north of home, in 0.001° of latitude
    std::function<double(double)> expected;  // the return height (m) from the distance d (m) to home
  };
  const auto held = [](double height) { return [height](double) { return height; }; };
  const std::vector<Case> cases = {
      {kMavAutopilotArduPilotMega, 6.0, 1.0, held(15.0)},                         // RTL_ALT: 3 d ≫ 15 m
      {kMavAutopilotArduPilotMega, 30.0, 1.0, held(30.0)},                        // above RTL_ALT: no climb
      {kMavAutopilotArduPilotMega, 6.0, 0.04, [](double d) { return 3.0 * d; }},  // the cone: 6 + 2.5 < 3 d < 15
      {kMavAutopilotArduPilotMega, 6.0, 0.01, held(6.0 + 2.5)},                   // 3 d < h + 2.5 m
      {kMavAutopilotPx4, 6.0, 1.0, held(60.0)},                                   // RTL_RETURN_ALT
      {kMavAutopilotPx4, 6.0, 0.04, [](double d) { return 2.0 * d; }},            // within NAV_ACC_RAD: 2 d
      {kMavAutopilotPx4, 80.0, 1.0, held(80.0)},                                  // above it: no climb
      {kMavAutopilotGeneric, 6.0, 1.0, held(6.0)},                                // neither: the current height
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(fmt::format("firmware {}, {} m, {} × 0.001°", c.firmware_type, c.height, c.north_steps));
    const std::string items = fmt::format(
        "{{\"type\": \"SimpleItem\", \"command\": 22, \"frame\": 3, \"params\": [0, 0, 0, null, {0}, {1}, {2}]}}, "
        "{{\"type\": \"SimpleItem\", \"command\": 16, \"frame\": 3, \"params\": [0, 0, 0, null, {3:.8f}, {1}, {2}]}}, "
        "{{\"type\": \"SimpleItem\", \"command\": 20, \"frame\": 2, \"params\": [0, 0, 0, 0, 0, 0, 0]}}",
        kHomeLat, kHomeLon, c.height, kHomeLat + 0.001 * c.north_steps);
    const Mission mission = ParseMission(
        fmt::format("{{\"fileType\": \"Plan\", \"mission\": {{\"firmwareType\": {}, \"plannedHomePosition\": "
                    "[{}, {}, {}], \"items\": [{}]}}}}",
                    c.firmware_type, kHomeLat, kHomeLon, kHomeAmsl, items),
        "m.plan", MissionFormat::kQgcPlan);
    // Take-off, the waypoint, [the climb,] above home, landed: the return flies home at its height.
    ASSERT_GE(mission.waypoints.size(), 4u);
    const double d = mission.waypoints[1].p_W.head<2>().norm();
    const Waypoint& above_home = mission.waypoints[mission.waypoints.size() - 2];
    EXPECT_NEAR(above_home.p_W.head<2>().norm(), 0.0, kExactHeight);
    EXPECT_NEAR(-above_home.p_W.z(), c.expected(d), kExactHeight) << "d = " << d << " m";
    EXPECT_EQ(AnyWarningContains(mission, "climbs to its return height"), c.expected(d) > c.height + 1e-6);
  }
}

}  // namespace
}  // namespace uascma::planning
