#include "uascma/sim/scenario.h"

#include <cmath>
#include <utility>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "uascma/common/bounds.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/common/frames.h"
#include "uascma/common/text.h"
#include "uascma/common/yaml_io.h"
#include "uascma/models/battery_pack.h"
#include "uascma/planning/land_pract.h"
#include "uascma/planning/landing_path.h"
#include "uascma/planning/map_import.h"
#include "uascma/planning/map_projection.h"
#include "uascma/planning/procedural_city.h"
#include "uascma/sim/scenario_bounds.h"
#include "uascma/sim/scenario_fields.h"
#include "uascma/sim/vehicle_file.h"

namespace uascma::sim {
namespace {

void ReadBattery(const YAML::Node& node, const std::string& source, BatterySpec& battery) {
  RequireOnlyKeys(node, ScenarioSectionKeys("battery"), source, "battery");
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
        const auto cells =
            RequireNumberList(holder, "pack", 3, source, fmt::format("battery.initial_cell_voltage_v[{}]", b));
        for (int c = 0; c < 3; ++c) battery.initial_cell_voltage_v[b][c] = cells[c];
      }
    }
  }
  if (const YAML::Node packs = node["packs"]) {
    if (!packs.IsSequence() || packs.size() != 2)
      throw InputError(source, "battery.packs", "a list of two health classes (G, M or P)");
    for (int b = 0; b < 2; ++b) {
      const std::string field = fmt::format("battery.packs[{}]", b);
      if (!packs[b].IsScalar()) throw InputError(source, field, "G, M or P");
      battery.cell_health[b] = PackHealthPreset(models::ParseHealthClass(packs[b].Scalar(), source + ": " + field));
    }
  }
}

// map: {procedural: {seed: 3}} | {buildings: [a.geojson, b.osm.pbf], sites: s.csv, origin: [lat, lon],
//       height_from_levels: bool, metres_per_level: m, skip_missing_height: bool, height_from_type: bool,
//       default_height_m: m, sites_from_map: bool}
// Sets sc.map, and sc.geo_origin for imported data. The import keys are `map info`'s options (map_import.h);
// sites_from_map adds the map's own sites (flat roofs, open areas) to those of `sites`.
void ReadMap(const YAML::Node& node, const std::string& source, Scenario& sc) {
  RequireOnlyKeys(node,
                  {"procedural", "buildings", "sites", "origin", "height_from_levels", "metres_per_level",
                   "skip_missing_height", "height_from_type", "default_height_m", "sites_from_map"},
                  source, "map");
  if (const YAML::Node procedural = node["procedural"]) {
    for (const char* key : {"buildings", "sites", "origin", "height_from_levels", "metres_per_level",
                            "skip_missing_height", "height_from_type", "default_height_m", "sites_from_map"}) {
      if (node[key]) throw InputError(source, std::string("map.") + key, "no import key beside map.procedural");
    }
    planning::ProceduralCityParams params;
    if (procedural.IsMap()) {
      RequireOnlyKeys(procedural, {"seed", "blocks_north", "blocks_east", "rooftop_site_probability"}, source,
                      "map.procedural");
      // Seeds are one unsigned 64-bit type everywhere (common/bounds.h ParseSeed): "-1" or 1e30 is refused, not cast.
      if (const YAML::Node seed = procedural["seed"]) {
        if (!seed.IsScalar()) throw InputError(source, "map.procedural.seed", "a seed from 0 to 2^64-1");
        params.seed = ParseSeed(seed.Scalar(), source, "map.procedural.seed");
      }
      // Block counts checked before the conversion to int (scenario_bounds::kBlocks).
      constexpr const Bounds& kBlockBounds = scenario_bounds::kBlocks;
      for (auto [key, count] :
           {std::pair{"blocks_north", &params.blocks_north}, std::pair{"blocks_east", &params.blocks_east}}) {
        const double value = OptionalNumber(procedural, key, *count, source, "map.procedural");
        RequireWithin(value, kBlockBounds, source, std::string("map.procedural.") + key);
        if (value != std::floor(value))
          throw InputError(source, std::string("map.procedural.") + key, "a whole number");
        *count = static_cast<int>(value);
      }
      params.rooftop_site_probability = OptionalNumber(procedural, "rooftop_site_probability",
                                                       params.rooftop_site_probability, source, "map.procedural");
      RequireWithin(params.rooftop_site_probability, scenario_bounds::kProbability, source,
                    "map.procedural.rooftop_site_probability");
    }
    sc.map = std::make_shared<const planning::CityMap>(planning::MakeProceduralCity(params));
    return;
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
    for (const auto& item : list) {
      if (!item.IsScalar()) throw InputError(source, "map.buildings", "a list of map file names");
      buildings.push_back(resolve(item.Scalar()));
    }
  }
  const std::filesystem::path sites = node["sites"] ? resolve(RequireString(node, "sites", source, "map")) : "";
  planning::MapImportOptions options;
  if (node["origin"]) {
    const auto origin = RequireNumberList(node, "origin", 2, source, "map");
    RequireWithin(origin[0], scenario_bounds::kLatitude, source, "map.origin[0] (latitude)");
    RequireWithin(origin[1], scenario_bounds::kLongitude, source, "map.origin[1] (longitude)");
    options.origin = planning::GeoPoint{origin[0], origin[1]};
  }
  // The import fall-backs, spelt as in campaign YAML (campaign/config.cc).
  options.height_from_levels = OptionalBool(node, "height_from_levels", options.height_from_levels, source, "map");
  options.metres_per_level = OptionalNumber(node, "metres_per_level", options.metres_per_level, source, "map");
  RequireWithin(options.metres_per_level, scenario_bounds::kMetresPerLevel, source, "map.metres_per_level");
  options.skip_missing_height = OptionalBool(node, "skip_missing_height", options.skip_missing_height, source, "map");
  options.height_from_type = OptionalBool(node, "height_from_type", options.height_from_type, source, "map");
  if (node["default_height_m"]) {
    options.default_height = OptionalNumber(node, "default_height_m", 0.0, source, "map");
    RequireWithin(*options.default_height, planning::kDefaultHeightBounds, source, "map.default_height_m");
  }
  options.sites_from_map = OptionalBool(node, "sites_from_map", options.sites_from_map, source, "map");
  std::string error;
  if (!options.IsValid(&error)) throw InputError(source + ": map." + error);
  planning::ImportedMap imported = planning::ImportCityMap(buildings, sites, options);
  sc.geo_origin = imported.summary.origin;
  sc.map = std::make_shared<const planning::CityMap>(std::move(imported.map));
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

bool BatterySpec::IsValid(std::string* error, const models::PackParams* pack) const {
  if (!std::isfinite(ambient_temp_degf)) {
    if (error) *error = "ambient_temp_degf: expected a finite temperature (°F)";
    return false;
  }
  try {
    models::BatteryPack(pack ? *pack : models::MakePackParams(cell_health, ambient_temp_degf))
        .MakeRestingState(initial_cell_voltage_v, models::PackAction::kUseBoth, "initial_cell_voltage_v");
  } catch (const InputError& e) {
    if (error) *error = e.what();
    return false;
  }
  return true;
}

bool SimOptions::IsValid(std::string* error) const {
  const struct {
    const char* name;
    double value;
  } positive[] = {{"gnc_rate_hz", gnc_rate_hz},
                  {"decision_rate_hz", decision_rate_hz},
                  {"telemetry_rate_hz", telemetry_rate_hz},
                  {"reference_bus_voltage_v", reference_bus_voltage_v},
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
  const double pack_ratio = gnc_rate_hz / pack_rate_hz;
  const double epoch_ratio = pack_rate_hz / decision_rate_hz;
  if (!(pack_rate_hz > 0.0 && pack_rate_hz <= gnc_rate_hz && std::abs(pack_ratio - std::round(pack_ratio)) <= 1e-9 &&
        std::abs(epoch_ratio - std::round(epoch_ratio)) <= 1e-9)) {
    if (error) {
      *error = fmt::format(
          "pack_rate_hz: expected a rate that divides gnc_rate_hz and that decision_rate_hz divides, "
          "got {} Hz",
          pack_rate_hz);
    }
    return false;
  }
  const double wind_ratio = gnc_rate_hz / wind_rate_hz;
  if (!(wind_rate_hz > 0.0 && wind_rate_hz <= gnc_rate_hz && std::abs(wind_ratio - std::round(wind_ratio)) <= 1e-9)) {
    if (error) *error = fmt::format("wind_rate_hz: expected a rate that divides gnc_rate_hz, got {} Hz", wind_rate_hz);
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
  if (!sensing.IsValid(error)) return false;
  return outcome.IsValid(error);
}

namespace {

// Whether the vehicle can hover at take-off with its packs: a combination of numbers that are
// each inside their bound can still be a vehicle that cannot fly, and flying it gives impossible numbers
// (cells pulled below zero volts, negative energy). Knowable from the inputs, so refused before flying:
//   1. thrust: hovering needs m g; the rotors give at most 6 T_max (Table 2.2 at 1900 µs, over six rotors;
//      models::PropulsionParams::max_thrust);
//   2. power: each rotor at m g / 6 draws P(T) (the power law fitted to Table 2.2), the bus I = P / V_bus
//      (eq. 2.10) plus the hotel load. The packs at rest at their initial voltages give V_bus(I) by eqs.
//      3.4–3.5 (BatteryPack::CalcSplit, diodes included), so I V_bus(I) has a largest value: a hover power
//      above it cannot be drawn at all (the bus collapses);
//   3. the current that does supply it must stay within I_max = 105 A (Table 4.1: the packs' rating, and the
//      range in which the cell model keeps positive voltages even for cold, poor packs near empty,
//      BoundsCliTest.TheWorstCaseInsideTheBoundsHasAPositiveBusVoltage).
// A pack that supplies the hover current but reaches the 3.3 V cut-off soon (even at take-off) is flown: that
// is the named outcome failed_battery, with physical numbers, as a campaign's cold, nearly empty packs are.
bool CheckCanHover(const Scenario& sc, std::string* error) {
  const models::PropulsionParams propulsion = ScenarioPropulsion(sc);
  constexpr int kRotors = 6;
  const double hover_thrust_n = sc.body.mass * kGravity;
  const double max_thrust_n = kRotors * propulsion.max_thrust;
  const std::string vehicle = sc.vehicle ? fmt::format("vehicle {}: mass_kg {:g} kg", sc.vehicle->source, sc.body.mass)
                                         : fmt::format("vehicle.mass_kg {:g} kg ({} propellers)", sc.body.mass,
                                                       models::PropellerConfigurationName(sc.configuration));
  if (hover_thrust_n > max_thrust_n) {
    if (error) {
      *error = fmt::format(
          "{}: expected a vehicle its rotors can hold up: hovering needs {:.1f} N, the six rotors give "
          "at most {:.2f} N ({}), so at most {:.3f} kg",
          vehicle, hover_thrust_n, max_thrust_n, sc.vehicle ? "its propulsion" : "Table 2.2", max_thrust_n / kGravity);
    }
    return false;
  }
  const double hover_power_w = kRotors * models::CalcElectricalPower(propulsion, hover_thrust_n / kRotors);
  const models::BatteryPack pack(ScenarioPackParams(sc, sc.battery.cell_health, sc.battery.ambient_temp_degf));
  const models::PackState state = pack.MakeRestingState(sc.battery.initial_cell_voltage_v);
  const auto power_at = [&](double current_a) { return current_a * pack.CalcSplit(state, current_a).bus_voltage_v; };
  // I V_bus(I) rises from 0, peaks and falls to 0 where V_bus reaches 0: golden-section search for the peak
  // on [0, I at V_bus = 0], found by doubling.
  double zero_a = 1.0;
  while (pack.CalcSplit(state, zero_a).bus_voltage_v > 0.0 && zero_a < 1e9) zero_a *= 2.0;
  double low = 0.0;
  double high = zero_a;
  const double ratio = (std::sqrt(5.0) - 1.0) / 2.0;
  for (int i = 0; i < 200 && high - low > 1e-9 * zero_a; ++i) {
    const double a = high - ratio * (high - low);
    const double b = low + ratio * (high - low);
    if (power_at(a) < power_at(b)) {
      low = a;
    } else {
      high = b;
    }
  }
  const double peak_a = 0.5 * (low + high);
  const double total_power_w = hover_power_w + sc.options.hotel_current_a * pack.CalcSplit(state, 0.0).bus_voltage_v;
  const std::string battery = fmt::format("battery (health {}, {:g} °F)",
                                          models::HealthClassName(models::ClassifyHealth(sc.battery.cell_health)),
                                          sc.battery.ambient_temp_degf);
  if (total_power_w > power_at(peak_a)) {
    if (error) {
      *error = fmt::format(
          "{} with {}: expected packs that can hover the vehicle: hovering draws {:.0f} W, the packs "
          "give at most {:.0f} W (at {:.0f} A)",
          vehicle, battery, total_power_w, power_at(peak_a), peak_a);
    }
    return false;
  }
  // The current that supplies the hover power: on the rising side of I V_bus(I), by bisection.
  double current_low = 0.0;
  double current_high = peak_a;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (current_low + current_high);
    (power_at(mid) < total_power_w ? current_low : current_high) = mid;
  }
  const double current_a = current_high;
  const models::PackOutputs outputs = pack.CalcOutputs(state, current_a);
  if (current_a > models::kMaxPackCurrent) {
    if (error) {
      *error = fmt::format(
          "{} with {}: expected packs that can hover the vehicle: hovering draws {:.1f} A ({:.0f} W; "
          "{} at {:.2f} V), beyond the packs' {:.0f} A (Table 4.1)",
          vehicle, battery, current_a, total_power_w,
          models::CellLabel(outputs.min_cell_branch, outputs.min_cell_index), outputs.min_cell_voltage_v,
          models::kMaxPackCurrent);
    }
    return false;
  }
  return true;
}

}  // namespace

bool Scenario::IsValid(std::string* error) const {
  // The plausibility bounds first: they name the file's key and the bound.
  if (!CheckScenarioBounds(*this, error)) return false;
  std::string part_error;
  auto fail = [&](const char* part) {
    if (error) *error = std::string(part) + ": " + part_error;
    return false;
  };
  if (!body.IsValid(&part_error)) return fail("vehicle");
  if (vehicle) {
    const models::PackParams pack = ScenarioPackParams(*this, battery.cell_health, battery.ambient_temp_degf);
    if (!battery.IsValid(&part_error, &pack)) return fail("battery");
  } else if (!battery.IsValid(&part_error)) {
    return fail("battery");
  }
  if (!wind.IsValid(&part_error)) return fail("wind");
  if (!mission.IsValid(&part_error)) return fail("mission");
  if (!limits.IsValid(&part_error)) return fail("limits");
  if (!fault.IsValid(&part_error)) return fail("fault");
  if (pack_fault && !pack_fault->IsValid(&part_error)) return fail("pack_fault");
  if (!lqr.IsValid(&part_error)) return fail("lqr");
  if (!imm.IsValid(&part_error)) return fail("imm");
  if (!options.IsValid(&part_error)) return fail("options");
  if (!CheckCanHover(*this, error)) return false;  // a combination of in-bounds numbers that cannot fly
  if (std::abs(lqr.dt * options.gnc_rate_hz - 1.0) > 1e-9) {
    part_error = "dt: expected 1 / options.gnc_rate_hz";
    return fail("lqr");
  }
  if (map_obstacles && (!map || map_obstacles->size() != static_cast<int>(map->buildings().size()))) {
    if (error) *error = "map_obstacles: expected the hulls of the map's own buildings (Scenario::map_obstacles)";
    return false;
  }
  if (geo_origin && !(std::abs(geo_origin->lat_deg) <= 90.0 && std::abs(geo_origin->lon_deg) <= 180.0)) {
    part_error = fmt::format("origin: expected [latitude, longitude] in degrees, got [{}, {}]", geo_origin->lat_deg,
                             geo_origin->lon_deg);
    return fail("mission");
  }
  if (route) {
    if (route->waypoints.empty()) {
      part_error = fmt::format("file: expected a mission with at least one waypoint ({})", route->source);
      return fail("mission");
    }
    if (!route->home_W.allFinite()) {
      part_error = "file: expected a finite home position";
      return fail("mission");
    }
    try {
      // Throws on a non-finite waypoint, a negative hover or speed limit, or invalid limits.
      (void)planning::MakeMissionPlan(*route, limits);
    } catch (const InputError& e) {
      part_error = fmt::format("file: expected a mission that can be flown ({})", e.what());
      return fail("mission");
    }
    if (map) {
      const Eigen::Vector3d& home = route->home_W;
      const int building = map->BuildingContaining(Eigen::Vector3d(home.x(), home.y(), -0.1));
      if (building != planning::kNoBuilding) {
        part_error = fmt::format(
            "file: expected the planned home on open ground, but building {} stands at "
            "({:.1f}, {:.1f}) m",
            map->building(building).id, home.x(), home.y());
        return fail("mission");
      }
    }
    return true;  // the delivery keys are not flown
  }
  if (map) {
    for (const auto& [key, point] :
         {std::pair{"home_ne_m", mission.home_NE}, std::pair{"destination_ne_m", mission.destination_NE}}) {
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

// vehicle:, wind:, limits:, options: — every key a row of the field table (scenario_fields.h).
void ReadSection(const YAML::Node& node, const char* section, const std::string& source, Scenario& sc) {
  RequireOnlyKeys(node, ScenarioSectionKeys(section), source, section);
  ReadScenarioSection(node, section, source, sc);
}

// mission.origin: [lat, lon], the geodetic position of W's origin. Over an imported map the frame is the map's
// (map.origin), so that buildings and route share it: there it is an error.
std::optional<planning::GeoPoint> ReadMissionOrigin(const YAML::Node& m, const std::string& source,
                                                    const Scenario& sc) {
  if (!m || !m["origin"]) return std::nullopt;
  if (sc.geo_origin) {
    throw InputError(source, "mission.origin",
                     "no origin over an imported map (the mission is flown in the map's frame: set map.origin)");
  }
  const auto origin = RequireNumberList(m, "origin", 2, source, "mission");
  return planning::GeoPoint{origin[0], origin[1]};
}

// The scenario flies `route`: its rally points join the landing sites LandPract and LandASAP may use, and the sites
// its geofence forbids leave (planning/mission_file.h, WithMissionSafety); the frame is the route's.
void AdoptRoute(Scenario& sc, planning::Mission route) {
  sc.route = std::move(route);
  if (!sc.route->rally_points.empty() || !sc.route->geofence.empty()) {
    sc.map = std::make_shared<const planning::CityMap>(
        planning::WithMissionSafety(sc.map ? *sc.map : planning::CityMap(), *sc.route));
  }
  sc.geo_origin = sc.route->origin;
  // Mirrored for the records (campaign metrics, the plot's extent): the route's home and its last point.
  sc.mission.home_NE = sc.route->home_W.head<2>();
  sc.mission.destination_NE =
      sc.route->waypoints.empty() ? sc.mission.home_NE : Eigen::Vector2d(sc.route->waypoints.back().p_W.head<2>());
}

// mission: {file: x.plan, land_at_end: true, origin: [lat, lon]} — a ground station's mission (mission_file.h),
// paths relative to the scenario file. Its options are read even when `mission_file` (simulate --mission)
// replaces the file.
void ReadMissionFile(const YAML::Node& m, const std::string& source,
                     const std::optional<std::filesystem::path>& mission_file, Scenario& sc) {
  planning::MissionImportOptions options;
  options.map = sc.map.get();
  if (m) {
    if (m["file"]) {
      for (const char* key : {"home_ne_m", "destination_ne_m", "cruise_altitude_m", "drop_hover_s"}) {
        if (m[key])
          throw InputError(source, std::string("mission.") + key,
                           "either mission.file or " + std::string(key) + ", not both");
      }
    }
    options.land_at_end = OptionalBool(m, "land_at_end", options.land_at_end, source, "mission");
  }
  options.origin = ReadMissionOrigin(m, source, sc);
  // Default origin: the imported map's, so that the mission and the buildings share a frame.
  if (!options.origin && sc.geo_origin) options.origin = sc.geo_origin;
  std::string error;
  if (!options.IsValid(&error)) throw InputError(source + ": mission." + error);
  std::filesystem::path path;
  if (mission_file) {
    path = *mission_file;
  } else {
    const std::filesystem::path name(RequireString(m, "file", source, "mission"));
    path = name.is_absolute() ? name : std::filesystem::path(source).parent_path() / name;
  }
  AdoptRoute(sc, planning::LoadMissionFile(path, options));
}

// Returns whether the file sets the cruise altitude.
bool ReadMission(const YAML::Node& m, const std::string& source, Scenario& sc) {
  RequireOnlyKeys(m, ScenarioSectionKeys("mission"), source, "mission");
  if (!m["file"]) {
    if (m["land_at_end"])
      throw InputError(source, "mission.land_at_end", "only with mission.file (or simulate --mission)");
  }
  ReadScenarioSection(m, "mission", source, sc);
  return static_cast<bool>(m["cruise_altitude_m"]);
}

// fault: — its presence is the fault (§5.4); motor and onset required.
void ReadFault(const YAML::Node& f, const std::string& source, Scenario& sc) {
  RequireOnlyKeys(f, ScenarioSectionKeys("fault"), source, "fault");
  sc.fault.enabled = true;
  ReadScenarioSection(f, "fault", source, sc);
}

// pack_fault: — its presence is the fault (models/pack_fault.h); kind, pack and onset required, the cell for the two
// cell faults.
void ReadPackFault(const YAML::Node& f, const std::string& source, Scenario& sc) {
  RequireOnlyKeys(f, ScenarioSectionKeys("pack_fault"), source, "pack_fault");
  models::PackFault fault;
  fault.kind = models::ParsePackFaultKind(RequireString(f, "kind", source, "pack_fault"), source, "pack_fault.kind");
  auto whole = [&](const char* key, int low, int high) {
    const double value = RequireNumber(f, key, source, "pack_fault");
    if (value != std::floor(value) || value < low || value > high) {
      throw InputError(source, std::string("pack_fault.") + key, fmt::format("a whole number {}..{}", low, high));
    }
    return static_cast<int>(value) - 1;
  };
  fault.branch = whole("pack", 1, models::kBranchCount);
  if (fault.kind != models::PackFaultKind::kConnector) fault.cell = whole("cell", 1, models::kCellsPerBranch);
  fault.onset_s = RequireNumber(f, "onset_s", source, "pack_fault");
  RequireWithin(fault.onset_s, models::kPackFaultOnsetBounds, source, "pack_fault.onset_s");
  fault.resistance_ohm = RequireNumber(f, "resistance_ohm", source, "pack_fault");
  RequireWithin(fault.resistance_ohm, models::kPackFaultResistanceBounds, source, "pack_fault.resistance_ohm");
  sc.pack_fault = fault;
}

// Over a map with landing sites the flight builds LandPract's database, whose checkpoints lie on the nominal plan
// (§5.3.2.2): one inside a building is a plan through it, said here with the file and the key that sets the height.
void CheckLandPractCheckpoints(const Scenario& sc, const std::string& source) {
  if (!sc.map || sc.map->sites().empty()) return;
  const planning::FlightPlan plan =
      sc.route ? planning::MakeMissionPlan(*sc.route, sc.limits) : planning::MakeDeliveryPlan(sc.mission, sc.limits);
  if (const auto inside = planning::FirstCheckpointInBuilding(*sc.map, plan)) {
    throw InputError(source, sc.route ? "mission.file" : "mission.cruise_altitude_m",
                     fmt::format("a nominal plan clear of the buildings, but LandPract's checkpoint {} at ({:.1f}, "
                                 "{:.1f}, {:.1f}) m (NED) is inside one: raise the cruise altitude",
                                 inside->checkpoint, inside->p_W.x(), inside->p_W.y(), inside->p_W.z()));
  }
}

}  // namespace

void FlyMissionRoute(Scenario& sc, planning::Mission route, const std::string& source) {
  AdoptRoute(sc, std::move(route));
  std::string error;
  if (!sc.IsValid(&error)) throw InputError(source + ": " + error);
  CheckLandPractCheckpoints(sc, source);
}

ScenarioFile ParseScenario(const std::string& yaml_text, const std::string& source, const ScenarioLoadOptions& load) {
  const YAML::Node root = ParseYamlText(yaml_text, source);  // duplicate keys and non-UTF-8 text refused
  if (!root.IsMap()) throw InputError(source, "(top level)", "a YAML mapping");
  RequireOnlyKeys(root,
                  {"name", "seed", "policy", "map", "vehicle", "battery", "wind", "mission", "limits", "fault",
                   "pack_fault", "options"},
                  source, "");
  ScenarioFile file;
  Scenario& sc = file.scenario;
  sc.name = root["name"] ? RequireString(root, "name", source, "") : std::filesystem::path(source).stem().string();
  // A name from the file's name reaches every writer (summary.json, plots, campaign rows): UTF-8 or refused.
  if (!root["name"]) RequireUtf8(sc.name, source, "name (taken from the file's name; give a name: key)");
  if (const YAML::Node seed = root["seed"]) {
    if (!seed.IsScalar()) throw InputError(source, "seed", "a seed from 0 to 2^64-1");
    sc.seed = ParseSeed(seed.Scalar(), source, "seed");
  }
  if (root["policy"]) file.policy = RequireString(root, "policy", source, "");
  if (const YAML::Node v = root["vehicle"]) {
    if (v.IsScalar()) {  // a vehicle file, relative to the scenario (sim/vehicle_file.h)
      const std::filesystem::path name(v.Scalar());
      UseVehicle(sc, LoadVehicleFile(name.is_absolute() ? name : std::filesystem::path(source).parent_path() / name));
    } else {
      ReadSection(v, "vehicle", source, sc);
    }
  }
  if (load.vehicle_file) UseVehicle(sc, LoadVehicleFile(*load.vehicle_file));
  if (const YAML::Node b = root["battery"]) {
    ReadBattery(b, source, sc.battery);
    ReadScenarioSection(b, "battery", source, sc);
  }
  if (const YAML::Node w = root["wind"]) ReadSection(w, "wind", source, sc);
  if (const YAML::Node map = root["map"]) ReadMap(map, source, sc);
  const YAML::Node mission = root["mission"];
  const bool cruise_altitude_given = mission && ReadMission(mission, source, sc);
  if (load.mission_file || (mission && mission["file"])) {
    ReadMissionFile(mission, source, load.mission_file, sc);
  } else if (const auto origin = ReadMissionOrigin(mission, source, sc)) {
    sc.geo_origin = origin;  // a local-metres mission placed on the globe (for the QGroundControl export)
  }
  if (const YAML::Node l = root["limits"]) ReadSection(l, "limits", source, sc);
  if (const YAML::Node f = root["fault"]) ReadFault(f, source, sc);
  if (const YAML::Node f = root["pack_fault"]) ReadPackFault(f, source, sc);
  if (const YAML::Node o = root["options"]) ReadSection(o, "options", source, sc);
  // The map's inflated hulls, once for every flight of this scenario (Scenario::map_obstacles).
  if (sc.map && !sc.map->sites().empty()) {
    sc.map_obstacles =
        planning::LandingPathPlanner::InflateBuildings(*sc.map, planning::LandingPathParams{}.lateral_margin);
  }
  // One validation for files, samplers and code alike (Scenario::IsValid).
  std::string error;
  if (!sc.IsValid(&error)) throw InputError(source + ": " + error);
  // Over a city the cruise altitude is 10 m above the tallest building under the route
  // (docs/defaults.md#guidance-and-control) unless the file sets it.
  if (sc.map && !sc.route && !cruise_altitude_given && !sc.map->buildings().empty()) {
    const std::array<Eigen::Vector2d, 2> route = {sc.mission.home_NE, sc.mission.destination_NE};
    sc.mission.cruise_altitude = sc.map->CruiseAltitude(route, planning::kCruiseClearanceAboveBuildings, 5.0);
  }
  CheckLandPractCheckpoints(sc, source);
  return file;
}

ScenarioFile LoadScenarioFile(const std::filesystem::path& path, const ScenarioLoadOptions& load) {
  return ParseScenario(ReadFile(path), path.string(), load);
}

}  // namespace uascma::sim
