// Battery figures (dissertation §3.3, §4.3):
//  - one pack EOD, six cells in two parallel branches, from a resting state (target ≤ 10 µs per call;
//    for scale, NASA ProgPy's battery EOD prediction takes 0.3–2.3 s, so this is 4–5 orders lower);
//  - the same from a state in mid-flight (polarised RC pairs, settled hysteresis);
//  - one simulation step of the pack (the simulator steps it at 200 Hz) and of a single cell;
//  - the fixed-step (10 ms) reference EOD the fast method replaces, for comparison;
//  - the EOD distribution of one epoch and a decision from it (<= 50 us per epoch), mid-flight.
#include <benchmark/benchmark.h>

#include "uascma/models/battery.h"
#include "uascma/prognostics/eod.h"
#include "uascma/prognostics/eod_distribution.h"
#include "uascma/prognostics/eod_reference.h"

namespace {

using namespace uascma::models;
using uascma::prognostics::CalcPackEod;
using uascma::prognostics::EodResult;
using uascma::prognostics::SimulatePackEod;

constexpr double kRestVoltage = 4.1;  // V, the `uascma eod` default, inside Table 4.4's 4.05–4.12 V

// 0: healthy (G); 1: every cell with both fades (P, symmetric); 2: pack 2 power-faded with its cell 1 also
// capacity-faded (P, asymmetric: the branches split unevenly and pack 2's cells discharge out of step).
BatteryPack MakePack(int health_case) {
  PerCell<CellHealth> health{};
  for (int b = 0; b < kBranchCount; ++b) {
    for (int c = 0; c < kCellsPerBranch; ++c) {
      if (health_case == 1) health[b][c] = {.capacity_fade = true, .power_fade = true};
      if (health_case == 2 && b == 1) health[b][c] = {.capacity_fade = c == 0, .power_fade = true};
    }
  }
  return BatteryPack(MakePackParams(health));
}

void BM_PackEodFromRest(benchmark::State& state) {
  const BatteryPack pack = MakePack(static_cast<int>(state.range(0)));
  const PackState start = pack.MakeRestingState(kRestVoltage);
  const double current_a = static_cast<double>(state.range(1));
  EodResult result;
  for (auto _ : state) {
    result = CalcPackEod(pack, start, current_a);
    benchmark::DoNotOptimize(result);
  }
  state.counters["eod_s"] = result.eod_s;
  state.counters["segments"] = result.segments;
}
BENCHMARK(BM_PackEodFromRest)
    ->ArgNames({"health", "current_a"})
    ->ArgsProduct({{0, 1, 2}, {10, 30, 60}})
    ->Unit(benchmark::kMicrosecond);

// After 120 s at 45 A followed by a drop to 25 A: the RC pairs recover during the prediction, so v(t) is
// not monotone and the crossing search must prove there is no earlier dip.
void BM_PackEodMidFlight(benchmark::State& state) {
  const BatteryPack pack = MakePack(static_cast<int>(state.range(0)));
  PackState flying = pack.MakeRestingState(kRestVoltage);
  for (int k = 0; k < 120; ++k) flying = pack.Step(flying, 45.0, 1.0);
  EodResult result;
  for (auto _ : state) {
    result = CalcPackEod(pack, flying, 25.0);
    benchmark::DoNotOptimize(result);
  }
  state.counters["eod_s"] = result.eod_s;
  state.counters["segments"] = result.segments;
}
BENCHMARK(BM_PackEodMidFlight)->ArgName("health")->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);

void BM_PackStep(benchmark::State& state) {
  const BatteryPack pack = MakePack(2);
  PackState pack_state = pack.MakeRestingState(kRestVoltage);
  const PackState start = pack_state;
  for (auto _ : state) {
    PackStepResult step = pack.StepWithOutputs(pack_state, 30.0, 0.005);  // 200 Hz
    pack_state = step.next;
    benchmark::DoNotOptimize(step.outputs.split.bus_voltage_v);
    if (pack_state.cells[0][0].soc_fraction < 0.2) pack_state = start;  // stay in the flight range
  }
}
BENCHMARK(BM_PackStep)->Unit(benchmark::kNanosecond);

void BM_CellStep(benchmark::State& state) {
  const SelfCorrectingCell cell;
  CellState cell_state = cell.MakeRestingState(kRestVoltage);
  const CellState start = cell_state;
  for (auto _ : state) {
    cell_state = cell.Step(cell_state, 15.0, 0.005);
    benchmark::DoNotOptimize(cell.CalcTerminalVoltage(cell_state, 15.0));
    if (cell_state.soc_fraction < 0.2) cell_state = start;
  }
}
BENCHMARK(BM_CellStep)->Unit(benchmark::kNanosecond);

void BM_PackEodFixedStepReference(benchmark::State& state) {
  const BatteryPack pack = MakePack(0);
  const PackState start = pack.MakeRestingState(kRestVoltage);
  EodResult result;
  for (auto _ : state) {
    result = SimulatePackEod(pack, start, 30.0, 0.01);
    benchmark::DoNotOptimize(result);
  }
  state.counters["eod_s"] = result.eod_s;
}
BENCHMARK(BM_PackEodFixedStepReference)->Unit(benchmark::kMillisecond)->Iterations(3);

// The EOD distribution at one 1 Hz epoch plus what a risk-aware decision reads from it, P(EOD <
// t_flight) and three quantiles, mid-flight (120 s at 45 A, then 25 A). Sources: 0 = load and SOC (what the
// flight's error model measures); 1 = every source and an uncertain temperature class (the most calls). The
// 1σ values are those of eod_distribution_test (the cost does not depend on them, only on which are > 0).
void BM_EodDistributionAndDecision(benchmark::State& state) {
  const BatteryPack pack = MakePack(static_cast<int>(state.range(0)));
  PackState flying = pack.MakeRestingState(kRestVoltage);
  for (int k = 0; k < 120; ++k) flying = pack.Step(flying, 45.0, 1.0);
  uascma::prognostics::EodUncertainty uncertainty;
  uncertainty.load_log_mean = 0.02;
  uncertainty.load_log_sigma = 0.08;
  uncertainty.soc_sigma = 0.02;
  if (state.range(1) == 1) {
    uncertainty.r0_log_sigma = 0.10;
    uncertainty.capacity_log_sigma = 0.03;
    uncertainty.cold_probability = 0.3;
  }
  const double flight_time_s = 0.8 * CalcPackEod(pack, flying, 25.0).eod_s;
  uascma::prognostics::EodDistribution distribution;
  double risk = 0.0;
  for (auto _ : state) {
    distribution = uascma::prognostics::CalcPackEodDistribution(pack, flying, 25.0, uncertainty);
    risk = distribution.ProbabilityBefore(flight_time_s);
    benchmark::DoNotOptimize(risk);
    benchmark::DoNotOptimize(distribution.Quantile(0.05) + distribution.Quantile(0.5) + distribution.Quantile(0.95));
  }
  state.counters["calls"] = distribution.evaluations;
  state.counters["risk"] = risk;
}
BENCHMARK(BM_EodDistributionAndDecision)
    ->ArgNames({"health", "sources"})
    ->ArgsProduct({{0, 2}, {0, 1}})
    ->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
