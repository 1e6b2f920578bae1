// Approximate footprint figures (dissertation §5.3.1, Algorithm 1; target ≤ 50 µs per footprint):
//  - one footprint (three PMP solutions, bounds, exact step-7 integration) with exact exponentials, for EODs
//    from 1 s to 600 s: the cost must not grow with the EOD (no time stepping);
//  - the same with the dissertation's 5th-order Maclaurin series (4×4 LU per case, polynomial pieces);
//  - for scale, a fixed-step (1 ms RK4) integration of step 7 for the backward case, what the exact pieces replace.
#include <benchmark/benchmark.h>

#include <algorithm>

#include "uascma/planning/footprint.h"

namespace {

using namespace uascma::planning;

FootprintParams Params(double eod, int maclaurin_order) {
  FootprintParams params;
  params.initial_speed = 9.0;  // m/s, Fig. 5.4
  params.eod = eod;
  params.drag_slope = 0.55;  // N·s/m, ≈ the default table's slope at 9 m/s
  params.maclaurin_order = maclaurin_order;
  return params;
}

void BM_Footprint(benchmark::State& state) {
  const FootprintParams params = Params(static_cast<double>(state.range(0)), static_cast<int>(state.range(1)));
  FootprintResult result;
  for (auto _ : state) {
    result = CalcFootprint(params);
    benchmark::DoNotOptimize(result);
  }
  state.counters["forward_m"] = result.forward_limit;
  state.counters["lateral_m"] = result.lateral_limit;
}
BENCHMARK(BM_Footprint)
    ->ArgNames({"eod_s", "maclaurin"})
    ->ArgsProduct({{1, 20, 50, 600}, {0, 5}})
    ->Unit(benchmark::kMicrosecond);

// Step 7 of the backward case by RK4 at 1 ms, the naive loop the closed-form pieces avoid.
void BM_BackwardStepSevenFixedStep(benchmark::State& state) {
  const FootprintParams params = Params(static_cast<double>(state.range(0)), 0);
  AxisProblem problem;
  problem.initial_velocity = params.initial_speed;
  problem.final_velocity = -params.initial_speed;
  problem.final_time = params.eod;
  problem.mass = params.mass;
  problem.drag_slope = params.drag_slope;
  const AxisOptimalSolution solution(problem);
  const double u_max = MaxLevelFlightForce(params.mass, params.max_tilt, params.available_thrust, nullptr);
  const double a = problem.drag_slope / problem.mass, dt = 1e-3;
  double position = 0.0;
  for (auto _ : state) {
    double x = 0.0, v = problem.initial_velocity;
    auto accel = [&](double t, double velocity) {
      return std::clamp(solution.Control(t), -u_max, u_max) / problem.mass - a * velocity;
    };
    for (double t = 0.0; t < problem.final_time; t += dt) {
      const double k1v = accel(t, v), k1x = v;
      const double k2v = accel(t + dt / 2, v + dt / 2 * k1v), k2x = v + dt / 2 * k1v;
      const double k3v = accel(t + dt / 2, v + dt / 2 * k2v), k3x = v + dt / 2 * k2v;
      const double k4v = accel(t + dt, v + dt * k3v), k4x = v + dt * k3v;
      x += dt / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
      v += dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    }
    position = x;
    benchmark::DoNotOptimize(position);
  }
  state.counters["backward_m"] = position;
}
BENCHMARK(BM_BackwardStepSevenFixedStep)->ArgNames({"eod_s"})->Arg(20)->Arg(600)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
