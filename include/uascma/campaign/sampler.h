#pragma once
// The scenario sampler of a Monte Carlo campaign (Table 4.4, §5.4, §5.5).
//
// A run's scenario is a pure function of (configuration, campaign seed, run index) (style habit 7):
//   run_seed          = DeriveSeed(campaign seed, run index)              (common/random.h)
//   sampler stream    = RandomStream(DeriveSeed(run_seed, kSamplerStream))
//   scenario.seed     = DeriveSeed(run_seed, kSimulatorStream)            (wind, sensor noise, spall growth)
// Every policy of the campaign flies the same scenario with the same scenario.seed: the comparison is
// paired (common random numbers), and any run replays alone from its recorded run_seed.
//
// Draws, in this fixed order (changing the order changes every campaign; CampaignConfigHash does not
// see it, so the code version is recorded beside the results):
//   1. destination: bearing uniform on [0, 2π) from North, distance uniform on mission.distance_m;
//      home at the origin; an empty map (the city map comes later)
//   2. cruise speed uniform on mission.cruise_speed_mps
//   3. safety margin t_sf uniform on safety_margin_s
//   4. six initial cell voltages, pack 1 cells 1–3 then pack 2, each uniform on the range
//   5. per pack: health F1/F2/F3 by the weights; for F2/F3 the degraded cells (a uniform subset of
//      degraded_cells_per_pack cells), each with models::CellHealthForClass (M: power fade; P: both)
//   6. cold (probability cold_probability) → ambient cold_temp_degf, else warm_temp_degf
//   7. wind speed, direction, then the Dryden category uniform over the list
//   8. fault (probability fault.probability); if so onset = fraction × nominal plan duration with the
//      fraction uniform on onset_fraction, then the motor uniform over the list.
//
// The safety margin t_sf (Table 4.4) goes to SimOptions::safety_margin_s: the reach margin judges the plan
// with t_sf of extra time, RM = 1 − (t_remaining + t_sf) / t_EOD (the battery MDP's S1 ↔ EOD > RFD + t_sf of
// Table 4.1, carried to the CMA).
#include <array>
#include <cstdint>
#include <string>

#include "uascma/campaign/config.h"
#include "uascma/decision/cma_mdp.h"
#include "uascma/models/battery_pack.h"
#include "uascma/sim/simulator.h"

namespace uascma::campaign {

// Sub-streams of one run (DeriveSeed indices).
enum RunStream : std::uint64_t { kSamplerStream = 1, kSimulatorStream = 2 };

std::uint64_t RunSeed(std::uint64_t campaign_seed, std::int64_t run_index);

struct SampledRun {
  std::int64_t run_index = 0;
  std::uint64_t run_seed = 0;
  double distance_m = 0.0;        // destination distance from home
  double bearing_rad = 0.0;       // destination bearing from North, clockwise
  double cruise_speed_mps = 0.0;
  double safety_margin_s = 0.0;   // t_sf, also in scenario.options.safety_margin_s
  models::PerBranch<models::HealthClass> pack_health{};  // F1/F2/F3 per pack = G/M/P
  decision::BatteryHealth battery_health = decision::BatteryHealth::kG;  // composite BH (decisions 8)
  bool cold = false;
  double plan_duration_s = 0.0;   // the nominal delivery plan
  sim::Scenario scenario;         // ready to fly
};

// The campaign's city (built once per configuration and shared by every run; seed 0: an empty map).
std::shared_ptr<const planning::CityMap> CampaignMap(const MapSampling& sampling);

// Throws InputError when the configuration is invalid (CampaignConfig::IsValid).
SampledRun SampleRun(const CampaignConfig& config, std::uint64_t campaign_seed, std::int64_t run_index);

// "F1" | "F2" | "F3" for a pack's health class G | M | P (Table 4.2).
const char* PackConditionName(models::HealthClass health);
// Per-cell degradation as text: "-" none, "Q" capacity fade, "R" power fade, "QR" both; cells of a
// pack joined by ',' and packs by '|', e.g. "QR,-,-|-,-,-".
std::string CellHealthCode(const models::PerCell<models::CellHealth>& health);

}  // namespace uascma::campaign
