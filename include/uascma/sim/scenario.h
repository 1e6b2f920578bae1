#pragma once
// Scenario files (YAML): everything one simulated flight needs. Every key is optional except where
// noted; absent keys take the defaults of sim::Scenario (each cited there). Unknown keys are errors, so
// a misspelt key never passes silently.
//
//   name: nominal
//   seed: 1
//   policy: noop                      # noop | cma | path/to/policy.json (the CLI's --policy overrides)
//   map:                              # absent: open ground, no landing sites
//     procedural: {seed: 3}           # the built-in procedural city, or real data:
//     # buildings: [city.geojson]     #   GeoJSON (Overpass) / .osm / .osm.pbf, relative to this file
//     # sites: sites.csv              #   landing sites: osm_id, lat, lon, alt, risk, radius
//     # origin: [40.78, -73.96]       #   local NED origin (default: the data's centre)
//   vehicle:
//     configuration: tractor          # tractor | pusher (§2.5)
//     mass_kg: 1.3
//     inertia_kg_m2: [0.011, 0.011, 0.021]
//   battery:
//     initial_cell_voltage_v: 4.1     # one value, or [[pack 1 cells], [pack 2 cells]]
//     ambient_temp_degf: 77
//     packs: [G, G]                   # per-pack health: G none, M power fade, P power and capacity fade
//   wind:
//     speed_mps: 2                    # mean wind (Table 4.4: 1–3 m/s)
//     direction_deg: 45               # towards, from North clockwise (Table 4.4: 0–180°)
//     turbulence: low-light           # none | low-light | low-moderate | medium-light | medium-moderate
//   mission:
//     home_ne_m: [0, 0]
//     destination_ne_m: [400, 300]
//     cruise_altitude_m: 30           # default over a map: 10 m above the tallest building under the route
//     drop_hover_s: 30
//   limits: {cruise_speed_mps: 5, vertical_speed_mps: 2, horizontal_accel_mps2: 2, vertical_accel_mps2: 1}
//   fault:                            # absent: no fault
//     motor: 3
//     spall_onset_s: 175
//     time_per_growth_step_s: 0.7128  # optional: faster growth than the Table 5.4 calibration
//     prognosis_time_per_growth_step_s: 0.7128  # optional: the prognosis knows it (default: Table 5.4)
//   options:
//     telemetry_rate_hz: 10
//     reconfiguration: true
//     sensor_noise: true
#include <filesystem>
#include <string>

#include "uascma/models/battery_pack.h"
#include "uascma/sim/simulator.h"

namespace uascma::sim {

struct ScenarioFile {
  Scenario scenario;
  std::string policy = "noop";
};

// Reads and validates a scenario; InputError names the file, the key path and what was expected.
ScenarioFile LoadScenarioFile(const std::filesystem::path& path);
ScenarioFile ParseScenario(const std::string& yaml_text, const std::string& source);

// The cells of a pack of health class G, M or P: every cell as models::CellHealthForClass says.
std::array<models::CellHealth, models::kCellsPerBranch> PackHealthPreset(models::HealthClass health);

}  // namespace uascma::sim
