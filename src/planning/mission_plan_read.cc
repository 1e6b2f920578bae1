// The QGroundControl .plan reader (JSON): the raw MAVLink items, the home, the geofence and the rally points
// (mission_items.h). Every member is read through common/json_reader.h, so a member of the wrong type is an
// InputError naming its full path ("mission.items[3].params[6]").
#include "mission_plan_read.h"

#include <cmath>
#include <string_view>
#include <utility>

#include <fmt/format.h>

#include "map_import_detail.h"
#include "mission_items.h"
#include "uascma/common/error.h"
#include "uascma/common/json_reader.h"

namespace uascma::planning::mission_detail {
namespace {

// A parameter: NaN where the file has null.
double NumberOrNull(const JsonValue& value) { return value.IsNull() ? kNaN : value.Number("a number or null"); }

// A member that should be a string: its text, `fallback` when absent, and for another JSON type its JSON text (for
// messages that quote what the file has).
std::string TextOf(const JsonValue& value, const std::string& fallback) {
  if (value.IsMissing()) return fallback;
  return value.IsString() ? value.String() : value.Brief();
}

// QGroundControl's earlier item layouts, which it still converts when it loads a plan (MissionItem::load and
// _convertJsonV1ToV2, src/MissionManager/MissionItem.cc): param1–4 in "params" (4 numbers) or, older still, in
// "param1" … "param4", and the position in "coordinate": [latitude, longitude, altitude].
void ReadOlderLayout(const JsonValue& item, RawItem* raw_item) {
  if (item.Has("params")) {
    const std::vector<JsonValue> params =
        item.Member("params").Elements(4, "a list of 4 numbers (param1–4) beside \"coordinate\"");
    for (int p = 0; p < 4; ++p) raw_item->params[p] = NumberOrNull(params[static_cast<std::size_t>(p)]);
  } else {
    for (int p = 0; p < 4; ++p) raw_item->params[p] = NumberOrNull(item.Member(fmt::format("param{}", p + 1)));
  }
  const std::vector<JsonValue> coordinate =
      item.Member("coordinate").Elements(3, "[latitude, longitude, altitude] (QGroundControl's earlier layout)");
  for (int p = 0; p < 3; ++p) raw_item->params[4 + p] = NumberOrNull(coordinate[static_cast<std::size_t>(p)]);
}

// One SimpleItem (a MAVLink mission item) of a .plan; `item`'s path names it ("mission.items[3]").
RawItem ReadSimpleItem(const JsonValue& item, int number) {
  RawItem raw_item;
  raw_item.number = number;
  raw_item.name = fmt::format("{} (item {})", item.path(), raw_item.number);
  // Integers in int's range: a larger number would wrap (2^32 + 16 read as command 16).
  raw_item.command = item.Member("command").Integer<int>();
  raw_item.frame = item.Member("frame").Integer<int>();
  if (item.Has("doJumpId")) raw_item.jump_id = item.Member("doJumpId").Integer<int>();
  if (item.Has("coordinate")) {
    ReadOlderLayout(item, &raw_item);
    return raw_item;
  }
  const std::vector<JsonValue> params =
      item.Member("params").Elements(7, "a list of 7 numbers (param1–4, latitude, longitude, altitude)");
  for (int p = 0; p < 7; ++p) raw_item.params[p] = NumberOrNull(params[static_cast<std::size_t>(p)]);
  // QGroundControl's AltitudeMode 3 ("calculated above terrain"): params[6] is the AMSL altitude it computed from
  // its terrain tiles, null when it had none; "Altitude" is the height above the terrain.
  const JsonValue mode = item.Member("AltitudeMode");
  if (mode.IsInteger() && mode.json() == 3 && std::isnan(raw_item.params[6])) {
    const JsonValue altitude = item.Member("Altitude");
    if (altitude.IsNumber()) raw_item.altitude_above_terrain = altitude.Number();
  }
  return raw_item;
}

// [lat, lon] of a fence vertex or centre.
GeoPoint LatLon(const JsonValue& value) {
  constexpr std::string_view kLatLon = "[latitude, longitude] in degrees";
  if (!value.IsArray() || value.size() < 2) value.FailExactly(kLatLon);
  const std::vector<JsonValue> numbers = value.Elements();
  if (!numbers[0].IsNumber() || !numbers[1].IsNumber()) value.FailExactly(kLatLon);
  const GeoPoint point{numbers[0].Number(), numbers[1].Number()};
  detail::CheckGeoPoint(point, value.source(), value.path());
  return point;
}

// A zone's "inclusion" (QGroundControl's default when absent: true).
bool Inclusion(const JsonValue& zone) {
  const JsonValue inclusion = zone.Member("inclusion");
  return inclusion.IsMissing() || inclusion.Bool();
}

// geoFence.polygons: [{"inclusion": bool, "polygon": [[lat, lon], …]}].
void ReadFencePolygons(const JsonValue& polygons, RawMission* raw) {
  for (const JsonValue& zone : polygons.Elements()) {
    zone.RequireObject();
    RawMission::Zone out;
    out.name = zone.path();
    out.inclusion = Inclusion(zone);
    const JsonValue vertices = zone.Member("polygon");
    if (!vertices.IsArray() || vertices.size() < 3) vertices.FailExactly("at least 3 [latitude, longitude] vertices");
    for (const JsonValue& vertex : vertices.Elements()) out.polygon.push_back(LatLon(vertex));
    raw->fence.push_back(std::move(out));
  }
}

// geoFence.circles: [{"inclusion": bool, "circle": {"center": [lat, lon], "radius": m}}].
void ReadFenceCircles(const JsonValue& circles, RawMission* raw) {
  for (const JsonValue& zone : circles.Elements()) {
    const JsonValue circle = zone.IsObject() ? zone.Member("circle") : zone;
    if (!zone.IsObject() || !circle.IsObject()) {
      zone.FailExactly("{\"circle\": {\"center\": [lat, lon], \"radius\": m}, \"inclusion\": bool}");
    }
    RawMission::Zone out;
    out.name = zone.path();
    out.inclusion = Inclusion(zone);
    out.centre = LatLon(circle.Member("center"));
    const JsonValue radius = circle.Member("radius");
    if (!radius.IsNumber() || !(radius.Number() > 0.0)) radius.FailExactly("a radius > 0 m");
    out.radius = radius.Number();
    raw->fence.push_back(std::move(out));
  }
}

// geoFence (version 2), when present as an object.
void ReadGeoFence(const JsonValue& document, RawMission* raw) {
  const JsonValue fence = document.Member("geoFence");
  if (!fence.IsObject()) return;
  if (const JsonValue polygons = fence.Member("polygons"); polygons.IsArray()) ReadFencePolygons(polygons, raw);
  if (const JsonValue circles = fence.Member("circles"); circles.IsArray()) ReadFenceCircles(circles, raw);
}

// rallyPoints (version 2): {"points": [[lat, lon, alt], …]}, the altitude relative to home.
void ReadRallyPoints(const JsonValue& document, RawMission* raw) {
  const JsonValue rally = document.Member("rallyPoints");
  if (!rally.IsObject()) return;
  const JsonValue points = rally.Member("points");
  if (!points.IsArray()) return;
  for (const JsonValue& point : points.Elements()) {
    const GeoPoint position = LatLon(point);
    const std::vector<JsonValue> values = point.Elements();
    const double altitude = values.size() >= 3 && values[2].IsNumber() ? values[2].Number() : 0.0;
    raw->rally.push_back({position.lat_deg, position.lon_deg, altitude});
  }
}

// MAV_TYPE of the rotorcraft a multicopter's mission is planned for (the MAVLink common message set). A plan for
// another vehicle (fixed wing, VTOL, rover, boat, submarine, …) is refused: its firmware flies it in ways a
// multicopter does not (ArduPlane's and PX4's fixed-wing turns and climbs, a rover's or a boat's drive on the
// surface with the altitudes ignored), so flying it as a multicopter would not be flying it as its firmware would.
bool IsRotorcraft(int vehicle_type) {
  switch (vehicle_type) {
    case 0:   // MAV_TYPE_GENERIC: QGroundControl's plan for no particular vehicle
    case 2:   // QUADROTOR
    case 3:   // COAXIAL
    case 4:   // HELICOPTER
    case 13:  // HEXAROTOR
    case 14:  // OCTOROTOR
    case 15:  // TRICOPTER
    case 29:  // DODECAROTOR
    case 35:  // DECAROTOR
      return true;
    default:
      return false;
  }
}

std::string_view MavTypeName(int vehicle_type) {
  switch (vehicle_type) {
    case 1:
      return "fixed wing";
    case 10:
      return "ground rover";
    case 11:
      return "surface boat";
    case 12:
      return "submarine";
    default:
      break;
  }
  if (vehicle_type >= 19 && vehicle_type <= 25) return "VTOL";
  return "not a rotorcraft";
}

// mission: the planned home, the hover speed, the firmware and vehicle types.
void ReadMissionHeader(const JsonValue& mission, RawMission* raw) {
  JsonValue home = mission.Member("plannedHomePosition");
  // QGroundControl's first layout stores the home as a mission item: {"coordinate": [lat, lon, alt], …}.
  if (home.IsObject() && home.Has("coordinate")) home = home.Member("coordinate");
  if (!home.IsArray() || home.size() < 2 || home.size() > 3) {
    home.FailExactly("[latitude, longitude, altitude AMSL] in degrees and m");
  }
  const std::vector<JsonValue> position = home.Elements();
  raw->home.lat_deg = NumberOrNull(position[0]);
  raw->home.lon_deg = NumberOrNull(position[1]);
  detail::CheckGeoPoint(raw->home, home.source(), home.path());
  raw->home_unset = raw->home.lat_deg == 0.0 && raw->home.lon_deg == 0.0;
  if (position.size() == 3) {
    const double altitude = NumberOrNull(position[2]);
    if (std::isfinite(altitude)) raw->home_amsl = altitude;
  }
  if (const JsonValue speed = mission.Member("hoverSpeed"); speed.IsNumber()) {
    if (speed.Number() > 0.0) raw->planned_speed = speed.Number(kMissionSpeedBounds);  // 0 or less: none
  }
  if (mission.Has("firmwareType")) raw->firmware_type = mission.Member("firmwareType").Integer<int>();
  // MAV_AUTOPILOT: 3 ArduPilot, 12 PX4; any other (0 generic, absent) names neither (mission_file.h).
  if (raw->firmware_type == kMavAutopilotArduPilotMega) {
    raw->firmware = MissionFirmware::kArduPilot;
  } else if (raw->firmware_type == kMavAutopilotPx4) {
    raw->firmware = MissionFirmware::kPx4;
  }
  raw->firmware_basis = raw->firmware_type ? fmt::format("mission.firmwareType {}", *raw->firmware_type)
                                           : std::string("no mission.firmwareType");
  if (mission.Has("vehicleType")) {
    const JsonValue vehicle = mission.Member("vehicleType");
    raw->vehicle_type = vehicle.Integer<int>();
    if (!IsRotorcraft(*raw->vehicle_type)) {
      vehicle.FailExactly(fmt::format(
          "a rotorcraft's plan (MAV_TYPE 0 generic, 2 quadrotor, 3 coaxial, 4 helicopter, 13 hexarotor, 14 "
          "octorotor, 15 tricopter, 29 dodecarotor, 35 decarotor), got {} ({}): uascma flies a multicopter, and "
          "this plan is for a vehicle its firmware flies otherwise",
          *raw->vehicle_type, MavTypeName(*raw->vehicle_type)));
    }
  }
}

// A ComplexItem: QGroundControl stores the waypoints it generated for a survey or corridor scan in the item
// (TransectStyleComplexItem.Items, SimpleItems): a ground station flies those.
void ReadComplexItem(const JsonValue& item, int* number, RawMission* raw) {
  const std::string kind = TextOf(item.Member("complexItemType"), "?");
  const JsonValue transect = item.Member("TransectStyleComplexItem");
  const JsonValue stored = transect.IsObject() ? transect.Member("Items") : transect;
  if (!transect.IsObject() || !stored.IsArray() || stored.size() == 0) {
    item.FailExactly(
        fmt::format("a ComplexItem with its generated items (TransectStyleComplexItem.Items); the "
                    "'{}' item stores none (QGroundControl generates it when the plan is loaded: "
                    "convert it to waypoints in QGroundControl first)",
                    kind));
  }
  for (const JsonValue& inner : stored.Elements()) {
    const JsonValue type = inner.IsObject() ? inner.Member("type") : inner;
    if (!inner.IsObject() || TextOf(type, "") != "SimpleItem") {
      throw InputError(inner.source(), inner.path() + ".type", "\"SimpleItem\"");
    }
    raw->items.push_back(ReadSimpleItem(inner, ++*number));
  }
  raw->warnings.push_back(fmt::format("{}: {}: the '{}' ComplexItem flown from its {} stored items", item.source(),
                                      item.path(), kind, stored.size()));
}

}  // namespace

RawMission ReadQgcPlan(std::string_view text, const std::string& source) {
  // The plain-text format under a .plan name: QGroundControl loads a .plan as JSON and refuses it; say what it is.
  if (detail::Trim(text).starts_with("QGC")) {
    throw InputError(source, "line 1",
                     "a QGroundControl .plan (JSON); the file holds plain text starting \"QGC\" (the QGC WPL format "
                     "of .waypoints files, which QGroundControl reads only under that extension)");
  }
  const JsonDocument document = JsonDocument::Parse(text, source);  // syntax, duplicate keys (common/json_io.h)
  const JsonValue root = document.root();
  if (!root.IsObject() || TextOf(root.Member("fileType"), "") != "Plan") {
    throw InputError(source, "fileType", "\"Plan\" (a QGroundControl .plan file)");
  }
  const JsonValue mission = root.Member("mission");
  mission.RequireObject();
  RawMission raw;
  ReadMissionHeader(mission, &raw);
  int number = 0;
  for (const JsonValue& item : mission.Member("items").Elements("a list of mission items")) {
    item.RequireObject();
    const JsonValue type = item.Member("type");
    const std::string type_text = TextOf(type, "");
    if (type_text == "ComplexItem") {
      ReadComplexItem(item, &number, &raw);
    } else if (type.IsString() && (type_text == "SimpleItem" || type_text == "missionItem")) {  // V1's name
      raw.items.push_back(ReadSimpleItem(item, ++number));
    } else {
      type.Fail("\"SimpleItem\"");
    }
  }
  ReadGeoFence(root, &raw);
  ReadRallyPoints(root, &raw);
  return raw;
}

}  // namespace uascma::planning::mission_detail
