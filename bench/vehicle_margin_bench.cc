// The vehicle-level motor margin's cost per 1 Hz epoch (sim/vehicle_margin.h) beside the epoch's Observe:
//  - BM_ObserveMidFlight: sim::Observe of the default campaign's first sampled flight (examples/campaign.yaml defaults,
//    seed 1) at 60 s, NoOp so far, a fresh copy of the state per iteration (the EOD to its crossing, the load
//    forecast, the margins; the vehicle-level margin costs two comparisons here, as in every epoch without a known
//    spall whose RUL is shorter than the plan);
//  - BM_QuadcopterReach: what the margin adds in an epoch whose spall's RUL is shorter than the plan: the capped
//    re-plan of the rest, its four-rotor load profile and the EOD bounded at t_quad + t_sf.
// Bound: the decision path within 1.5x of the epoch's Observe in the epochs where the margin runs, i.e.
// BM_QuadcopterReach <= 0.5 x BM_ObserveMidFlight; in every other epoch the cost is unchanged.
#include <benchmark/benchmark.h>

#include "uascma/campaign/config.h"
#include "uascma/campaign/sampler.h"
#include "uascma/sim/epoch.h"
#include "uascma/sim/flight.h"
#include "uascma/sim/initial_state.h"
#include "uascma/sim/vehicle_margin.h"

namespace {

using namespace uascma;

struct MidFlight {
  MidFlight() : model(Run().scenario), state(sim::MakeInitialState(model, Run().scenario.seed)) {
    while (!state.done() && state.time_s < 60.0) {
      if (sim::IsDecisionEpoch(model, state)) sim::Observe(model, state);
      sim::Step(model, state);
    }
    while (!state.done() && !sim::IsDecisionEpoch(model, state)) sim::Step(model, state);
  }
  static const campaign::SampledRun& Run() {
    static const campaign::CampaignConfig config;
    static const campaign::CampaignWorld world = campaign::BuildCampaignWorld(config.map);
    static const campaign::SampledRun run = campaign::SampleRun(config, world, 1, 0);
    return run;
  }
  sim::FlightModel model;
  sim::FlightState state;
};

const MidFlight& Flight() {
  static const MidFlight flight;
  return flight;
}

void BM_ObserveMidFlight(benchmark::State& state) {
  const MidFlight& flight = Flight();
  for (auto _ : state) {
    sim::FlightState copy = flight.state;
    benchmark::DoNotOptimize(sim::Observe(flight.model, copy).vehicle_motor_margin);
  }
}
BENCHMARK(BM_ObserveMidFlight)->Unit(benchmark::kMicrosecond);

void BM_QuadcopterReach(benchmark::State& state) {
  const MidFlight& flight = Flight();
  for (auto _ : state) {
    benchmark::DoNotOptimize(sim::CalcQuadcopterReach(flight.model, flight.state, flight.state.power.pack).eod_s);
  }
}
BENCHMARK(BM_QuadcopterReach)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
