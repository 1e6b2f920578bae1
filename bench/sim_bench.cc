// Simulator speed (issue: the hexacopter flight simulator): a full 15-minute delivery mission at full
// fidelity — 200 Hz GNC (LQR, allocation, rotor lag, midpoint 6-DOF with drag and Dryden gusts), the 7-mode
// IMM every step, the battery pack every step, EOD/RUL/decisions at 1 Hz — without telemetry recording.
// Target: ≥ 10,000× real time on one core (< 90 ms per flight). Reported as counters:
//   sim_s (simulated seconds), realtime_factor (sim_s / wall s).
#include <benchmark/benchmark.h>

#include "uascma/sim/environment.h"
#include "uascma/sim/epoch.h"
#include "uascma/sim/flight.h"
#include "uascma/sim/initial_state.h"
#include "uascma/sim/policy.h"
#include "uascma/sim/simulator.h"

namespace {

using namespace uascma;

sim::Scenario FifteenMinuteMission() {
  sim::Scenario scenario;
  scenario.name = "15-minute delivery";
  // 2 × 2,059 m at 5 m/s, a 30 s drop and two 30 m vertical legs: 893 s of plan.
  scenario.mission.destination_NE = Eigen::Vector2d(1800, 1000);
  scenario.mission.cruise_altitude = 30.0;
  // A full charge (top of the OCV table) so that the healthy pack lasts the whole mission.
  for (auto& pack : scenario.battery.initial_cell_voltage_v) pack.fill(4.2);
  scenario.wind.mean_speed = 2.0;
  scenario.wind.direction_rad = 0.5;
  scenario.wind.turbulence = models::TurbulenceCategory::kLowLight;
  scenario.seed = 11;
  return scenario;
}

void BM_FifteenMinuteMission(benchmark::State& state) {
  const sim::Simulator simulator(FifteenMinuteMission());
  sim::NoOpPolicy policy;
  sim::SimResult result;
  for (auto _ : state) {
    result = simulator.Run(policy, {}, {.record_telemetry = false});
    // A const copy: DoNotOptimize on a non-const double lvalue can clobber it with GCC 12 (its "+r"
    // constraint), which zeroed sim_time_s here.
    const double simulated = result.sim_time_s;
    benchmark::DoNotOptimize(simulated);
  }
  if (result.outcome != sim::Outcome::kCompleted) state.SkipWithError("the benchmark mission did not complete");
  state.counters["sim_s"] = result.sim_time_s;
  state.counters["realtime_factor"] =
      benchmark::Counter(result.sim_time_s * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_FifteenMinuteMission)->Unit(benchmark::kMillisecond)->MinTime(2.0);

// The same flight through the decision environment (stepping by epochs costs no more than Run): Reset,
// then Step(NoOp) at every 1 Hz epoch, with the observation and the reward computed each time.
void BM_FifteenMinuteMissionByEpochs(benchmark::State& state) {
  const sim::Scenario scenario = FifteenMinuteMission();
  sim::DecisionEnvironment environment(scenario);
  double simulated = 0.0;
  for (auto _ : state) {
    environment.Reset(scenario.seed);
    sim::EnvironmentStep step;
    do step = environment.Step(decision::CmaAction::kNoOp);
    while (!step.done);
    simulated = environment.state().time_s;
    benchmark::DoNotOptimize(step.reward);
    if (step.outcome != sim::Outcome::kCompleted) state.SkipWithError("the benchmark mission did not complete");
  }
  state.counters["sim_s"] = simulated;
  state.counters["realtime_factor"] =
      benchmark::Counter(simulated * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_FifteenMinuteMissionByEpochs)->Unit(benchmark::kMillisecond)->MinTime(2.0);

// The onboard decision path at one 1 Hz epoch (within 2x of the present-current EOD's cost): Observe (the
// EOD at the chosen load, the RUL, the margins, the abstract state) and the CMA table's decision, mid-cruise of the
// 15-minute mission. Arg 0: the present current (docs/modelling-choices.md#pack-eod); 1: the load forecast
// (docs/modelling-choices.md#eod-load-forecast).
void BM_DecisionEpoch(benchmark::State& state) {
  sim::Scenario scenario = FifteenMinuteMission();
  scenario.options.eod_load = state.range(0) == 0 ? sim::EodLoad::kPresent : sim::EodLoad::kForecast;
  const sim::FlightModel model(scenario);
  sim::FlightState flight = sim::MakeInitialState(model, scenario.seed);
  for (int k = 0; k < 300; ++k) sim::StepEpoch(model, flight, sim::Controllers{});
  const auto policy = sim::MakePolicy("cma", "bench");
  for (auto _ : state) {
    const sim::DecisionInputs& inputs = sim::Observe(model, flight);
    const decision::CmaAction action = policy->Decide(inputs);
    benchmark::DoNotOptimize(action);
  }
  state.SetLabel(sim::EodLoadName(scenario.options.eod_load));
}
BENCHMARK(BM_DecisionEpoch)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

// The load profile of a plan (docs/modelling-choices.md#eod-load-forecast), computed once when a plan starts: the 893 s
// mission, six rotors.
void BM_LoadProfile(benchmark::State& state) {
  const sim::FlightModel model(FifteenMinuteMission());
  for (auto _ : state) {
    const sim::LoadProfile profile(model.nominal_plan(), model.steady_load(), models::kRotorCount);
    benchmark::DoNotOptimize(profile.RemainingEnergyJ(0.0));
  }
}
BENCHMARK(BM_LoadProfile)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
