#include "uascma/learning/battery_transition_estimation.h"

#include <algorithm>
#include <chrono>
#include <memory>
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
  std::vector<StateIndex> ours_states;  // the same epochs in ours' abstraction (the pack-fault flags read)
  bool completed = false;
  bool failed = false;
  bool isolation = false;  // the isolation flight of a faulted draw: counted in ours' abstraction only
};

bool AnyFlagged(const std::vector<StateIndex>& states) {
  return std::any_of(states.begin(), states.end(), decision::IsFlaggedBatteryState);
}

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
  if (params.pack_fault) {
    // The isolation flight (decision/battery_mdp.h ours item 10): UseBoth, then from the first epoch the pack-fault
    // indicator flags a pack, the other pack alone for good: the rows of a flagged pack set aside, which flights
    // flown with one action throughout cannot observe. Flown only in a draw with a pack fault, so the flights of a
    // draw without one are what they were.
    auto kept = std::make_shared<PackAction>(PackAction::kUseBoth);
    flights.push_back(
        {PackAction::kUseBoth, [kept](double, const decision::BatteryObservation& observation, StateIndex) {
           if (*kept == PackAction::kUseBoth && observation.switch_on[0] && observation.switch_on[1]) {
             if (observation.pack_fault[0])
               *kept = PackAction::kUseBatt2;
             else if (observation.pack_fault[1])
               *kept = PackAction::kUseBatt1;
           }
           return *kept;
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
  // The kinds of DrawControllers' flights, in its order: constant-action, drop, isolation.
  std::size_t constant = 0;
  for (PackAction action : decision::kBatteryActions) {
    if (per_draw * d + static_cast<std::int64_t>(action) < options.runs) ++constant;
  }
  const std::size_t drop = options.drop_flights && per_draw * d + 3 < options.runs ? constant : results.size();
  for (std::size_t k = 0; k < results.size(); ++k) {
    CountedFlight flight;
    flight.action = controllers[k].initial_switches;
    if (k >= constant) {  // the drop flight, the isolation flight
      for (const campaign::BatteryEpoch& e : results[k].epochs) flight.actions.push_back(e.action);
    }
    flight.isolation = k >= constant && k != drop;
    flight.states = std::move(results[k].states);
    flight.ours_states = std::move(results[k].ours_states);
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
  if (r.pack_faults.share > 0.0) {
    provenance["pack_fault_share"] = r.pack_faults.share;
    provenance["isolation_flights"] =
        "every draw with a pack fault also flies UseBoth then the unflagged pack alone from the first flag, counted "
        "in ours' abstraction only (ours)";
  }
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
  decision::BatteryTransitionCounts ours_counts;  // ours' abstraction: kept when a flight flagged a pack
  bool flagged = false;
  BatteryLearningSummary total;
  ParallelOptions parallel;
  parallel.jobs = options.jobs;
  // Counted in draw order (sums: the result does not depend on the number of threads).
  const std::int64_t merged = ParallelFor(
      draws, parallel, [&](std::int64_t d) { return FlyDraw(options, per_draw, d); },
      [&](std::int64_t, DrawFlights&& draw) {
        for (const CountedFlight& flight : draw.flights) {
          flagged = flagged || AnyFlagged(flight.ours_states);
          if (flight.actions.empty()) {
            model.counts.AddFlight(draw.context, flight.action, flight.states, flight.completed);
            ours_counts.AddFlight(draw.context, flight.action, flight.ours_states, flight.completed);
          } else {
            if (!flight.isolation) {
              model.counts.AddSwitchingFlight(draw.context, flight.states, flight.actions, flight.completed);
            }
            ours_counts.AddSwitchingFlight(draw.context, flight.ours_states, flight.actions, flight.completed);
          }
          if (flight.isolation) {
            ++total.isolation_flights;
            continue;  // beyond the N flights
          }
          if (flight.failed) ++total.failures;
          if (options.on_flight_done) options.on_flight_done(++total.flights);
        }
        total.sharing.shared_steps += draw.sharing.shared_steps;
        total.sharing.alone_steps += draw.sharing.alone_steps;
      });
  if (merged < draws) throw Cancelled();
  if (flagged) model.ours_counts = std::move(ours_counts);
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
