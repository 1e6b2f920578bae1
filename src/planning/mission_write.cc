// Mission files out: a flight plan as a QGroundControl .plan or a QGC WPL 110 .waypoints file
// (include/uascma/planning/mission_write.h).
#include "uascma/planning/mission_write.h"

#include <array>
#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "mission_items.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"

namespace uascma::planning {

using mission_detail::kSamePlace;

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

namespace {

// The plan's MAVLink items, heights relative to home (`home_W`), positions through `projection`.
std::vector<MissionItem> ItemsOf(const FlightPlan& plan, const QgcPlanExportOptions& options,
                                 const LocalProjection& projection, const Eigen::Vector3d& home_W) {
  std::vector<MissionItem> items;
  auto add = [&](int command, const Eigen::Vector3d& p_W, double param1) {
    const GeoPoint point = projection.ToGeodetic(p_W.head<2>());
    // Heights in the relative frame are above home; W's z is measured from the ground at home's level.
    const double height = -p_W.z() + home_W.z();
    items.push_back({command,
                     static_cast<int>(kMavFrameGlobalRelativeAlt),
                     {param1, 0.0, 0.0, mission_detail::kNaN, point.lat_deg, point.lon_deg, height}});
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
      if (items.empty() || items.back().command != kMavCmdNavWaypoint) add(kMavCmdNavWaypoint, segment.end_W, 0.0);
      items.back().params[0] += segment.duration;
      continue;
    }
    const Eigen::Vector3d delta = segment.end_W - segment.start_W;
    const bool vertical = delta.head<2>().norm() <= kSamePlace;
    if (!vertical && segment.cruise_speed > 0.0 && segment.cruise_speed != speed) {
      // DO_CHANGE_SPEED, ground speed (type 1), throttle unchanged (−1): this move and the ones after it.
      speed = segment.cruise_speed;
      items.push_back({static_cast<int>(kMavCmdDoChangeSpeed),
                       static_cast<int>(kMavFrameMission),
                       {1.0, speed, -1.0, 0.0, 0.0, 0.0, 0.0}});
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
  return items;
}

// The items as QGroundControl's SimpleItems (a null where the item has NaN).
nlohmann::json ItemsJson(const std::vector<MissionItem>& items) {
  nlohmann::json json = nlohmann::json::array();
  for (const MissionItem& item : items) {
    nlohmann::json params = nlohmann::json::array();
    for (double value : item.params)
      params.push_back(std::isnan(value) ? nlohmann::json(nullptr) : nlohmann::json(value));
    nlohmann::json entry = {{"type", "SimpleItem"},
                            {"command", item.command},
                            {"frame", item.frame},
                            {"autoContinue", true},
                            {"doJumpId", static_cast<int>(json.size()) + 1}};
    if (item.frame == kMavFrameGlobalRelativeAlt) {
      entry["AltitudeMode"] = 1;  // QGroundControl: relative to home
      entry["Altitude"] = item.params[6];
      entry["AMSLAltAboveTerrain"] = nullptr;
    }
    entry["params"] = std::move(params);
    json.push_back(std::move(entry));
  }
  return json;
}

// The export's home in W: QgcPlanExportOptions::home_W, else the plan's start on the ground. Checks the options.
Eigen::Vector3d ExportHome(const FlightPlan& plan, const QgcPlanExportOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("plan export options: " + error);
  if (plan.empty()) throw InputError("plan export", "plan", "a flight plan with at least one segment");
  return options.home_W.value_or(Eigen::Vector3d(plan.start_W().x(), plan.start_W().y(), 0.0));
}

}  // namespace

std::vector<MissionItem> PlanMissionItems(const FlightPlan& plan, const QgcPlanExportOptions& options) {
  const Eigen::Vector3d home_W = ExportHome(plan, options);
  return ItemsOf(plan, options, LocalProjection(options.origin), home_W);
}

std::string QgcPlanJson(const FlightPlan& plan, const QgcPlanExportOptions& options) {
  const Eigen::Vector3d home_W = ExportHome(plan, options);
  const GeoPoint home = LocalProjection(options.origin).ToGeodetic(home_W.head<2>());
  const nlohmann::json items = ItemsJson(PlanMissionItems(plan, options));
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
