#include "uascma/learning/battery_transition_estimation.h"

#include <chrono>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "uascma/common/error.h"
#include "uascma/common/parallel_for.h"
#include "uascma/common/random.h"

namespace uascma::learning {
namespace {

using campaign::BatteryFlightController;
using campaign::BatteryFlightParams;
using campaign::BatteryFlightResult;
using decision::StateIndex;
using models::PackAction;

// One flight of a draw as the counts take it: `actions` empty for a flight flown with `action` throughout
// (AddFlight), else the action of every epoch (a drop flight, AddSwitchingFlight).
struct CountedFlight {
  PackAction action = PackAction::kUseBoth;
  std::vector<PackAction> actions;
  std::vector<StateIndex> states;
  bool completed = false;
  bool failed = false;
};

struct DrawFlights {
  decision::BatteryContext context;
  std::vector<CountedFlight> flights;
  campaign::BatteryFlightSharing sharing;
};

// The controllers of draw d: its constant-action flights (those of the first `runs` flights), then the drop
// flight when asked for.
std::vector<BatteryFlightController> DrawControllers(const BatteryLearningOptions& options, std::int64_t per_draw,
                                                     std::int64_t d, const BatteryFlightParams& params) {
  std::vector<BatteryFlightController> flights;
  for (PackAction action : decision::kBatteryActions) {
    if (per_draw * d + static_cast<std::int64_t>(action) >= options.runs) break;
    flights.push_back({action, [action](double, const decision::BatteryObservation&, StateIndex) { return action; }});
  }
  if (options.drop_flights && per_draw * d + 3 < options.runs) {
    RandomStream drop_random(
        DeriveSeed(DeriveSeed(options.seed, static_cast<std::uint64_t>(d)), campaign::kBatteryDropStream));
    const PackAction alone = drop_random.Bernoulli(0.5) ? PackAction::kUseBatt2 : PackAction::kUseBatt1;
    const double drop_s = drop_random.Uniform(0.0, params.plan_duration_s);
    flights.push_back(
        {PackAction::kUseBoth, [alone, drop_s](double time_s, const decision::BatteryObservation&, StateIndex) {
           return time_s >= drop_s ? alone : PackAction::kUseBoth;
         }});
  }
  return flights;
}

// Flies draw d's flights together (campaign::FlyBatteryFlights: one vehicle while the packs cap the rotors alike).
DrawFlights FlyDraw(const BatteryLearningOptions& options, std::int64_t per_draw, std::int64_t d) {
  const BatteryFlightParams params = campaign::SampleBatteryFlight(options.ranges, options.seed, d);
  const std::vector<BatteryFlightController> controllers = DrawControllers(options, per_draw, d, params);
  DrawFlights out;
  out.context = params.context();
  std::vector<BatteryFlightResult> results = campaign::FlyBatteryFlights(params, controllers, {}, &out.sharing);
  for (std::size_t k = 0; k < results.size(); ++k) {
    CountedFlight flight;
    flight.action = controllers[k].initial_switches;
    if (k == 3) {  // the drop flight
      for (const campaign::BatteryEpoch& e : results[k].epochs) flight.actions.push_back(e.action);
    }
    flight.states = std::move(results[k].states);
    flight.completed = results[k].outcome == sim::Outcome::kCompleted;
    flight.failed = results[k].outcome == sim::Outcome::kFailedBattery;
    out.flights.push_back(std::move(flight));
  }
  return out;
}

// How the counts were gathered (the model file's "provenance", fingerprinted with the counts).
nlohmann::json LearningProvenance(const BatteryLearningOptions& options) {
  const campaign::BatteryFlightRanges& r = options.ranges;
  nlohmann::json turbulence = nlohmann::json::array();
  for (auto category : r.turbulence) turbulence.push_back(models::TurbulenceCategoryName(category));
  nlohmann::json provenance = {
      {"flights", options.runs},
      {"seed", options.seed},
      {"method",
       "Monte Carlo flights of the full simulator (dissertation 4.3.2, Table 4.4), action held throughout, "
       "counted at 1 Hz (campaign/battery_flights.h)"},
      {"ranges",
       {{"safety_margin_s", {r.safety_margin_s[0], r.safety_margin_s[1]}},
        {"initial_cell_voltage_v", {r.initial_cell_voltage_v[0], r.initial_cell_voltage_v[1]}},
        {"cruise_speed_mps", {r.cruise_speed_mps[0], r.cruise_speed_mps[1]}},
        {"wind_speed_mps", {r.wind_speed_mps[0], r.wind_speed_mps[1]}},
        {"wind_direction_rad", {r.wind_direction_rad[0], r.wind_direction_rad[1]}},
        {"turbulence", turbulence},
        {"plan_fraction_of_reference_eod", {r.plan_fraction[0], r.plan_fraction[1]}},
        {"cold_probability", r.cold_probability}}},
  };
  if (options.drop_flights) {
    provenance["drop_flights"] =
        "every draw also flies UseBoth then one pack alone for good from a uniform time (ours)";
  }
  return provenance;
}

}  // namespace

decision::BatteryModel LearnBatteryModel(const BatteryLearningOptions& options, BatteryLearningSummary* summary) {
  if (options.runs < 1) throw InputError("--runs", "value", fmt::format("at least 1 flight, got {}", options.runs));
  if (options.jobs < 1) throw InputError("--jobs", "value", fmt::format("at least 1 thread, got {}", options.jobs));
  const auto start = std::chrono::steady_clock::now();
  const std::int64_t per_draw = options.drop_flights ? 4 : 3;
  const std::int64_t draws = (options.runs + per_draw - 1) / per_draw;
  decision::BatteryModel model;
  BatteryLearningSummary total;
  ParallelOptions parallel;
  parallel.jobs = options.jobs;
  // Counted in draw order (sums: the result does not depend on the number of threads).
  const std::int64_t merged = ParallelFor(
      draws, parallel, [&](std::int64_t d) { return FlyDraw(options, per_draw, d); },
      [&](std::int64_t, DrawFlights&& draw) {
        for (const CountedFlight& flight : draw.flights) {
          if (flight.actions.empty()) {
            model.counts.AddFlight(draw.context, flight.action, flight.states, flight.completed);
          } else {
            model.counts.AddSwitchingFlight(draw.context, flight.states, flight.actions, flight.completed);
          }
          if (flight.failed) ++total.failures;
          if (options.on_flight_done) options.on_flight_done(++total.flights);
        }
        total.sharing.shared_steps += draw.sharing.shared_steps;
        total.sharing.alone_steps += draw.sharing.alone_steps;
      });
  if (merged < draws) throw Cancelled();
  model.provenance = LearningProvenance(options);
  if (summary) {
    *summary = total;
    summary->flights = options.runs;
    summary->parameter_draws = draws;
    summary->wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return model;
}

}  // namespace uascma::learning
