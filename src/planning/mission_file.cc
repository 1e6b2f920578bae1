// Mission files in (QGroundControl .plan, QGC WPL 110 .waypoints) and out (.plan): the contract is in
// include/uascma/planning/mission_file.h. Reading is two steps: the format readers collect the raw MAVLink items
// (command, frame, seven parameters), then BuildMission flies them in order, item by item, as a multicopter's
// mission executor would, and writes the waypoints in the local frame.
#include "uascma/planning/mission_file.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "map_import_detail.h"
#include "uascma/common/bounds.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/common/json_io.h"

namespace uascma::planning {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = 3.14159265358979323846;
// m: a take-off item's position farther than this from where the vehicle stands is reported (it climbs where it
// stands). Our estimate: well above GNSS-level differences between a planned home and a take-off point.
constexpr double kTakeoffPositionTolerance = 1.0;
// m: moves shorter than this are no moves (FlightPlan::Through skips them too); heights within it of the ground
// count as on the ground.
constexpr double kSamePlace = 1e-6;

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
  std::vector<std::array<double, 3>> rally;  // latitude, longitude (degrees), altitude (m, relative)
  struct Zone {
    bool inclusion = true;
    std::vector<GeoPoint> polygon;       // empty for a circle
    GeoPoint centre;                     // of a circle
    double radius = 0.0;                 // m, of a circle
    std::string name;
  };
  std::vector<Zone> fence;
};

// Commands that move the vehicle in a way uascma does not fly, with the reason a refusal gives. Every other command
// outside the MAVLink navigation range (MAV_CMD 16-99: NAV_*) and the navigation-like user commands does not move
// the vehicle (camera, gimbal, servo, relay, gripper, parachute, auxiliary functions, region of interest, yaw,
// markers, …): it is skipped with a warning, whatever its number.
std::optional<std::string> RefusalReason(int command) {
  switch (command) {
    case 17: return "it loiters until the operator intervenes (the mission never ends)";
    case 113: return "it climbs or descends at a rate and holds the mission until then (not modelled)";
    case 176: return "it changes the flight mode (the mission may stop)";
    case 179: return "it moves the home that RETURN_TO_LAUNCH flies to (not modelled)";
    case 185: return "it terminates the flight";
    case 186: return "it changes the altitude outside a mission item (not modelled)";
    case 190: return "it lands at a rally point chosen by the autopilot";
    case 191: return "it aborts a landing (not modelled)";
    case 192: return "it repositions the vehicle outside the mission (not modelled)";
    case 193: return "it pauses the mission until the operator continues it";
    case 224: return "it jumps to another item (not modelled)";
    case 601: return "it jumps to a tag (not modelled)";
    default: break;
  }
  if ((command >= 16 && command <= 99) || (command >= 31000 && command <= 31004)) {
    return "a navigation command that uascma does not fly";
  }
  return std::nullopt;
}
bool IsNavigation(int command) { return (command >= 16 && command <= 99) || (command >= 31000 && command <= 31004); }

constexpr int kMavCmdDoJump = 177;
constexpr int kMavCmdNavSplineWaypoint = 82;
constexpr int kMavCmdNavRoi = 80;  // deprecated: points the camera, does not move the vehicle
// A mission unrolled from DO_JUMPs is refused beyond this many items (nested loops multiply).
constexpr std::size_t kMaxUnrolledItems = 100'000;

std::string Lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

// --- the .plan reader (JSON) ------------------------------------------------------------------------------------
double JsonNumber(const nlohmann::json& value, const std::string& source, const std::string& field) {
  if (value.is_null()) return kNaN;
  if (!value.is_number()) throw InputError(source, field, fmt::format("a number or null, got {}", value.dump()));
  return value.get<double>();
}

// Plausibility bounds of a mission's numbers (issue 16; common/bounds.h), the scenario's bounds for the same
// quantities (sim/scenario_bounds.h): a height above home up to 1000 m (mission.cruise_altitude_m), a hover,
// delay or loiter of at most an hour (mission.drop_hover_s: four times the packs' ~15 min hover endurance), a
// speed of 0.1 to 30 m/s (limits.cruise_speed_mps). A value outside is an InputError naming the item.
constexpr Bounds kMissionHeightBounds{0.0, 1000.0, "m above home"};
constexpr Bounds kMissionHoverBounds{0.0, 3600.0, "s"};
constexpr Bounds kMissionSpeedBounds{0.1, 30.0, "m/s"};

// A member that should be a string: its text, `fallback` when absent, and for another JSON type its JSON text
// (json::value() threw type_error on a mistyped member, escaping as an internal error; issue 16's fuzzing).
std::string JsonText(const nlohmann::json& object, const char* key, const std::string& fallback) {
  const auto it = object.find(key);
  if (it == object.end()) return fallback;
  return it->is_string() ? it->get<std::string>() : it->dump();
}

int JsonInteger(const nlohmann::json& object, const char* key, const std::string& source, const std::string& field) {
  const auto it = object.find(key);
  if (it == object.end() || !it->is_number_integer()) {
    throw InputError(source, fmt::format("{}.{}", field, key), "an integer");
  }
  // In int's range: a larger number would wrap (2^32 + 16 read as command 16; issue 16).
  constexpr int kMax = std::numeric_limits<int>::max(), kMin = std::numeric_limits<int>::min();
  const bool in_range = it->is_number_unsigned() ? it->get<std::uint64_t>() <= static_cast<std::uint64_t>(kMax)
                                                 : it->get<std::int64_t>() >= kMin && it->get<std::int64_t>() <= kMax;
  if (!in_range) {
    throw InputError(source, fmt::format("{}.{}", field, key), fmt::format("an integer, got {}", it->dump()));
  }
  return it->get<int>();
}

// One SimpleItem (a MAVLink mission item) of a .plan.
RawItem ReadSimpleItem(const nlohmann::json& item, const std::string& field, const std::string& source, int number) {
  RawItem raw_item;
  raw_item.number = number;
  raw_item.name = fmt::format("{} (item {})", field, raw_item.number);
  raw_item.command = JsonInteger(item, "command", source, field);
  raw_item.frame = JsonInteger(item, "frame", source, field);
  if (item.contains("doJumpId")) raw_item.jump_id = JsonInteger(item, "doJumpId", source, field);
  const auto params = item.find("params");
  if (params == item.end() || !params->is_array() || params->size() != 7) {
    throw InputError(source, field + ".params", "a list of 7 numbers (param1–4, latitude, longitude, altitude)");
  }
  for (int p = 0; p < 7; ++p) {
    raw_item.params[p] = JsonNumber((*params)[p], source, fmt::format("{}.params[{}]", field, p));
  }
  // QGroundControl's AltitudeMode 3 ("calculated above terrain"): params[6] is the AMSL altitude it computed from
  // its terrain tiles, null when it had none; "Altitude" is the height above the terrain.
  const auto mode = item.find("AltitudeMode");
  if (mode != item.end() && mode->is_number_integer() && mode->get<int>() == 3 && std::isnan(raw_item.params[6])) {
    const auto altitude = item.find("Altitude");
    if (altitude != item.end() && altitude->is_number()) raw_item.altitude_above_terrain = altitude->get<double>();
  }
  return raw_item;
}

// [lat, lon] of a fence vertex or centre.
GeoPoint JsonLatLon(const nlohmann::json& value, const std::string& source, const std::string& field) {
  if (!value.is_array() || value.size() < 2 || !value[0].is_number() || !value[1].is_number()) {
    throw InputError(source, field, "[latitude, longitude] in degrees");
  }
  const GeoPoint point{value[0].get<double>(), value[1].get<double>()};
  detail::CheckGeoPoint(point, source, field);
  return point;
}

// geoFence (version 2): {"polygons": [{"inclusion": bool, "polygon": [[lat, lon], …]}], "circles": [{"inclusion":
// bool, "circle": {"center": [lat, lon], "radius": m}}]}.
void ReadGeoFence(const nlohmann::json& document, const std::string& source, RawMission* raw) {
  const auto fence = document.find("geoFence");
  if (fence == document.end() || !fence->is_object()) return;
  auto inclusion = [&](const nlohmann::json& zone, const std::string& field) {
    const auto it = zone.find("inclusion");
    if (it == zone.end()) return true;  // QGroundControl's default
    if (!it->is_boolean()) throw InputError(source, field + ".inclusion", "true or false");
    return it->get<bool>();
  };
  if (const auto polygons = fence->find("polygons"); polygons != fence->end() && polygons->is_array()) {
    for (std::size_t i = 0; i < polygons->size(); ++i) {
      const std::string field = fmt::format("geoFence.polygons[{}]", i);
      const nlohmann::json& zone = (*polygons)[i];
      if (!zone.is_object()) throw InputError(source, field, "an object");
      RawMission::Zone out;
      out.name = field;
      out.inclusion = inclusion(zone, field);
      const auto vertices = zone.find("polygon");
      if (vertices == zone.end() || !vertices->is_array() || vertices->size() < 3) {
        throw InputError(source, field + ".polygon", "at least 3 [latitude, longitude] vertices");
      }
      for (std::size_t v = 0; v < vertices->size(); ++v) {
        out.polygon.push_back(JsonLatLon((*vertices)[v], source, fmt::format("{}.polygon[{}]", field, v)));
      }
      raw->fence.push_back(std::move(out));
    }
  }
  if (const auto circles = fence->find("circles"); circles != fence->end() && circles->is_array()) {
    for (std::size_t i = 0; i < circles->size(); ++i) {
      const std::string field = fmt::format("geoFence.circles[{}]", i);
      const nlohmann::json& zone = (*circles)[i];
      const auto circle = zone.is_object() ? zone.find("circle") : zone.end();
      if (!zone.is_object() || circle == zone.end() || !circle->is_object()) {
        throw InputError(source, field, "{\"circle\": {\"center\": [lat, lon], \"radius\": m}, \"inclusion\": bool}");
      }
      RawMission::Zone out;
      out.name = field;
      out.inclusion = inclusion(zone, field);
      out.centre = JsonLatLon(circle->value("center", nlohmann::json()), source, field + ".circle.center");
      const auto radius = circle->find("radius");
      if (radius == circle->end() || !radius->is_number() || !(radius->get<double>() > 0.0)) {
        throw InputError(source, field + ".circle.radius", "a radius > 0 m");
      }
      out.radius = radius->get<double>();
      raw->fence.push_back(std::move(out));
    }
  }
}

// rallyPoints (version 2): {"points": [[lat, lon, alt], …]}, the altitude relative to home.
void ReadRallyPoints(const nlohmann::json& document, const std::string& source, RawMission* raw) {
  const auto rally = document.find("rallyPoints");
  if (rally == document.end() || !rally->is_object()) return;
  const auto points = rally->find("points");
  if (points == rally->end() || !points->is_array()) return;
  for (std::size_t i = 0; i < points->size(); ++i) {
    const std::string field = fmt::format("rallyPoints.points[{}]", i);
    const nlohmann::json& point = (*points)[i];
    const GeoPoint position = JsonLatLon(point, source, field);
    const double altitude = point.size() >= 3 && point[2].is_number() ? point[2].get<double>() : 0.0;
    raw->rally.push_back({position.lat_deg, position.lon_deg, altitude});
  }
}

RawMission ReadQgcPlan(std::string_view text, const std::string& source) {
  nlohmann::json document;
  try {
    document = nlohmann::json::parse(text);
    CheckJsonKeysUnique(text, source);  // common/json_io.h (issue 26 item 6)
  } catch (const nlohmann::json::exception& error) {  // parse_error, or out_of_range for a number like 1e999
    throw InputError(source, "JSON", fmt::format("a QGroundControl plan; the parser says: {}", error.what()));
  }
  if (!document.is_object() || JsonText(document, "fileType", "") != "Plan") {
    throw InputError(source, "fileType", "\"Plan\" (a QGroundControl .plan file)");
  }
  const auto mission_it = document.find("mission");
  if (mission_it == document.end() || !mission_it->is_object()) throw InputError(source, "mission", "an object");
  const nlohmann::json& mission = *mission_it;

  RawMission raw;
  const auto home_it = mission.find("plannedHomePosition");
  if (home_it == mission.end() || !home_it->is_array() || home_it->size() < 2 || home_it->size() > 3) {
    throw InputError(source, "mission.plannedHomePosition", "[latitude, longitude, altitude AMSL] in degrees and m");
  }
  raw.home.lat_deg = JsonNumber((*home_it)[0], source, "mission.plannedHomePosition[0]");
  raw.home.lon_deg = JsonNumber((*home_it)[1], source, "mission.plannedHomePosition[1]");
  detail::CheckGeoPoint(raw.home, source, "mission.plannedHomePosition");
  raw.home_unset = raw.home.lat_deg == 0.0 && raw.home.lon_deg == 0.0;
  if (home_it->size() == 3) {
    const double altitude = JsonNumber((*home_it)[2], source, "mission.plannedHomePosition[2]");
    if (std::isfinite(altitude)) raw.home_amsl = altitude;
  }
  if (const auto speed = mission.find("hoverSpeed"); speed != mission.end() && speed->is_number()) {
    if (speed->get<double>() > 0.0) {  // 0 or less: none (QGroundControl's default then applies)
      RequireWithin(speed->get<double>(), kMissionSpeedBounds, source, "mission.hoverSpeed");
      raw.planned_speed = speed->get<double>();
    }
  }

  for (const auto& [key, target] : {std::pair{"firmwareType", &raw.firmware_type}, std::pair{"vehicleType", &raw.vehicle_type}}) {
    if (mission.contains(key)) *target = JsonInteger(mission, key, source, "mission");
  }

  const auto items = mission.find("items");
  if (items == mission.end() || !items->is_array()) throw InputError(source, "mission.items", "a list of mission items");
  int number = 0;
  for (std::size_t i = 0; i < items->size(); ++i) {
    const nlohmann::json& item = (*items)[i];
    const std::string field = fmt::format("mission.items[{}]", i);
    if (!item.is_object()) throw InputError(source, field, "an object");
    const std::string type = JsonText(item, "type", "");
    if (type == "ComplexItem") {
      // QGroundControl stores the waypoints it generated for a survey or corridor scan in the item
      // (TransectStyleComplexItem.Items, SimpleItems): a ground station flies those.
      const std::string kind = JsonText(item, "complexItemType", "?");
      const auto transect = item.find("TransectStyleComplexItem");
      const nlohmann::json* stored = nullptr;
      if (transect != item.end() && transect->is_object()) {
        const auto list = transect->find("Items");
        if (list != transect->end() && list->is_array() && !list->empty()) stored = &*list;
      }
      if (stored == nullptr) {
        throw InputError(source, field,
                         fmt::format("a ComplexItem with its generated items (TransectStyleComplexItem.Items); the "
                                     "'{}' item stores none (QGroundControl generates it when the plan is loaded: "
                                     "convert it to waypoints in QGroundControl first)", kind));
      }
      for (std::size_t j = 0; j < stored->size(); ++j) {
        const std::string inner = fmt::format("{}.TransectStyleComplexItem.Items[{}]", field, j);
        if (!(*stored)[j].is_object() || JsonText((*stored)[j], "type", "") != "SimpleItem") {
          throw InputError(source, inner + ".type", "\"SimpleItem\"");
        }
        raw.items.push_back(ReadSimpleItem((*stored)[j], inner, source, ++number));
      }
      raw.warnings.push_back(fmt::format("{}: {}: the '{}' ComplexItem flown from its {} stored items", source, field,
                                         kind, stored->size()));
      continue;
    }
    if (type != "SimpleItem") {
      throw InputError(source, field + ".type", fmt::format("\"SimpleItem\", got {}", JsonText(item, "type", "none")));
    }
    raw.items.push_back(ReadSimpleItem(item, field, source, ++number));
  }
  ReadGeoFence(document, source, &raw);
  ReadRallyPoints(document, source, &raw);
  return raw;
}

// --- the QGC WPL 110 reader ---------------------------------------------------------------------------------------
RawMission ReadQgcWpl(std::string_view text, const std::string& source) {
  RawMission raw;
  std::vector<std::pair<int, std::string>> lines;
  {
    int number = 0;
    for (std::size_t start = 0; start < text.size();) {
      std::size_t end = text.find('\n', start);
      if (end == std::string_view::npos) end = text.size();
      ++number;
      std::string_view line = detail::Trim(text.substr(start, end - start));
      if (!line.empty()) lines.emplace_back(number, std::string(line));
      start = end + 1;
    }
  }
  if (lines.empty() || lines.front().second.rfind("QGC WPL", 0) != 0) {
    throw InputError(source, "line 1", "the header \"QGC WPL 110\"");
  }
  {
    std::istringstream header(lines.front().second);
    std::string qgc, wpl, version;
    header >> qgc >> wpl >> version;
    if (version != "110") {
      throw InputError(source, "line 1", fmt::format("format version 110 (\"QGC WPL 110\"), got \"{}\"", version));
    }
  }
  bool have_home = false;
  int number = 0;
  for (std::size_t l = 1; l < lines.size(); ++l) {
    const auto& [line_number, line] = lines[l];
    // Fields split at tabs or spaces.
    std::vector<std::string> fields;
    std::istringstream stream(line);
    for (std::string field; stream >> field;) fields.push_back(field);
    const std::string where = fmt::format("line {}", line_number);
    if (fields.size() != 12) {
      throw InputError(source, where,
                       fmt::format("12 fields (index, current, frame, command, param1–4, latitude, longitude, altitude, "
                                   "autocontinue), got {}", fields.size()));
    }
    std::array<double, 12> values{};
    for (int f = 0; f < 12; ++f) {
      const auto value = detail::ParseNumber(fields[f]);
      if (!value) throw InputError(source, fmt::format("{} field {}", where, f + 1), fmt::format("a number, got '{}'", fields[f]));
      values[f] = *value;
    }
    auto integer = [&](int f, const char* what) {
      // Whole and in int's range (the cast of 1e15 to int is undefined behaviour; found by fuzz/mission_wpl_fuzzer).
      if (values[f] != std::floor(values[f]) || !(std::abs(values[f]) <= std::numeric_limits<int>::max())) {
        throw InputError(source, fmt::format("{} {}", where, what), fmt::format("an integer, got {}", fields[f]));
      }
      return static_cast<int>(values[f]);
    };
    const int index = integer(0, "index");
    RawItem item;
    item.command = integer(3, "command");
    item.frame = integer(2, "frame");
    for (int p = 0; p < 7; ++p) item.params[p] = values[4 + p];
    if (index == 0) {
      // Mission Planner and ArduPilot write the home as the item of index 0, its altitude above mean sea level.
      if (have_home) throw InputError(source, where, "one home line (index 0)");
      if (item.command != kMavCmdNavWaypoint) {
        throw InputError(source, where, fmt::format("the home position (index 0, command 16), got command {}", item.command));
      }
      have_home = true;
      raw.home = {item.params[4], item.params[5]};
      detail::CheckGeoPoint(raw.home, source, where + " (home)");
      raw.home_unset = raw.home.lat_deg == 0.0 && raw.home.lon_deg == 0.0;
      if (raw.home_unset) {
        // Not known when the file was written: neither is its altitude (RawMission::home_unset).
      } else if (item.frame == kMavFrameGlobal || item.frame == kMavFrameGlobalInt) {
        raw.home_amsl = item.params[6];
      } else {
        raw.warnings.push_back(fmt::format("{}: {} (home): frame {} is not absolute: the home altitude is unknown, "
                                           "so items above mean sea level cannot be read", source, where, item.frame));
      }
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

// --- before flying: the home, the loops -------------------------------------------------------------------------
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
  throw InputError(source, "home", "a home position, or an item with a position to take it from; the home is (0, 0) "
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
                                   "and the mission would never end", repeat));
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
        throw InputError(source, item.name, fmt::format("a mission of at most {} items once its DO_JUMPs are unrolled",
                                                        kMaxUnrolledItems));
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

// --- flying the items ---------------------------------------------------------------------------------------------
class MissionBuilder {
 public:
  MissionBuilder(const RawMission& raw, const std::string& source, const MissionImportOptions& options)
      : raw_(raw), source_(source), options_(options),
        projection_(options.origin.value_or(raw.home)) {
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
      throw InputError(source_, "home",
                       fmt::format("a planned home on open ground; ({:.1f}, {:.1f}) m is inside building {}",
                                   mission_.home_W.x(), mission_.home_W.y(),
                                   options_.map->building(options_.map->BuildingContaining(
                                       mission_.home_W + Eigen::Vector3d(0, 0, -0.1))).id));
    }
  }

  Mission Build() && {
    for (std::size_t i = 0; i < raw_.items.size(); ++i) {
      if (ended_) {
        std::string names;
        for (std::size_t j = i; j < raw_.items.size(); ++j) {
          names += fmt::format("{}{} {}", j == i ? "" : ", ", raw_.items[j].number, MavCommandName(raw_.items[j].command));
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
      Warn(fmt::format("the mission ends in the air at {:.1f} m: landing vertically there", -position_.z()));
      Push(TouchdownBelow(position_.head<2>()), "land");
    }
    return std::move(mission_);
  }

 private:
  bool Airborne() const {
    return position_.z() < -kSamePlace + (options_.map ? -options_.map->SurfaceAltitudeAt(position_.head<2>()) : 0.0);
  }

  void Warn(const std::string& message) { mission_.warnings.push_back(fmt::format("{}: {}", source_, message)); }

  Eigen::Vector2d Local(const GeoPoint& point, const std::string& field) const {
    detail::CheckGeoPoint(point, source_, field);
    const Eigen::Vector2d p_NE = projection_.ToLocal(point);
    if (!(p_NE.allFinite() && p_NE.norm() <= options_.max_distance_from_origin)) {
      throw InputError(source_, field,
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
        Warn(fmt::format("{}: terrain-calculated altitude (AltitudeMode 3) with params[6] null: flown at its "
                         "\"Altitude\" {:.1f} m over the map's ground (flat)", item.name, *item.altitude_above_terrain));
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
      case kMavFrameGlobalRelativeAltInt: return altitude;
      case kMavFrameGlobal:
      case kMavFrameGlobalInt:
        if (!raw_.home_amsl) {
          throw InputError(source_, item.name + " frame",
                           fmt::format("a relative altitude (frame 3): frame {} gives the altitude above mean sea "
                                       "level, and the file gives no home altitude to refer it to", item.frame));
        }
        return altitude - *raw_.home_amsl;
      case kMavFrameGlobalTerrainAlt:
      case kMavFrameGlobalTerrainAltInt:
        if (!terrain_warned_) {
          Warn(fmt::format("{} frame {} (above terrain): read as above home, the map's ground being flat",
                           item.name, item.frame));
          terrain_warned_ = true;
        }
        return altitude;
      default:
        throw InputError(source_, item.name + " frame",
                         fmt::format("a global frame (0, 3, 5, 6, 10 or 11) for {}, got {}", MavCommandName(item.command),
                                     item.frame));
    }
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
      throw InputError(source_, item.name,
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
    if (!Airborne() && target.z() < position_.z() - kSamePlace &&
        (target.head<2>() - position_.head<2>()).norm() > kSamePlace) {
      Warn(fmt::format("{}: no NAV_TAKEOFF before it: climbing vertically to {:.1f} m first", item.name, -target.z()));
      const Eigen::Vector3d climb(position_.x(), position_.y(), target.z());
      CheckLeg(climb, item);
      Push(climb, "takeoff");
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

  // A loiter's altitude: 0 (with no position) keeps the current one.
  Eigen::Vector3d LoiterPoint(const RawItem& item) {
    const Eigen::Vector2d p_NE = Horizontal(item, true);
    const bool here = item.params[6] == 0.0 && (p_NE - position_.head<2>()).norm() <= kSamePlace;
    const double z = here ? position_.z() : -Height(item);
    return Eigen::Vector3d(p_NE.x(), p_NE.y(), z);
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

  void Fly(const RawItem& item) {
    const std::string number = std::to_string(item.number);
    if (item.command != kMavCmdDoChangeSpeed && (item.command == kMavCmdNavRoi || !RefusalReason(item.command))) {
      Warn(fmt::format("{}: {} does not move the vehicle: skipped", item.name, MavCommandName(item.command)));
      return;
    }
    switch (item.frame) {
      case kMavFrameGlobal: case kMavFrameMission: case kMavFrameGlobalRelativeAlt: case kMavFrameGlobalInt:
      case kMavFrameGlobalRelativeAltInt: case kMavFrameGlobalTerrainAlt: case kMavFrameGlobalTerrainAltInt: break;
      default:
        throw InputError(source_, item.name + " frame",
                         fmt::format("a global frame (0, 3, 5, 6, 10 or 11) or 2 (no position); frame {} (local "
                                     "coordinates) is not modelled", item.frame));
    }
    switch (item.command) {
      case kMavCmdNavSplineWaypoint:
        Warn(fmt::format("{}: NAV_SPLINE_WAYPOINT flown as a NAV_WAYPOINT (straight legs, not the spline)", item.name));
        [[fallthrough]];
      case kMavCmdNavWaypoint: {
        const Eigen::Vector2d p_NE = Horizontal(item, true);
        MoveTo(Eigen::Vector3d(p_NE.x(), p_NE.y(), -Height(item)), item, "waypoint " + number);
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
      case kMavCmdNavLoiterTurns: {
        const Eigen::Vector3d p_W = LoiterPoint(item);
        if ((p_W - position_).norm() > kSamePlace) MoveTo(p_W, item, "loiter " + number);
        const double turns = item.params[0], radius = std::abs(item.params[2]);
        if (!(turns >= 0.0 && std::isfinite(turns)) || !std::isfinite(radius)) {
          throw InputError(source_, item.name, "param1 turns ≥ 0 and a finite param3 radius (m)");
        }
        const double seconds = turns * 2.0 * kPi * radius / options_.loiter_turn_speed;
        Warn(fmt::format("{}: NAV_LOITER_TURNS ({} turns of {} m) flown as a hover of {:.1f} s at the centre (the "
                         "circle is not modelled)", item.name, turns, radius, seconds));
        Hover(seconds, item, "loiter " + number);
        return;
      }
      case kMavCmdNavLoiterToAlt: {
        const Eigen::Vector2d p_NE = Horizontal(item, true);
        MoveTo(Eigen::Vector3d(p_NE.x(), p_NE.y(), -Height(item)), item, "loiter " + number);
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
      case kMavCmdNavTakeoff: {
        const double height = Height(item);
        if (!(height > 0.0)) throw InputError(source_, item.name + " altitude", fmt::format("a height > 0 m, got {}", height));
        const double lat = item.params[4], lon = item.params[5];
        if (std::isfinite(lat) && std::isfinite(lon) && !(lat == 0.0 && lon == 0.0)) {
          const double off = (Local({lat, lon}, item.name) - position_.head<2>()).norm();
          if (off > kTakeoffPositionTolerance) {
            Warn(fmt::format("{}: the take-off position is {:.1f} m away: the vehicle climbs where it stands",
                             item.name, off));
          }
        }
        if (Airborne()) Warn(fmt::format("{}: NAV_TAKEOFF in the air: climbing or descending to {:.1f} m", item.name, height));
        MoveTo(Eigen::Vector3d(position_.x(), position_.y(), -height), item, "takeoff");
        return;
      }
      case kMavCmdNavLand: LandAt(Horizontal(item, true), item, "land"); return;
      case kMavCmdNavReturnToLaunch: LandAt(mission_.home_W.head<2>(), item, "return"); return;
      case kMavCmdDoChangeSpeed: {
        const double type = item.params[0], speed = item.params[1];
        if (type == 0.0 || type == 1.0) {
          if (speed > 0.0) {  // −1 (or 0): no change
            RequireWithin(speed, kMissionSpeedBounds, source_, item.name + " param2");
            speed_ = speed;
          }
        } else {
          Warn(fmt::format("{}: DO_CHANGE_SPEED of type {} (climb or descent speed) is not modelled", item.name, type));
        }
        return;
      }
      default: break;
    }
    const std::optional<std::string> refused = RefusalReason(item.command);
    UASCMA_CHECK(refused.has_value(), "commands that do not move the vehicle are skipped before");
    throw InputError(source_, item.name,
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
  bool ended_ = false;
  bool terrain_warned_ = false;
};

}  // namespace

std::string MavCommandName(int command) {
  static const std::map<int, const char*> names = {
      {16, "NAV_WAYPOINT"}, {17, "NAV_LOITER_UNLIM"}, {18, "NAV_LOITER_TURNS"}, {19, "NAV_LOITER_TIME"},
      {20, "NAV_RETURN_TO_LAUNCH"}, {21, "NAV_LAND"}, {22, "NAV_TAKEOFF"}, {23, "NAV_LAND_LOCAL"},
      {24, "NAV_TAKEOFF_LOCAL"}, {25, "NAV_FOLLOW"}, {30, "NAV_CONTINUE_AND_CHANGE_ALT"}, {31, "NAV_LOITER_TO_ALT"},
      {32, "DO_FOLLOW"}, {34, "DO_ORBIT"}, {80, "NAV_ROI"}, {82, "NAV_SPLINE_WAYPOINT"}, {84, "NAV_VTOL_TAKEOFF"},
      {85, "NAV_VTOL_LAND"}, {92, "NAV_GUIDED_ENABLE"}, {93, "NAV_DELAY"}, {94, "NAV_PAYLOAD_PLACE"},
      {112, "CONDITION_DELAY"}, {113, "CONDITION_CHANGE_ALT"}, {114, "CONDITION_DISTANCE"}, {115, "CONDITION_YAW"},
      {176, "DO_SET_MODE"}, {177, "DO_JUMP"}, {178, "DO_CHANGE_SPEED"}, {179, "DO_SET_HOME"},
      {180, "DO_SET_PARAMETER"}, {181, "DO_SET_RELAY"}, {182, "DO_REPEAT_RELAY"}, {183, "DO_SET_SERVO"},
      {184, "DO_REPEAT_SERVO"}, {185, "DO_FLIGHTTERMINATION"}, {186, "DO_CHANGE_ALTITUDE"}, {189, "DO_LAND_START"},
      {190, "DO_RALLY_LAND"}, {191, "DO_GO_AROUND"}, {192, "DO_REPOSITION"}, {193, "DO_PAUSE_CONTINUE"},
      {195, "DO_SET_ROI_LOCATION"}, {197, "DO_SET_ROI_NONE"}, {200, "DO_CONTROL_VIDEO"}, {201, "DO_SET_ROI"},
      {202, "DO_DIGICAM_CONFIGURE"}, {203, "DO_DIGICAM_CONTROL"}, {204, "DO_MOUNT_CONFIGURE"},
      {205, "DO_MOUNT_CONTROL"}, {206, "DO_SET_CAM_TRIGG_DIST"}, {207, "DO_FENCE_ENABLE"}, {208, "DO_PARACHUTE"},
      {211, "DO_GRIPPER"}, {214, "DO_SET_CAM_TRIGG_INTERVAL"}, {218, "DO_AUX_FUNCTION"}, {224, "DO_SET_MISSION_CURRENT"},
      {601, "DO_JUMP_TAG"}, {31000, "WAYPOINT_USER_1"}, {530, "SET_CAMERA_MODE"}, {531, "SET_CAMERA_ZOOM"},
      {532, "SET_CAMERA_FOCUS"}, {1000, "DO_GIMBAL_MANAGER_PITCHYAW"}, {2000, "IMAGE_START_CAPTURE"},
      {2001, "IMAGE_STOP_CAPTURE"}, {2500, "VIDEO_START_CAPTURE"}, {2501, "VIDEO_STOP_CAPTURE"},
  };
  const auto it = names.find(command);
  return it != names.end() ? fmt::format("{} ({})", it->second, command) : fmt::format("command {}", command);
}

MissionFormat DetectMissionFormat(const std::filesystem::path& path) {
  const std::string extension = Lower(path.extension().string());
  if (extension == ".plan") return MissionFormat::kQgcPlan;
  if (extension == ".waypoints" || extension == ".wpl" || extension == ".txt") return MissionFormat::kQgcWpl;
  throw InputError(path.string(), "extension",
                   ".plan (QGroundControl JSON) or .waypoints / .wpl / .txt (QGC WPL 110)");
}

bool MissionImportOptions::IsValid(std::string* error) const {
  if (!(loiter_turn_speed > 0.0 && std::isfinite(loiter_turn_speed))) {
    if (error) *error = fmt::format("loiter_turn_speed: expected a positive speed (m/s), got {}", loiter_turn_speed);
    return false;
  }
  if (!(max_distance_from_origin > 0.0)) {
    if (error) *error = fmt::format("max_distance_from_origin: expected a positive distance (m), got {}",
                                    max_distance_from_origin);
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

Mission ParseMission(std::string_view text, const std::string& source, MissionFormat format,
                     const MissionImportOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("mission import options: " + error);
  RawMission raw = format == MissionFormat::kQgcPlan ? ReadQgcPlan(text, source) : ReadQgcWpl(text, source);
  ResolveUnsetHome(raw, source);
  raw.items = UnrollJumps(raw.items, source, &raw.warnings);
  Mission mission = MissionBuilder(raw, source, options).Build();
  mission.format = format;
  return mission;
}

Mission LoadMissionFile(const std::filesystem::path& path, const MissionImportOptions& options) {
  const MissionFormat format = DetectMissionFormat(path);
  return ParseMission(ReadFile(path), path.string(), format, options);
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

// --- export -----------------------------------------------------------------------------------------------------
bool QgcPlanExportOptions::IsValid(std::string* error) const {
  if (!(std::isfinite(home_amsl))) {
    if (error) *error = fmt::format("home_amsl: expected a finite altitude (m), got {}", home_amsl);
    return false;
  }
  if (!(cruise_speed > 0.0 && std::isfinite(cruise_speed))) {
    if (error) *error = fmt::format("cruise_speed: expected a positive speed (m/s), got {}", cruise_speed);
    return false;
  }
  if (home_W && !home_W->allFinite()) {
    if (error) *error = "home_W: expected finite coordinates";
    return false;
  }
  return true;
}

std::string QgcPlanJson(const FlightPlan& plan, const QgcPlanExportOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("plan export options: " + error);
  if (plan.empty()) throw InputError("plan export", "plan", "a flight plan with at least one segment");
  const LocalProjection projection(options.origin);
  const Eigen::Vector3d home_W =
      options.home_W.value_or(Eigen::Vector3d(plan.start_W().x(), plan.start_W().y(), 0.0));
  const GeoPoint home = projection.ToGeodetic(home_W.head<2>());

  nlohmann::json items = nlohmann::json::array();
  auto add = [&](int command, const Eigen::Vector3d& p_W, double param1) {
    const GeoPoint point = projection.ToGeodetic(p_W.head<2>());
    // Heights in the relative frame are above home; W's z is measured from the ground at home's level.
    const double height = -p_W.z() + home_W.z();
    items.push_back({{"type", "SimpleItem"},
                     {"command", command},
                     {"frame", static_cast<int>(kMavFrameGlobalRelativeAlt)},
                     {"autoContinue", true},
                     {"doJumpId", static_cast<int>(items.size()) + 1},
                     {"AltitudeMode", 1},  // QGroundControl: relative to home
                     {"Altitude", height},
                     {"AMSLAltAboveTerrain", nullptr},
                     {"params", {param1, 0.0, 0.0, nullptr, point.lat_deg, point.lon_deg, height}}});
  };

  const auto& segments = plan.segments();
  const Eigen::Vector3d start = plan.start_W();
  const bool starts_on_ground = start.z() >= home_W.z() - kSamePlace;
  if (!starts_on_ground) add(kMavCmdNavWaypoint, start, 0.0);  // an emergency plan: from where the vehicle is
  bool first_move = true;
  double speed = options.cruise_speed;  // m/s: the ground station's speed until a DO_CHANGE_SPEED
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const PlanSegment& segment = segments[s];
    if (segment.kind == PlanSegment::Kind::kHover) {
      // A hover is the hold time (param1) of a NAV_WAYPOINT there; after a take-off or a landing, a waypoint of
      // its own at the same place.
      if (items.empty() || items.back()["command"].get<int>() != kMavCmdNavWaypoint) {
        add(kMavCmdNavWaypoint, segment.end_W, 0.0);
      }
      auto& hold = items.back()["params"][0];
      hold = hold.get<double>() + segment.duration;
      continue;
    }
    const Eigen::Vector3d delta = segment.end_W - segment.start_W;
    const bool vertical = delta.head<2>().norm() <= kSamePlace;
    if (!vertical && segment.cruise_speed > 0.0 && segment.cruise_speed != speed) {
      // DO_CHANGE_SPEED, ground speed (type 1), throttle unchanged (−1): this move and the ones after it.
      speed = segment.cruise_speed;
      items.push_back({{"type", "SimpleItem"},
                       {"command", static_cast<int>(kMavCmdDoChangeSpeed)},
                       {"frame", static_cast<int>(kMavFrameMission)},
                       {"autoContinue", true},
                       {"doJumpId", static_cast<int>(items.size()) + 1},
                       {"params", {1.0, speed, -1.0, 0.0, 0.0, 0.0, 0.0}}});
    }
    bool last_move = true;
    for (std::size_t later = s + 1; later < segments.size(); ++later) {
      if (segments[later].kind == PlanSegment::Kind::kMove) last_move = false;
    }
    if (first_move && starts_on_ground && vertical && delta.z() < 0.0) {
      add(kMavCmdNavTakeoff, segment.end_W, 0.0);
    } else if (last_move && vertical && delta.z() > 0.0) {
      add(kMavCmdNavLand, segment.end_W, 0.0);
    } else {
      add(kMavCmdNavWaypoint, segment.end_W, 0.0);
    }
    first_move = false;
  }

  const nlohmann::json document = {
      {"fileType", "Plan"},
      {"version", 1},
      {"groundStation", "uascma"},
      {"geoFence", {{"circles", nlohmann::json::array()}, {"polygons", nlohmann::json::array()}, {"version", 2}}},
      {"rallyPoints", {{"points", nlohmann::json::array()}, {"version", 2}}},
      {"mission",
       {{"version", 2},
        {"firmwareType", options.firmware_type},  // MAV_AUTOPILOT
        {"vehicleType", options.vehicle_type},    // MAV_TYPE
        {"cruiseSpeed", options.cruise_speed},
        {"hoverSpeed", options.cruise_speed},
        {"globalPlanAltitudeMode", 1},
        {"plannedHomePosition", {home.lat_deg, home.lon_deg, options.home_amsl}},
        {"items", items}}},
  };
  return document.dump(4) + "\n";
}

void WriteQgcPlan(const std::filesystem::path& path, const FlightPlan& plan, const QgcPlanExportOptions& options) {
  WriteFileAtomically(path, QgcPlanJson(plan, options));
}

std::string QgcWplText(const FlightPlan& plan, const QgcPlanExportOptions& options) {
  // The items of the .plan export, one line each: the two formats carry the same MAVLink items.
  const nlohmann::json document = nlohmann::json::parse(QgcPlanJson(plan, options));
  const nlohmann::json& mission = document["mission"];
  const nlohmann::json& home = mission["plannedHomePosition"];
  std::string text = "QGC WPL 110\n";
  text += fmt::format("0\t1\t{}\t{}\t0\t0\t0\t0\t{:.9f}\t{:.9f}\t{:.4f}\t1\n", static_cast<int>(kMavFrameGlobal),
                      static_cast<int>(kMavCmdNavWaypoint), home[0].get<double>(), home[1].get<double>(),
                      home[2].get<double>());
  int index = 0;
  for (const nlohmann::json& item : mission["items"]) {
    std::array<double, 7> p{};
    for (int k = 0; k < 7; ++k) p[k] = item["params"][k].is_null() ? 0.0 : item["params"][k].get<double>();
    text += fmt::format("{}\t0\t{}\t{}\t{:.4f}\t{:.4f}\t{:.4f}\t{:.4f}\t{:.9f}\t{:.9f}\t{:.4f}\t1\n", ++index,
                        item["frame"].get<int>(), item["command"].get<int>(), p[0], p[1], p[2], p[3], p[4], p[5], p[6]);
  }
  return text;
}

void WriteMissionFile(const std::filesystem::path& path, const FlightPlan& plan, const QgcPlanExportOptions& options) {
  const MissionFormat format = DetectMissionFormat(path);
  WriteFileAtomically(path, format == MissionFormat::kQgcPlan ? QgcPlanJson(plan, options) : QgcWplText(plan, options));
}

}  // namespace uascma::planning
