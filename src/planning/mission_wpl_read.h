#pragma once
// The QGC WPL 110 reader (mission_wpl_read.cc: .waypoints, as Mission Planner and ArduPilot write them), and what
// both readers need before the items are flown: an unset home resolved, DO_JUMP loops unrolled (mission_items.h).
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "mission_items.h"

namespace uascma::planning::mission_detail {

constexpr int kMavCmdDoJump = 177;
// A mission unrolled from DO_JUMPs is refused beyond this many items (nested loops multiply).
constexpr std::size_t kMaxUnrolledItems = 100'000;

// The .waypoints file's raw mission (InputError naming the source, the field and what was expected).
RawMission ReadQgcWpl(std::string_view text, const std::string& source);

// ArduPilot's unset home (0, 0): taken from the first item with a position (warned).
void ResolveUnsetHome(RawMission& raw, const std::string& source);
// DO_JUMPs unrolled into the items they repeat (an endless one is refused).
std::vector<RawItem> UnrollJumps(const std::vector<RawItem>& items, const std::string& source,
                                 std::vector<std::string>* warnings);

}  // namespace uascma::planning::mission_detail
