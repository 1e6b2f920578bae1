#include "uascma/campaign/sampler.h"

#include <algorithm>
#include <array>
#include <memory>

#include <cmath>
#include <limits>
#include <numeric>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/frames.h"
#include "uascma/common/random.h"
#include "uascma/models/drag.h"
#include "uascma/models/mixer.h"
#include "uascma/models/propulsion.h"
#include "uascma/models/wind.h"
#include "uascma/planning/flight_plan.h"
#include "uascma/planning/land_pract.h"
#include "uascma/prognostics/eod.h"
#include "uascma/sim/load_forecast.h"
#include "uascma/sim/vehicle_file.h"

namespace uascma::campaign {
namespace {

double Draw(RandomStream& random, const Range& range) { return random.Uniform(range.low, range.high); }

// Index drawn with probability weight[i] / Σ weight.
int DrawWeighted(RandomStream& random, const std::vector<double>& weight) {
  const double total = std::accumulate(weight.begin(), weight.end(), 0.0);
  double u = random.Uniform() * total;
  for (std::size_t i = 0; i < weight.size(); ++i) {
    if (u < weight[i]) return static_cast<int>(i);
    u -= weight[i];
  }
  // Round-off at the top end: the last category with a positive weight.
  for (std::size_t i = weight.size(); i-- > 0;) {
    if (weight[i] > 0.0) return static_cast<int>(i);
  }
  return 0;
}

// Step 4 of the header: the flight's battery health and the cells that realise it (Table 4.2).
decision::BatteryHealth DrawBatteryHealth(RandomStream& random, const BatterySampling& battery,
                                          models::PerCell<models::CellHealth>& cells) {
  const auto health = static_cast<decision::BatteryHealth>(DrawWeighted(random, battery.health_weights));
  cells = {};
  if (health == decision::BatteryHealth::kG) return health;
  const int k = battery.degraded_cells.low + static_cast<int>(random.UniformIndex(static_cast<std::uint64_t>(
                                                 battery.degraded_cells.high - battery.degraded_cells.low + 1)));
  std::array<models::CellHealth*, models::kBranchCount * models::kCellsPerBranch> six;
  for (int b = 0; b < models::kBranchCount; ++b) {
    for (int c = 0; c < models::kCellsPerBranch; ++c) six[b * models::kCellsPerBranch + c] = &cells[b][c];
  }
  DrawCellFades(random, static_cast<models::HealthClass>(static_cast<int>(health)), k, battery.medium_fades, six);
  return health;
}

// Horizontal point clear of every building by `clearance` (m): not inside an outline and no wall nearer.
bool ClearOfBuildings(const planning::CityMap& map, const Eigen::Vector2d& p_NE, double clearance) {
  if (map.BuildingContaining(Eigen::Vector3d(p_NE.x(), p_NE.y(), -0.1)) != planning::kNoBuilding) return false;
  const std::array<Eigen::Vector2d, 1> point = {p_NE};
  return map.TallestBuildingUnder(point, clearance).building == planning::kNoBuilding;
}

// The inverse of the delivery plan's duration in the horizontal distance (planning::MakeDeliveryPlan: a
// vertical climb, the move out, the drop hover, the move back, the vertical descent, each rest to rest with
// the trapezoid of planning::CalcTrapezoid). Returns the distance whose plan lasts `duration` s, or a
// negative number when even a zero distance lasts longer.
double DistanceForPlanDuration(double duration, double cruise_altitude, double drop_hover_s,
                               const planning::PlanLimits& limits) {
  const double vertical =
      planning::CalcTrapezoid(cruise_altitude, limits.vertical_speed, limits.vertical_accel).duration;
  const double leg = 0.5 * (duration - 2.0 * vertical - drop_hover_s);  // s per horizontal move
  if (leg < 0.0) return -1.0;
  const double v = limits.cruise_speed;
  const double a = limits.horizontal_accel;
  // Trapezoid: t = 2 v/a + (d − v²/a)/v for d ≥ v²/a; triangle: t = 2 √(d/a) below.
  if (leg >= 2.0 * v / a) return v * v / a + (leg - 2.0 * v / a) * v;
  return a * 0.25 * leg * leg;
}

}  // namespace

void DrawCellFades(RandomStream& random, models::HealthClass health, int k, MediumFades medium_fades,
                   std::span<models::CellHealth* const> cells) {
  if (health == models::HealthClass::kG) return;
  UASCMA_CHECK(k >= 0 && static_cast<std::size_t>(k) <= cells.size(), "at most as many faded cells as cells");
  // A uniform k-subset: the first k of a partial Fisher–Yates shuffle.
  std::array<int, models::kBranchCount * models::kCellsPerBranch> order;
  UASCMA_CHECK(cells.size() <= order.size(), "at most a battery's cells");
  const int n = static_cast<int>(cells.size());
  for (int i = 0; i < n; ++i) order[i] = i;
  for (int i = 0; i < k; ++i) {
    const int j = i + static_cast<int>(random.UniformIndex(static_cast<std::uint64_t>(n - i)));
    std::swap(order[i], order[j]);
  }
  // M, one kind for all k cells (Table 4.2, config.h MediumFades): drawn once, after the cells.
  const bool one_kind = health == models::HealthClass::kM && medium_fades == MediumFades::kOneKind;
  const bool capacity_kind = one_kind && random.Bernoulli(0.5);
  for (int i = 0; i < k; ++i) {
    models::CellHealth& cell = *cells[order[i]];
    if (one_kind) {
      cell.capacity_fade = capacity_kind;
      cell.power_fade = !capacity_kind;
    } else if (health == models::HealthClass::kM) {
      // M per cell: one fade, not both; which one drawn per cell (docs/modelling-choices.md#battery-health-draw).
      if (random.Bernoulli(0.5)) {
        cell.capacity_fade = true;
      } else {
        cell.power_fade = true;
      }
    } else if (i == 0) {
      // P: at least one cell with both fades.
      cell.capacity_fade = cell.power_fade = true;
    } else {
      // P, the other cells: capacity fade, power fade or both, ⅓ each.
      const auto kind = random.UniformIndex(3);
      cell.capacity_fade = kind != 1;
      cell.power_fade = kind != 0;
    }
  }
}

std::uint64_t RunSeed(std::uint64_t campaign_seed, std::int64_t run_index) {
  return DeriveSeed(campaign_seed, static_cast<std::uint64_t>(run_index));
}

Eigen::AlignedBox2d BuildingsExtent(const planning::CityMap& map) {
  Eigen::AlignedBox2d extent;
  for (int k = 0; k < static_cast<int>(map.buildings().size()); ++k) extent.extend(map.building_box(k));
  return extent;
}

Eigen::AlignedBox2d RouteArea(const planning::CityMap& map, const MapSampling& sampling) {
  return sampling.imported() ? BuildingsExtent(map) : map.bounds();
}

bool IsBuiltUp(const planning::CityMap& map, const Eigen::Vector2d& p_NE) {
  const double radius = planning::LandPractParams{}.site_search_radius;
  const std::array<Eigen::Vector2d, 1> point = {p_NE};
  if (map.TallestBuildingUnder(point, radius).building != planning::kNoBuilding) return true;
  return !map.SitesWithinRadius(p_NE, radius).empty();
}

double CalcPlanningCellVoltage(const sim::Scenario& scenario) {
  if (!scenario.vehicle) return kPlanningCellVoltage;
  const models::PackParams pack = sim::ScenarioPackParams(scenario, {}, scenario.battery.ambient_temp_degf);
  const models::CellParams& cell = pack.cells[0][0];
  double resistance_ohm = cell.r0_ohm;
  for (int j = 0; j < cell.rc_pair_count; ++j) resistance_ohm += cell.rc[j].resistance_ohm;
  const double ocv_v = pack.ocv.CalcVoltage(0.5);
  const double hover_w =
      models::kRotorCount * models::CalcElectricalPower(sim::ScenarioPropulsion(scenario),
                                                        scenario.body.mass * kGravity / models::kRotorCount);
  // v = OCV(0.5) − R i, i = P / (2 branches × 3 cells × v): the larger root of 6 v² − 6 OCV v + R P = 0.
  const double discriminant =
      ocv_v * ocv_v - 4.0 * resistance_ohm * hover_w / (models::kBranchCount * models::kCellsPerBranch);
  if (!(discriminant > 0.0)) return std::min(kPlanningCellVoltage, 0.5 * ocv_v);  // past the pack's peak power
  return std::min(kPlanningCellVoltage, 0.5 * (ocv_v + std::sqrt(discriminant)));
}

double CalcLevelFlightCurrent(const sim::Scenario& scenario, const models::DragTable& drag, double airspeed) {
  if (!(std::isfinite(airspeed) && airspeed >= 0.0)) {
    throw InputError("CalcLevelFlightCurrent", "airspeed", fmt::format("a finite speed >= 0 m/s, got {}", airspeed));
  }
  const double weight = scenario.body.mass * kGravity;
  // Level flight: the thrust tilts by φ until its horizontal part balances the drag at that incidence,
  // tan φ = D(V, φ) / (m g) (the rigid body's drag, models/drag.h); a fixed-point iteration, a contraction
  // since D/(m g) < 0.3 over the table.
  double tilt = 0.0;
  for (int i = 0; i < 100; ++i) {
    const double next = std::atan(drag.Drag(airspeed, tilt) / weight);
    const bool converged = std::abs(next - tilt) < 1e-12;
    tilt = next;
    if (converged) break;
  }
  const double thrust = weight / std::cos(tilt);  // = √((m g)² + D²)
  // Six rotors share it equally; each draws the power law of docs/defaults.md#vehicle; I = P / V_bus (eq. 2.10).
  const models::PropulsionParams propulsion = sim::ScenarioPropulsion(scenario);
  const double power = 6.0 * models::CalcElectricalPower(propulsion, thrust / 6.0);
  return scenario.options.hotel_current_a + power / (CalcPlanningCellVoltage(scenario) * models::kCellsPerBranch);
}

double CalcPlanCruiseCurrent(const sim::Scenario& scenario, const models::DragTable& drag,
                             const Eigen::Vector2d& direction_NE) {
  const Eigen::Vector2d wind_NE = scenario.wind.mean_speed * Eigen::Vector2d(std::cos(scenario.wind.direction_rad),
                                                                             std::sin(scenario.wind.direction_rad));
  const Eigen::Vector2d ground_NE = scenario.limits.cruise_speed * direction_NE.normalized();
  // The out leg, the leg back, and the drop hover (airspeed = the wind): the largest current of the three.
  return std::max({CalcLevelFlightCurrent(scenario, drag, (ground_NE - wind_NE).norm()),
                   CalcLevelFlightCurrent(scenario, drag, (-ground_NE - wind_NE).norm()),
                   CalcLevelFlightCurrent(scenario, drag, wind_NE.norm())});
}

double CalcHealthyPackEod(const sim::BatterySpec& battery, double current_a) {
  sim::Scenario scenario;
  scenario.battery = battery;
  return CalcHealthyPackEod(scenario, current_a);
}

double CalcHealthyPackEod(const sim::Scenario& scenario, double current_a) {
  const sim::BatterySpec& battery = scenario.battery;
  const models::BatteryPack pack(sim::ScenarioPackParams(scenario, {}, battery.ambient_temp_degf));
  const models::PackState state = pack.MakeRestingState(battery.initial_cell_voltage_v);
  return prognostics::CalcPackEod(pack, state, current_a).eod_s;
}

WholeLoad CalcWholeLoad(const sim::Scenario& scenario, const models::DragTable& drag,
                        const planning::FlightPlan& plan) {
  const double duration = plan.duration();
  UASCMA_CHECK(duration > 0.0, "a nominal plan of positive duration");
  WholeLoad load;
  const models::ElectricalPowerTable power(sim::ScenarioPropulsion(scenario));
  const Eigen::Vector3d mean_wind_W = models::WindModel(scenario.wind).MeanWind_W();
  // The flight's own load model (sim/flight.cc's steady_load_): the take-off climb, both legs, the drop hover and
  // the descent, each second's thrust with its acceleration and drag.
  const sim::SteadyLoadModel model{&scenario.body, &drag, &power, mean_wind_W};
  load.profile = std::make_shared<const sim::KeyedLoadProfile>(sim::KeyedLoadProfile{
      plan, scenario.body, scenario.configuration, mean_wind_W, sim::LoadProfile(plan, model, models::kRotorCount),
      scenario.vehicle ? scenario.vehicle->content_hash : std::string()});
  load.rotor_energy_j = load.profile->profile.RemainingEnergyJ(0.0);
  // The gust allowance (ours, the speed cap's 1σ, sim/speed_cap.h): at each level airspeed of the plan the steady
  // power at that airspeed raised by σ_u, less the power at it; the largest of the three over the whole plan.
  load.gust_sigma_u_mps = models::CalcDrydenIntensity(scenario.wind.turbulence, scenario.mission.cruise_altitude,
                                                      scenario.wind.medium_band_altitude)
                              .sigma_u;
  const sim::SteadyLoadModel still_air{&scenario.body, &drag, &power, Eigen::Vector3d::Zero()};
  const auto level_power = [&](double airspeed) {
    return sim::CalcSteadyRotorPower(still_air, Eigen::Vector3d(airspeed, 0.0, 0.0), Eigen::Vector3d::Zero(),
                                     models::kRotorCount);
  };
  const Eigen::Vector2d wind_NE = mean_wind_W.head<2>();
  const Eigen::Vector2d route_NE = scenario.mission.destination_NE - scenario.mission.home_NE;
  const Eigen::Vector2d ground_NE = route_NE.norm() > 0.0
                                        ? Eigen::Vector2d(scenario.limits.cruise_speed * route_NE.normalized())
                                        : Eigen::Vector2d::Zero();
  for (const double airspeed : {(ground_NE - wind_NE).norm(), (-ground_NE - wind_NE).norm(), wind_NE.norm()}) {
    load.gust_power_w =
        std::max(load.gust_power_w, level_power(airspeed + load.gust_sigma_u_mps) - level_power(airspeed));
  }
  // Power to pack current as CalcLevelFlightCurrent: over a bus at the planning voltage, plus the hotel load.
  const double bus_voltage = CalcPlanningCellVoltage(scenario) * models::kCellsPerBranch;
  load.current_a = scenario.options.hotel_current_a +
                   (load.rotor_energy_j + load.gust_power_w * duration) / (duration * bus_voltage);
  load.eod_s = CalcHealthyPackEod(scenario, load.current_a);
  return load;
}

namespace {

// Route attempts at most (step 7): the whole route, and the home within one route.
constexpr int kMaxRouteAttempts = 10000;

// Steps 1–2: cruise speed, then the safety margin t_sf.
void DrawMission(RandomStream& random, const CampaignConfig& config, SampledRun& run) {
  // 1. Cruise speed.
  run.cruise_speed_mps = Draw(random, config.mission.cruise_speed_mps);
  run.scenario.limits.cruise_speed = run.cruise_speed_mps;

  // 2. Safety margin t_sf.
  run.safety_margin_s = Draw(random, config.safety_margin_s);
  run.scenario.options.safety_margin_s = run.safety_margin_s;
}

// Steps 3–5: the initial cell voltages, the battery health with its degraded cells, the ambient temperature.
void DrawBattery(RandomStream& random, const BatterySampling& battery, SampledRun& run) {
  sim::Scenario& scenario = run.scenario;
  // 3. Initial cell voltages, pack 1 cells 1–3 then pack 2.
  for (auto& pack : scenario.battery.initial_cell_voltage_v) {
    for (double& voltage : pack) voltage = Draw(random, battery.initial_cell_voltage_v);
  }

  // 4. Battery health and the degraded cells; the per-pack labels follow from the cells.
  run.battery_health = DrawBatteryHealth(random, battery, scenario.battery.cell_health);
  for (int b = 0; b < models::kBranchCount; ++b) {
    run.pack_health[b] = models::ClassifyHealth(scenario.battery.cell_health[b]);
  }
  UASCMA_CHECK(
      static_cast<int>(models::ClassifyHealth(scenario.battery.cell_health)) == static_cast<int>(run.battery_health),
      "the drawn cells realise the drawn battery health");

  // 5. Ambient temperature: only the 50 °F split matters (Table 3.2).
  run.cold = random.Bernoulli(battery.cold_probability);
  scenario.battery.ambient_temp_degf = run.cold ? battery.cold_temp_degf : battery.warm_temp_degf;
}

// Step 6: wind speed, direction, then the Dryden category.
void DrawWind(RandomStream& random, const WindSampling& wind, SampledRun& run) {
  run.scenario.wind.mean_speed = Draw(random, wind.speed_mps);
  run.scenario.wind.direction_rad = Draw(random, wind.direction_rad);
  run.scenario.wind.turbulence = wind.turbulence[random.UniformIndex(wind.turbulence.size())];
}

// Step 7, the home of one route attempt: uniform over `bounds` (the city's area, RouteArea) until it is on open
// ground with `clearance` (m) from every wall and, with `built_up` (an imported map), where the map is built up
// (IsBuiltUp); the origin on an empty map.
Eigen::Vector2d DrawHome(RandomStream& random, const planning::CityMap& map, const Eigen::AlignedBox2d& bounds,
                         double clearance, bool built_up) {
  if (map.buildings().empty()) return Eigen::Vector2d::Zero();
  Eigen::Vector2d home_NE;
  int home_attempts = 0;
  do {
    if (++home_attempts > kMaxRouteAttempts) {
      throw InputError("campaign", "mission.wall_clearance_m",
                       fmt::format("a clearance that leaves open ground in the city, got {} m", clearance));
    }
    home_NE = Eigen::Vector2d(random.Uniform(bounds.min().x(), bounds.max().x()),
                              random.Uniform(bounds.min().y(), bounds.max().y()));
  } while (!ClearOfBuildings(map, home_NE, clearance) || (built_up && !IsBuiltUp(map, home_NE)));
  return home_NE;
}

// Step 7, the distance tied to the pack for the home and bearing of one route attempt (no draw): sets the run's
// I_cruise and EOD_healthy, on a city the cruise altitude, and the distance. `lowest_cruise`: the cruise
// altitude never goes below it (DrawRoute).
void SetEnduranceTiedDistance(SampledRun& run, const models::DragTable& drag, const Eigen::Vector2d& direction,
                              double clearance, double lowest_cruise, double longest_plan_s) {
  sim::Scenario& scenario = run.scenario;
  const planning::CityMap& map = *scenario.map;
  // docs/modelling-choices.md#campaign-missions: plan = f (EOD_healthy − t_sf) at the plan's cruise current, the
  // distance from it.
  run.cruise_current_a = CalcPlanCruiseCurrent(scenario, drag, direction);
  run.healthy_eod_s = CalcHealthyPackEod(scenario, run.cruise_current_a);
  // `longest_plan_s`: the whole-load check's shortening (DrawRoute); +inf on a route's first pass.
  const double target_s = std::min(run.endurance_fraction * (run.healthy_eod_s - run.safety_margin_s), longest_plan_s);
  if (!map.buildings().empty()) {
    // The altitude over the route and the route's length depend on each other. The route drawn with the
    // lowest possible altitude (no building under it) is the longest; 10 m above its tallest building
    // clears every shorter route along the same bearing, and the distance is then derived at that altitude.
    const double lowest = planning::kCruiseClearanceAboveBuildings;
    const double longest = DistanceForPlanDuration(target_s, lowest, scenario.mission.drop_hover_s, scenario.limits);
    if (longest < 0.0) {
      throw InputError("campaign", "mission.endurance_fraction",
                       "plans long enough for the climb, the drop hover and the descent");
    }
    const std::array<Eigen::Vector2d, 2> outer = {scenario.mission.home_NE,
                                                  scenario.mission.home_NE + longest * direction};
    scenario.mission.cruise_altitude =
        std::max(map.CruiseAltitude(outer, planning::kCruiseClearanceAboveBuildings, clearance), lowest_cruise);
  }
  run.distance_m = DistanceForPlanDuration(target_s, scenario.mission.cruise_altitude, scenario.mission.drop_hover_s,
                                           scenario.limits);
  if (run.distance_m < 0.0) {
    throw InputError("campaign", "mission.endurance_fraction",
                     "plans long enough for the climb, the drop hover and the descent");
  }
}

// What DrawRoute needs of one campaign for every route attempt.
struct RouteContext {
  const planning::CityMap& map;
  Eigen::AlignedBox2d bounds;
  double clearance = 0.0;
  bool endurance_tied = false;
  double lowest_cruise = 0.0;
  models::DragTable drag;
  bool built_up_ends = false;  // home and destination where the map is built up (IsBuiltUp): an imported map
};

// Step 7 for the home and bearing of one attempt (drawn already; only a fixed distance is drawn here): the distance,
// the destination, the cruise altitude, the nominal plan's duration and its whole-load check
// (docs/modelling-choices.md#dissertation-profile). False when the attempt is to be redrawn: the destination outside
// the city's area or too near a wall, or the plan failing the whole-load check after kMaxWholeLoadShortenings
// shortenings (an endurance-tied plan) or at once (a fixed distance).
bool FitRoute(RandomStream& random, const CampaignConfig& config, const RouteContext& route, SampledRun& run) {
  sim::Scenario& scenario = run.scenario;
  const bool city = !route.map.buildings().empty();
  const Eigen::Vector2d direction(std::cos(run.bearing_rad), std::sin(run.bearing_rad));
  if (!route.endurance_tied) run.distance_m = Draw(random, *config.mission.distance_m);
  double longest_plan_s = std::numeric_limits<double>::infinity();
  for (int shortening = 0;; ++shortening) {
    scenario.mission.cruise_altitude = config.mission.cruise_altitude_m;
    if (route.endurance_tied) {
      SetEnduranceTiedDistance(run, route.drag, direction, route.clearance, route.lowest_cruise, longest_plan_s);
    }
    scenario.mission.destination_NE = scenario.mission.home_NE + run.distance_m * direction;
    if (city) {
      if (!route.bounds.contains(scenario.mission.destination_NE) ||
          !ClearOfBuildings(route.map, scenario.mission.destination_NE, route.clearance) ||
          (route.built_up_ends && !IsBuiltUp(route.map, scenario.mission.destination_NE))) {
        return false;
      }
      if (!route.endurance_tied) {
        const std::array<Eigen::Vector2d, 2> ends = {scenario.mission.home_NE, scenario.mission.destination_NE};
        scenario.mission.cruise_altitude =
            std::max(route.map.CruiseAltitude(ends, planning::kCruiseClearanceAboveBuildings, route.clearance),
                     route.lowest_cruise);
      }
    }
    const planning::FlightPlan plan = planning::MakeDeliveryPlan(scenario.mission, scenario.limits);
    run.plan_duration_s = plan.duration();
    const WholeLoad load = CalcWholeLoad(scenario, route.drag, plan);
    run.whole_load_current_a = load.current_a;
    run.whole_load_eod_s = load.eod_s;
    if (run.whole_load_eod_s >= run.plan_duration_s + run.safety_margin_s) {
      // The flight model's own profile (route.drag is the configuration's default table, DrawRoute; FlightModel
      // checks the rest of the key): built once per run.
      scenario.nominal_load_profile = load.profile;
      return true;
    }
    ++run.whole_load_refits;
    if (!route.endurance_tied || shortening >= kMaxWholeLoadShortenings) return false;
    // 1 s (the load profile's bin) below what the whole load allows: a shorter plan's mean current is a little
    // higher (the climb and descent weigh more), so the limit itself would be approached from above only.
    longest_plan_s = run.whole_load_eod_s - run.safety_margin_s - 1.0;
  }
}

// Step 7: the route. The endurance fraction, then home (on open ground, clear of every wall) and the bearing,
// redrawn until the destination is inside the city and clear of every wall too and the nominal plan passes the
// whole-load check (FitRoute); I_cruise and EOD_healthy also of a drawn distance.
void DrawRoute(RandomStream& random, const CampaignConfig& config, SampledRun& run) {
  sim::Scenario& scenario = run.scenario;
  const planning::CityMap& map = *scenario.map;
  // An imported map covers only what its files hold: a route with no building under it crosses a hole in the data
  // (Manhattan is built up), not open ground, so it never cruises below the open-ground altitude. Measured:
  // at 10 m over such holes the low-altitude Dryden gusts upset 2 of 300 fault-free flights at ~8 m/s.
  const RouteContext route{map,
                           RouteArea(map, config.map),
                           config.mission.wall_clearance_m,
                           !config.mission.distance_m.has_value(),
                           config.map.imported() ? config.mission.cruise_altitude_m : 0.0,
                           sim::ScenarioDrag(scenario),
                           config.map.imported()};
  if (route.endurance_tied) run.endurance_fraction = Draw(random, config.mission.endurance_fraction);
  for (int attempt = 0;; ++attempt) {
    if (attempt > kMaxRouteAttempts) {
      throw InputError("campaign", route.endurance_tied ? "map" : "mission.distance_m",
                       fmt::format("a city large enough for the sampled routes with {} m from every wall, and plans a "
                                   "healthy pack flies over their whole load (no route fit in {} attempts, run {})",
                                   route.clearance, kMaxRouteAttempts, run.run_index));
    }
    scenario.mission.home_NE = DrawHome(random, map, route.bounds, route.clearance, route.built_up_ends);
    run.bearing_rad = random.Uniform(0.0, 2.0 * kPi);
    if (FitRoute(random, config, route, run)) break;
  }
  if (!route.endurance_tied) {
    // Recorded for every run: the healthy pack's EOD at the plan's cruise current (not used to draw it).
    run.cruise_current_a = CalcPlanCruiseCurrent(scenario, route.drag,
                                                 Eigen::Vector2d(std::cos(run.bearing_rad), std::sin(run.bearing_rad)));
    run.healthy_eod_s = CalcHealthyPackEod(scenario, run.cruise_current_a);
  }
}

// Step 8: the spall fault, its onset uniform over the nominal flight (after DrawRoute: needs the plan's duration).
void DrawFault(RandomStream& random, const FaultSampling& fault, SampledRun& run) {
  sim::FaultSpec& spec = run.scenario.fault;
  spec = sim::FaultSpec{};
  spec.enabled = random.Bernoulli(fault.probability);
  if (spec.enabled) {
    spec.spall_onset_s = Draw(random, fault.onset_fraction) * run.plan_duration_s;
    spec.motor = fault.motors[random.UniformIndex(fault.motors.size())];
    spec.time_per_growth_step_s = fault.time_per_growth_step_s;
    spec.prognosis_time_per_growth_step_s = fault.prognosis_time_per_growth_step_s;
  }
}

}  // namespace

SampledRun SampleRun(const CampaignConfig& config, std::uint64_t campaign_seed, std::int64_t run_index) {
  return SampleRun(config, BuildCampaignWorld(config), campaign_seed, run_index);
}

SampledRun SampleRun(const CampaignConfig& config, const CampaignWorld& world, std::uint64_t campaign_seed,
                     std::int64_t run_index) {
  std::string error;
  if (!config.IsValid(&error)) throw InputError("campaign configuration: " + error);
  if (run_index < 0) throw InputError("campaign", "run index", fmt::format(">= 0, got {}", run_index));

  SampledRun run;
  run.run_index = run_index;
  run.run_seed = RunSeed(campaign_seed, run_index);
  RandomStream random(DeriveSeed(run.run_seed, kSamplerStream));
  sim::Scenario& scenario = run.scenario;
  scenario.name = fmt::format("{} run {}", config.name, run_index);
  scenario.seed = DeriveSeed(run.run_seed, kSimulatorStream);
  scenario.map = world.map;
  scenario.map_obstacles = world.obstacles;
  sim::UseVehicle(scenario, world.vehicle);  // the campaign's vehicle file, or the dissertation's (null)
  // Over an imported map the run has a geodetic frame (the map's origin): its plans export for QGroundControl,
  // also when it is replayed from the results database.
  if (config.map.imported()) scenario.geo_origin = world.origin;
  scenario.mission.drop_hover_s = config.mission.drop_hover_s;
  scenario.options.eod_load = config.options.eod_load;
  scenario.options.cap_speed_after_isolation = config.options.cap_speed_after_isolation;
  if (config.options.termination) scenario.options.termination = *config.options.termination;
  if (config.options.pack_rate_hz) scenario.options.pack_rate_hz = *config.options.pack_rate_hz;
  if (config.options.wind_rate_hz) scenario.options.wind_rate_hz = *config.options.wind_rate_hz;
  if (config.options.noisy_sensing) scenario.options.noisy_sensing = *config.options.noisy_sensing;

  // The draws in the header's fixed order (sampler.h): changing it changes every campaign.
  DrawMission(random, config, run);          // 1–2
  DrawBattery(random, config.battery, run);  // 3–5
  DrawWind(random, config.wind, run);        // 6
  DrawRoute(random, config, run);            // 7
  DrawFault(random, config.fault, run);      // 8
  // 9: a sudden pack fault (campaign/pack_fault_sampling.h), from its own stream so that every draw above keeps its
  // value; nothing is drawn without one.
  if (config.pack_faults.share) {
    RandomStream pack_fault_random(DeriveSeed(run.run_seed, kPackFaultStream));
    scenario.pack_fault = DrawPackFault(pack_fault_random, config.pack_faults.Sampling(), run.plan_duration_s);
  }
  return run;
}

SiteCoverage CalcSiteCoverage(const CampaignConfig& config, std::uint64_t campaign_seed, std::int64_t runs) {
  const planning::LandPractParams land_pract;  // the simulator's (sim/emergency_planner.cc builds it with defaults)
  SiteCoverage coverage;
  coverage.reach = land_pract.site_search_radius;
  const CampaignWorld world = BuildCampaignWorld(config);
  const std::shared_ptr<const planning::CityMap> map = world.map;
  coverage.sites = static_cast<int>(map->sites().size());
  coverage.sites_from_map = world.sites_from_map;
  coverage.rooftop_sites_from_map = world.rooftop_sites_from_map;
  coverage.open_area_sites_from_map = world.open_area_sites_from_map;
  for (std::int64_t r = 0; r < runs; ++r) {
    const SampledRun run = SampleRun(config, world, campaign_seed, r);
    const planning::FlightPlan plan = planning::MakeDeliveryPlan(run.scenario.mission, run.scenario.limits);
    const double length = plan.Length();
    bool uncovered = false;
    for (int k = 1; k <= land_pract.checkpoint_count; ++k) {
      // LandPract's checkpoints (land_pract.cc): arc lengths k L / (N + 1).
      const Eigen::Vector2d p_NE = plan.PointAtDistance(length * k / (land_pract.checkpoint_count + 1)).head<2>();
      double nearest = std::numeric_limits<double>::infinity();
      for (const planning::LandingSite& site : map->sites())
        nearest = std::min(nearest, (site.p_W.head<2>() - p_NE).norm());
      coverage.largest_gap = std::max(coverage.largest_gap, nearest);
      ++coverage.checkpoints;
      if (!(nearest <= coverage.reach)) {
        ++coverage.checkpoints_without_site;
        uncovered = true;
      }
    }
    ++coverage.runs;
    coverage.runs_with_uncovered_checkpoint += uncovered ? 1 : 0;
  }
  return coverage;
}

std::string SiteCoverage::BriefReport() const {
  std::string text = fmt::format(
      "landing-site coverage: {} of {} checkpoints ({} runs, {} per plan) have no landing site within {:.0f} m "
      "(LandPract's reach); {} of the runs have such a checkpoint; largest checkpoint-to-site distance {:.0f} m; "
      "{} sites\n",
      checkpoints_without_site, checkpoints, runs, runs > 0 ? checkpoints / runs : 0, reach,
      runs_with_uncovered_checkpoint, largest_gap, sites);
  if (sites_from_map) {
    text += fmt::format("  of the sites, {} are the map's flat roofs and {} lie in its open areas; {} come from the "
                        "sites file\n",
                        rooftop_sites_from_map, open_area_sites_from_map,
                        sites - rooftop_sites_from_map - open_area_sites_from_map);
  }
  if (covered()) return text;
  if (!sites_from_map) {
    return text +
           "  the sites do not cover the routes: give a sites file of the same district, or none (the map then "
           "supplies its flat roofs and open areas)\n";
  }
  // The kinds of land planning/map_import.h takes sites from (its header comment), and how to widen them.
  return text +
         "  the map's own sites do not cover the routes: they come from buildings with flat roofs (roof:shape flat "
         "or absent) and from open areas tagged leisure=park|pitch|playground|garden|common|recreation_ground|"
         "dog_park, amenity=parking (surface) or landuse=grass|recreation_ground|meadow|village_green; widen them "
         "with a map extract that holds more of those areas, or add a sites file of the same district (its sites "
         "join the map's)\n";
}

const char* PackConditionName(models::HealthClass health) {
  switch (health) {
    case models::HealthClass::kG:
      return "F1";
    case models::HealthClass::kM:
      return "F2";
    case models::HealthClass::kP:
      return "F3";
  }
  return "F1";
}

std::string CellHealthCode(const models::PerCell<models::CellHealth>& health) {
  std::string code;
  for (int b = 0; b < models::kBranchCount; ++b) {
    if (b > 0) code += '|';
    for (int c = 0; c < models::kCellsPerBranch; ++c) {
      if (c > 0) code += ',';
      const models::CellHealth& cell = health[b][c];
      if (!cell.capacity_fade && !cell.power_fade) code += '-';
      if (cell.capacity_fade) code += 'Q';
      if (cell.power_fade) code += 'R';
    }
  }
  return code;
}

}  // namespace uascma::campaign
