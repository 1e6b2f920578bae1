#pragma once
// The configuration of a Monte Carlo campaign (dissertation §4.3.2 Table 4.4, §5.4, §5.5;
// docs/defaults.md#environment-and-monte-carlo): which parameters are sampled for every run,
// over which ranges, and which policies fly them.
//
// A campaign file is YAML; every key is optional and the defaults below are the dissertation's:
//
//   name: dissertation-5.5          # a label
//   seed: 1                         # campaign seed (the command's --seed overrides it)
//   runs: 465                       # sampled scenarios (--runs overrides); each is flown by every policy
//   policies: [cma, noop]           # cma | noop | cma-vehicle | cma-risk[@P] | cma-qmdp | cma-vehicle-risk[@P] | cma-vehicle-qmdp | a policy JSON
//                                   # file (--policies overrides)
//   mission:
//     endurance_fraction: [0.5, 0.9]  # plan = f × (healthy pack's EOD at the cruise current − t_sf); ours
//                                     # (docs/modelling-choices.md#campaign-missions)
//     # distance_m: [300, 900]        # optional: draw the distance instead (the plan is then not tied to the pack)
//     cruise_speed_mps: [1, 9]      # Table 4.4, "hexacopter velocity"
//     cruise_altitude_m: 30         # open ground only; over a city 10 m above the tallest building
//                                   # (docs/defaults.md#guidance-and-control)
//     wall_clearance_m: 5           # home, destination, route corridor: from every building wall
//                                   # (docs/modelling-choices.md#battery-health-draw)
//     drop_hover_s: 30              # fixed; docs/defaults.md#guidance-and-control
//   safety_margin_s: [5, 10]        # Table 4.4, t_sf (see SampledRun::safety_margin_s for its use)
//   battery:
//     initial_cell_voltage_v: [4.05, 4.12]      # Table 4.4, drawn per cell
//     health_weights: {G: 1, M: 1, P: 1}        # BH per flight, equally likely
//                                               # (docs/modelling-choices.md#battery-health-draw)
//     degraded_cells: [1, 6]                     # how many of the six cells carry a fade in M and P (ours)
//     medium_fades: one_kind                     # M: one fade kind per flight (Table 4.2) | per_cell
//     cold_probability: 0.5                      # Table 4.2, T_L (< 50 °F) vs T_H (ours: equally likely)
//     cold_temp_degf: 40                         # any value below 50 °F acts alike (Table 3.2)
//     warm_temp_degf: 77                         # room temperature (models/battery_cell.h)
//   wind:
//     speed_mps: [1, 3]                          # Table 4.4
//     direction_rad: [0, 3.141592653589793]      # Table 4.4
//     turbulence: [low-light, low-moderate, medium-light, medium-moderate]  # Table 4.4, uniform
//   fault:
//     probability: 0.5                           # §5.4, P(SF|NF) = 0.5 per simulated flight
//     onset_fraction: [0, 1]                     # onset uniform over the nominal flight (§5.4)
//     motors: [1, 2, 3, 4, 5, 6]                 # the spalled motor, uniform (§5.4)
//     time_per_growth_step_s: 0.7128             # spall → jam in ~17 s, as in §5.5.1–5.5.2
//     prognosis_time_per_growth_step_s: 0.7128   # optional: the prognoser shares it (unset: Table 5.4)
//   options:
//     eod_load: forecast                         # the 1 Hz EOD's load: forecast | present
//                                                # (docs/modelling-choices.md#eod-load-forecast, #pack-eod)
//     cap_speed_after_isolation: true            # §4.4.2: four rotors fly within their authority (sim/speed_cap.h)
//     termination: last-resort                   # Terminate only when nothing else reaches the ground (sim/termination.h)
//     noisy_sensing: false                       # sensor noise, vibration, a spall indicator (sim/sensing.h)
//   vehicle: my-hexacopter.yaml                  # optional: the user's vehicle file (sim/vehicle_file.h), relative
//                                                # to this file; the fingerprint takes its content hash
//   pack_faults:                                 # absent: none (docs/modelling-choices.md#pack-faults)
//     share: 0.2                                 # of the flights with one sudden pack fault (ours)
//     onset_fraction: [0, 1]                     # of the nominal plan (ours, as §5.4's spall)
//     short_resistance_ohm: [1, 20]              # R_s (ours)
//     failed_cell_resistance_ohm: [0.1, 10]      # R_f (ours)
//     connector_resistance_ohm: [0.05, 0.5]      # R_c (ours)
//
// Ranges are [low, high] lists with low ≤ high; a draw is uniform on [low, high). Unknown keys are
// errors (a typo would otherwise be silently ignored). Each key is declared once, in the field table of
// campaign/config_fields.h, which drives the parser, IsValid, the canonical YAML, the hash, the Python
// properties and docs/input-bounds.md.
//
// Identity: CampaignConfigHash() fingerprints every sampled-parameter setting and the seed; the runs
// count is not part of it (a campaign can be extended with --resume --runs N). The policies' identity is
// added by the runner (campaign/policies.h).
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "uascma/campaign/pack_fault_sampling.h"
#include "uascma/common/bounds.h"
#include "uascma/models/wind.h"
#include "uascma/sim/load_forecast.h"
#include "uascma/sim/termination.h"

namespace uascma::campaign {

inline constexpr double kPi = 3.14159265358979323846;

// Plausibility bounds of every number of a campaign file (common/bounds.h), checked by
// CampaignConfig::IsValid; ranges [low, high] must lie inside them. Where the dissertation gives a value
// the bound contains it with room; the bounds themselves are ours unless cited.
namespace bounds {
// Runs: our bound; 10^7 runs of two policies take ~6 days at the measured 42 flights/s (README).
inline constexpr Bounds kRuns{0.0, 1e7, "runs"};
// The map importer refuses data farther than 50 km from its origin (planning/map_import.h).
inline constexpr Bounds kDistance{1.0, 50000.0, "m"};
inline constexpr Bounds kCruiseSpeed{0.1, 30.0, "m/s"};     // Table 4.4 samples 1-9 m/s
inline constexpr Bounds kCruiseAltitude{1.0, 1000.0, "m"};  // above the tallest building of any city
inline constexpr Bounds kDropHover{0.0, 3600.0, "s"};       // 4x the packs' ~15 min hover endurance
inline constexpr Bounds kSafetyMargin{0.0, 600.0, "s"};     // Table 4.4 samples 5-10 s
// The default OCV table spans 3.27-4.20 V (docs/defaults.md#battery); the cut-off is 3.3 V (§3.3.2.1).
inline constexpr Bounds kInitialCellVoltage{3.3, 4.2, "V"};
inline constexpr Bounds kHealthWeight{0.0, 1e6, ""};        // relative weights
inline constexpr Bounds kDegradedCells{1.0, 6.0, "cells"};  // two 3S packs
inline constexpr Bounds kEnduranceFraction{0.01, 1.0, ""};  // of EOD − t_sf: at most all of it
                                                            // (docs/modelling-choices.md#campaign-missions)
inline constexpr Bounds kWallClearance{0.0, 100.0, "m"};    // our bound: a city block is ~60 m deep
inline constexpr Bounds kProbability{0.0, 1.0, ""};
inline constexpr Bounds kColdTemperature{-40.0, 49.999,
                                         "°F"};  // below 50 °F (Table 3.2), models::kAmbientTemperatureBounds
inline constexpr Bounds kWarmTemperature{50.0, 140.0, "°F"};  // 50 °F or above (Table 3.2)
inline constexpr Bounds kWindSpeed{0.0, 50.0, "m/s"};         // Table 4.4 samples 1-3 m/s
inline constexpr Bounds kWindDirection{-4.0 * kPi, 4.0 * kPi, "rad"};
inline constexpr Bounds kMotor{1.0, 6.0, ""};                    // the hexacopter's motors
inline constexpr Bounds kTimePerGrowthStep{0.001, 3600.0, "s"};  // docs/modelling-choices.md#spall-growth-time-scale:
                                                                 // 0.7128 s, Table 5.4: 15.3 s
inline constexpr Bounds kBlocks{1.0, 200.0, "blocks"};           // procedural city size per side
}  // namespace bounds

// A closed interval of a sampled parameter, in the unit its owner's name states.
struct Range {
  double low = 0.0;
  double high = 0.0;
  double width() const { return high - low; }
  bool Contains(double value) const { return value >= low && value <= high; }
};

struct MissionSampling {
  // The nominal plan is one a fully charged healthy (F1/F1) pack flies with its safety margin (§4.3.2: a
  // "representative flight plan for a package drop", the pack "fully charged";
  // docs/modelling-choices.md#campaign-missions): its duration is f × (EOD_healthy − t_sf), EOD_healthy the end of
  // discharge of this run's initial cell voltages and temperature with every cell healthy at the plan's cruise current
  // (campaign/sampler.h), and f uniform on this range. Ours: from 0.5, the dissertation's own healthy study ("battery
  // pack EOD time is twice the flight time", §4.3.3), to 0.9: the steady-current estimate leaves out the climbs (to 10
  // m above the tallest building, up to a minute at 2 m/s) and the gust corrections, and in flight the vehicle's own
  // 1 Hz EOD prognosis came out up to ~10 % below it — measured over 150 default runs with f up to 1, CMA judged
  // RM < 0 and landed 4 of 23 healthy fault-free flights, all with f ≥ 0.90, which NoOp completed with the
  // lowest cell at 3.39–3.52 V. Above 0.9 a plan is no longer flyable "with its safety margin" in the vehicle's
  // own judgement. Degraded packs then fail or not because of their health
  // (docs/modelling-choices.md#campaign-missions).
  Range endurance_fraction{0.5, 0.9};
  // Set: the destination distance (m) is drawn uniformly on this range instead, and the plan is not tied to
  // the pack's endurance (short test campaigns, small imported maps). Absent by default.
  std::optional<Range> distance_m;
  Range cruise_speed_mps{1.0, 9.0};  // Table 4.4 ("Hexacopter Velocity, [1, 9] m/s")
  // open ground only; over a city 10 m above the tallest building (docs/defaults.md#guidance-and-control)
  double cruise_altitude_m = 30.0;
  // Horizontal clearance (m) of home and the destination (the hover points: take-off, drop, landing) from every
  // building wall, and the half-width of the route corridor whose buildings set the cruise altitude
  // (docs/modelling-choices.md#battery-health-draw). It covers the vehicle's radius, 0.30 m (arm 0.225 m,
  // docs/defaults.md#vehicle, plus a 6-inch propeller's 0.076 m), and its horizontal tracking error near a hover point,
  // bounded by our measurement: the largest tracking error of whole flights cruising at 1–3 m/s (near-hover speeds;
  // wind 1–3 m/s, every gust category) was 3.46 m over 67 fault-free completed flights of two 150-run default campaigns
  // (median 0.88 m; sim::kHoverTrackingErrorBound, also the landing radius of sim/outcome.h). 0.30 + 3.46 = 3.8 m; 5 m
  // (ours) leaves 1.2 m for what that sample missed, and equals the corridor half-width the cruise altitude was already
  // computed over. (Faster cruise lags further behind the reference — up to 9.5 m
  // at 6–9 m/s, the controller's business — but away from the hover points, above the buildings.)
  double wall_clearance_m = 5.0;
  double drop_hover_s = 30.0;  // docs/defaults.md#guidance-and-control
};

// An inclusive range of counts.
struct CountRange {
  int low = 0;
  int high = 0;
};

enum class MediumFades { kOneKind, kPerCell };
const char* MediumFadesName(MediumFades fades);  // "one_kind", "per_cell"

struct BatterySampling {
  Range initial_cell_voltage_v{4.05, 4.12};  // Table 4.4, drawn independently per cell
  // Relative weights of the flight's battery health BH = G, M, P (docs/modelling-choices.md#battery-health-draw: drawn
  // per flight, equally likely by default).
  std::vector<double> health_weights{1.0, 1.0, 1.0};
  // M and P are realised as Table 4.2 defines them (docs/modelling-choices.md#battery-health-draw; campaign/sampler.h):
  // k degraded cells, k uniform on this range, chosen uniformly among the six; in M they carry one fade, capacity (Q →
  // 0.8 Q) or power (R0 → 2 R0), as medium_fades says; in P the first carries both and each other one fade or both,
  // drawn ⅓ each (Table 3.2's factors). Table 4.2 says "at least one cell"; ours: every count from one cell to
  // the whole battery equally likely. The per-pack F1/F2/F3 labels follow from the cells (models::ClassifyHealth).
  CountRange degraded_cells{1, 6};
  // How an M battery's fade kind is drawn. Table 4.2: "Medium health battery = either power or capacity fade in
  // at least one cell", "Unhealthy battery = has power and capacity fade". kOneKind (default, our reading of
  // "either … or" as said of the battery): one kind drawn per flight, ½ each, carried by all k degraded cells, so
  // an M battery never holds both kinds. kPerCell: each degraded cell draws its own kind, ½ each (the sampler
  // until this setting existed), so most M batteries with k > 1 hold both kinds in different cells and, with the
  // capacity-faded cell deciding the end of discharge, fly much like P (measured: 465 runs, seed 1, NoOp M 19.5 %
  // vs P 21.0 % failures).
  MediumFades medium_fades = MediumFades::kOneKind;
  double cold_probability = 0.5;  // Table 4.2 T_L vs T_H. Ours: equally likely.
  double cold_temp_degf = 40.0;   // below 50 °F: R0 → 1.5 R0 (Table 3.2); only the split matters
  double warm_temp_degf = 77.0;   // models::kRoomTemperatureDegf
};

struct WindSampling {
  Range speed_mps{1.0, 3.0};      // Table 4.4
  Range direction_rad{0.0, kPi};  // Table 4.4
  std::vector<models::TurbulenceCategory> turbulence{
      models::TurbulenceCategory::kLowLight, models::TurbulenceCategory::kLowModerate,
      models::TurbulenceCategory::kMediumLight, models::TurbulenceCategory::kMediumModerate};  // Table 4.4
};

struct FaultSampling {
  double probability = 0.5;                   // §5.4: P(SF|NF) = 0.5 per simulated flight
  Range onset_fraction{0.0, 1.0};             // of the nominal plan's duration: "uniform over the flight", §5.4
  std::vector<int> motors{1, 2, 3, 4, 5, 6};  // §5.4, uniform
  // Growth speed of the simulated spall (sim::FaultSpec, docs/modelling-choices.md#spall-growth-time-scale). 0.7128 s
  // per Paris-law step jams the motor ~17 s after the onset, as in §5.5.1 (175 → 192 s) and §5.5.2 (525 → 542 s).
  // Absent (YAML: null) → the prognosis default calibrated to Table 5.4 (minutes to jam).
  std::optional<double> time_per_growth_step_s = 0.7128;
  // The prognoser's own time scale (sim::FaultSpec::prognosis_time_per_growth_step_s). Absent (the default):
  // Table 5.4's calibration, 21.5 times slower than the 0.7128 s above, so the CMA's RUL (~356 s) misses every
  // jam (~17 s; `uascma rul --calibrate`). Set to time_per_growth_step_s, the prognoser's particles
  // follow the law the spall follows (§3.4.1: one Paris law for both) and its RUL intervals cover the jam times.
  std::optional<double> prognosis_time_per_growth_step_s;
};

// Sudden pack faults (campaign/pack_fault_sampling.h): off unless `share` is set. Each key is written and fingerprinted
// only when set, so a campaign without the block keeps its fingerprint; an unset range takes PackFaultSampling's.
struct PackFaultConfig {
  std::optional<double> share;
  std::optional<Range> onset_fraction;
  std::optional<Range> short_resistance_ohm;
  std::optional<Range> failed_cell_resistance_ohm;
  std::optional<Range> connector_resistance_ohm;
  PackFaultSampling Sampling() const;  // the draw's settings, defaults where unset
};

// The city the flights fly over: the built-in procedural city of this seed (0: open ground, no buildings
// and no landing sites — the emergency actions then have nowhere to go). Home and destination are drawn on
// open ground with mission.wall_clearance_m from every wall, the cruise altitude is 10 m above the tallest
// building under the route (docs/defaults.md#guidance-and-control).
//
// Or an imported city (planning/map_import.h), when `buildings` names files:
//   map:
//     buildings: [upper-east-side-buildings.geojson]  # GeoJSON / .osm / .osm.pbf, relative to the campaign file
//     sites: midtown-landing-sites.csv                # landing sites (optional)
//     origin: [40.77, -73.96]                         # local frame origin (default: the data's centre)
//     height_from_levels: true                        # import fall-backs, as `map info`'s flags
//     metres_per_level: 3
//     skip_missing_height: true
//     height_from_type: true                          # then the building=* table (map_import.h)
//     default_height_m: 10                            # then this height, m (1-500 m, kDefaultHeightBounds)
//     sites_from_map: true                            # landing sites from flat roofs and open areas
// Home and destination are then drawn over the imported map's extent (buildings and sites), on open ground.
// Landing sites (ours): without `sites_from_map` the map supplies its own sites only when there is no `sites`
// file; `sites_from_map: true` adds them beside the file's, `false` keeps only the file's (none without one).
// The canonical YAML writes the last three keys only when set, and the fingerprint takes them only when they
// change the import, so the fingerprints of campaigns written before them stay as they were.
struct MapSampling {
  std::uint64_t procedural_seed = 3;
  // City size in blocks (procedural_city.h): 56 × 20 blocks ≈ 4.4 km × 4.2 km. The plans of the default
  // mission sampling reach destinations ~3 km from home (90 % of a healthy pack's ~13 min at 9 m/s, out and
  // back), and both ends must lie inside the city with room to draw the bearing.
  int blocks_north = 56;
  int blocks_east = 20;
  // Imported map (none when `buildings` is empty). Paths as LoadCampaignConfig resolved them (absolute).
  std::vector<std::string> buildings;
  std::string sites;
  std::optional<std::array<double, 2>> origin_deg;  // latitude, longitude
  bool height_from_levels = false;                  // planning::MapImportOptions (defaults there)
  double metres_per_level = 3.0;                    // m per storey, the importer's estimate
  bool skip_missing_height = false;
  bool height_from_type = false;
  std::optional<double> default_height_m;  // m
  std::optional<bool> sites_from_map;      // unset: derive sites when there is no `sites` file
  bool imported() const { return !buildings.empty(); }
  // Whether the import derives landing sites from the map (above).
  bool DerivesSites() const { return sites_from_map.value_or(sites.empty()); }
  bool operator==(const MapSampling&) const = default;
};

// The simulator options a campaign sets for every flight (sim::SimOptions); the rest keep their defaults.
struct FlightOptions {
  sim::EodLoad eod_load = sim::EodLoad::kForecast;  // docs/modelling-choices.md#eod-load-forecast; present:
                                                    // docs/modelling-choices.md#pack-eod
  bool cap_speed_after_isolation = true;            // §4.4.2, sim/speed_cap.h
  // sim/termination.h (ours); unset: the simulator's default, last-resort (so a configuration without the key keeps
  // its hash).
  std::optional<sim::TerminationRule> termination;
  // The pack's and the Dryden filters' rates (sim::SimOptions); unset: the simulator's defaults. Set to the GNC rate
  // (200) to fly the campaign with both at the GNC rate (README "Subsystem rates").
  std::optional<double> pack_rate_hz;
  std::optional<double> wind_rate_hz;
  // Noisy sensing for every flight (sim::SimOptions::noisy_sensing, sim/sensing.h); unset: off.
  std::optional<bool> noisy_sensing;
};

struct CampaignConfig {
  std::string name = "campaign";
  MapSampling map;
  std::uint64_t seed = 1;
  std::int64_t runs = 465;  // §5.5: 930 flights split equally between CMA and NoOp
  std::vector<std::string> policies{"cma", "noop"};
  MissionSampling mission;
  Range safety_margin_s{5.0, 10.0};  // Table 4.4, t_sf
  BatterySampling battery;
  WindSampling wind;
  FaultSampling fault;
  PackFaultConfig pack_faults;
  FlightOptions options;
  // The vehicle every run flies (sim/vehicle_file.h, docs/identification.md#vehicle-file), its path made absolute on
  // reading, and its content hash (16 hex digits), which the fingerprint takes. Empty: the dissertation's vehicle.
  std::string vehicle;
  std::string vehicle_hash;

  // Every range ordered and inside its physical domain, weights non-negative with a positive sum,
  // probabilities in [0, 1], motors in 1..6, policies non-empty. Writes "field: expected …" to *error.
  bool IsValid(std::string* error) const;
};

// Parses a campaign file (format above); InputError names the file and the key path.
CampaignConfig LoadCampaignConfig(const std::filesystem::path& path);
// The same from YAML text; `source` names it in messages.
CampaignConfig ParseCampaignConfig(const std::string& yaml_text, const std::string& source);
// The canonical YAML of a configuration: every key, numbers in shortest round-trip form, so that
// ParseCampaignConfig(CampaignConfigYaml(c)) reproduces c exactly (the results store keeps it).
std::string CampaignConfigYaml(const CampaignConfig& config);
// 16 hex digits: the fingerprint of the seed and every sampling setting (not runs, name or policies).
std::string CampaignConfigHash(const CampaignConfig& config);

}  // namespace uascma::campaign
