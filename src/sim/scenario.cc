#include "uascma/sim/scenario.h"

#include <cmath>
#include <numbers>
#include <utility>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/common/yaml_io.h"
#include "uascma/planning/map_import.h"
#include "uascma/planning/procedural_city.h"

namespace uascma::sim {
namespace {

constexpr double kRadiansPerDegree = std::numbers::pi / 180.0;

void ReadBattery(const YAML::Node& node, const std::string& source, BatterySpec& battery) {
  RequireOnlyKeys(node, {"initial_cell_voltage_v", "ambient_temp_degf", "packs"}, source, "battery");
  if (const YAML::Node voltage = node["initial_cell_voltage_v"]) {
    if (voltage.IsScalar()) {
      const double v = RequireNumber(node, "initial_cell_voltage_v", source, "battery");
      for (auto& pack : battery.initial_cell_voltage_v) pack.fill(v);
    } else {
      if (!voltage.IsSequence() || voltage.size() != 2) {
        throw InputError(source, "battery.initial_cell_voltage_v", "a number or two lists of three numbers");
      }
      for (int b = 0; b < 2; ++b) {
        YAML::Node holder;
        holder["pack"] = voltage[b];
        const auto cells = RequireNumberList(holder, "pack", 3, source, fmt::format("battery.initial_cell_voltage_v[{}]", b));
        for (int c = 0; c < 3; ++c) battery.initial_cell_voltage_v[b][c] = cells[c];
      }
    }
  }
  battery.ambient_temp_degf = OptionalNumber(node, "ambient_temp_degf", battery.ambient_temp_degf, source, "battery");
  if (const YAML::Node packs = node["packs"]) {
    if (!packs.IsSequence() || packs.size() != 2) throw InputError(source, "battery.packs", "a list of two health classes (G, M or P)");
    for (int b = 0; b < 2; ++b) {
      const std::string field = fmt::format("battery.packs[{}]", b);
      if (!packs[b].IsScalar()) throw InputError(source, field, "G, M or P");
      battery.cell_health[b] = PackHealthPreset(models::ParseHealthClass(packs[b].Scalar(), source + ": " + field));
    }
  }
}

// map: {procedural: {seed: 3}} | {buildings: [a.geojson, b.osm.pbf], sites: s.csv, origin: [lat, lon]}
std::shared_ptr<const planning::CityMap> ReadMap(const YAML::Node& node, const std::string& source) {
  RequireOnlyKeys(node, {"procedural", "buildings", "sites", "origin"}, source, "map");
  if (const YAML::Node procedural = node["procedural"]) {
    if (node["buildings"] || node["sites"]) {
      throw InputError(source, "map", "either procedural or buildings/sites, not both");
    }
    planning::ProceduralCityParams params;
    if (procedural.IsMap()) {
      RequireOnlyKeys(procedural, {"seed", "blocks_north", "blocks_east", "rooftop_site_probability"}, source,
                      "map.procedural");
      params.seed = static_cast<std::uint64_t>(OptionalNumber(procedural, "seed", 1, source, "map.procedural"));
      params.blocks_north = static_cast<int>(OptionalNumber(procedural, "blocks_north", params.blocks_north, source, "map.procedural"));
      params.blocks_east = static_cast<int>(OptionalNumber(procedural, "blocks_east", params.blocks_east, source, "map.procedural"));
      params.rooftop_site_probability = OptionalNumber(procedural, "rooftop_site_probability",
                                                       params.rooftop_site_probability, source, "map.procedural");
    }
    return std::make_shared<const planning::CityMap>(planning::MakeProceduralCity(params));
  }
  // Paths are relative to the scenario file.
  const std::filesystem::path folder = std::filesystem::path(source).parent_path();
  auto resolve = [&](const std::string& name) {
    const std::filesystem::path path(name);
    return path.is_absolute() ? path : folder / path;
  };
  std::vector<std::filesystem::path> buildings;
  if (const YAML::Node list = node["buildings"]) {
    if (!list.IsSequence()) throw InputError(source, "map.buildings", "a list of map files");
    for (const auto& item : list) buildings.push_back(resolve(item.as<std::string>()));
  }
  const std::filesystem::path sites = node["sites"] ? resolve(RequireString(node, "sites", source, "map")) : "";
  planning::MapImportOptions options;
  if (node["origin"]) {
    const auto origin = RequireNumberList(node, "origin", 2, source, "map");
    options.origin = planning::GeoPoint{origin[0], origin[1]};
  }
  return std::make_shared<const planning::CityMap>(planning::ImportCityMap(buildings, sites, options).map);
}

}  // namespace

std::array<models::CellHealth, models::kCellsPerBranch> PackHealthPreset(models::HealthClass health) {
  std::array<models::CellHealth, models::kCellsPerBranch> cells{};
  cells.fill(models::CellHealthForClass(health));
  return cells;
}

bool FaultSpec::IsValid(std::string* error) const {
  if (!enabled) return true;
  if (motor < 1 || motor > 6) {
    if (error) *error = fmt::format("motor: expected a motor number 1..6, got {}", motor);
    return false;
  }
  if (!(spall_onset_s >= 0.0 && std::isfinite(spall_onset_s))) {
    if (error) *error = fmt::format("spall_onset_s: expected a time >= 0 s, got {}", spall_onset_s);
    return false;
  }
  for (const auto& [name, tau] : {std::pair{"time_per_growth_step_s", time_per_growth_step_s},
                                  std::pair{"prognosis_time_per_growth_step_s", prognosis_time_per_growth_step_s}}) {
    if (tau && !(*tau > 0.0 && std::isfinite(*tau))) {
      if (error) *error = fmt::format("{}: expected a positive time (s), got {}", name, *tau);
      return false;
    }
  }
  return true;
}

bool BatterySpec::IsValid(std::string* error) const {
  if (!std::isfinite(ambient_temp_degf)) {
    if (error) *error = "ambient_temp_degf: expected a finite temperature (°F)";
    return false;
  }
  try {
    models::BatteryPack(models::MakePackParams(cell_health, ambient_temp_degf))
        .MakeRestingState(initial_cell_voltage_v, models::PackAction::kUseBoth, "initial_cell_voltage_v");
  } catch (const InputError& e) {
    if (error) *error = e.what();
    return false;
  }
  return true;
}

bool SimOptions::IsValid(std::string* error) const {
  const struct { const char* name; double value; } positive[] = {
      {"gnc_rate_hz", gnc_rate_hz}, {"decision_rate_hz", decision_rate_hz},
      {"telemetry_rate_hz", telemetry_rate_hz}, {"reference_bus_voltage_v", reference_bus_voltage_v},
      {"load_current_time_constant_s", load_current_time_constant_s}};
  for (const auto& f : positive) {
    if (!(f.value > 0.0 && std::isfinite(f.value))) {
      if (error) *error = fmt::format("{}: expected a positive number, got {}", f.name, f.value);
      return false;
    }
  }
  const double ratio = gnc_rate_hz / decision_rate_hz;
  if (std::abs(ratio - std::round(ratio)) > 1e-9) {
    if (error) *error = "decision_rate_hz: expected to divide gnc_rate_hz";
    return false;
  }
  if (!(safety_margin_s >= 0.0 && std::isfinite(safety_margin_s))) {
    if (error) *error = "safety_margin_s: expected >= 0 s";
    return false;
  }
  if (!(hotel_current_a >= 0.0 && std::isfinite(hotel_current_a))) {
    if (error) *error = "hotel_current_a: expected >= 0 A";
    return false;
  }
  return outcome.IsValid(error);
}

bool Scenario::IsValid(std::string* error) const {
  std::string part_error;
  auto fail = [&](const char* part) {
    if (error) *error = std::string(part) + ": " + part_error;
    return false;
  };
  if (!body.IsValid(&part_error)) return fail("vehicle");
  if (!battery.IsValid(&part_error)) return fail("battery");
  if (!wind.IsValid(&part_error)) return fail("wind");
  if (!mission.IsValid(&part_error)) return fail("mission");
  if (!limits.IsValid(&part_error)) return fail("limits");
  if (!fault.IsValid(&part_error)) return fail("fault");
  if (!lqr.IsValid(&part_error)) return fail("lqr");
  if (!imm.IsValid(&part_error)) return fail("imm");
  if (!options.IsValid(&part_error)) return fail("options");
  if (std::abs(lqr.dt * options.gnc_rate_hz - 1.0) > 1e-9) {
    part_error = "dt: expected 1 / options.gnc_rate_hz";
    return fail("lqr");
  }
  if (map) {
    for (const auto& [key, point] : {std::pair{"home_ne_m", mission.home_NE},
                                      std::pair{"destination_ne_m", mission.destination_NE}}) {
      const int building = map->BuildingContaining(Eigen::Vector3d(point.x(), point.y(), -0.1));
      if (building != planning::kNoBuilding) {
        part_error = fmt::format("{}: expected a point on open ground, but building {} stands at ({:.1f}, {:.1f}) m",
                                 key, map->building(building).id, point.x(), point.y());
        return fail("mission");
      }
    }
  }
  return true;
}

namespace {

void ReadVehicle(const YAML::Node& v, const std::string& source, Scenario& sc) {
  RequireOnlyKeys(v, {"configuration", "mass_kg", "inertia_kg_m2"}, source, "vehicle");
  if (v["configuration"]) {
    sc.configuration = models::ParsePropellerConfiguration(RequireString(v, "configuration", source, "vehicle"),
                                                           source + ": vehicle.configuration");
  }
  sc.body.mass = OptionalNumber(v, "mass_kg", sc.body.mass, source, "vehicle");
  if (v["inertia_kg_m2"]) {
    const auto inertia = RequireNumberList(v, "inertia_kg_m2", 3, source, "vehicle");
    sc.body.inertia_diagonal = Eigen::Vector3d(inertia[0], inertia[1], inertia[2]);
  }
}

void ReadWind(const YAML::Node& w, const std::string& source, models::WindParams& wind) {
  RequireOnlyKeys(w, {"speed_mps", "direction_deg", "turbulence"}, source, "wind");
  wind.mean_speed = OptionalNumber(w, "speed_mps", wind.mean_speed, source, "wind");
  wind.direction_rad = OptionalNumber(w, "direction_deg", 0.0, source, "wind") * kRadiansPerDegree;
  if (w["turbulence"]) {
    wind.turbulence = models::ParseTurbulenceCategory(RequireString(w, "turbulence", source, "wind"),
                                                      source + ": wind.turbulence");
  }
}

// Returns whether the file sets the cruise altitude.
bool ReadMission(const YAML::Node& m, const std::string& source, planning::DeliveryMission& mission) {
  RequireOnlyKeys(m, {"home_ne_m", "destination_ne_m", "cruise_altitude_m", "drop_hover_s"}, source, "mission");
  if (m["home_ne_m"]) {
    const auto home = RequireNumberList(m, "home_ne_m", 2, source, "mission");
    mission.home_NE = Eigen::Vector2d(home[0], home[1]);
  }
  if (m["destination_ne_m"]) {
    const auto destination = RequireNumberList(m, "destination_ne_m", 2, source, "mission");
    mission.destination_NE = Eigen::Vector2d(destination[0], destination[1]);
  }
  mission.cruise_altitude = OptionalNumber(m, "cruise_altitude_m", mission.cruise_altitude, source, "mission");
  mission.drop_hover_s = OptionalNumber(m, "drop_hover_s", mission.drop_hover_s, source, "mission");
  return static_cast<bool>(m["cruise_altitude_m"]);
}

void ReadLimits(const YAML::Node& l, const std::string& source, planning::PlanLimits& limits) {
  RequireOnlyKeys(l, {"cruise_speed_mps", "vertical_speed_mps", "horizontal_accel_mps2", "vertical_accel_mps2"},
                  source, "limits");
  limits.cruise_speed = OptionalNumber(l, "cruise_speed_mps", limits.cruise_speed, source, "limits");
  limits.vertical_speed = OptionalNumber(l, "vertical_speed_mps", limits.vertical_speed, source, "limits");
  limits.horizontal_accel = OptionalNumber(l, "horizontal_accel_mps2", limits.horizontal_accel, source, "limits");
  limits.vertical_accel = OptionalNumber(l, "vertical_accel_mps2", limits.vertical_accel, source, "limits");
}

void ReadFault(const YAML::Node& f, const std::string& source, FaultSpec& fault) {
  RequireOnlyKeys(f, {"motor", "spall_onset_s", "time_per_growth_step_s", "prognosis_time_per_growth_step_s"}, source,
                  "fault");
  fault.enabled = true;
  const double motor = RequireNumber(f, "motor", source, "fault");
  if (motor != std::floor(motor) || motor < 1 || motor > 6) throw InputError(source, "fault.motor", "a motor number 1..6");
  fault.motor = static_cast<int>(motor);
  fault.spall_onset_s = RequireNumber(f, "spall_onset_s", source, "fault");
  if (f["time_per_growth_step_s"]) fault.time_per_growth_step_s = RequireNumber(f, "time_per_growth_step_s", source, "fault");
  if (f["prognosis_time_per_growth_step_s"]) {
    fault.prognosis_time_per_growth_step_s = RequireNumber(f, "prognosis_time_per_growth_step_s", source, "fault");
  }
}

void ReadOptions(const YAML::Node& o, const std::string& source, SimOptions& options) {
  RequireOnlyKeys(o, {"telemetry_rate_hz", "reconfiguration", "sensor_noise", "max_tilt_deg", "max_tracking_error_m",
                      "safety_margin_s"},
                  source, "options");
  options.safety_margin_s = OptionalNumber(o, "safety_margin_s", options.safety_margin_s, source, "options");
  options.telemetry_rate_hz = OptionalNumber(o, "telemetry_rate_hz", options.telemetry_rate_hz, source, "options");
  options.reconfiguration = OptionalBool(o, "reconfiguration", options.reconfiguration, source, "options");
  options.sensor_noise = OptionalBool(o, "sensor_noise", options.sensor_noise, source, "options");
  OutcomeThresholds& outcome = options.outcome;
  outcome.max_tilt = OptionalNumber(o, "max_tilt_deg", outcome.max_tilt / kRadiansPerDegree, source, "options") *
                     kRadiansPerDegree;
  outcome.max_tracking_error = OptionalNumber(o, "max_tracking_error_m", outcome.max_tracking_error, source, "options");
}

}  // namespace

ScenarioFile ParseScenario(const std::string& yaml_text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw InputError(source, "line " + std::to_string(e.mark.line + 1), "valid YAML (" + e.msg + ")");
  }
  if (!root.IsMap()) throw InputError(source, "(top level)", "a YAML mapping");
  RequireOnlyKeys(root, {"name", "seed", "policy", "map", "vehicle", "battery", "wind", "mission", "limits", "fault",
                         "options"},
                  source, "");
  ScenarioFile file;
  Scenario& sc = file.scenario;
  sc.name = root["name"] ? RequireString(root, "name", source, "") : std::filesystem::path(source).stem().string();
  if (root["seed"]) {
    const double seed = RequireNumber(root, "seed", source, "");
    if (seed < 0 || seed != std::floor(seed) || seed > 9007199254740992.0) {
      throw InputError(source, "seed", "a non-negative integer");
    }
    sc.seed = static_cast<std::uint64_t>(seed);
  }
  if (root["policy"]) file.policy = RequireString(root, "policy", source, "");
  if (const YAML::Node v = root["vehicle"]) ReadVehicle(v, source, sc);
  if (const YAML::Node b = root["battery"]) ReadBattery(b, source, sc.battery);
  if (const YAML::Node w = root["wind"]) ReadWind(w, source, sc.wind);
  if (const YAML::Node map = root["map"]) sc.map = ReadMap(map, source);
  const bool cruise_altitude_given = root["mission"] && ReadMission(root["mission"], source, sc.mission);
  if (const YAML::Node l = root["limits"]) ReadLimits(l, source, sc.limits);
  if (const YAML::Node f = root["fault"]) ReadFault(f, source, sc.fault);
  if (const YAML::Node o = root["options"]) ReadOptions(o, source, sc.options);
  // One validation for files, samplers and code alike (Scenario::IsValid).
  std::string error;
  if (!sc.IsValid(&error)) throw InputError(source + ": " + error);
  // Over a city the cruise altitude is 10 m above the tallest building under the route (defaults.md)
  // unless the file sets it.
  if (sc.map && !cruise_altitude_given && !sc.map->buildings().empty()) {
    const std::array<Eigen::Vector2d, 2> route = {sc.mission.home_NE, sc.mission.destination_NE};
    sc.mission.cruise_altitude = sc.map->CruiseAltitude(route, planning::kCruiseClearanceAboveBuildings, 5.0);
  }
  return file;
}

ScenarioFile LoadScenarioFile(const std::filesystem::path& path) {
  return ParseScenario(ReadFile(path), path.string());
}

}  // namespace uascma::sim
