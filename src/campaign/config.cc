#include "uascma/campaign/config.h"

#include <cmath>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/common/hash.h"
#include "uascma/common/yaml_io.h"

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

std::int64_t ReadInteger(const YAML::Node& node, const std::string& key, std::int64_t fallback,
                         const std::string& source, const std::string& where) {
  if (!node[key]) return fallback;
  const double value = RequireNumber(node, key, source, where);
  if (value != std::floor(value) || std::abs(value) > 9.0e15) {
    throw InputError(source, Join(where, key), fmt::format("an integer, got {}", value));
  }
  return static_cast<std::int64_t>(value);
}

std::uint64_t ReadSeed(const YAML::Node& node, const std::string& source) {
  const YAML::Node value = node["seed"];
  if (!value.IsScalar()) throw InputError(source, "seed", "a non-negative integer");
  try {
    return value.as<std::uint64_t>();
  } catch (const YAML::Exception&) {
    throw InputError(source, "seed", "a non-negative integer, got '" + value.Scalar() + "'");
  }
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
  RequireOnlyKeys(node, {"distance_m", "cruise_speed_mps", "cruise_altitude_m", "drop_hover_s"}, source, "mission");
  m.distance_m = ReadRange(node, "distance_m", m.distance_m, source, "mission");
  m.cruise_speed_mps = ReadRange(node, "cruise_speed_mps", m.cruise_speed_mps, source, "mission");
  m.cruise_altitude_m = OptionalNumber(node, "cruise_altitude_m", m.cruise_altitude_m, source, "mission");
  m.drop_hover_s = OptionalNumber(node, "drop_hover_s", m.drop_hover_s, source, "mission");
}

void ReadBattery(const YAML::Node& root, const std::string& source, BatterySampling& b) {
  const YAML::Node node = OptionalMap(root, "battery", source, "");
  RequireOnlyKeys(node, {"initial_cell_voltage_v", "pack_health_weights", "degraded_cells_per_pack",
                         "cold_probability", "cold_temp_degf", "warm_temp_degf"},
                  source, "battery");
  b.initial_cell_voltage_v = ReadRange(node, "initial_cell_voltage_v", b.initial_cell_voltage_v, source, "battery");
  if (node["pack_health_weights"]) {
    const YAML::Node weights = RequireMap(node, "pack_health_weights", source, "battery");
    RequireOnlyKeys(weights, {"F1", "F2", "F3"}, source, "battery.pack_health_weights");
    const char* names[] = {"F1", "F2", "F3"};
    for (int i = 0; i < 3; ++i) {
      b.pack_health_weights[i] =
          OptionalNumber(weights, names[i], b.pack_health_weights[i], source, "battery.pack_health_weights");
    }
  }
  b.degraded_cells_per_pack = static_cast<int>(
      ReadInteger(node, "degraded_cells_per_pack", b.degraded_cells_per_pack, source, "battery"));
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
      int motor = 0;
      try {
        motor = motors[i].as<int>();
      } catch (const YAML::Exception&) {
        throw InputError(source, field, "a motor number 1..6");
      }
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

bool CampaignConfig::IsValid(std::string* error) const {
  auto fail = [error](std::string message) {
    if (error) *error = std::move(message);
    return false;
  };
  auto check_range = [&](const Range& r, const char* field, double min, double max) {
    if (!(std::isfinite(r.low) && std::isfinite(r.high) && r.low <= r.high && r.low >= min && r.high <= max)) {
      if (error) *error = fmt::format("{}: expected [low, high] with {} <= low <= high <= {}, got [{}, {}]", field, min,
                                      max, r.low, r.high);
      return false;
    }
    return true;
  };
  constexpr double kHuge = 1e9;
  auto plain = [](const std::string& text) {
    return text.find_first_of("\"\\\n\r") == std::string::npos;
  };
  if (!plain(name)) return fail("name: expected a label without quotes, backslashes or line breaks");
  if (runs < 0) return fail(fmt::format("runs: expected >= 0, got {}", runs));
  if (policies.empty()) return fail("policies: expected at least one policy");
  for (const auto& policy : policies) {
    if (policy.empty() || !plain(policy)) return fail("policies: expected names or paths without quotes");
  }
  if (!check_range(mission.distance_m, "mission.distance_m", 1.0, 1e6)) return false;
  if (!check_range(mission.cruise_speed_mps, "mission.cruise_speed_mps", 0.1, 30.0)) return false;
  if (!(mission.cruise_altitude_m > 0.0 && mission.cruise_altitude_m < 1e4)) {
    return fail("mission.cruise_altitude_m: expected a positive altitude in m");
  }
  if (!(mission.drop_hover_s >= 0.0 && mission.drop_hover_s < kHuge)) {
    return fail("mission.drop_hover_s: expected a non-negative time in s");
  }
  if (!check_range(safety_margin_s, "safety_margin_s", 0.0, kHuge)) return false;
  // The default OCV table spans 3.27–4.20 V (defaults.md); the cut-off is 3.3 V.
  if (!check_range(battery.initial_cell_voltage_v, "battery.initial_cell_voltage_v", 3.3, 4.2)) return false;
  double weight_sum = 0.0;
  for (double w : battery.pack_health_weights) {
    if (!(w >= 0.0 && std::isfinite(w))) return fail("battery.pack_health_weights: expected non-negative numbers");
    weight_sum += w;
  }
  if (battery.pack_health_weights.size() != 3 || !(weight_sum > 0.0)) {
    return fail("battery.pack_health_weights: expected F1, F2, F3 with a positive sum");
  }
  if (battery.degraded_cells_per_pack < 1 || battery.degraded_cells_per_pack > 3) {
    return fail(fmt::format("battery.degraded_cells_per_pack: expected 1..3, got {}", battery.degraded_cells_per_pack));
  }
  if (!(battery.cold_probability >= 0.0 && battery.cold_probability <= 1.0)) {
    return fail("battery.cold_probability: expected a probability in [0, 1]");
  }
  if (!(battery.cold_temp_degf < 50.0 && battery.cold_temp_degf > -100.0)) {
    return fail(fmt::format("battery.cold_temp_degf: expected below 50 F (Table 3.2), got {}", battery.cold_temp_degf));
  }
  if (!(battery.warm_temp_degf >= 50.0 && battery.warm_temp_degf < 200.0)) {
    return fail(fmt::format("battery.warm_temp_degf: expected 50 F or above (Table 3.2), got {}", battery.warm_temp_degf));
  }
  if (!check_range(wind.speed_mps, "wind.speed_mps", 0.0, 50.0)) return false;
  if (!check_range(wind.direction_rad, "wind.direction_rad", -4.0 * kPi, 4.0 * kPi)) return false;
  if (wind.turbulence.empty()) return fail("wind.turbulence: expected at least one category");
  if (!(fault.probability >= 0.0 && fault.probability <= 1.0)) {
    return fail("fault.probability: expected a probability in [0, 1]");
  }
  if (!check_range(fault.onset_fraction, "fault.onset_fraction", 0.0, 1.0)) return false;
  if (fault.motors.empty()) return fail("fault.motors: expected at least one motor");
  for (int motor : fault.motors) {
    if (motor < 1 || motor > 6) return fail(fmt::format("fault.motors: expected motors 1..6, got {}", motor));
  }
  if (fault.time_per_growth_step_s && !(*fault.time_per_growth_step_s > 0.0 && *fault.time_per_growth_step_s < kHuge)) {
    return fail("fault.time_per_growth_step_s: expected a positive time in s (or null for the default)");
  }
  return true;
}

CampaignConfig ParseCampaignConfig(const std::string& yaml_text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw InputError(source, "line " + std::to_string(e.mark.line + 1), "valid YAML (" + e.msg + ")");
  }
  CampaignConfig config;
  if (root.IsNull()) return config;  // an empty file: every default
  if (!root.IsMap()) throw InputError(source, "(top level)", "a YAML mapping");
  RequireOnlyKeys(root, {"name", "seed", "runs", "policies", "map", "mission", "safety_margin_s", "battery", "wind",
                         "fault"},
                  source, "");
  if (const YAML::Node map = root["map"]) {
    RequireOnlyKeys(map, {"procedural_seed", "blocks_north", "blocks_east"}, source, "map");
    config.map.blocks_north = static_cast<int>(OptionalNumber(map, "blocks_north", config.map.blocks_north, source, "map"));
    config.map.blocks_east = static_cast<int>(OptionalNumber(map, "blocks_east", config.map.blocks_east, source, "map"));
    if (config.map.blocks_north < 1 || config.map.blocks_east < 1 || config.map.blocks_north > 200 ||
        config.map.blocks_east > 200) {
      throw InputError(source, "map.blocks_north/blocks_east", "between 1 and 200 blocks");
    }
    const double seed = OptionalNumber(map, "procedural_seed", 3.0, source, "map");
    if (seed < 0 || seed != std::floor(seed) || seed > 9007199254740992.0) {
      throw InputError(source, "map.procedural_seed", "a non-negative integer (0: no city)");
    }
    config.map.procedural_seed = static_cast<std::uint64_t>(seed);
  }
  if (root["name"]) config.name = RequireString(root, "name", source, "");
  if (root["seed"]) config.seed = ReadSeed(root, source);
  config.runs = ReadInteger(root, "runs", config.runs, source, "");
  if (root["policies"]) config.policies = ReadStringList(root, "policies", source, "");
  ReadMission(root, source, config.mission);
  config.safety_margin_s = ReadRange(root, "safety_margin_s", config.safety_margin_s, source, "");
  ReadBattery(root, source, config.battery);
  ReadWind(root, source, config.wind);
  ReadFault(root, source, config.fault);
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
  return ParseCampaignConfig(ReadFile(path), path.string());
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
  out += "  procedural_seed: " + std::to_string(c.map.procedural_seed) + "\n";
  out += "  blocks_north: " + std::to_string(c.map.blocks_north) + "\n";
  out += "  blocks_east: " + std::to_string(c.map.blocks_east) + "\n";
  out += "mission:\n";
  out += "  distance_m: " + RangeYaml(c.mission.distance_m) + "\n";
  out += "  cruise_speed_mps: " + RangeYaml(c.mission.cruise_speed_mps) + "\n";
  out += "  cruise_altitude_m: " + Number(c.mission.cruise_altitude_m) + "\n";
  out += "  drop_hover_s: " + Number(c.mission.drop_hover_s) + "\n";
  out += "safety_margin_s: " + RangeYaml(c.safety_margin_s) + "\n";
  out += "battery:\n";
  out += "  initial_cell_voltage_v: " + RangeYaml(c.battery.initial_cell_voltage_v) + "\n";
  out += fmt::format("  pack_health_weights: {{F1: {}, F2: {}, F3: {}}}\n", c.battery.pack_health_weights[0],
                     c.battery.pack_health_weights[1], c.battery.pack_health_weights[2]);
  out += fmt::format("  degraded_cells_per_pack: {}\n", c.battery.degraded_cells_per_pack);
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
  add_range(c.mission.distance_m);
  add_range(c.mission.cruise_speed_mps);
  f.Add(c.mission.cruise_altitude_m);
  f.Add(c.mission.drop_hover_s);
  add_range(c.safety_margin_s);
  add_range(c.battery.initial_cell_voltage_v);
  for (double w : c.battery.pack_health_weights) f.Add(w);
  f.Add(c.battery.degraded_cells_per_pack);
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
  return f.Hex();
}

}  // namespace uascma::campaign
