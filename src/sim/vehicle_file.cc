// Vehicle files (see vehicle_file.h).
#include "uascma/sim/vehicle_file.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <array>
#include <string>
#include <utility>

#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/common/hash.h"
#include "uascma/common/yaml_io.h"
#include "uascma/identification/model_files.h"
#include "uascma/sim/scenario.h"
#include "uascma/sim/scenario_bounds.h"

namespace uascma::sim {
namespace {

double BoundedNumber(const YAML::Node& node, const std::string& key, const Bounds& bounds, const std::string& source,
                     const std::string& section) {
  const double value = RequireNumber(node, key, source, section);
  if (!bounds.Contains(value)) {
    throw InputError(source, section.empty() ? key : section + "." + key,
                     fmt::format("from {:g} to {:g} {}, got {:g}", bounds.low, bounds.high, bounds.unit, value));
  }
  return value;
}

// The file a key names, relative to the vehicle file; InputError naming the vehicle file and the key when it is absent.
std::filesystem::path NamedFile(const YAML::Node& node, const std::string& key, const std::filesystem::path& file,
                                const std::string& section, const char* what) {
  const std::string name = RequireString(node, key, file.string(), section);
  const std::filesystem::path path =
      std::filesystem::path(name).is_absolute() ? std::filesystem::path(name) : file.parent_path() / name;
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) {
    throw InputError(file.string(), section.empty() ? key : section + "." + key,
                     fmt::format("an existing {} file, got '{}'", what, path.string()));
  }
  return path;
}

// rotor_directions: six "cw" / "ccw", alternating (the mixer's geometry, models/mixer.h): whether rotor 1 is "cw".
bool ReadRotorDirections(const YAML::Node& root, const std::string& source) {
  const YAML::Node list = root["rotor_directions"];
  constexpr const char* kExpected = "six of cw | ccw, alternating (rotors 1…6 of Fig. 4.12, seen from above)";
  if (!list.IsSequence() || list.size() != 6) throw InputError(source, "rotor_directions", kExpected);
  std::array<bool, 6> clockwise{};
  for (std::size_t k = 0; k < 6; ++k) {
    const std::string text = list[k].IsScalar() ? list[k].Scalar() : "";
    if (text != "cw" && text != "ccw") throw InputError(source, fmt::format("rotor_directions[{}]", k), kExpected);
    clockwise[k] = text == "cw";
  }
  for (std::size_t k = 1; k < 6; ++k) {
    if (clockwise[k] == clockwise[k - 1]) {
      throw InputError(source, fmt::format("rotor_directions[{}]", k),
                       fmt::format("{} (the spins alternate, §2.4, eq. 4.11)", clockwise[k - 1] ? "ccw" : "cw"));
    }
  }
  return clockwise[0];
}

// PROP.json to the simulator's rotor: C_T, C_Q (Table 2.1's when absent), eq. 2.12's surface term by term, T_max,
// the power law (docs/modelling-choices.md#vehicle-file).
void ReadPropulsion(const std::filesystem::path& path, Vehicle& vehicle) {
  const identification::PropulsionModel model = identification::ReadPropulsionModelFile(path);
  models::PropulsionParams& p = vehicle.propulsion;
  p.thrust_coefficient_n_per_rpm2 = model.thrust_coefficient_n_per_rpm2;
  if (model.torque_coefficient_nm_per_rpm2) {
    p.torque_coefficient_nm_per_rpm2 = *model.torque_coefficient_nm_per_rpm2;
  } else {
    vehicle.defaulted.push_back("propulsion C_Q (no torque measured)");
  }
  if (model.max_thrust_n) {
    p.max_thrust = *model.max_thrust_n;
  } else {
    vehicle.defaulted.push_back("propulsion max thrust");
  }
  if (model.power_law_w_at_one_newton && model.power_law_exponent) {
    p.electrical_power = {*model.power_law_w_at_one_newton, *model.power_law_exponent};
  } else {
    vehicle.defaulted.push_back("propulsion power law");
  }
  const identification::RpmSurface& s = model.surface;
  models::RpmEstimatorParams rpm;
  for (double* c : {&rpm.p00, &rpm.p10, &rpm.p01, &rpm.p20, &rpm.p11, &rpm.p02, &rpm.p30, &rpm.p21, &rpm.p12}) *c = 0.0;
  for (std::size_t t = 0; t < s.terms.size(); ++t) {
    const std::string name = identification::TermName(s.terms[t]);
    double* slot = name == "p00"   ? &rpm.p00
                   : name == "p10" ? &rpm.p10
                   : name == "p01" ? &rpm.p01
                   : name == "p20" ? &rpm.p20
                   : name == "p11" ? &rpm.p11
                   : name == "p02" ? &rpm.p02
                   : name == "p30" ? &rpm.p30
                   : name == "p21" ? &rpm.p21
                   : name == "p12" ? &rpm.p12
                                   : nullptr;
    if (slot == nullptr) throw InputError(path.string(), "surface.coefficients_rpm", "eq. 2.12's terms");
    *slot = s.coefficients[static_cast<Eigen::Index>(t)];
  }
  rpm.throttle_mean_us = s.throttle_mean_us;
  rpm.throttle_std_us = s.throttle_std_us;
  rpm.power_mean = s.power_mean_w;
  rpm.power_std = s.power_std_w;
  rpm.min_throttle_us = s.min_throttle_us;
  rpm.max_throttle_us = s.max_throttle_us;
  p.rpm_estimator = rpm;
  std::string error;
  if (!p.IsValid(&error)) throw InputError(path.string(), "propulsion", error);
}

void ReadVehicleBattery(const YAML::Node& node, const std::filesystem::path& file, Vehicle& vehicle,
                        Fingerprint& hash) {
  const std::string source = file.string();
  if (!node.IsMap()) throw InputError(source, "battery", "a mapping of cell, cells_in_series, cells_in_parallel");
  RequireOnlyKeys(node, {"cell", "cells_in_series", "cells_in_parallel"}, source, "battery");
  if (node["cell"]) {
    const std::filesystem::path cell = NamedFile(node, "cell", file, "battery", "CELL.json");
    hash.Add(ReadFile(cell));
    vehicle.cell = identification::ReadCellModelFile(cell);
  } else {
    vehicle.defaulted.push_back("battery.cell");
  }
  if (node["cells_in_series"]) {
    const double series = RequireNumber(node, "cells_in_series", source, "battery");
    if (series != models::kCellsPerBranch) {
      throw InputError(source, "battery.cells_in_series",
                       fmt::format("{} (each of the two packs of Fig. 4.1 is 3S; other counts are not modelled), got "
                                   "{:g}",
                                   models::kCellsPerBranch, series));
    }
  }
  if (node["cells_in_parallel"]) {
    const double parallel = BoundedNumber(node, "cells_in_parallel", kCellsInParallelBounds, source, "battery");
    if (parallel != static_cast<int>(parallel)) throw InputError(source, "battery.cells_in_parallel", "a whole number");
    vehicle.cells_in_parallel = static_cast<int>(parallel);
  }
}

// The keys of the body and the frame: mass, inertia, arm length, rotor directions.
void ReadAirframe(const YAML::Node& root, const std::string& source, Vehicle& vehicle) {
  if (root["mass_kg"]) {
    vehicle.body.mass = BoundedNumber(root, "mass_kg", scenario_bounds::kMass, source, "");
  } else {
    vehicle.defaulted.push_back("mass_kg");
  }
  if (root["inertia_kg_m2"]) {
    const std::vector<double> inertia = RequireNumberList(root, "inertia_kg_m2", 3, source, "");
    for (std::size_t k = 0; k < 3; ++k) {
      if (!scenario_bounds::kInertia.Contains(inertia[k])) {
        throw InputError(source, fmt::format("inertia_kg_m2[{}]", k),
                         fmt::format("from {:g} to {:g} kg m^2, got {:g}", scenario_bounds::kInertia.low,
                                     scenario_bounds::kInertia.high, inertia[k]));
      }
    }
    vehicle.body.inertia_diagonal = Eigen::Vector3d(inertia[0], inertia[1], inertia[2]);
  } else {
    vehicle.defaulted.push_back("inertia_kg_m2");
  }
  std::string error;
  if (!vehicle.body.IsValid(&error)) throw InputError(source, "inertia_kg_m2", error);
  if (root["arm_length_m"]) {
    vehicle.mixer.arm_length = BoundedNumber(root, "arm_length_m", kArmLengthBounds, source, "");
  } else {
    vehicle.defaulted.push_back("arm_length_m");
  }
  if (root["rotor_directions"]) {
    vehicle.mixer.rotor1_clockwise = ReadRotorDirections(root, source);
  } else {
    vehicle.defaulted.push_back("rotor_directions");
  }
}

}  // namespace

std::string Vehicle::DefaultedLine() const {
  if (defaulted.empty()) return "";
  std::string parts;
  for (const std::string& part : defaulted) parts += (parts.empty() ? "" : ", ") + part;
  return fmt::format("vehicle {}: kept the dissertation's {} ({} propellers; docs/identification.md#vehicle-file)",
                     source, parts, models::PropellerConfigurationName(configuration));
}

models::CellParams ParallelCell(const models::CellParams& cell, int parallel) {
  UASCMA_CHECK(parallel >= 1, "at least one cell in parallel");
  models::CellParams out = cell;
  out.capacity_ah *= parallel;
  out.r0_ohm /= parallel;
  for (int j = 0; j < out.rc_pair_count; ++j) {
    out.rc[j].resistance_ohm /= parallel;
    out.rc[j].capacitance_f *= parallel;
  }
  return out;
}

std::shared_ptr<const Vehicle> LoadVehicleFile(const std::filesystem::path& path) {
  const std::string source = path.string();
  const std::string text = ReadFile(path);
  const YAML::Node root = ParseYamlText(text, source);
  if (!root.IsMap()) throw InputError(source, "(top level)", "a YAML mapping (docs/identification.md#vehicle-file)");
  RequireOnlyKeys(root,
                  {"name", "configuration", "mass_kg", "inertia_kg_m2", "arm_length_m", "rotor_directions", "battery",
                   "propulsion", "drag"},
                  source, "");
  auto vehicle = std::make_shared<Vehicle>();
  vehicle->source = source;
  vehicle->name = root["name"] ? RequireString(root, "name", source, "") : path.stem().string();
  Fingerprint hash;
  hash.Add(std::string_view("uascma-vehicle/1"));
  hash.Add(text);
  if (root["configuration"]) {
    vehicle->configuration = models::ParsePropellerConfiguration(RequireString(root, "configuration", source, ""),
                                                                 source + ": configuration");
  }
  vehicle->propulsion = models::PropulsionParams::ForConfiguration(vehicle->configuration);
  ReadAirframe(root, source, *vehicle);
  if (root["battery"]) {
    ReadVehicleBattery(root["battery"], path, *vehicle, hash);
  } else {
    vehicle->defaulted.push_back("battery");
  }
  if (root["propulsion"]) {
    const std::filesystem::path prop = NamedFile(root, "propulsion", path, "", "PROP.json");
    hash.Add(ReadFile(prop));
    ReadPropulsion(prop, *vehicle);
  } else {
    vehicle->defaulted.push_back("propulsion");
  }
  const double arm_length = vehicle->mixer.arm_length;
  const bool clockwise = vehicle->mixer.rotor1_clockwise;
  vehicle->mixer = models::MixerParams::ForPropulsion(vehicle->propulsion);
  vehicle->mixer.arm_length = arm_length;
  vehicle->mixer.rotor1_clockwise = clockwise;
  if (root["drag"]) {
    const std::filesystem::path drag = NamedFile(root, "drag", path, "", "drag table (CSV)");
    hash.Add(ReadFile(drag));
    vehicle->drag = models::DragTable::FromCsv(drag);
  } else {
    vehicle->defaulted.push_back("drag");
  }
  vehicle->content_hash = hash.Hex();
  return vehicle;
}

models::PropulsionParams ScenarioPropulsion(const Scenario& scenario) {
  return scenario.vehicle ? scenario.vehicle->propulsion
                          : models::PropulsionParams::ForConfiguration(scenario.configuration);
}

models::MixerParams ScenarioMixer(const Scenario& scenario) {
  return scenario.vehicle ? scenario.vehicle->mixer : models::MixerParams::ForPropulsion(ScenarioPropulsion(scenario));
}

models::DragTable ScenarioDrag(const Scenario& scenario) {
  if (scenario.vehicle && scenario.vehicle->drag) return *scenario.vehicle->drag;
  return models::DragTable::Default(scenario.configuration);
}

models::PackParams ScenarioPackParams(const Scenario& scenario, const models::PerCell<models::CellHealth>& health,
                                      double ambient_temp_degf) {
  if (!scenario.vehicle || !scenario.vehicle->cell) {
    models::PackParams params = models::MakePackParams(health, ambient_temp_degf);
    if (scenario.vehicle && scenario.vehicle->cells_in_parallel > 1) {
      for (auto& branch : params.cells) {
        for (auto& cell : branch) cell = ParallelCell(cell, scenario.vehicle->cells_in_parallel);
      }
    }
    return params;
  }
  const models::SelfCorrectingCell& cell = *scenario.vehicle->cell;
  const models::SelfCorrectingCell parallel(ParallelCell(cell.params(), scenario.vehicle->cells_in_parallel),
                                            cell.ocv(), scenario.vehicle->source);
  return identification::MakeIdentifiedPackParams(parallel, health, ambient_temp_degf);
}

void UseVehicle(Scenario& scenario, std::shared_ptr<const Vehicle> vehicle) {
  if (vehicle) {
    scenario.body = vehicle->body;
    scenario.configuration = vehicle->configuration;
  }
  scenario.vehicle = std::move(vehicle);
}

}  // namespace uascma::sim
