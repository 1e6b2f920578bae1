#include "uascma/campaign/battery_flights.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "uascma/campaign/sampler.h"
#include "uascma/common/error.h"
#include "uascma/common/frames.h"
#include "uascma/common/random.h"
#include "uascma/decision/battery_mdp_file.h"
#include "uascma/models/propulsion.h"
#include "uascma/planning/flight_plan.h"
#include "uascma/prognostics/eod.h"
#include "uascma/prognostics/pack_fault_monitor.h"
#include "uascma/sim/act.h"
#include "uascma/sim/branching.h"
#include "uascma/sim/initial_state.h"

namespace uascma::campaign {
namespace {

using decision::BatteryContext;
using decision::StateIndex;
using models::HealthClass;
using models::PackAction;

double DrawInRange(RandomStream& random, const double (&range)[2]) { return random.Uniform(range[0], range[1]); }

// Usable charge left in a pack (A·h): its cells are in series, so the pack stops at its emptiest cell.
double PackChargeLeftAh(const models::BatteryPack& pack, const models::PackState& state, int branch) {
  double charge_as = std::numeric_limits<double>::infinity();
  for (int c = 0; c < models::kCellsPerBranch; ++c) {
    charge_as =
        std::min(charge_as, std::max(0.0, state.cells[branch][c].soc_fraction) * pack.cell(branch, c).capacity_as());
  }
  return charge_as / 3600.0;
}

double HoverCurrent(const models::BatteryPack& pack, const models::PackState& state) {
  const sim::Scenario defaults;
  const models::PropulsionParams propulsion = models::PropulsionParams::ForConfiguration(defaults.configuration);
  const double power_w = 6.0 * models::CalcElectricalPower(propulsion, defaults.body.mass * kGravity / 6.0) +
                         defaults.options.hotel_current_a * defaults.options.reference_bus_voltage_v;
  double current_a = power_w / defaults.options.reference_bus_voltage_v;
  for (int i = 0; i < 20; ++i) current_a = power_w / pack.CalcSplit(state, current_a).bus_voltage_v;  // I = P/V(I)
  return current_a;
}

}  // namespace

decision::BatteryObservation ObserveBatteryFlight(const sim::FlightModel& model, const sim::FlightState& state) {
  const double remaining_s = state.plan(model).TimeRemaining(state.time_s - state.guidance.plan_start_s);
  return decision::ObserveBattery(model.pack(), state.power.pack, state.power.load_current_a, remaining_s,
                                  model.options().safety_margin_s);
}

// ================================ parameters ======================================================
BatteryContext BatteryFlightParams::context() const {
  return {health[0], health[1], decision::ClassifyTemperature(ambient_temp_degf)};
}

std::array<models::CellHealth, models::kCellsPerBranch> DrawPackCells(RandomStream& random, HealthClass health) {
  std::array<models::CellHealth, models::kCellsPerBranch> cells{};
  if (health == HealthClass::kG) return cells;
  const int k = 1 + static_cast<int>(random.UniformIndex(models::kCellsPerBranch));
  const std::array<models::CellHealth*, models::kCellsPerBranch> three = {&cells[0], &cells[1], &cells[2]};
  DrawCellFades(random, health, k, MediumFades::kOneKind, three);
  return cells;
}

BatteryFlightParams SampleBatteryFlight(const BatteryFlightRanges& ranges, std::uint64_t seed, std::int64_t draw) {
  const std::uint64_t draw_seed = DeriveSeed(seed, static_cast<std::uint64_t>(draw));
  RandomStream random(DeriveSeed(draw_seed, kBatteryParameterStream));
  BatteryFlightParams p;
  p.seed = DeriveSeed(draw_seed, kBatteryVehicleStream);
  // Table 4.4, in a fixed order (changing it changes every learned model).
  p.safety_margin_s = DrawInRange(random, ranges.safety_margin_s);
  for (auto& pack : p.initial_cell_voltage_v) {
    for (double& v : pack) v = DrawInRange(random, ranges.initial_cell_voltage_v);
  }
  p.cruise_speed_mps = DrawInRange(random, ranges.cruise_speed_mps);
  p.wind_speed_mps = DrawInRange(random, ranges.wind_speed_mps);
  p.wind_direction_rad = DrawInRange(random, ranges.wind_direction_rad);
  p.turbulence = ranges.turbulence[random.UniformIndex(ranges.turbulence.size())];
  for (auto& h : p.health) h = static_cast<HealthClass>(random.UniformIndex(3));
  p.ambient_temp_degf = random.Bernoulli(ranges.cold_probability) ? ranges.cold_temp_degf : ranges.warm_temp_degf;
  p.plan_duration_s = DrawInRange(random, ranges.plan_fraction) * ReferenceBatteryEod();
  // Drawn last, so the draws above keep their values (a change of this realisation leaves them alone).
  for (int j = 0; j < models::kBranchCount; ++j) p.cells[j] = DrawPackCells(random, p.health[j]);
  if (ranges.pack_faults.share > 0.0) {
    RandomStream fault_random(DeriveSeed(draw_seed, kBatteryPackFaultStream));
    p.pack_fault = DrawPackFault(fault_random, ranges.pack_faults, p.plan_duration_s);
  }
  return p;
}

double ReferenceBatteryEod(PackAction switches) {
  static const auto eods = [] {
    const models::BatteryPack pack;
    std::array<double, 3> out{};
    for (PackAction action : decision::kBatteryActions) {
      const models::PackState state = pack.MakeRestingState(4.1, action);
      out[static_cast<std::size_t>(action)] = prognostics::CalcPackEod(pack, state, HoverCurrent(pack, state)).eod_s;
    }
    return out;
  }();
  return eods[static_cast<std::size_t>(switches)];
}

double OursBatteryDiscount(const BatteryFlightRanges& ranges) {
  const double longest_plan_s = ranges.plan_fraction[1] * ReferenceBatteryEod();
  return std::pow(0.5, 1.0 / longest_plan_s);  // one epoch = 1 s (docs/modelling-choices.md#battery-mdp-policies)
}

sim::Scenario MakeBatteryScenario(const BatteryFlightParams& params) {
  sim::Scenario scenario;
  scenario.name = "battery-flight";
  scenario.seed = params.seed;
  scenario.battery.initial_cell_voltage_v = params.initial_cell_voltage_v;
  scenario.battery.cell_health = params.cells;
  scenario.battery.ambient_temp_degf = params.ambient_temp_degf;
  scenario.options.safety_margin_s = params.safety_margin_s;
  scenario.pack_fault = params.pack_fault;
  // Fig. 4.3's loop has no rotor-fault detector and Table 4.4 no motor fault (sim/scenario.h fault_detection).
  scenario.options.fault_detection = false;
  scenario.wind.mean_speed = params.wind_speed_mps;
  scenario.wind.direction_rad = params.wind_direction_rad;
  scenario.wind.turbulence = params.turbulence;
  scenario.limits.cruise_speed = params.cruise_speed_mps;
  // The destination distance that makes the plan last plan_duration_s: the duration grows with the
  // distance (monotone), so bisect on [1 m, v·T].
  double low = 1.0, high = std::max(2.0, params.cruise_speed_mps * params.plan_duration_s);
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (low + high);
    scenario.mission.destination_NE = Eigen::Vector2d(mid, 0.0);
    (planning::MakeDeliveryPlan(scenario.mission, scenario.limits).duration() < params.plan_duration_s ? low : high) =
        mid;
  }
  scenario.mission.destination_NE = Eigen::Vector2d(0.5 * (low + high), 0.0);
  return scenario;
}

// ================================ one flight =======================================================
namespace {

// The 1 Hz executor of sim/flight.h: abstracts the pack, records, asks the controller, returns the switches.
class RecordingExecutor final : public sim::BatterySwitchPolicy {
 public:
  RecordingExecutor(const BatterySwitchController& controller, bool observe_pair_eod,
                    const decision::BatteryThresholds& thresholds, BatteryFlightResult& result)
      : controller_(controller), observe_pair_eod_(observe_pair_eod), thresholds_(thresholds), result_(result) {}

  PackAction Decide(const sim::FlightModel& model, const sim::FlightState& state) override {
    decision::BatteryObservation observation = ObserveBatteryFlight(model, state);
    // The pack monitor reads the packs at every epoch (prognostics/pack_fault_monitor.h).
    if (!monitor_) monitor_.emplace(model.pack(), state.power.pack);
    monitor_->Update(prognostics::ReadPackMonitor(model.pack(), state.power.pack, state.power.pack_current_a,
                                                  state.power.branch_charge_as, state.time_s));
    observation.pack_fault = monitor_->faulted();
    result_.fault_detected_s = monitor_->detection_time_s();
    if (observe_pair_eod_) {
      const prognostics::EodResult pair =
          prognostics::CalcPackEod(model.pack(), state.power.pack, state.power.load_current_a);
      observation.pair_eod_s = pair.eod_s;
      observation.pair_limiting_branch = pair.limiting_branch;
      // Ours' drop check reads it only while both packs are in (a dropped pack stays dropped).
      if (state.power.pack.branch_on[0] && state.power.pack.branch_on[1]) {
        decision::ObserveAloneAtPower(model.pack(), state.power.pack, state.power.load_current_a, observation);
      }
    }
    const double remaining_s = observation.remaining_flight_s;
    const StateIndex s = decision::AbstractBatteryState(observation, thresholds_);
    const PackAction action = controller_(state.time_s, observation, s);
    result_.states.push_back(s);
    result_.ours_states.push_back(
        decision::AbstractBatteryState(observation, thresholds_, decision::BatteryFormulation::kOurs));
    if (result_.switches.empty() || result_.switches.back().second != action) {
      result_.switches.emplace_back(state.time_s, action);
    }
    models::PackState switched = state.power.pack;
    switched.branch_on = models::SwitchesFor(action);
    BatteryEpoch epoch;
    epoch.time_s = state.time_s;
    epoch.state = s;
    epoch.action = action;
    epoch.total_current_a = state.power.pack_current_a;
    epoch.branch_current_a = model.pack().CalcSplit(switched, state.power.pack_current_a).current_a;
    epoch.eod_s = observation.eod_s;
    epoch.min_cell_voltage_v = observation.min_cell_voltage_v;
    epoch.remaining_flight_s = remaining_s;
    result_.epochs.push_back(epoch);
    return action;
  }

 private:
  const BatterySwitchController& controller_;
  bool observe_pair_eod_;
  decision::BatteryThresholds thresholds_;
  BatteryFlightResult& result_;
  std::optional<prognostics::PackFaultMonitor> monitor_;
};

}  // namespace

BatteryFlightResult FlyBatteryFlight(const BatteryFlightParams& params, PackAction initial_switches,
                                     const BatterySwitchController& controller,
                                     const decision::BatteryThresholds& thresholds) {
  const std::array<BatteryFlightController, 1> one = {{{initial_switches, controller}}};
  return std::move(FlyBatteryFlights(params, one, thresholds).front());
}

BatteryFlightResult FlyBatteryFlight(const BatteryFlightParams& params, const BatteryFlightController& flight,
                                     const decision::BatteryThresholds& thresholds) {
  const std::array<BatteryFlightController, 1> one = {flight};
  return std::move(FlyBatteryFlights(params, one, thresholds).front());
}

std::vector<BatteryFlightResult> FlyBatteryFlights(const BatteryFlightParams& params,
                                                   std::span<const BatteryFlightController> flights,
                                                   const decision::BatteryThresholds& thresholds,
                                                   BatteryFlightSharing* sharing) {
  const sim::FlightModel model(MakeBatteryScenario(params));
  const std::size_t n = flights.size();
  std::vector<sim::FlightState> states(n, sim::MakeInitialState(model, params.seed));
  std::vector<BatteryFlightResult> results(n);
  std::vector<RecordingExecutor> executors;
  executors.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    sim::SwitchPacks(states[k], flights[k].initial_switches);
    executors.emplace_back(flights[k].controller, flights[k].observe_pair_eod, thresholds, results[k]);
  }
  // The flights fly one vehicle while their packs cap the rotors alike; one that leaves the group flies on alone
  // (sim/branching.h FlyFollowing: Fig. 4.3's loop, the battery executor at 1 Hz, the GNC steps between, no CMA).
  std::vector<sim::BatterySwitchPolicy*> executor_pointers;
  for (RecordingExecutor& executor : executors) executor_pointers.push_back(&executor);
  const sim::SharingCounts counts = sim::FlyFollowing(model, states, executor_pointers);
  for (std::size_t k = 0; k < n; ++k) {
    results[k].outcome = states[k].outcome;
    results[k].end_time_s = states[k].time_s;
    results[k].energy_used_wh = states[k].power.energy_wh;
    if (flights[k].decisions) results[k].decisions = *flights[k].decisions;
    for (int j = 0; j < models::kBranchCount; ++j)
      results[k].charge_left_ah[j] = PackChargeLeftAh(model.pack(), states[k].power.pack, j);
    // The ESCs cut out at 3.3 V (Table 4.1): the flight's last transition is into FAILURE.
    if (states[k].outcome == sim::Outcome::kFailedBattery) {
      results[k].states.push_back(decision::kBatteryFailureState);
      results[k].ours_states.push_back(decision::kBatteryFailureState);
    }
  }
  if (sharing) {
    sharing->shared_steps += counts.shared_steps;
    sharing->alone_steps += counts.alone_steps;
  }
  return results;
}

// ================================ the executor for any flight ======================================
BatteryPolicySwitch::BatteryPolicySwitch(const decision::BatteryPolicySet& policies, const sim::Scenario& scenario)
    : executor_(policies,
                decision::BatteryContextOf(scenario.battery.cell_health, scenario.battery.ambient_temp_degf)) {}

PackAction BatteryPolicySwitch::Decide(const sim::FlightModel& model, const sim::FlightState& state) {
  return executor_.Decide(ObserveBatteryFlight(model, state));
}

std::unique_ptr<sim::BatterySwitchPolicy> LoadBatterySwitchPolicy(const std::filesystem::path& policy_file,
                                                                  const sim::Scenario& scenario) {
  return std::make_unique<BatteryPolicySwitch>(decision::ReadBatteryPolicyFile(policy_file), scenario);
}

}  // namespace uascma::campaign
