// The QGC WPL 110 reader (.waypoints, as Mission Planner and ArduPilot write them), and what both readers need
// before the items are flown: an unset home resolved, DO_JUMP loops unrolled (mission_items.h).
#include "mission_wpl_read.h"

#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include <fmt/format.h>

#include "map_import_detail.h"
#include "mission_builder.h"
#include "mission_items.h"
#include "uascma/common/error.h"
#include "uascma/common/text.h"

namespace uascma::planning::mission_detail {
namespace {

// The non-blank lines of `text`, trimmed, with their numbers from 1.
std::vector<std::pair<int, std::string>> NonBlankLines(std::string_view text) {
  std::vector<std::pair<int, std::string>> lines;
  int number = 0;
  for (std::size_t start = 0; start < text.size();) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    ++number;
    std::string_view line = detail::Trim(text.substr(start, end - start));
    if (!line.empty()) lines.emplace_back(number, std::string(line));
    start = end + 1;
  }
  return lines;
}

// The first line: "QGC WPL 110".
void CheckHeader(const std::vector<std::pair<int, std::string>>& lines, const std::string& source) {
  if (lines.empty() || lines.front().second.rfind("QGC WPL", 0) != 0) {
    throw InputError(source, "line 1", "the header \"QGC WPL 110\"");
  }
  std::istringstream header(lines.front().second);
  std::string qgc, wpl, version;
  header >> qgc >> wpl >> version;
  if (version != "110") {
    throw InputError(source, "line 1",
                     fmt::format("format version 110 (\"QGC WPL 110\"), got \"{}\"", BriefForMessage(version)));
  }
}

// One item line: index, current, frame, command, param1–4, latitude, longitude, altitude, autocontinue (fields split
// at tabs or spaces). Returns the index; `item` gets command, frame and parameters.
int ReadItemLine(const std::string& line, const std::string& where, const std::string& source, RawItem* item) {
  std::vector<std::string> fields;
  std::istringstream stream(line);
  for (std::string field; stream >> field;) fields.push_back(field);
  if (fields.size() != 12) {
    throw InputError(source, where,
                     fmt::format("12 fields (index, current, frame, command, param1–4, latitude, longitude, altitude, "
                                 "autocontinue), got {}",
                                 fields.size()));
  }
  std::array<double, 12> values{};
  for (int f = 0; f < 12; ++f) {
    const auto value = detail::ParseNumber(fields[f]);
    if (!value)
      throw InputError(source, fmt::format("{} field {}", where, f + 1),
                       fmt::format("a number, got '{}'", BriefForMessage(fields[f])));
    values[f] = *value;
  }
  auto integer = [&](int f, const char* what) {
    // Whole and in int's range (the cast of 1e15 to int is undefined behaviour; found by fuzz/mission_wpl_fuzzer).
    if (values[f] != std::floor(values[f]) || !(std::abs(values[f]) <= std::numeric_limits<int>::max())) {
      throw InputError(source, fmt::format("{} {}", where, what),
                       fmt::format("an integer, got {}", BriefForMessage(fields[f])));
    }
    return static_cast<int>(values[f]);
  };
  const int index = integer(0, "index");
  item->command = integer(3, "command");
  item->frame = integer(2, "frame");
  for (int p = 0; p < 7; ++p) item->params[p] = values[4 + p];
  return index;
}

// The home line (index 0): Mission Planner and ArduPilot write the home as its item, the altitude above mean sea
// level. Index 0 is the home whatever its command: Mission Planner reads the line's position as the home
// (WaypointFile.ReadWaypointFile), and ArduPilot answers item 0 with its own home and never flies it
// (AP_Mission::read_cmd_from_storage, libraries/AP_Mission/AP_Mission.cpp); another command there is reported.
void ReadHomeLine(const RawItem& item, const std::string& where, const std::string& source, RawMission* raw) {
  if (item.command != kMavCmdNavWaypoint) {
    raw->warnings.push_back(fmt::format(
        "{}: {} (home): {} in the home slot (index 0) is not flown: ArduPilot keeps item 0 as its home, and Mission "
        "Planner reads the line's position as the home",
        source, where, MavCommandName(item.command)));
  }
  raw->home = {item.params[4], item.params[5]};
  detail::CheckGeoPoint(raw->home, source, where + " (home)");
  raw->home_unset = raw->home.lat_deg == 0.0 && raw->home.lon_deg == 0.0;
  if (raw->home_unset) {
    // Not known when the file was written: neither is its altitude (RawMission::home_unset).
  } else if (item.frame == kMavFrameGlobal || item.frame == kMavFrameGlobalInt) {
    raw->home_amsl = item.params[6];
  } else {
    raw->warnings.push_back(
        fmt::format("{}: {} (home): frame {} is not absolute: the home altitude is unknown, "
                    "so items above mean sea level cannot be read",
                    source, where, item.frame));
  }
}

}  // namespace

RawMission ReadQgcWpl(std::string_view text, const std::string& source) {
  RawMission raw;
  // The plain-text format names no autopilot; it is Mission Planner's, whose missions ArduPilot flies.
  raw.firmware = MissionFirmware::kArduPilot;
  raw.firmware_basis = "a .waypoints file, Mission Planner's format for ArduPilot";
  const std::vector<std::pair<int, std::string>> lines = NonBlankLines(text);
  CheckHeader(lines, source);
  bool have_home = false;
  int number = 0;
  for (std::size_t l = 1; l < lines.size(); ++l) {
    const auto& [line_number, line] = lines[l];
    const std::string where = fmt::format("line {}", line_number);
    RawItem item;
    const int index = ReadItemLine(line, where, source, &item);
    if (index == 0) {
      if (have_home) throw InputError(source, where, "one home line (index 0)");
      have_home = true;
      ReadHomeLine(item, where, source, &raw);
      continue;
    }
    if (!have_home) throw InputError(source, where, "the home position (index 0) before the mission items");
    item.number = ++number;
    item.jump_id = index;
    item.name = fmt::format("{} (item {})", where, item.number);
    raw.items.push_back(std::move(item));
  }
  if (!have_home) throw InputError(source, "home", "a home line (index 0)");
  return raw;
}

// --- before flying: the home, the loops ---------------------------------------------------------------------------
// ArduPilot writes a home of (0, 0) when the vehicle's home was not yet known: a ground station then takes the
// launch point from the mission, so does this: the first item with a position (warned).
void ResolveUnsetHome(RawMission& raw, const std::string& source) {
  if (!raw.home_unset) return;
  for (const RawItem& item : raw.items) {
    const double lat = item.params[4], lon = item.params[5];
    if (IsNavigation(item.command) && std::isfinite(lat) && std::isfinite(lon) && !(lat == 0.0 && lon == 0.0)) {
      raw.home = {lat, lon};
      raw.home_amsl.reset();
      raw.warnings.push_back(fmt::format("{}: home: unset (0, 0) in the file: taken from {} at ({:.7f}, {:.7f})",
                                         source, item.name, lat, lon));
      return;
    }
  }
  throw InputError(source, "home",
                   "a home position, or an item with a position to take it from; the home is (0, 0) "
                   "(unset) and no item has a position");
}

// DO_JUMP (param1: the target item's doJumpId, or its index in a .waypoints file; param2: how many times to jump)
// is unrolled into the items it repeats, as the autopilot would fly them; an endless one (param2 < 0) is refused.
std::vector<RawItem> UnrollJumps(const std::vector<RawItem>& items, const std::string& source,
                                 std::vector<std::string>* warnings) {
  std::vector<int> jumps_left(items.size(), 0);
  bool any = false;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (items[i].command != kMavCmdDoJump) continue;
    any = true;
    const double repeat = items[i].params[1];
    if (!std::isfinite(repeat) || repeat < 0.0) {
      throw InputError(source, items[i].name,
                       fmt::format("a DO_JUMP with a finite repeat count (param2 ≥ 0); param2 = {} repeats forever "
                                   "and the mission would never end",
                                   repeat));
    }
    if (repeat != std::floor(repeat) || repeat > 1e6) {
      throw InputError(source, items[i].name + " param2", fmt::format("a whole repeat count, got {}", repeat));
    }
    jumps_left[i] = static_cast<int>(repeat);
  }
  if (!any) return items;
  std::vector<RawItem> flown;
  std::vector<int> passes(items.size(), 0);
  for (std::size_t pc = 0; pc < items.size();) {
    const RawItem& item = items[pc];
    if (item.command != kMavCmdDoJump) {
      RawItem copy = item;
      if (++passes[pc] > 1) copy.name += fmt::format(" (pass {})", passes[pc]);
      flown.push_back(std::move(copy));
      if (flown.size() > kMaxUnrolledItems) {
        throw InputError(
            source, item.name,
            fmt::format("a mission of at most {} items once its DO_JUMPs are unrolled", kMaxUnrolledItems));
      }
      ++pc;
      continue;
    }
    if (jumps_left[pc] == 0) {
      ++pc;
      continue;
    }
    --jumps_left[pc];
    const double target = item.params[0];
    std::size_t to = items.size();
    for (std::size_t k = 0; k < items.size(); ++k) {
      if (items[k].jump_id >= 0 && items[k].jump_id == target) to = k;
    }
    if (to == items.size()) {
      throw InputError(source, item.name + " param1",
                       fmt::format("the number of an item of the mission to jump to, got {}", target));
    }
    pc = to;
  }
  int total = 0;
  for (std::size_t i = 0; i < items.size(); ++i) total += items[i].command == kMavCmdDoJump ? 1 : 0;
  warnings->push_back(fmt::format("{}: {} DO_JUMP{} unrolled: {} items flown from {}", source, total,
                                  total == 1 ? "" : "s", flown.size(), items.size()));
  return flown;
}

}  // namespace uascma::planning::mission_detail
