#pragma once
// A vehicle file (YAML): the user's own hexacopter for the simulator, the CMA loop and campaigns
// (docs/identification.md#vehicle-file). Every key is optional; a part left out keeps the dissertation's value
// (docs/defaults.md#vehicle, Tables 2.1, 2.2, 3.1) and the loader lists it in Vehicle::defaulted, which the tool
// prints as one line.
//
//   name: strawson-g8-hex
//   configuration: tractor            # the dissertation's parts the file leaves out: tractor | pusher (§2.5)
//   mass_kg: 1.0
//   inertia_kg_m2: [0.011, 0.011, 0.021]
//   arm_length_m: 0.225
//   rotor_directions: [cw, ccw, cw, ccw, cw, ccw]   # rotors 1…6 of models/mixer.h, seen from above
//   battery:
//     cell: cell.json                 # `uascma identify battery --out` (CELL.json), relative to this file
//     cells_in_series: 3              # per pack; the model's packs are 3S (Fig. 4.1): 3 only
//     cells_in_parallel: 2            # identical cells in parallel act as one cell of P Q, R0 / P, R_j / P, P C_j
//   propulsion: prop.json             # `uascma identify propulsion --out` (PROP.json)
//   drag: drag.csv                    # the drag table of models/drag.h (DragTable::FromCsv)
//
// What each part sets, and what it derives (docs/modelling-choices.md#vehicle-file):
//   propulsion  C_T (eq. 2.1), C_Q (eq. 2.2; Table 2.1's when the file has none), eq. 2.12's surface, T_max (the
//               largest thrust measured on the stand) and the power law P = k T^b (fitted to the stand's points);
//               the rotor lag keeps docs/defaults.md#vehicle's 0.03 s.
//   arm length, rotor directions, C_Q / C_T and T_max make the mixer (eq. 4.11 built from the geometry), so the
//               allocation, the reconfiguration after a jam and the authority square (§4.4.2) are this vehicle's;
//               mass and inertia make the LQR's hover linearisation (§4.4), its gains recomputed.
//   the cell    builds both packs of Fig. 4.1 (models::PackParams) that the simulator flies and the CMA's EOD
//               prognosis (§3.3.2.1) reads.
// The content hash covers the file's bytes and every file it names, so a campaign's fingerprint changes when any
// of them does.
#include <Eigen/Core>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "uascma/common/bounds.h"
#include "uascma/models/battery_cell.h"
#include "uascma/models/battery_pack.h"
#include "uascma/models/drag.h"
#include "uascma/models/mixer.h"
#include "uascma/models/propulsion.h"
#include "uascma/models/rigid_body.h"

namespace uascma::sim {

struct Scenario;

// Plausibility bounds of the vehicle file's own numbers (ours): an arm of a 100 mm micro frame to a 2 m heavy lift
// frame; 1 to 16 cells in parallel.
inline constexpr Bounds kArmLengthBounds{0.03, 1.0, "m"};
inline constexpr Bounds kCellsInParallelBounds{1.0, 16.0, "cells"};

struct Vehicle {
  std::string name;
  std::string source;        // the file
  std::string content_hash;  // 16 hex digits over the file and the files it names
  models::PropellerConfiguration configuration = models::PropellerConfiguration::kTractor;
  models::RigidBodyParams body;
  models::PropulsionParams propulsion;
  models::MixerParams mixer;
  // The identified cell (every cell of both packs, before the parallel scaling); none: Table 3.1's cells 1-3.
  std::optional<models::SelfCorrectingCell> cell;
  int cells_in_parallel = 1;
  std::optional<models::DragTable> drag;  // none: DragTable::Default(configuration)
  std::vector<std::string> defaulted;     // the parts kept at the dissertation's values, named as the file's keys
  // "vehicle FILE: kept the dissertation's mass_kg, inertia_kg_m2 (…)" or "" when nothing was defaulted.
  std::string DefaultedLine() const;
};

// Reads a vehicle file and the files it names; InputError naming the file and the key for anything missing or
// implausible (nothing is flown or written then).
std::shared_ptr<const Vehicle> LoadVehicleFile(const std::filesystem::path& path);

// The cell of `parallel` identical cells in parallel: Q × P, R0 / P, R_j / P, C_j × P (the same terminal voltage
// at P times the current; hysteresis and efficiencies unchanged).
models::CellParams ParallelCell(const models::CellParams& cell, int parallel);

// The scenario's vehicle models: its vehicle file's when it has one, else the dissertation's for its configuration
// (exactly what the simulator built before vehicle files existed).
models::PropulsionParams ScenarioPropulsion(const Scenario& scenario);
models::MixerParams ScenarioMixer(const Scenario& scenario);
models::DragTable ScenarioDrag(const Scenario& scenario);
models::PackParams ScenarioPackParams(const Scenario& scenario, const models::PerCell<models::CellHealth>& health,
                                      double ambient_temp_degf);
// The scenario flies `vehicle`: its body and configuration are the vehicle's.
void UseVehicle(Scenario& scenario, std::shared_ptr<const Vehicle> vehicle);

}  // namespace uascma::sim
