// Control-allocation figures (issue: propulsion, mixing and control authority). Allocate runs at the
// 200 Hz GNC rate inside a simulator meant to go ≥ 10,000× real time, i.e. 2·10⁶ calls per simulated-
// vehicle second of wall time: one call must cost well under a microsecond and never touch the heap.
//  - one allocation of a hexacopter wrench inside the envelope, and with excess yaw (saturated);
//  - one allocation after motor 3 failed (quadcopter on rotors 1, 2, 4, 5);
//  - for reference, the rotor-speed lag step and the eq. 2.12 RPM estimate.
#include <benchmark/benchmark.h>

#include "uascma/common/frames.h"
#include "uascma/models/mixer.h"
#include "uascma/models/propulsion.h"

namespace {

using namespace uascma::models;

// Cycles through a few wrenches so the optimiser cannot hoist the call out of the loop.
void RunAllocation(benchmark::State& state, int failed_motor, double yaw) {
  const Mixer mixer(MixerParams{});
  const double hover = 1.3 * uascma::kGravity;
  const BodyWrench wrenches[4] = {{hover, 0.05, -0.04, yaw},
                                  {hover + 0.5, -0.03, 0.02, -yaw},
                                  {hover - 0.4, 0.01, 0.06, yaw},
                                  {hover, -0.06, -0.01, -yaw}};
  int k = 0;
  for (auto _ : state) {
    AllocationResult result = mixer.Allocate(wrenches[k], failed_motor);
    benchmark::DoNotOptimize(result);
    k = (k + 1) & 3;
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_AllocateHexacopter(benchmark::State& state) { RunAllocation(state, kNoFailedMotor, 0.005); }
BENCHMARK(BM_AllocateHexacopter);

void BM_AllocateHexacopterSaturatedYaw(benchmark::State& state) { RunAllocation(state, kNoFailedMotor, 0.5); }
BENCHMARK(BM_AllocateHexacopterSaturatedYaw);

void BM_AllocateReconfiguredMotor3Failed(benchmark::State& state) { RunAllocation(state, 3, 0.005); }
BENCHMARK(BM_AllocateReconfiguredMotor3Failed);

void BM_RotorSpeedLagStep(benchmark::State& state) {
  const RotorSpeedLag lag(0.03, 0.005);
  double speed = 100.0;
  double command = 1500.0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(speed = lag.Step(speed, command));
    command = 3000.0 - command;
  }
}
BENCHMARK(BM_RotorSpeedLagStep);

void BM_EstimateRpm(benchmark::State& state) {
  const RpmEstimatorParams params;
  double throttle_us = 1500.0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(EstimateRpm(params, throttle_us, 60.0));
    throttle_us = throttle_us > 1800.0 ? 1200.0 : throttle_us + 1.0;
  }
}
BENCHMARK(BM_EstimateRpm);

}  // namespace

BENCHMARK_MAIN();
