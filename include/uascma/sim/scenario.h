#pragma once
// Scenario files (YAML): everything one simulated flight needs. Every key is optional except where
// noted; absent keys take the defaults of sim::Scenario (each cited there). Unknown keys are errors, so
// a misspelt key never passes silently.
//
//   name: nominal
//   seed: 1
//   policy: noop                      # noop | cma | cma-vehicle | cma-risk[@P] | cma-qmdp | cma-vehicle-risk[@P] | cma-vehicle-qmdp | policy.json (--policy overrides)
//   map:                              # absent: open ground, no landing sites
//     procedural: {seed: 3}           # the built-in procedural city, or real data:
//     # buildings: [city.geojson]     #   GeoJSON (Overpass) / .osm / .osm.pbf, relative to this file
//     # sites: sites.csv              #   landing sites: osm_id, lat, lon, alt, risk, radius
//     # origin: [40.78, -73.96]       #   local NED origin (default: the data's centre)
//     # height_from_levels: false     #   a building without a height: building:levels × metres_per_level
//     # metres_per_level: 3           #   m per storey (our estimate, map_import.h)
//     # height_from_type: false       #   then the typical height of its building=* value (map_import.h table)
//     # default_height_m: 10          #   then this height, m (1-500 m)
//     # skip_missing_height: false    #   a building still without a height is skipped (counted), not an error
//     # sites_from_map: false         #   add landing sites on flat roofs and open areas (beside `sites`)
//   vehicle:                          # or the name of a vehicle file, relative to this file (sim/vehicle_file.h):
//                                     #   vehicle: my-hexacopter.yaml
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
//     # or a ground station's mission instead of the four keys above (planning/mission_file.h):
//     # file: delivery.plan           #   QGroundControl .plan or QGC WPL 110 .waypoints, relative to this file
//     # land_at_end: true             #   a mission ending in the air lands where it ends (warned); false: error
//     # origin: [40.78, -73.96]       #   lat, lon of the local frame's origin: default the mission's planned
//     #                               #   home; with home_ne_m etc. it places the local mission on the globe (for
//     #                               #   simulate --out's .plan files); over an imported map an error: the
//     #                               #   frame is the map's (map.origin)
//   limits: {cruise_speed_mps: 5, vertical_speed_mps: 2, horizontal_accel_mps2: 2, vertical_accel_mps2: 1}
//   fault:                            # absent: no fault
//     motor: 3
//     spall_onset_s: 175
//     time_per_growth_step_s: 0.7128  # optional: faster growth than the Table 5.4 calibration
//     prognosis_time_per_growth_step_s: 0.7128  # optional: the prognosis knows it (default: Table 5.4)
//   pack_fault:                       # absent: none (models/pack_fault.h, docs/modelling-choices.md#pack-faults)
//     kind: internal_short            # internal_short | failed_cell | connector
//     pack: 1                         # 1 | 2
//     cell: 2                         # 1..3 (not read by a connector fault)
//     onset_s: 120                    # s after take-off
//     resistance_ohm: 5               # R_s of the short, R_f of the failed cell, R_c of the poor contact
//   options:
//     telemetry_rate_hz: 10
//     reconfiguration: true
//     sensor_noise: true
//     drag_feedforward: true          # the LQR compensates the drag at the reference airspeed (gnc/lqr.h)
//     eod_load: forecast              # the 1 Hz EOD's load: the plan's expected current
//                                     # (docs/modelling-choices.md#eod-load-forecast) | present
//     cap_speed_after_isolation: true # after an isolation, fly within the quadcopter's authority (sim/speed_cap.h)
//     termination: last-resort      # Terminate only when nothing else reaches the ground | policy | never
//     safety_margin_s: 0              # t_sf in the reach margin (Table 4.4: 5-10 s in campaigns)
//     noisy_sensing: false            # sensor noise, vibration and a spall indicator for the CMA (sim/sensing.h)
//     max_tilt_deg: 69                # loss of control beyond it (sim/outcome.h)
//     max_cross_track_error_m: 15     # loss of control beyond it (distance from the path, not the schedule)
//
// The scenario itself (struct Scenario below) is plain data with defaults, each cited; Scenario::IsValid composes
// the validators of its parts and is the one check for scenarios from files, from campaign samplers and from code
// (FlightModel's constructor calls it).
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "uascma/gnc/imm.h"
#include "uascma/gnc/lqr.h"
#include "uascma/models/battery_pack.h"
#include "uascma/models/propulsion.h"
#include "uascma/models/rigid_body.h"
#include "uascma/models/wind.h"
#include "uascma/planning/city_map.h"
#include "uascma/planning/flight_plan.h"
#include "uascma/planning/landing_detour.h"
#include "uascma/planning/map_projection.h"
#include "uascma/planning/mission_file.h"
#include "uascma/sim/eod_error_model.h"
#include "uascma/sim/load_forecast.h"
#include "uascma/sim/outcome.h"
#include "uascma/sim/sensing.h"
#include "uascma/sim/termination.h"

namespace uascma::sim {

// A spall fault in one motor (§5.4): onset at a time, growth by the motor prognosis model until the
// spall crosses D_f and the rotor jams (its thrust goes to zero).
struct FaultSpec {
  bool enabled = false;
  int motor = 3;                 // 1…6 (Fig. 2.2 numbering)
  double spall_onset_s = 175.0;  // s after take-off
  // Growth speed of the simulated spall: seconds per Paris-law step. The prognosis default (calibrated to
  // Table 5.4) is used when absent; scenarios use faster growth (docs/modelling-choices.md#spall-growth-time-scale).
  std::optional<double> time_per_growth_step_s;
  // The prognosis's own time scale (§3.4.1): absent, the Table 5.4 calibration
  // (docs/modelling-choices.md#spall-growth-time-scale), so a fast-growing spall surprises it; set, the prognosis knows
  // this motor's growth speed.
  std::optional<double> prognosis_time_per_growth_step_s;
  bool IsValid(std::string* error) const;
};

struct Vehicle;  // sim/vehicle_file.h

struct BatterySpec {
  models::PerCell<double> initial_cell_voltage_v = {{{4.1, 4.1, 4.1}, {4.1, 4.1, 4.1}}};  // Table 4.4: 4.05–4.12
  models::PerCell<models::CellHealth> cell_health{};
  double ambient_temp_degf = models::kRoomTemperatureDegf;
  // The initial voltages lie on the OCV table (they set the initial state of charge, docs/defaults.md#battery): the
  // dissertation's packs, or `pack` (a vehicle file's cells).
  bool IsValid(std::string* error, const models::PackParams* pack = nullptr) const;
};

struct SimOptions {
  double gnc_rate_hz = 200.0;       // §4.3.2, §5.4
  double decision_rate_hz = 1.0;    // EOD, RUL, CMA: §5.4
  double telemetry_rate_hz = 10.0;  // rows per simulated second in the CSV
  // The battery pack's state advances at this rate (its outputs stay at the GNC rate; models/battery_pack.h
  // PackLinearisation). Ours, measured (README "Subsystem rates"): 10 Hz. It divides the GNC rate, and the decision
  // rate divides it (the 1 Hz EOD reads an advanced state).
  double pack_rate_hz = 10.0;
  // The Dryden filters' rate (models/wind.h, `substeps`: exact discretisation, interpolated at the GNC rate). Ours,
  // measured (README "Subsystem rates"). It divides the GNC rate.
  double wind_rate_hz = 200.0;
  OutcomeThresholds outcome;  // how a flight ends (outcome.h)
  // The IMM rotor-fault detector runs every GNC step (§4.4, §5.4). Off: no detection, so no isolation and no
  // reconfiguration — the loop of Ch. IV's battery simulations (Fig. 4.3: DLQR → motor model → battery → EOD →
  // battery MDP, no fault detector; Table 4.4 draws no motor fault), which the battery MDP's learning flights
  // fly (campaign/battery_flights.h).
  bool fault_detection = true;
  bool reconfiguration = true;  // switch to the quadcopter allocation when the IMM isolates a rotor
  bool sensor_noise = true;     // gyro and accelerometer noise for the IMM
  // The LQR adds the drag at the reference air velocity (less the steady wind) to its reference acceleration
  // (gnc/lqr.h CalcDragFeedForward). Off: the dissertation's bare DLQR (§4.3.3).
  bool drag_feedforward = true;
  double hotel_current_a = 0.5;  // A: onboard computer, radio, sensors (our estimate; §4.3.2 calls it small)
  // Bus voltage at which the rotors reach their Table 2.2 maximum thrust; rotor thrust capacity scales
  // as (V_bus / V_ref)² (speed ∝ voltage, thrust ∝ speed²). Our estimate: a 3S pack at 3.7 V per cell.
  double reference_bus_voltage_v = 11.1;
  // s: the 1 Hz EOD prediction runs at the pack current low-passed with this time constant (our estimate:
  // long enough to ignore gusts and the take-off climb, short enough to see a rotor failure's extra load
  // within half a minute; the dissertation's EOD curves, Figs. 5.22 and 5.25, are smooth).
  double load_current_time_constant_s = 10.0;
  // The constant current the 1 Hz EOD is propagated at (docs/modelling-choices.md#eod-load-forecast,
  // sim/load_forecast.h): the expected load of the rest of the executing plan (forecast, the default), or the present
  // current low-passed as above (present, docs/modelling-choices.md#pack-eod).
  EodLoad eod_load = EodLoad::kForecast;
  // After a rotor is isolated, guidance caps the executing plan's horizontal speed to what the quadcopter can hold
  // against the mean wind with a gust allowance (§4.4.2, sim/speed_cap.h). Off: the plan's own speeds.
  bool cap_speed_after_isolation = true;
  // When the CMA's Terminate is carried out (sim/termination.h): only when no other action reaches the ground before
  // the pack's EOD (last-resort, the default), as the policy ranks it (policy), or never (termination disarmed).
  TerminationRule termination = TerminationRule::kLastResort;
  // s, t_sf of Table 4.4: the reach margin judges the plan with this much extra time,
  // RM = 1 − (t_remaining + t_sf) / t_EOD (the battery MDP's S1 ↔ EOD > RFD + t_sf, Table 4.1, carried to the
  // CMA). 0 by default; campaigns sample it in [5, 10] s.
  double safety_margin_s = 0.0;
  // Noisy sensing (sim/sensing.h): the CMA reads the pack current and bus voltage through a power module
  // with errors and noise (its SOC by coulomb counting from the rest voltage read at take-off), the IMM's samples
  // carry vibration noise, and the spall is seen through an indicator with false positives and misses. Off (the
  // default): the truth, as always.
  bool noisy_sensing = false;
  SensingParams sensing;  // the magnitudes (cited in sim/sensing.h)
  bool IsValid(std::string* error) const;
};

struct Scenario {
  std::string name = "default";
  // The city: buildings the vehicle can strike and the landing sites the emergency planners use. Shared
  // and immutable, so campaigns copy scenarios cheaply. Null: open ground, no sites.
  std::shared_ptr<const planning::CityMap> map;
  // The map's buildings grown by the emergency planners' lateral margin (planning::LandingPathPlanner::
  // InflateBuildings at LandingPathParams' default), built once with the map and shared by every flight over it
  // (ParseScenario; a campaign's world, campaign/world.h). Null: each flight model inflates them itself.
  std::shared_ptr<const planning::ObstacleSet> map_obstacles;
  // The nominal plan's load profile when the scenario's builder has it already (a campaign's sampler, for its
  // whole-load check): FlightModel reuses it when its key is this scenario's nominal plan, body, configuration and
  // mean wind, and builds its own otherwise (sim/load_forecast.h KeyedLoadProfile). Null: built by the model.
  std::shared_ptr<const KeyedLoadProfile> nominal_load_profile;
  // The load forecast's error table of the 1 Hz EOD distribution (sim/eod_error_model.h; `uascma calibrate eod
  // --model`). Null: EodErrorModel::Default(), the committed table. Read only by the distribution, which no built-in
  // policy but the risk-aware ones reads.
  std::shared_ptr<const EodErrorModel> eod_error_model;
  models::RigidBodyParams body;
  models::PropellerConfiguration configuration = models::PropellerConfiguration::kTractor;
  // The user's vehicle (scenario key `vehicle: FILE`, `simulate --vehicle`, a campaign's `vehicle`;
  // sim/vehicle_file.h): its propulsion, mixer, drag table and cells replace the dissertation's, and body and
  // configuration above are its own (sim::UseVehicle). Null: the dissertation's vehicle.
  std::shared_ptr<const Vehicle> vehicle;
  BatterySpec battery;
  models::WindParams wind;
  planning::DeliveryMission mission;
  // A ground station's mission (scenario key mission.file, `simulate --mission`): when set, the nominal plan
  // is planning::MakeMissionPlan(*route, limits) through its waypoints instead of the delivery plan of
  // `mission` (whose home_NE/destination_NE then mirror the route's home and last waypoint for the records).
  // Its warnings (items read but not modelled) are the importer's; the CLI prints them.
  std::optional<planning::Mission> route;
  // The geodetic origin of the local frame W, when the scenario has one: the route's origin, else the
  // imported map's, else the scenario's mission.origin. Absent for local-metres scenarios without it (procedural
  // city, open ground): nothing can be exported in latitude/longitude then.
  std::optional<planning::GeoPoint> geo_origin;
  planning::PlanLimits limits;
  FaultSpec fault;
  // A sudden fault of one pack (models/pack_fault.h); none by default. Its connector draws come from the flight's
  // seed (FlightModel).
  std::optional<models::PackFault> pack_fault;
  gnc::LqrOptions lqr;
  gnc::ImmParams imm;
  SimOptions options;
  std::uint64_t seed = 1;
  // Every part's validator, then the checks across parts (the LQR's step is the GNC step; home and destination
  // on open ground, or with a route: its home and waypoints finite and its home on open ground, and a plan
  // can be built through them). `error` reads "part.field: expected …", the part named as in scenario files.
  bool IsValid(std::string* error) const;
};

struct ScenarioFile {
  Scenario scenario;
  std::string policy = "noop";
};

struct ScenarioLoadOptions {
  // Flies this mission file (relative to the current folder) instead of the scenario's mission (its file or
  // its home/destination keys); mission.land_at_end and mission.origin of the scenario still apply.
  std::optional<std::filesystem::path> mission_file;
  // Flies this vehicle file (sim/vehicle_file.h, relative to the current folder) instead of the scenario's vehicle
  // (its `vehicle:` keys or file).
  std::optional<std::filesystem::path> vehicle_file;
};

// The scenario flying `route` (a mission read or uploaded, planning::MissionFromItems) in place of its plan, as
// `mission: {file: …}` flies a file: the route's rally points join the landing sites and its geofence removes sites
// (planning::WithMissionSafety), the frame is the route's, and the scenario is checked as a file is (Scenario::IsValid;
// LandPract's checkpoints on the new plan clear of the buildings). InputError naming `source` otherwise.
void FlyMissionRoute(Scenario& sc, planning::Mission route, const std::string& source);

// Reads and validates a scenario; InputError names the file, the key path and what was expected.
ScenarioFile LoadScenarioFile(const std::filesystem::path& path, const ScenarioLoadOptions& load = {});
ScenarioFile ParseScenario(const std::string& yaml_text, const std::string& source,
                           const ScenarioLoadOptions& load = {});

// The cells of a pack of health class G, M or P: every cell as models::CellHealthForClass says.
std::array<models::CellHealth, models::kCellsPerBranch> PackHealthPreset(models::HealthClass health);

}  // namespace uascma::sim
