#pragma once
// The configuration of a Monte Carlo campaign (dissertation §4.3.2 Table 4.4, §5.4, §5.5;
// shared/spec/defaults.md "Environment and Monte Carlo"): which parameters are sampled for every run,
// over which ranges, and which policies fly them.
//
// A campaign file is YAML; every key is optional and the defaults below are the dissertation's:
//
//   name: dissertation-5.5          # a label
//   seed: 1                         # campaign seed (the command's --seed overrides it)
//   runs: 465                       # sampled scenarios (--runs overrides); each is flown by every policy
//   policies: [cma, noop]           # cma | noop | a policy JSON file (--policies overrides)
//   mission:
//     distance_m: [300, 900]        # destination distance from home (ours; empty map, city map later)
//     cruise_speed_mps: [1, 9]      # Table 4.4, "hexacopter velocity"
//     cruise_altitude_m: 30         # fixed; defaults.md (10 m above the tallest building; empty map)
//     drop_hover_s: 30              # fixed; defaults.md
//   safety_margin_s: [5, 10]        # Table 4.4, t_sf (see SampledRun::safety_margin_s for its use)
//   battery:
//     initial_cell_voltage_v: [4.05, 4.12]      # Table 4.4, drawn per cell
//     pack_health_weights: {F1: 1, F2: 1, F3: 1} # per pack, Tables 3.2/4.2 (ours: equally likely)
//     degraded_cells_per_pack: 3                 # Table 4.2 "in at least one cell" (ours: the whole pack)
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
//
// Ranges are [low, high] lists with low ≤ high; a draw is uniform on [low, high). Unknown keys are
// errors (a typo would otherwise be silently ignored).
//
// Identity: CampaignConfigHash() fingerprints every sampled-parameter setting and the seed; the runs
// count is not part of it (a campaign can be extended with --resume --runs N). The policies' identity is
// added by the runner (campaign/policies.h).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "uascma/models/wind.h"

namespace uascma::campaign {

inline constexpr double kPi = 3.14159265358979323846;

// A closed interval of a sampled parameter, in the unit its owner's name states.
struct Range {
  double low = 0.0;
  double high = 0.0;
  double width() const { return high - low; }
  bool Contains(double value) const { return value >= low && value <= high; }
};

struct MissionSampling {
  // Distance of the destination from home, m. Our estimate: flights of 3–20 min at 1–9 m/s, so that the
  // battery (≈ 15 min of hover with both packs) matters, as in §5.5.1–5.5.2 (spalls at 175 s and 525 s).
  // Our estimate: the dissertation's scenarios fly for 500 s and more (a spall at 525 s in §5.5.2), which at
  // the sampled cruise speeds needs destinations 0.6–1.6 km away.
  Range distance_m{600.0, 1600.0};
  Range cruise_speed_mps{1.0, 9.0};  // Table 4.4 ("Hexacopter Velocity, [1, 9] m/s")
  double cruise_altitude_m = 30.0;   // defaults.md: 10 m above the tallest building (empty map: fixed)
  double drop_hover_s = 30.0;        // defaults.md
};

struct BatterySampling {
  Range initial_cell_voltage_v{4.05, 4.12};  // Table 4.4, drawn independently per cell
  // Relative weights of F1 (G), F2 (M), F3 (P) per pack (Tables 3.2, 4.2). Ours: equally likely. The
  // pack healths are independent, so the composite BH (decisions item 8) is G 1/9, M 3/9, P 5/9.
  std::vector<double> pack_health_weights{1.0, 1.0, 1.0};
  // How many cells of a degraded pack carry its fade; which cells is drawn uniformly. Each of them gets
  // models::CellHealthForClass: F2 (M) power fade, R0 → 2 R0; F3 (P) power and capacity fade, also
  // Q → 0.8 Q (Table 3.2, decisions item 8; the same cells as scenario files' `packs: [M, P]`).
  // Table 4.2 classifies a pack by "at least one cell"; ours: all three, since the cells of one pack age
  // together and a pack's health is what Table 4.2 names. With 1, one aged cell among six barely changes
  // a flight (measured: the failure rate then no longer depends on BH, unlike Fig. 5.30).
  int degraded_cells_per_pack = 3;
  double cold_probability = 0.5;  // Table 4.2 T_L vs T_H. Ours: equally likely.
  double cold_temp_degf = 40.0;   // below 50 °F: R0 → 1.5 R0 (Table 3.2); only the split matters
  double warm_temp_degf = 77.0;   // models::kRoomTemperatureDegf
};

struct WindSampling {
  Range speed_mps{1.0, 3.0};        // Table 4.4
  Range direction_rad{0.0, kPi};    // Table 4.4
  std::vector<models::TurbulenceCategory> turbulence{
      models::TurbulenceCategory::kLowLight, models::TurbulenceCategory::kLowModerate,
      models::TurbulenceCategory::kMediumLight, models::TurbulenceCategory::kMediumModerate};  // Table 4.4
};

struct FaultSampling {
  double probability = 0.5;            // §5.4: P(SF|NF) = 0.5 per simulated flight
  Range onset_fraction{0.0, 1.0};      // of the nominal plan's duration: "uniform over the flight", §5.4
  std::vector<int> motors{1, 2, 3, 4, 5, 6};  // §5.4, uniform
  // Growth speed of the simulated spall (sim::FaultSpec, decisions item 15). 0.7128 s per Paris-law
  // step jams the motor ~17 s after the onset, as in §5.5.1 (175 → 192 s) and §5.5.2 (525 → 542 s).
  // Absent (YAML: null) → the prognosis default calibrated to Table 5.4 (minutes to jam).
  std::optional<double> time_per_growth_step_s = 0.7128;
};

// The city the flights fly over: the built-in procedural city of this seed (0: open ground, no buildings
// and no landing sites — the emergency actions then have nowhere to go). Home and destination are drawn on
// open ground, the cruise altitude is 10 m above the tallest building under the route (defaults.md).
struct MapSampling {
  std::uint64_t procedural_seed = 3;
  // City size in blocks (procedural_city.h): 24 × 8 blocks ≈ 1.9 km × 1.7 km, large enough for the
  // distance band below.
  int blocks_north = 24;
  int blocks_east = 8;
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
