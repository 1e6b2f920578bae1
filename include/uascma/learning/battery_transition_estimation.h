#pragma once
// The battery MDP's transition counts learned from Monte Carlo flights (dissertation §4.3.2, Table 4.4,
// docs/modelling-choices.md#battery-mdp-transitions), beside the CMA's (learning/transition_estimation.h). The counts
// and the MDP built from them are decision/battery_model.h; the flights campaign/battery_flights.h.
//
// Flights. Flights k = 3·d + a share the parameter draw d (campaign::SampleBatteryFlight: Table 4.4) and the
// simulator seed, and fly action a ∈ {UseBatt1, UseBatt2, UseBoth} throughout (paired, common random numbers, as
// the campaigns do); N flights are split equally between the actions. A draw's flights fly together
// (campaign::FlyBatteryFlights: one vehicle while their packs cap the rotors alike, each result bit for bit the
// flight flown alone). Every flight replays from (seed, k).
//
// Counting. At 1 Hz per (B1 health, B2 health, temperature): decision::BatteryTransitionCounts::AddFlight (the
// drop flights below: AddSwitchingFlight).
//
// Determinism. Draws are split over `jobs` threads (common/parallel_for.h) and their counts added in draw order,
// so the model (and its hash) is the same for any number of threads.
#include <cstdint>
#include <functional>

#include "uascma/campaign/battery_flights.h"
#include "uascma/decision/battery_model.h"

namespace uascma::learning {

struct BatteryLearningOptions {
  std::int64_t runs = 5000;  // §4.3.2: 5,000 flights split equally between the actions
  std::uint64_t seed = 1;
  int jobs = 1;
  campaign::BatteryFlightRanges ranges;
  // Ours (`battery learn --drop-flights`): every draw flies a fourth flight, UseBoth then pack k alone for
  // good from τ (k uniform on {1, 2}, τ uniform on [0, plan duration], drawn from the draw's own sub-stream, so the
  // three constant-action flights are unchanged), counted with AddSwitchingFlight. Why: flights flown with one
  // action throughout never visit the states a switching policy flies into (a pack dropped late, drained, beside a
  // fresh one): their rows stay unobserved, and ours (decision/battery_mdp.h item 5) offers nothing there. N flights
  // are then split between four kinds.
  bool drop_flights = false;
  // With pack faults drawn (ranges.pack_faults), every draw with a fault also flies an isolation flight: UseBoth,
  // then the unflagged pack alone for good from the first epoch the indicator flags a pack (beyond the N flights).
  // Counted in ours' abstraction only (decision::BatteryModel::ours_counts, kept when a flight flagged a pack): the
  // rows of ours' flagged states (decision/battery_mdp.h item 10) with the flagged pack set aside.
  // Called after every flight with the number done (one call at a time, in draw order; may be empty).
  std::function<void(std::int64_t)> on_flight_done;
};

struct BatteryLearningSummary {
  std::int64_t flights = 0;
  std::int64_t parameter_draws = 0;        // Table 4.4 draws, each flown with the three actions
  std::int64_t failures = 0;               // flights that reached FAILURE
  // With pack faults drawn: the isolation flights of the faulted draws (beyond the N flights; ours' flagged
  // states, decision/battery_mdp.h item 10).
  std::int64_t isolation_flights = 0;
  campaign::BatteryFlightSharing sharing;  // GNC steps that followed another flight's vehicle, and alone
  double wall_time_s = 0.0;
};

// InputError for runs or jobs below 1; uascma::Cancelled when the process token (common/cancellation.h) stops
// the work before every draw was flown.
decision::BatteryModel LearnBatteryModel(const BatteryLearningOptions& options,
                                         BatteryLearningSummary* summary = nullptr);

}  // namespace uascma::learning
