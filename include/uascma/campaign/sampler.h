#pragma once
// The scenario sampler of a Monte Carlo campaign (Table 4.4, §5.4, §5.5).
//
// A run's scenario is a pure function of (configuration, campaign seed, run index) (randomness is explicit):
//   run_seed          = DeriveSeed(campaign seed, run index)              (common/random.h)
//   sampler stream    = RandomStream(DeriveSeed(run_seed, kSamplerStream))
//   scenario.seed     = DeriveSeed(run_seed, kSimulatorStream)            (wind, sensor noise, spall growth)
// Every policy of the campaign flies the same scenario with the same scenario.seed: the comparison is
// paired (common random numbers), and any run replays alone from its recorded run_seed.
//
// Draws, in this fixed order (changing the order changes every campaign; CampaignConfigHash does not
// see it, so the code version is recorded beside the results):
//   1. cruise speed uniform on mission.cruise_speed_mps
//   2. safety margin t_sf uniform on safety_margin_s
//   3. six initial cell voltages, pack 1 cells 1–3 then pack 2, each uniform on the range
//   4. battery health BH (docs/modelling-choices.md#battery-health-draw): G, M or P by battery.health_weights; for M
//      and P, k cells (k uniform on battery.degraded_cells) chosen uniformly among the six; M: one fade kind, capacity
//      or power (½ each), drawn once for all k cells (battery.medium_fades: one_kind) or per cell (per_cell); P: the
//      first both, the others capacity, power or both (⅓ each). Pack labels F1/F2/F3
//      follow from the cells (models::ClassifyHealth), and the composite BH is the drawn one.
//   5. cold (probability cold_probability) → ambient cold_temp_degf, else warm_temp_degf
//   6. wind speed, direction, then the Dryden category uniform over the list
//   7. the route (docs/modelling-choices.md#campaign-missions, #battery-health-draw). The endurance fraction f uniform
//      on mission.endurance_fraction; then, until the route fits: home uniform over the city's area (RouteArea: over an
//      imported map the buildings' extent, so that routes fly over the city and not beside it, whatever the sites file
//      covers) on open ground with mission.wall_clearance_m from every wall (the origin on an empty map) and, over an
//      imported map, where it is built up (IsBuiltUp; a redraw of the home, no other draw), the bearing
//      uniform on [0, 2π) from North, and
//        I_cruise   = the largest steady current of the plan: level flight out, level flight back (airspeed
//                     |±V ê − w|, V the cruise speed, ê the bearing, w the mean wind) and the drop hover
//                     (airspeed |w|), CalcLevelFlightCurrent;
//        EOD_healthy = the end of discharge at I_cruise of this run's cell voltages and temperature with
//                     every cell healthy (F1/F1; prognostics::CalcPackEod);
//        plan duration = f (EOD_healthy − t_sf), so that plan + t_sf ≤ EOD_healthy;
//        distance   = the one whose delivery plan (planning::MakeDeliveryPlan) lasts exactly that long, at a
//                     cruise altitude 10 m above the tallest building within wall_clearance_m of the route
//                     that the lowest altitude would give (the longest route along the bearing; it clears
//                     the shorter final route too);
//      the destination must lie inside the city's area with wall_clearance_m from every wall, and over an imported map
//      where it is built up (IsBuiltUp; otherwise the attempt is redrawn). With mission.distance_m
//      set, the distance is drawn on it instead (the plan is then not tied to the pack).
//      Then the whole-load check (docs/modelling-choices.md#dissertation-profile, CalcWholeLoad below): a route whose
//      nominal plan fails it is not kept. An endurance-tied plan is first shortened, with the same home and bearing and
//      no draw, to 1 s (the load profile's bin; ours) below EOD_whole − t_sf, up to kMaxWholeLoadShortenings times; a
//      fixed-distance route, or one still failing, is redrawn (the next route attempt). Measured (seed 1, 465 runs
//      each): no run of examples/campaign.yaml fails it (smallest margin EOD_whole − (T + t_sf) 0.4 s), so the default
//      campaign is unchanged; 2 of examples/campaign-dissertation.yaml do (runs 257 and 336, short by 7.0 s and 16.1 s
//      of their whole load), each shortened once.
//   8. fault (probability fault.probability); if so onset = fraction × nominal plan duration with the
//      fraction uniform on onset_fraction, then the motor uniform over the list.
//   9. with pack_faults.share set, a sudden pack fault (campaign/pack_fault_sampling.h DrawPackFault) from its own
//      stream RandomStream(DeriveSeed(run_seed, kPackFaultStream)): the draws above do not change with it.
//
// The safety margin t_sf (Table 4.4) goes to SimOptions::safety_margin_s: the reach margin judges the plan
// with t_sf of extra time, RM = 1 − (t_remaining + t_sf) / t_EOD (the battery MDP's S1 ↔ EOD > RFD + t_sf of
// Table 4.1, carried to the CMA).
//
// The planning current is conservative where the flight draws more than its steady value: the bus voltage
// is the nominal 3.7 V per cell (kPlanningCellVoltage), below the ~3.8–4.1 V a pack holds over most of its
// discharge (the OCV table of docs/defaults.md#battery), so the current is overestimated while the climbs, gust
// corrections and the final sag are not modelled.
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "uascma/campaign/config.h"
#include "uascma/campaign/world.h"
#include "uascma/common/random.h"
#include "uascma/decision/cma_mdp.h"
#include "uascma/models/battery_pack.h"
#include "uascma/models/drag.h"
#include "uascma/planning/flight_plan.h"
#include "uascma/sim/simulator.h"

namespace uascma::campaign {

// The fades of k cells chosen uniformly among `cells` (the first k of a partial Fisher–Yates shuffle), realising
// health class M or P as Table 4.2 defines it (docs/modelling-choices.md#battery-health-draw): M one fade per cell,
// capacity (Q → 0.8 Q) or power (R0 → 2 R0), its kind drawn once for all k cells (MediumFades::kOneKind) or per cell; P
// the first cell both fades, each other one capacity fade, power fade or both, ⅓ each. G draws nothing. The cells start
// healthy. Campaigns draw over a battery's six cells (step 4 below), the battery MDP's flights over one pack's three.
void DrawCellFades(RandomStream& random, models::HealthClass health, int k, MediumFades medium_fades,
                   std::span<models::CellHealth* const> cells);

// Sub-streams of one run (DeriveSeed indices).
enum RunStream : std::uint64_t { kSamplerStream = 1, kSimulatorStream = 2, kPackFaultStream = 3 };

std::uint64_t RunSeed(std::uint64_t campaign_seed, std::int64_t run_index);

// V per cell: the nominal voltage of a LiPo cell (the usual 3.7 V rating; below the default OCV table's
// 3.8–4.1 V over most of a discharge, so the planning current errs high). Ours.
inline constexpr double kPlanningCellVoltage = 3.7;
// The planning voltage per cell of a scenario: kPlanningCellVoltage, and for a vehicle file's cells no more than the
// terminal voltage its healthy cell holds at half charge at the vehicle's hover power (eq. 3.3 with the RC pairs at
// their steady current, v = OCV(0.5) − (R0 + Σ R_j) i, the hover power shared by the six cells of the two
// branches): cells whose sag under the hover load takes them below 3.7 V would otherwise be planned too long
// (docs/modelling-choices.md#vehicle-file). The dissertation's vehicle keeps 3.7 V.
double CalcPlanningCellVoltage(const sim::Scenario& scenario);

// The pack current (A) of steady level flight at `airspeed` (m/s): the thrust tilted until its horizontal part
// balances the drag table's drag (models::DragTable::Default of the scenario's configuration), shared by six
// rotors, each drawing the power law of docs/defaults.md#vehicle, over a bus at kPlanningCellVoltage × 3, plus the
// hotel load.
double CalcLevelFlightCurrent(const sim::Scenario& scenario, const models::DragTable& drag, double airspeed);
// The largest of the out-leg, back-leg and drop-hover currents of a plan along `direction_NE` (step 7).
double CalcPlanCruiseCurrent(const sim::Scenario& scenario, const models::DragTable& drag,
                             const Eigen::Vector2d& direction_NE);
// End of discharge (s) of the battery with this spec's voltages and temperature but every cell healthy, at
// a constant current (A).
double CalcHealthyPackEod(const sim::BatterySpec& battery, double current_a);
// The same for the scenario's vehicle: its cells when it has a vehicle file (sim/vehicle_file.h).
double CalcHealthyPackEod(const sim::Scenario& scenario, double current_a);

// Flyability by a healthy pack (docs/modelling-choices.md#dissertation-profile) judged over the nominal plan's whole
// load (take-off climb, cruise, drop hover, descent, a gust allowance and t_sf), not at the cruise current alone
// (#campaign-missions).
//   E_rotor  = the plan's steady rotor energy, sim::LoadProfile(plan, {body, drag, power table, mean wind}, 6)
//              .RemainingEnergyJ(0): each one-second bin's thrust against gravity, the reference acceleration and
//              the drag at the reference air velocity (sim/load_forecast.h, what the flight's forecast uses);
//   P_gust   = the gust allowance, ours: the largest, over the plan's three level airspeeds (out leg, leg back, drop
//              hover; CalcPlanCruiseCurrent's), of the steady power at that airspeed raised by σ_u less the power at
//              it, σ_u the scenario's Dryden longitudinal intensity at the cruise altitude (models/wind.h), the same
//              1σ allowance as the speed cap's (sim/speed_cap.h); charged over the whole plan duration T;
//   I_whole  = I_hotel + (E_rotor + P_gust T) / (T V_bus), V_bus = kPlanningCellVoltage × 3 (as
//   CalcLevelFlightCurrent); EOD_whole = CalcHealthyPackEod at I_whole; the plan is flyable when EOD_whole >= T + t_sf.
struct WholeLoad {
  double rotor_energy_j = 0.0;    // E_rotor
  double gust_sigma_u_mps = 0.0;  // σ_u at the cruise altitude
  double gust_power_w = 0.0;      // P_gust
  double current_a = 0.0;         // I_whole
  double eod_s = 0.0;             // EOD_whole
  // The plan's load profile (rotor_energy_j is its whole energy), keyed for a flight model (sim/load_forecast.h):
  // with `drag` the configuration's default table it is the flight's nominal profile.
  std::shared_ptr<const sim::KeyedLoadProfile> profile;
};
// At most this many shortenings of one route attempt's endurance-tied plan before the route is redrawn (step 7).
inline constexpr int kMaxWholeLoadShortenings = 20;
WholeLoad CalcWholeLoad(const sim::Scenario& scenario, const models::DragTable& drag, const planning::FlightPlan& plan);

struct SampledRun {
  std::int64_t run_index = 0;
  std::uint64_t run_seed = 0;
  double distance_m = 0.0;   // destination distance from home
  double bearing_rad = 0.0;  // destination bearing from North, clockwise
  double cruise_speed_mps = 0.0;
  double safety_margin_s = 0.0;                          // t_sf, also in scenario.options.safety_margin_s
  models::PerBranch<models::HealthClass> pack_health{};  // F1/F2/F3 per pack = G/M/P, from the cells
  // BH drawn (docs/modelling-choices.md#battery-health-label, #battery-health-draw)
  decision::BatteryHealth battery_health = decision::BatteryHealth::kG;
  bool cold = false;
  double plan_duration_s = 0.0;       // the nominal delivery plan
  double endurance_fraction = 0.0;    // f of step 7 (0 when the distance was drawn instead)
  double cruise_current_a = 0.0;      // I_cruise of step 7
  double healthy_eod_s = 0.0;         // EOD_healthy of step 7
  // I_whole of the nominal plan (CalcWholeLoad, docs/modelling-choices.md#dissertation-profile)
  double whole_load_current_a = 0.0;
  double whole_load_eod_s = 0.0;      // EOD_whole: >= plan_duration_s + safety_margin_s for every sampled run
  int whole_load_refits = 0;          // how often the check failed while step 7 drew this run (shortened or redrawn)
  sim::Scenario scenario;             // ready to fly
};

// The horizontal extent of the map's buildings (m; empty without buildings).
Eigen::AlignedBox2d BuildingsExtent(const planning::CityMap& map);
// Where step 7 draws homes and destinations: an imported map's buildings' extent (its sites may lie elsewhere);
// the procedural city's bounds (unchanged: its sites lie among its blocks).
Eigen::AlignedBox2d RouteArea(const planning::CityMap& map, const MapSampling& sampling);
// Is the map built up at `p_NE`: a building's outline or a landing site within LandPract's reach
// (planning::LandPractParams::site_search_radius, 500 m)? Over an imported map step 7 keeps a home and a
// destination only where it is (docs/modelling-choices.md#campaign-routes-built-up): an extract of a region holds
// towns and the open land between them, and deliveries start and end where people are.
bool IsBuiltUp(const planning::CityMap& map, const Eigen::Vector2d& p_NE);

// Do the landing sites cover the sampled routes? For the first `runs` runs of the campaign (their nominal delivery
// plans), the LandPract checkpoints (planning::LandPractParams: checkpoint_count at arc lengths k L / (N + 1)) and
// whether any site lies within the planners' reach of each (LandPractParams::site_search_radius, 500 m).
struct SiteCoverage {
  int runs = 0;
  int checkpoints = 0;
  int checkpoints_without_site = 0;  // no site within `reach`
  int runs_with_uncovered_checkpoint = 0;
  double reach = 0.0;        // m
  double largest_gap = 0.0;  // m: the largest distance from a checkpoint to its nearest site (≤ the
                             // map's diagonal; +inf without sites)
  int sites = 0;             // the map's, of every origin:
  bool sites_from_map = false;   // the map supplies sites of its own (map.sites_from_map, or no sites file)
  int rooftop_sites_from_map = 0;
  int open_area_sites_from_map = 0;
  bool covered() const { return checkpoints_without_site == 0; }
  // One paragraph: the numbers, and what to do when checkpoints are uncovered.
  std::string BriefReport() const;
};
SiteCoverage CalcSiteCoverage(const CampaignConfig& config, std::uint64_t campaign_seed, std::int64_t runs);

// Throws InputError when the configuration is invalid (CampaignConfig::IsValid). `world` is
// BuildCampaignWorld(config.map), built once by the caller and shared by every run (campaign/world.h).
SampledRun SampleRun(const CampaignConfig& config, const CampaignWorld& world, std::uint64_t campaign_seed,
                     std::int64_t run_index);
// One run alone (a replay, a test): builds the world for it. Callers sampling many runs build it once (above).
SampledRun SampleRun(const CampaignConfig& config, std::uint64_t campaign_seed, std::int64_t run_index);

// "F1" | "F2" | "F3" for a pack's health class G | M | P (Table 4.2).
const char* PackConditionName(models::HealthClass health);
// Per-cell degradation as text: "-" none, "Q" capacity fade, "R" power fade, "QR" both; cells of a
// pack joined by ',' and packs by '|', e.g. "QR,-,-|-,-,-".
std::string CellHealthCode(const models::PerCell<models::CellHealth>& health);

}  // namespace uascma::campaign
