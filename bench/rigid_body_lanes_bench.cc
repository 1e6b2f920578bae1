// The rigid body's midpoint step with drag (models::StepRigidBody, the simulator's) for four bodies,
// scalar (four calls, as four flights flown alone would make) against the four-lane form of models/rigid_body_lanes.h
// on SSE2 (two 2-wide halves) and AVX2, bit-identical per body. Each iteration flies the four bodies 200 steps
// (1 s at 200 Hz) from the same starting states, every step depending on the last, with each body's own held thrust,
// torque and wind; the counter is per body-step. The bodies fly as in a campaign: tilt up to ~0.3 rad, 0-10 m/s
// against the air (the incidence inside the table's ±30°, so DragAtSine calls libm's asin). The lanes run with each
// drag lookup of models/rigid_body_lanes.h (path 0 = SSE2, 1 = AVX2; lookup 0 = libm's asin and the table per lane,
// bit-identical to the scalar step; 1 = our asin and the table per lane; 2 = our asin and the table in the lanes;
// 3 = libm's asin per lane and the table in the lanes, bit-identical to the scalar step).
// Instructions: valgrind --tool=callgrind --toggle-collect='*FlyScalar*' (or '*FlyLanes*') on this binary.
#include <array>
#include <cmath>
#include <string>

#include <benchmark/benchmark.h>

#include "uascma/common/frames.h"
#include "uascma/models/rigid_body_lanes.h"

namespace uascma::models {
namespace {

constexpr int kSteps = 200;
constexpr double kDt = 0.005;

struct Fleet {
  std::array<RigidBodyState, kBodyLanes> states;
  std::array<BodyInputs, kBodyLanes> inputs;
};

// Four bodies in forward flight through a 4 m/s wind from different directions, pitched and rolled differently.
Fleet StartingFleet() {
  const RigidBodyParams params;
  Fleet fleet;
  for (int i = 0; i < kBodyLanes; ++i) {
    const double a = 0.7 * i;
    fleet.states[i].p_WB_W = Eigen::Vector3d(10.0 * i, -5.0 * i, -30.0 - i);
    fleet.states[i].v_WB_W = Eigen::Vector3d(6.0 * std::cos(a), 6.0 * std::sin(a), 0.3 * (i - 1.5));
    fleet.states[i].q_WB = Eigen::Quaterniond(1.0, 0.05 * std::sin(a), -0.1 * std::cos(a), 0.2 * i).normalized();
    fleet.states[i].w_WB_B = Eigen::Vector3d(0.1 * i, -0.05, 0.02 * i);
    fleet.inputs[i].total_thrust = params.mass * kGravity * (1.0 + 0.03 * i);
    fleet.inputs[i].torque_B = Eigen::Vector3d(1e-3 * i, -2e-3, 5e-4 * i);
    fleet.inputs[i].wind_W = Eigen::Vector3d(4.0 * std::cos(2.0 * a), 4.0 * std::sin(2.0 * a), 0.2);
  }
  return fleet;
}

// Pattern "chain": each step from the last (a flight). Pattern "throughput": each step from the starting states, so
// that the steps are independent and only the instructions' throughput bounds them (the latency of a flight's
// chain hidden, as far as the rest of a simulator's step could hide it).
enum Pattern { kChain = 0, kThroughput = 1 };

[[gnu::noinline]] void FlyScalar(Pattern pattern, const DragTable& drag, const Fleet& start,
                                 std::array<RigidBodyState, 4>& states) {
  const RigidBodyParams params;
  states = start.states;
  for (int k = 0; k < kSteps; ++k) {
    if (pattern == kThroughput) states = start.states;
    for (int i = 0; i < kBodyLanes; ++i) states[i] = StepRigidBody(params, drag, states[i], start.inputs[i], kDt);
    benchmark::DoNotOptimize(states);
  }
}

[[gnu::noinline]] void FlyLanes(Pattern pattern, lane_math::LaneMathPath path, LaneDragLookup lookup,
                                const DragTable& drag, const RigidBodyLanes& start, const BodyInputLanes& inputs,
                                RigidBodyLanes& lanes) {
  const RigidBodyParams params;
  lanes = start;
  for (int k = 0; k < kSteps; ++k) {
    if (pattern == kThroughput) lanes = start;
    StepRigidBodyLanes(path, params, drag, lanes, inputs, kDt, lookup);
    benchmark::DoNotOptimize(lanes);
  }
}

void SetCounters(benchmark::State& state) {
  state.counters["ns_per_body_step"] = benchmark::Counter(static_cast<double>(state.iterations()) * kSteps * kBodyLanes,
                                                          benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_RigidBodyScalarX4(benchmark::State& state) {
  const DragTable drag = DragTable::Default(PropellerConfiguration::kTractor);
  const Fleet fleet = StartingFleet();
  std::array<RigidBodyState, 4> states;
  for (auto _ : state) {
    FlyScalar(static_cast<Pattern>(state.range(0)), drag, fleet, states);
    benchmark::DoNotOptimize(states);
  }
  SetCounters(state);
}
BENCHMARK(BM_RigidBodyScalarX4)->ArgName("pattern")->Arg(kChain)->Arg(kThroughput);

void BM_RigidBodyLanes(benchmark::State& state) {
  const auto path = static_cast<lane_math::LaneMathPath>(state.range(0));
  const auto lookup = static_cast<LaneDragLookup>(state.range(1));
  if (!lane_math::LaneMathPathSupported(path)) {
    state.SkipWithError("this CPU lacks AVX2");
    return;
  }
  const char* lookups[] = {"libm asin + lookup per lane", "our asin + lookup per lane", "our asin + lookup in lanes",
                           "libm asin per lane + lookup in lanes"};
  state.SetLabel(std::string(lane_math::LaneMathPathName(path)) + ", " + lookups[state.range(1)]);
  const DragTable drag = DragTable::Default(PropellerConfiguration::kTractor);
  const Fleet fleet = StartingFleet();
  RigidBodyLanes start, lanes;
  BodyInputLanes inputs;
  for (int i = 0; i < kBodyLanes; ++i) {
    start.Set(i, fleet.states[i]);
    inputs.Set(i, fleet.inputs[i]);
  }
  for (auto _ : state) {
    FlyLanes(static_cast<Pattern>(state.range(2)), path, lookup, drag, start, inputs, lanes);
    benchmark::DoNotOptimize(lanes);
  }
  SetCounters(state);
}
BENCHMARK(BM_RigidBodyLanes)
    ->ArgNames({"path", "lookup", "pattern"})
    ->ArgsProduct({{static_cast<int>(lane_math::LaneMathPath::kSse2), static_cast<int>(lane_math::LaneMathPath::kAvx2)},
                   {static_cast<int>(LaneDragLookup::kLibmPerLane), static_cast<int>(LaneDragLookup::kOursPerLane),
                    static_cast<int>(LaneDragLookup::kOursInLanes),
                    static_cast<int>(LaneDragLookup::kLibmAsinTableInLanes)},
                   {kChain, kThroughput}});

}  // namespace
}  // namespace uascma::models

BENCHMARK_MAIN();
