// The battery MDP's counts learned from flights (learning/battery_transition_estimation.h): the counts are those of
// the draw's flights flown by hand and counted (two computations of the same thing), the model does not depend on
// the number of threads, and a failure in the work reaches the caller instead of ending the process.
#include "uascma/learning/battery_transition_estimation.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "uascma/common/error.h"
#include "uascma/decision/battery_model.h"

namespace uascma::learning {
namespace {

using models::PackAction;

// Short plans keep the test quick (ours: 5-10 % of the reference EOD); the draw is otherwise Table 4.4's.
BatteryLearningOptions ShortFlights(std::int64_t runs, std::uint64_t seed) {
  BatteryLearningOptions options;
  options.runs = runs;
  options.seed = seed;
  options.ranges.plan_fraction[0] = 0.05;
  options.ranges.plan_fraction[1] = 0.10;
  return options;
}

TEST(BatteryLearningTest, TheCountsAreTheDrawsFlightsFlownAndCountedByHand) {
  const BatteryLearningOptions options = ShortFlights(6, 7);  // two draws, three actions each
  BatteryLearningSummary summary;
  const decision::BatteryModel learned = LearnBatteryModel(options, &summary);
  decision::BatteryModel by_hand;
  by_hand.provenance = learned.provenance;
  std::int64_t failures = 0;
  for (std::int64_t d = 0; d < 2; ++d) {
    const campaign::BatteryFlightParams params = campaign::SampleBatteryFlight(options.ranges, options.seed, d);
    for (PackAction action : decision::kBatteryActions) {
      const campaign::BatteryFlightResult flight = campaign::FlyBatteryFlight(
          params, action,
          [action](double, const decision::BatteryObservation&, decision::StateIndex) { return action; });
      by_hand.counts.AddFlight(params.context(), action, flight.states, flight.outcome == sim::Outcome::kCompleted);
      if (flight.outcome == sim::Outcome::kFailedBattery) ++failures;
    }
  }
  EXPECT_EQ(decision::BatteryModelHash(learned), decision::BatteryModelHash(by_hand));
  EXPECT_GT(learned.counts.total_transitions(), 0);
  EXPECT_EQ(summary.flights, 6);
  EXPECT_EQ(summary.parameter_draws, 2);
  EXPECT_EQ(summary.failures, failures);
}

TEST(BatteryLearningTest, TheModelDoesNotDependOnTheNumberOfThreads) {
  BatteryLearningOptions options = ShortFlights(11, 3);
  options.drop_flights = true;  // 3 draws of four flights, the last of three
  std::vector<std::int64_t> done;
  options.on_flight_done = [&done](std::int64_t count) { done.push_back(count); };
  BatteryLearningSummary serial_summary, parallel_summary;
  const decision::BatteryModel serial = LearnBatteryModel(options, &serial_summary);
  std::vector<std::int64_t> expected_done(11);
  for (std::size_t k = 0; k < expected_done.size(); ++k) expected_done[k] = static_cast<std::int64_t>(k) + 1;
  EXPECT_EQ(done, expected_done);  // one call per flight, counting up
  done.clear();
  options.jobs = 3;
  const decision::BatteryModel parallel = LearnBatteryModel(options, &parallel_summary);
  EXPECT_EQ(done, expected_done);  // merged in draw order: the same calls on three threads
  EXPECT_EQ(decision::BatteryModelHash(serial), decision::BatteryModelHash(parallel));
  EXPECT_EQ(serial.counts.total_flights(), 11);
  EXPECT_EQ(serial_summary.parameter_draws, 3);
  EXPECT_EQ(serial_summary.failures, parallel_summary.failures);
  EXPECT_EQ(serial_summary.sharing.shared_steps, parallel_summary.sharing.shared_steps);
  EXPECT_EQ(serial_summary.sharing.alone_steps, parallel_summary.sharing.alone_steps);
  EXPECT_TRUE(serial.provenance.contains("drop_flights"));
}

// The flights' old thread pool let an exception escape a worker thread, which ends the process. Now it
// reaches the caller (common/parallel_for.h), whichever thread raised it.
TEST(BatteryLearningTest, AFailureDuringTheWorkReachesTheCaller) {
  BatteryLearningOptions options = ShortFlights(9, 5);
  options.jobs = 2;
  options.on_flight_done = [](std::int64_t count) {
    if (count == 4) throw std::runtime_error("progress report failed");
  };
  EXPECT_THROW(LearnBatteryModel(options), std::runtime_error);
  options.on_flight_done = nullptr;
  options.runs = 0;
  EXPECT_THROW(LearnBatteryModel(options), InputError);
  options.runs = 3;
  options.jobs = 0;
  EXPECT_THROW(LearnBatteryModel(options), InputError);
}

}  // namespace
}  // namespace uascma::learning
