#include "uascma/campaign/config.h"

#include <cmath>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/common/hash.h"
#include "uascma/common/yaml_io.h"
#include "uascma/planning/map_import.h"

namespace uascma::campaign {
namespace {

std::string Join(const std::string& where, const std::string& key) {
  return where.empty() ? key : where + "." + key;
}

Range ReadRange(const YAML::Node& node, const std::string& key, Range fallback, const std::string& source,
                const std::string& where) {
  if (!node[key]) return fallback;
  const std::vector<double> values = RequireNumberList(node, key, 2, source, where);
  return {values[0], values[1]};
}

// An integer within `bounds`, checked before the conversion (a cast of 1e300 to an integer is undefined).
std::int64_t ReadInteger(const YAML::Node& node, const std::string& key, std::int64_t fallback, const Bounds& bounds,
                         const std::string& source, const std::string& where) {
  if (!node[key]) return fallback;
  const double value = RequireNumber(node, key, source, where);
  RequireWithin(value, bounds, source, Join(where, key));
  if (value != std::floor(value)) {
    throw InputError(source, Join(where, key), fmt::format("an integer, got {}", value));
  }
  return static_cast<std::int64_t>(value);
}

// Seeds are unsigned 64-bit integers everywhere (common/bounds.h): "-1" is refused, not wrapped.
std::uint64_t ReadSeed(const YAML::Node& node, const std::string& key, const std::string& source,
                       const std::string& where) {
  const YAML::Node value = node[key];
  if (!value.IsScalar()) throw InputError(source, Join(where, key), "a seed from 0 to 2^64-1");
  return ParseSeed(value.Scalar(), source, Join(where, key));
}

std::vector<std::string> ReadStringList(const YAML::Node& node, const std::string& key,
                                        const std::string& source, const std::string& where) {
  const YAML::Node value = node[key];
  if (!value.IsSequence()) throw InputError(source, Join(where, key), "a list of names");
  std::vector<std::string> names;
  for (std::size_t i = 0; i < value.size(); ++i) {
    if (!value[i].IsScalar()) {
      throw InputError(source, fmt::format("{}[{}]", Join(where, key), i), "a name");
    }
    names.push_back(value[i].Scalar());
  }
  return names;
}

YAML::Node OptionalMap(const YAML::Node& node, const std::string& key, const std::string& source,
                       const std::string& where) {
  if (!node[key]) return YAML::Node(YAML::NodeType::Map);
  return RequireMap(node, key, source, where);
}

void ReadMission(const YAML::Node& root, const std::string& source, MissionSampling& m) {
  const YAML::Node node = OptionalMap(root, "mission", source, "");
  RequireOnlyKeys(node, {"endurance_fraction", "distance_m", "cruise_speed_mps", "cruise_altitude_m",
                         "wall_clearance_m", "drop_hover_s"},
                  source, "mission");
  m.endurance_fraction = ReadRange(node, "endurance_fraction", m.endurance_fraction, source, "mission");
  if (node["distance_m"]) {
    if (node["distance_m"].IsNull()) {
      m.distance_m.reset();
    } else {
      m.distance_m = ReadRange(node, "distance_m", Range{}, source, "mission");
    }
  }
  m.wall_clearance_m = OptionalNumber(node, "wall_clearance_m", m.wall_clearance_m, source, "mission");
  m.cruise_speed_mps = ReadRange(node, "cruise_speed_mps", m.cruise_speed_mps, source, "mission");
  m.cruise_altitude_m = OptionalNumber(node, "cruise_altitude_m", m.cruise_altitude_m, source, "mission");
  m.drop_hover_s = OptionalNumber(node, "drop_hover_s", m.drop_hover_s, source, "mission");
}

void ReadBattery(const YAML::Node& root, const std::string& source, BatterySampling& b) {
  const YAML::Node node = OptionalMap(root, "battery", source, "");
  RequireOnlyKeys(node, {"initial_cell_voltage_v", "health_weights", "degraded_cells", "medium_fades",
                         "cold_probability", "cold_temp_degf", "warm_temp_degf"},
                  source, "battery");
  b.initial_cell_voltage_v = ReadRange(node, "initial_cell_voltage_v", b.initial_cell_voltage_v, source, "battery");
  if (node["health_weights"]) {
    const YAML::Node weights = RequireMap(node, "health_weights", source, "battery");
    RequireOnlyKeys(weights, {"G", "M", "P"}, source, "battery.health_weights");
    const char* names[] = {"G", "M", "P"};
    for (int i = 0; i < 3; ++i) {
      b.health_weights[i] = OptionalNumber(weights, names[i], b.health_weights[i], source, "battery.health_weights");
    }
  }
  if (node["degraded_cells"]) {
    const std::vector<double> counts = RequireNumberList(node, "degraded_cells", 2, source, "battery");
    for (double count : counts) {
      RequireWithin(count, bounds::kDegradedCells, source, "battery.degraded_cells");
      if (count != std::floor(count)) {
        throw InputError(source, "battery.degraded_cells", fmt::format("whole numbers of cells, got {}", count));
      }
    }
    b.degraded_cells = {static_cast<int>(counts[0]), static_cast<int>(counts[1])};
  }
  if (node["medium_fades"]) {
    const std::string fades = RequireString(node, "medium_fades", source, "battery");
    if (fades == MediumFadesName(MediumFades::kOneKind)) {
      b.medium_fades = MediumFades::kOneKind;
    } else if (fades == MediumFadesName(MediumFades::kPerCell)) {
      b.medium_fades = MediumFades::kPerCell;
    } else {
      throw InputError(source, "battery.medium_fades", fmt::format("one_kind | per_cell, got '{}'", fades));
    }
  }
  b.cold_probability = OptionalNumber(node, "cold_probability", b.cold_probability, source, "battery");
  b.cold_temp_degf = OptionalNumber(node, "cold_temp_degf", b.cold_temp_degf, source, "battery");
  b.warm_temp_degf = OptionalNumber(node, "warm_temp_degf", b.warm_temp_degf, source, "battery");
}

void ReadWind(const YAML::Node& root, const std::string& source, WindSampling& w) {
  const YAML::Node node = OptionalMap(root, "wind", source, "");
  RequireOnlyKeys(node, {"speed_mps", "direction_rad", "turbulence"}, source, "wind");
  w.speed_mps = ReadRange(node, "speed_mps", w.speed_mps, source, "wind");
  w.direction_rad = ReadRange(node, "direction_rad", w.direction_rad, source, "wind");
  if (node["turbulence"]) {
    w.turbulence.clear();
    const std::vector<std::string> names = ReadStringList(node, "turbulence", source, "wind");
    for (std::size_t i = 0; i < names.size(); ++i) {
      try {
        w.turbulence.push_back(models::ParseTurbulenceCategory(names[i], source));
      } catch (const InputError&) {
        throw InputError(source, fmt::format("wind.turbulence[{}]", i),
                         "one of low-light, low-moderate, medium-light, medium-moderate, none; got '" +
                             names[i] + "'");
      }
    }
  }
}

void ReadFault(const YAML::Node& root, const std::string& source, FaultSampling& f) {
  const YAML::Node node = OptionalMap(root, "fault", source, "");
  RequireOnlyKeys(node, {"probability", "onset_fraction", "motors", "time_per_growth_step_s"}, source, "fault");
  f.probability = OptionalNumber(node, "probability", f.probability, source, "fault");
  f.onset_fraction = ReadRange(node, "onset_fraction", f.onset_fraction, source, "fault");
  if (node["motors"]) {
    const YAML::Node motors = node["motors"];
    if (!motors.IsSequence()) throw InputError(source, "fault.motors", "a list of motors 1..6");
    f.motors.clear();
    for (std::size_t i = 0; i < motors.size(); ++i) {
      const std::string field = fmt::format("fault.motors[{}]", i);
      if (!motors[i].IsScalar()) throw InputError(source, field, "a motor number 1..6");
      int motor = 0;
      try {
        motor = motors[i].as<int>();
      } catch (const YAML::Exception&) {
        throw InputError(source, field, "a motor number 1..6, got '" + motors[i].Scalar() + "'");
      }
      RequireWithin(motor, bounds::kMotor, source, field);
      f.motors.push_back(motor);
    }
  }
  if (node["time_per_growth_step_s"]) {
    if (node["time_per_growth_step_s"].IsNull()) {
      f.time_per_growth_step_s.reset();
    } else {
      f.time_per_growth_step_s = RequireNumber(node, "time_per_growth_step_s", source, "fault");
    }
  }
}

std::string Number(double value) { return fmt::format("{}", value); }
std::string RangeYaml(const Range& r) { return fmt::format("[{}, {}]", r.low, r.high); }

}  // namespace

const char* MediumFadesName(MediumFades fades) {
  return fades == MediumFades::kPerCell ? "per_cell" : "one_kind";
}

bool CampaignConfig::IsValid(std::string* error) const {
  auto fail = [error](std::string message) {
    if (error) *error = std::move(message);
    return false;
  };
  auto check_range = [&](const Range& r, const char* field, const Bounds& b) {
    if (!(b.Contains(r.low) && b.Contains(r.high) && r.low <= r.high)) {
      if (error) *error = fmt::format("{}: expected [low, high] with low <= high, both from {}, got [{}, {}]", field,
                                      b.Text(), r.low, r.high);
      return false;
    }
    return true;
  };
  auto plain = [](const std::string& text) {
    return text.find_first_of("\"\\\n\r") == std::string::npos;
  };
  if (!plain(name)) return fail("name: expected a label without quotes, backslashes or line breaks");
  if (!CheckWithin(static_cast<double>(runs), bounds::kRuns, "runs", error)) return false;
  if (!CheckWithin(map.blocks_north, bounds::kBlocks, "map.blocks_north", error)) return false;
  if (!CheckWithin(map.blocks_east, bounds::kBlocks, "map.blocks_east", error)) return false;
  if (map.imported()) {
    for (const auto& file : map.buildings) {
      if (file.empty() || !plain(file)) return fail("map.buildings: expected file paths without quotes");
    }
    if (!plain(map.sites)) return fail("map.sites: expected a file path without quotes");
    if (map.origin_deg && !((*map.origin_deg)[0] >= -90.0 && (*map.origin_deg)[0] <= 90.0 &&
                            (*map.origin_deg)[1] >= -180.0 && (*map.origin_deg)[1] <= 180.0)) {
      return fail("map.origin: expected [latitude in [-90, 90], longitude in [-180, 180]] in degrees");
    }
    if (!(map.metres_per_level > 0.0 && map.metres_per_level <= 20.0)) {
      return fail(fmt::format("map.metres_per_level: expected a storey height in (0, 20] m, got {}", map.metres_per_level));
    }
    if (map.default_height_m &&
        !CheckWithin(*map.default_height_m, planning::kDefaultHeightBounds, "map.default_height_m", error)) {
      return false;
    }
  }
  if (policies.empty()) return fail("policies: expected at least one policy");
  for (const auto& policy : policies) {
    if (policy.empty() || !plain(policy)) return fail("policies: expected names or paths without quotes");
  }
  if (!check_range(mission.endurance_fraction, "mission.endurance_fraction", bounds::kEnduranceFraction)) return false;
  if (mission.distance_m && !check_range(*mission.distance_m, "mission.distance_m", bounds::kDistance)) return false;
  if (!CheckWithin(mission.wall_clearance_m, bounds::kWallClearance, "mission.wall_clearance_m", error)) return false;
  if (!check_range(mission.cruise_speed_mps, "mission.cruise_speed_mps", bounds::kCruiseSpeed)) return false;
  if (!CheckWithin(mission.cruise_altitude_m, bounds::kCruiseAltitude, "mission.cruise_altitude_m", error)) return false;
  if (!CheckWithin(mission.drop_hover_s, bounds::kDropHover, "mission.drop_hover_s", error)) return false;
  if (!check_range(safety_margin_s, "safety_margin_s", bounds::kSafetyMargin)) return false;
  if (!check_range(battery.initial_cell_voltage_v, "battery.initial_cell_voltage_v", bounds::kInitialCellVoltage)) {
    return false;
  }
  double weight_sum = 0.0;
  for (double w : battery.health_weights) {
    if (!CheckWithin(w, bounds::kHealthWeight, "battery.health_weights", error)) return false;
    weight_sum += w;
  }
  if (battery.health_weights.size() != 3 || !(weight_sum > 0.0)) {
    return fail("battery.health_weights: expected G, M, P with a positive sum");
  }
  if (!(CheckWithin(battery.degraded_cells.low, bounds::kDegradedCells, "battery.degraded_cells", error) &&
        CheckWithin(battery.degraded_cells.high, bounds::kDegradedCells, "battery.degraded_cells", error))) {
    return false;
  }
  if (battery.degraded_cells.low > battery.degraded_cells.high) {
    return fail(fmt::format("battery.degraded_cells: expected [low, high] with low <= high, got [{}, {}]",
                            battery.degraded_cells.low, battery.degraded_cells.high));
  }
  if (!CheckWithin(battery.cold_probability, bounds::kProbability, "battery.cold_probability", error)) return false;
  if (!CheckWithin(battery.cold_temp_degf, bounds::kColdTemperature, "battery.cold_temp_degf", error)) return false;
  if (!CheckWithin(battery.warm_temp_degf, bounds::kWarmTemperature, "battery.warm_temp_degf", error)) return false;
  if (!check_range(wind.speed_mps, "wind.speed_mps", bounds::kWindSpeed)) return false;
  if (!check_range(wind.direction_rad, "wind.direction_rad", bounds::kWindDirection)) return false;
  if (wind.turbulence.empty()) return fail("wind.turbulence: expected at least one category");
  if (!CheckWithin(fault.probability, bounds::kProbability, "fault.probability", error)) return false;
  if (!check_range(fault.onset_fraction, "fault.onset_fraction", bounds::kProbability)) return false;
  if (fault.motors.empty()) return fail("fault.motors: expected at least one motor");
  for (int motor : fault.motors) {
    if (!CheckWithin(motor, bounds::kMotor, "fault.motors", error)) return false;
  }
  if (fault.time_per_growth_step_s &&
      !CheckWithin(*fault.time_per_growth_step_s, bounds::kTimePerGrowthStep, "fault.time_per_growth_step_s", error)) {
    return false;
  }
  return true;
}

// The imported-map keys of `map:` (config.h, MapSampling). Paths stay as written; LoadCampaignConfig resolves them.
void ReadImportedMap(const YAML::Node& map, const std::string& source, MapSampling& m) {
  if (map["buildings"]) {
    m.buildings = ReadStringList(map, "buildings", source, "map");
    if (m.buildings.empty()) throw InputError(source, "map.buildings", "a list of building files (GeoJSON or OSM)");
    if (map["procedural_seed"]) {
      throw InputError(source, "map", "either procedural_seed (the built-in city) or buildings (an imported one)");
    }
  }
  if (map["sites"]) m.sites = RequireString(map, "sites", source, "map");
  if (map["origin"]) {
    const std::vector<double> origin = RequireNumberList(map, "origin", 2, source, "map");
    m.origin_deg = std::array<double, 2>{origin[0], origin[1]};
  }
  m.height_from_levels = OptionalBool(map, "height_from_levels", m.height_from_levels, source, "map");
  m.metres_per_level = OptionalNumber(map, "metres_per_level", m.metres_per_level, source, "map");
  m.skip_missing_height = OptionalBool(map, "skip_missing_height", m.skip_missing_height, source, "map");
  m.height_from_type = OptionalBool(map, "height_from_type", m.height_from_type, source, "map");
  if (map["default_height_m"]) {
    m.default_height_m = OptionalNumber(map, "default_height_m", 0.0, source, "map");
    RequireWithin(*m.default_height_m, planning::kDefaultHeightBounds, source, "map.default_height_m");
  }
  if (map["sites_from_map"]) m.sites_from_map = OptionalBool(map, "sites_from_map", false, source, "map");
  if (!m.imported() && (!m.sites.empty() || m.origin_deg || m.height_from_type || m.default_height_m ||
                        m.sites_from_map)) {
    throw InputError(source, "map.buildings",
                     "building files: sites, origin, height_from_type, default_height_m and sites_from_map belong to "
                     "an imported map");
  }
}

CampaignConfig ParseCampaignConfig(const std::string& yaml_text, const std::string& source) {
  const YAML::Node root = ParseYamlText(yaml_text, source);  // duplicate keys and non-UTF-8 text refused
  CampaignConfig config;
  if (root.IsNull()) return config;  // an empty file: every default
  if (!root.IsMap()) throw InputError(source, "(top level)", "a YAML mapping");
  RequireOnlyKeys(root, {"name", "seed", "runs", "policies", "map", "mission", "safety_margin_s", "battery", "wind",
                         "fault", "options"},
                  source, "");
  if (const YAML::Node map = root["map"]) {
    RequireOnlyKeys(map, {"procedural_seed", "blocks_north", "blocks_east", "buildings", "sites", "origin",
                          "height_from_levels", "metres_per_level", "skip_missing_height", "height_from_type",
                          "default_height_m", "sites_from_map"},
                    source, "map");
    ReadImportedMap(map, source, config.map);
    config.map.blocks_north =
        static_cast<int>(ReadInteger(map, "blocks_north", config.map.blocks_north, bounds::kBlocks, source, "map"));
    config.map.blocks_east =
        static_cast<int>(ReadInteger(map, "blocks_east", config.map.blocks_east, bounds::kBlocks, source, "map"));
    if (map["procedural_seed"]) config.map.procedural_seed = ReadSeed(map, "procedural_seed", source, "map");
  }
  if (root["name"]) config.name = RequireString(root, "name", source, "");
  if (root["seed"]) config.seed = ReadSeed(root, "seed", source, "");
  config.runs = ReadInteger(root, "runs", config.runs, bounds::kRuns, source, "");
  if (root["policies"]) config.policies = ReadStringList(root, "policies", source, "");
  ReadMission(root, source, config.mission);
  config.safety_margin_s = ReadRange(root, "safety_margin_s", config.safety_margin_s, source, "");
  ReadBattery(root, source, config.battery);
  ReadWind(root, source, config.wind);
  ReadFault(root, source, config.fault);
  if (const YAML::Node options = root["options"]) {
    RequireOnlyKeys(options, {"eod_load", "cap_speed_after_isolation"}, source, "options");
    if (options["eod_load"]) {
      config.options.eod_load =
          sim::ParseEodLoad(RequireString(options, "eod_load", source, "options"), source, "options.eod_load");
    }
    config.options.cap_speed_after_isolation = OptionalBool(
        options, "cap_speed_after_isolation", config.options.cap_speed_after_isolation, source, "options");
  }
  std::string error;
  if (!config.IsValid(&error)) {
    const auto colon = error.find(": ");
    throw InputError(source, error.substr(0, colon), colon == std::string::npos ? "valid" : error.substr(colon + 2));
  }
  return config;
}

CampaignConfig LoadCampaignConfig(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(path.string(), "file", "an existing campaign YAML file");
  }
  CampaignConfig config = ParseCampaignConfig(ReadFile(path), path.string());
  // Map files are relative to the campaign file; kept absolute so that the stored configuration replays anywhere.
  auto resolve = [&](std::string& file) {
    if (!file.empty()) file = std::filesystem::absolute(path.parent_path() / file).lexically_normal().string();
  };
  for (std::string& file : config.map.buildings) resolve(file);
  resolve(config.map.sites);
  return config;
}

std::string CampaignConfigYaml(const CampaignConfig& c) {
  std::string out;
  out += fmt::format("name: \"{}\"\n", c.name);
  out += fmt::format("seed: {}\n", c.seed);
  out += fmt::format("runs: {}\n", c.runs);
  out += "policies: [";
  for (std::size_t i = 0; i < c.policies.size(); ++i) out += (i ? ", \"" : "\"") + c.policies[i] + "\"";
  out += "]\n";
  out += "map:\n";
  // An imported map has no procedural seed (the two exclude each other): it keeps the default, unwritten.
  if (!c.map.imported()) out += "  procedural_seed: " + std::to_string(c.map.procedural_seed) + "\n";
  out += "  blocks_north: " + std::to_string(c.map.blocks_north) + "\n";
  out += "  blocks_east: " + std::to_string(c.map.blocks_east) + "\n";
  if (c.map.imported()) {
    out += "  buildings: [";
    for (std::size_t i = 0; i < c.map.buildings.size(); ++i) out += (i ? ", \"" : "\"") + c.map.buildings[i] + "\"";
    out += "]\n";
    if (!c.map.sites.empty()) out += "  sites: \"" + c.map.sites + "\"\n";
    if (c.map.origin_deg) {
      out += "  origin: [" + Number((*c.map.origin_deg)[0]) + ", " + Number((*c.map.origin_deg)[1]) + "]\n";
    }
    out += fmt::format("  height_from_levels: {}\n", c.map.height_from_levels);
    out += "  metres_per_level: " + Number(c.map.metres_per_level) + "\n";
    out += fmt::format("  skip_missing_height: {}\n", c.map.skip_missing_height);
    if (c.map.height_from_type) out += "  height_from_type: true\n";
    if (c.map.default_height_m) out += "  default_height_m: " + Number(*c.map.default_height_m) + "\n";
    if (c.map.sites_from_map) out += fmt::format("  sites_from_map: {}\n", *c.map.sites_from_map);
  }
  out += "mission:\n";
  out += "  endurance_fraction: " + RangeYaml(c.mission.endurance_fraction) + "\n";
  out += "  distance_m: " + (c.mission.distance_m ? RangeYaml(*c.mission.distance_m) : std::string("null")) + "\n";
  out += "  wall_clearance_m: " + Number(c.mission.wall_clearance_m) + "\n";
  out += "  cruise_speed_mps: " + RangeYaml(c.mission.cruise_speed_mps) + "\n";
  out += "  cruise_altitude_m: " + Number(c.mission.cruise_altitude_m) + "\n";
  out += "  drop_hover_s: " + Number(c.mission.drop_hover_s) + "\n";
  out += "safety_margin_s: " + RangeYaml(c.safety_margin_s) + "\n";
  out += "battery:\n";
  out += "  initial_cell_voltage_v: " + RangeYaml(c.battery.initial_cell_voltage_v) + "\n";
  out += fmt::format("  health_weights: {{G: {}, M: {}, P: {}}}\n", c.battery.health_weights[0],
                     c.battery.health_weights[1], c.battery.health_weights[2]);
  out += fmt::format("  degraded_cells: [{}, {}]\n", c.battery.degraded_cells.low, c.battery.degraded_cells.high);
  out += fmt::format("  medium_fades: {}\n", MediumFadesName(c.battery.medium_fades));
  out += "  cold_probability: " + Number(c.battery.cold_probability) + "\n";
  out += "  cold_temp_degf: " + Number(c.battery.cold_temp_degf) + "\n";
  out += "  warm_temp_degf: " + Number(c.battery.warm_temp_degf) + "\n";
  out += "wind:\n";
  out += "  speed_mps: " + RangeYaml(c.wind.speed_mps) + "\n";
  out += "  direction_rad: " + RangeYaml(c.wind.direction_rad) + "\n";
  out += "  turbulence: [";
  for (std::size_t i = 0; i < c.wind.turbulence.size(); ++i) {
    out += (i ? ", " : "") + std::string(models::TurbulenceCategoryName(c.wind.turbulence[i]));
  }
  out += "]\n";
  out += "fault:\n";
  out += "  probability: " + Number(c.fault.probability) + "\n";
  out += "  onset_fraction: " + RangeYaml(c.fault.onset_fraction) + "\n";
  out += "  motors: [";
  for (std::size_t i = 0; i < c.fault.motors.size(); ++i) out += fmt::format("{}{}", i ? ", " : "", c.fault.motors[i]);
  out += "]\n";
  out += "  time_per_growth_step_s: " +
         (c.fault.time_per_growth_step_s ? Number(*c.fault.time_per_growth_step_s) : std::string("null")) + "\n";
  out += "options:\n";
  out += fmt::format("  eod_load: {}\n", sim::EodLoadName(c.options.eod_load));
  out += fmt::format("  cap_speed_after_isolation: {}\n", c.options.cap_speed_after_isolation);
  return out;
}

std::string CampaignConfigHash(const CampaignConfig& c) {
  Fingerprint f;
  f.Add(std::string_view("uascma-campaign/1"));
  f.Add(c.seed);
  auto add_range = [&f](const Range& r) {
    f.Add(r.low);
    f.Add(r.high);
  };
  f.Add(c.map.procedural_seed);
  f.Add(c.map.blocks_north);
  f.Add(c.map.blocks_east);
  if (c.map.imported()) {  // absent from older configurations' fingerprints, which stay as they were
    for (const std::string& file : c.map.buildings) f.Add(std::string_view(file));
    f.Add(std::string_view(c.map.sites));
    f.Add(c.map.origin_deg ? (*c.map.origin_deg)[0] : 1000.0);  // 1000: no origin (outside the latitudes)
    f.Add(c.map.origin_deg ? (*c.map.origin_deg)[1] : 1000.0);
    f.Add(c.map.height_from_levels ? 1 : 0);
    f.Add(c.map.metres_per_level);
    f.Add(c.map.skip_missing_height ? 1 : 0);
    // Later keys, each only when it changes the import (config.h): older fingerprints stay as they were.
    if (c.map.height_from_type) f.Add(std::string_view("height_from_type"));
    if (c.map.default_height_m) {
      f.Add(std::string_view("default_height_m"));
      f.Add(*c.map.default_height_m);
    }
    if (c.map.DerivesSites() != c.map.sites.empty()) {
      f.Add(std::string_view("sites_from_map"));
      f.Add(c.map.DerivesSites() ? 1 : 0);
    }
  }
  f.Add(std::string_view("mission/2"));  // the endurance-tied plan of decisions item 19
  add_range(c.mission.endurance_fraction);
  f.Add(c.mission.distance_m ? 1 : 0);
  if (c.mission.distance_m) add_range(*c.mission.distance_m);
  f.Add(c.mission.wall_clearance_m);
  add_range(c.mission.cruise_speed_mps);
  f.Add(c.mission.cruise_altitude_m);
  f.Add(c.mission.drop_hover_s);
  add_range(c.safety_margin_s);
  add_range(c.battery.initial_cell_voltage_v);
  f.Add(std::string_view("battery/2"));  // BH drawn per flight, decisions item 20
  for (double w : c.battery.health_weights) f.Add(w);
  f.Add(c.battery.degraded_cells.low);
  f.Add(c.battery.degraded_cells.high);
  f.Add(std::string_view(MediumFadesName(c.battery.medium_fades)));
  f.Add(c.battery.cold_probability);
  f.Add(c.battery.cold_temp_degf);
  f.Add(c.battery.warm_temp_degf);
  add_range(c.wind.speed_mps);
  add_range(c.wind.direction_rad);
  f.Add(static_cast<std::uint64_t>(c.wind.turbulence.size()));
  for (auto category : c.wind.turbulence) f.Add(static_cast<int>(category));
  f.Add(c.fault.probability);
  add_range(c.fault.onset_fraction);
  f.Add(static_cast<std::uint64_t>(c.fault.motors.size()));
  for (int motor : c.fault.motors) f.Add(motor);
  f.Add(c.fault.time_per_growth_step_s ? *c.fault.time_per_growth_step_s : -1.0);
  f.Add(std::string_view("options/1"));  // decision 25's load and §4.4.2's speed cap
  f.Add(std::string_view(sim::EodLoadName(c.options.eod_load)));
  f.Add(c.options.cap_speed_after_isolation ? 1 : 0);
  return f.Hex();
}

}  // namespace uascma::campaign
