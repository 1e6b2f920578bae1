#pragma once
// The QGroundControl .plan reader (mission_plan_read.cc): the raw MAVLink items, the home, the geofence and the rally
// points of a .plan file (mission_items.h).
#include <string>
#include <string_view>

#include "mission_items.h"

namespace uascma::planning::mission_detail {

// The .plan file's raw mission (InputError naming the source, the field and what was expected).
RawMission ReadQgcPlan(std::string_view text, const std::string& source);

}  // namespace uascma::planning::mission_detail
