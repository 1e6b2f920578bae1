#include "uascma/campaign/sampler.h"

#include <array>
#include <map>
#include <memory>
#include <mutex>
#include <tuple>

#include "uascma/planning/procedural_city.h"

#include <cmath>
#include <numeric>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/random.h"
#include "uascma/planning/flight_plan.h"

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

// Step 5 of the header: one pack's health class and its cells' degradation.
models::HealthClass DrawPack(RandomStream& random, const BatterySampling& battery,
                             std::array<models::CellHealth, models::kCellsPerBranch>& cells) {
  const auto health = static_cast<models::HealthClass>(DrawWeighted(random, battery.pack_health_weights));
  cells = {};
  if (health == models::HealthClass::kG) return health;
  // A uniform subset of `degraded_cells_per_pack` cells: the first k of a partial Fisher–Yates shuffle.
  std::array<int, models::kCellsPerBranch> order = {0, 1, 2};
  for (int i = 0; i < battery.degraded_cells_per_pack; ++i) {
    const int j = i + static_cast<int>(random.UniformIndex(static_cast<std::uint64_t>(models::kCellsPerBranch - i)));
    std::swap(order[i], order[j]);
  }
  // The fade of a class-M or class-P cell, as every builder of packs of a given health uses it.
  for (int i = 0; i < battery.degraded_cells_per_pack; ++i) cells[order[i]] = models::CellHealthForClass(health);
  return health;
}

}  // namespace

std::uint64_t RunSeed(std::uint64_t campaign_seed, std::int64_t run_index) {
  return DeriveSeed(campaign_seed, static_cast<std::uint64_t>(run_index));
}

std::shared_ptr<const planning::CityMap> CampaignMap(const MapSampling& sampling) {
  static std::mutex mutex;
  static std::map<std::tuple<std::uint64_t, int, int>, std::shared_ptr<const planning::CityMap>> cache;
  std::lock_guard lock(mutex);
  auto& map = cache[{sampling.procedural_seed, sampling.blocks_north, sampling.blocks_east}];
  if (!map) {
    if (sampling.procedural_seed == 0) {
      map = std::make_shared<const planning::CityMap>();
    } else {
      planning::ProceduralCityParams params;
      params.seed = sampling.procedural_seed;
      params.blocks_north = sampling.blocks_north;
      params.blocks_east = sampling.blocks_east;
      map = std::make_shared<const planning::CityMap>(planning::MakeProceduralCity(params));
    }
  }
  return map;
}

SampledRun SampleRun(const CampaignConfig& config, std::uint64_t campaign_seed, std::int64_t run_index) {
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

  // 1–2. The delivery mission over the city: home on open ground inside the map, the destination at the
  // sampled distance and bearing, also on open ground inside the map (redrawn until it is; on an empty map
  // home is the origin).
  scenario.map = CampaignMap(config.map);
  const planning::CityMap& map = *scenario.map;
  auto open_ground = [&map](const Eigen::Vector2d& p) {
    return map.BuildingContaining(Eigen::Vector3d(p.x(), p.y(), -0.1)) == planning::kNoBuilding;
  };
  const bool city = !map.buildings().empty();
  const Eigen::AlignedBox2d bounds = map.bounds();
  for (int attempt = 0;; ++attempt) {
    if (city) {
      do {
        scenario.mission.home_NE = Eigen::Vector2d(random.Uniform(bounds.min().x(), bounds.max().x()),
                                                   random.Uniform(bounds.min().y(), bounds.max().y()));
      } while (!open_ground(scenario.mission.home_NE));
    } else {
      scenario.mission.home_NE = Eigen::Vector2d::Zero();
    }
    run.bearing_rad = random.Uniform(0.0, 2.0 * kPi);
    run.distance_m = Draw(random, config.mission.distance_m);
    scenario.mission.destination_NE =
        scenario.mission.home_NE + run.distance_m * Eigen::Vector2d(std::cos(run.bearing_rad), std::sin(run.bearing_rad));
    if (!city || (bounds.contains(scenario.mission.destination_NE) && open_ground(scenario.mission.destination_NE))) break;
    if (attempt > 10000) throw InputError("campaign", "mission.distance_m", "distances that fit inside the city");
  }
  scenario.mission.cruise_altitude = config.mission.cruise_altitude_m;
  if (city) {
    const std::array<Eigen::Vector2d, 2> route = {scenario.mission.home_NE, scenario.mission.destination_NE};
    scenario.mission.cruise_altitude = map.CruiseAltitude(route, planning::kCruiseClearanceAboveBuildings, 5.0);
  }
  scenario.mission.drop_hover_s = config.mission.drop_hover_s;
  run.cruise_speed_mps = Draw(random, config.mission.cruise_speed_mps);
  scenario.limits.cruise_speed = run.cruise_speed_mps;

  // 3. Safety margin t_sf (recorded only; see the header).
  run.safety_margin_s = Draw(random, config.safety_margin_s);
  scenario.options.safety_margin_s = run.safety_margin_s;

  // 4. Initial cell voltages, pack 1 cells 1–3 then pack 2.
  for (auto& pack : scenario.battery.initial_cell_voltage_v) {
    for (double& voltage : pack) voltage = Draw(random, config.battery.initial_cell_voltage_v);
  }

  // 5. Pack health and the degraded cells.
  for (int b = 0; b < models::kBranchCount; ++b) {
    run.pack_health[b] = DrawPack(random, config.battery, scenario.battery.cell_health[b]);
  }
  run.battery_health =
      static_cast<decision::BatteryHealth>(static_cast<int>(models::ClassifyHealth(scenario.battery.cell_health)));

  // 6. Ambient temperature: only the 50 °F split matters (Table 3.2).
  run.cold = random.Bernoulli(config.battery.cold_probability);
  scenario.battery.ambient_temp_degf = run.cold ? config.battery.cold_temp_degf : config.battery.warm_temp_degf;

  // 7. Wind.
  scenario.wind.mean_speed = Draw(random, config.wind.speed_mps);
  scenario.wind.direction_rad = Draw(random, config.wind.direction_rad);
  scenario.wind.turbulence = config.wind.turbulence[random.UniformIndex(config.wind.turbulence.size())];

  // 8. The spall fault, its onset uniform over the nominal flight.
  run.plan_duration_s = planning::MakeDeliveryPlan(scenario.mission, scenario.limits).duration();
  scenario.fault = sim::FaultSpec{};
  scenario.fault.enabled = random.Bernoulli(config.fault.probability);
  if (scenario.fault.enabled) {
    scenario.fault.spall_onset_s = Draw(random, config.fault.onset_fraction) * run.plan_duration_s;
    scenario.fault.motor = config.fault.motors[random.UniformIndex(config.fault.motors.size())];
    scenario.fault.time_per_growth_step_s = config.fault.time_per_growth_step_s;
  }
  return run;
}

const char* PackConditionName(models::HealthClass health) {
  switch (health) {
    case models::HealthClass::kG: return "F1";
    case models::HealthClass::kM: return "F2";
    case models::HealthClass::kP: return "F3";
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
