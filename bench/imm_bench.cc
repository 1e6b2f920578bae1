// One cycle of the 7-mode IMM (gnc/imm.h) on each instruction set the CPU has (gnc/imm_lanes.h: SSE2, AVX2,
// AVX-512; the same bits on all), fed a recorded hover with noise: time per step (ns). The simulator calls it
// every 200 Hz step until a rotor is isolated. Instructions per step: callgrind on `uascma simulate` (README);
// valgrind emulates no AVX-512, so under it the widest path is AVX2. Also e^x on eight lanes against std::exp.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "uascma/common/frames.h"
#include "uascma/common/random.h"
#include "uascma/gnc/imm.h"
#include "uascma/gnc/imm_lanes.h"
#include "uascma/models/mixer.h"
#include "uascma/models/propulsion.h"

namespace {

using namespace uascma;

constexpr double kDt = 0.005;  // s, the 200 Hz GNC step (§5.4)
constexpr int kRecordedSteps = 4096;

struct Recording {
  models::RigidBodyParams body;
  models::MixingMatrix mixing = models::CalcMixingMatrix(
      models::MixerParams::ForPropulsion(
          models::PropulsionParams::ForConfiguration(models::PropellerConfiguration::kTractor)),
      models::kNoFailedMotor);
  std::vector<models::RotorThrusts> believed;
  std::vector<gnc::ImmMeasurement> measured;
};

// A healthy hover: commands with 5 % noise, the gyro and accelerometer with the noise the filter assumes.
const Recording& Hover() {
  static const Recording recording = [] {
    Recording r;
    RandomStream random(17);
    const gnc::ImmParams params;
    for (int k = 0; k < kRecordedSteps; ++k) {
      models::RotorThrusts thrusts;
      for (int i = 0; i < 6; ++i) thrusts[i] = r.body.mass * kGravity / 6.0 * (1.0 + 0.05 * random.Normal());
      const models::BodyWrench wrench = r.mixing * thrusts;
      gnc::ImmMeasurement z;
      z.gyro_B = params.gyro_noise * Eigen::Vector3d(random.Normal(), random.Normal(), random.Normal());
      z.specific_force_z_B = -wrench(0) / r.body.mass + params.accel_noise * random.Normal();
      r.believed.push_back(thrusts);
      r.measured.push_back(z);
    }
    return r;
  }();
  return recording;
}

void BM_ImmStep(benchmark::State& state) {
  const auto path = static_cast<gnc::SimdPath>(state.range(0));
  if (!gnc::CpuSupports(path)) {
    state.SkipWithError("this CPU lacks the instruction set");
    return;
  }
  state.SetLabel(gnc::SimdPathName(path));
  const Recording& hover = Hover();
  gnc::ImmFilter imm(gnc::ImmParams{}, hover.body, hover.mixing);
  int k = 0;
  for (auto _ : state) {
    imm.StepOn(path, hover.believed[k], hover.measured[k], kDt);
    k = (k + 1) % kRecordedSteps;
  }
  const double nominal = imm.ModeProbability(0);
  benchmark::DoNotOptimize(nominal);
}
BENCHMARK(BM_ImmStep)
    ->ArgName("path")
    ->Arg(static_cast<int>(gnc::SimdPath::kSse2))
    ->Arg(static_cast<int>(gnc::SimdPath::kAvx2))
    ->Arg(static_cast<int>(gnc::SimdPath::kAvx512));

void BM_ExpLanes(benchmark::State& state) {
  const auto path = static_cast<gnc::SimdPath>(state.range(0));
  if (!gnc::CpuSupports(path)) {
    state.SkipWithError("this CPU lacks the instruction set");
    return;
  }
  state.SetLabel(gnc::SimdPathName(path));
  gnc::ImmLaneArray x = {0.0, -0.3, -1.7, -5.0, -12.5, -40.0, -111.0, -0.01};
  for (auto _ : state) {
    benchmark::DoNotOptimize(x);  // read afresh every iteration
    const gnc::ImmLaneArray y = gnc::ExpLanes(path, x);
    benchmark::DoNotOptimize(y);
  }
}
BENCHMARK(BM_ExpLanes)
    ->ArgName("path")
    ->Arg(static_cast<int>(gnc::SimdPath::kSse2))
    ->Arg(static_cast<int>(gnc::SimdPath::kAvx2))
    ->Arg(static_cast<int>(gnc::SimdPath::kAvx512));

void BM_StdExpEightTimes(benchmark::State& state) {
  gnc::ImmLaneArray x = {0.0, -0.3, -1.7, -5.0, -12.5, -40.0, -111.0, -0.01};
  for (auto _ : state) {
    benchmark::DoNotOptimize(x);  // read afresh every iteration
    gnc::ImmLaneArray y;
    for (int i = 0; i < gnc::kImmLanes; ++i) y[i] = std::exp(x[i]);
    benchmark::DoNotOptimize(y);
  }
}
BENCHMARK(BM_StdExpEightTimes);

}  // namespace

BENCHMARK_MAIN();
