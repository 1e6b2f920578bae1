#pragma once
// Flying a mission's raw items (mission_builder.cc, mission_items.h): the waypoints in the local frame, as a
// multicopter's mission executor would fly the items in order, and which MAVLink commands it flies.
#include <optional>
#include <string>

#include "mission_items.h"
#include "uascma/planning/mission_file.h"

namespace uascma::planning::mission_detail {

// Commands that move the vehicle in a way uascma does not fly, with the reason a refusal gives (nullopt: the
// command does not move the vehicle and is skipped with a warning).
std::optional<std::string> RefusalReason(int command);
bool IsNavigation(int command);

constexpr int kMavCmdNavSplineWaypoint = 82;
constexpr int kMavCmdNavRoi = 80;  // deprecated: points the camera, does not move the vehicle

// Flies the items.
Mission BuildMission(const RawMission& raw, const std::string& source, const MissionImportOptions& options);

}  // namespace uascma::planning::mission_detail
