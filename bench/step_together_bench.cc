// Four flights of one model (examples/scenario-1.yaml, seeds 1-4, from 30 s into the flight, the
// cruise) stepped one GNC step at a time, per flight-step:
//   alone/sequential  each flight its 200 steps (one decision epoch) with Step, one after the other: how a campaign
//                     thread flies its runs today, each flight's state hot in the cache;
//   alone/interleaved each step of the four flights with Step in turn: the order lockstep needs, without lanes;
//   together          StepTogether: the four flights' control and rigid bodies in lanes, the rest flight by flight,
//                     bit for bit each flight alone (tests/sim/step_together_test.cc).
// Each iteration copies the four states at 30 s (the copy is in every variant's time) and flies them one epoch.
#include <array>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "uascma/sim/epoch.h"
#include "uascma/sim/flight.h"
#include "uascma/sim/initial_state.h"
#include "uascma/sim/policy.h"
#include "uascma/sim/scenario.h"

namespace uascma::sim {
namespace {

constexpr int kFlights = 4;

struct Fleet {
  FlightModel model;
  std::vector<FlightState> at_cruise;
};

const Fleet& CruisingFleet() {
  static const Fleet fleet = [] {
    Fleet f{FlightModel(LoadScenarioFile(std::string(UASCMA_SOURCE_DIR) + "/examples/scenario-1.yaml").scenario), {}};
    NoOpPolicy noop;
    const Controllers controllers{&noop, nullptr, {}};
    for (std::uint64_t seed = 1; seed <= kFlights; ++seed) {
      FlightState state = MakeInitialState(f.model, seed);
      for (int epoch = 0; epoch < 30; ++epoch) StepEpoch(f.model, state, controllers);
      f.at_cruise.push_back(state);
    }
    return f;
  }();
  return fleet;
}

void BM_FourFlights(benchmark::State& bench) {
  const int mode = static_cast<int>(bench.range(0));
  const Fleet& fleet = CruisingFleet();
  const FlightModel& model = fleet.model;
  const int steps = model.steps_per_epoch();
  std::array<FlightState*, kFlights> pointers{};
  std::array<const FlightModel*, kFlights> flight_models{};
  flight_models.fill(&model);
  const std::array<FlightLog*, kFlights> logs{};
  for (auto _ : bench) {
    std::vector<FlightState> states = fleet.at_cruise;
    for (int k = 0; k < kFlights; ++k) pointers[k] = &states[k];
    if (mode == 0) {
      for (FlightState& state : states) {
        for (int i = 0; i < steps; ++i) Step(model, state);
      }
    } else if (mode == 1) {
      for (int i = 0; i < steps; ++i) {
        for (FlightState& state : states) Step(model, state);
      }
    } else {
      for (int i = 0; i < steps; ++i) StepTogether(flight_models, pointers, logs);
    }
    benchmark::DoNotOptimize(states.data());
    benchmark::ClobberMemory();
  }
  bench.counters["ns_per_flight_step"] = benchmark::Counter(static_cast<double>(bench.iterations()) * kFlights * steps,
                                                            benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  bench.SetLabel(mode == 0 ? "alone, sequential" : mode == 1 ? "alone, interleaved" : "together (lanes)");
}
BENCHMARK(BM_FourFlights)->ArgName("mode")->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace uascma::sim

BENCHMARK_MAIN();
