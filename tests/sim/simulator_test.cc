#include <gtest/gtest.h>

#include "uascma/common/frames.h"
#include "uascma/sim/simulator.h"

namespace uascma::sim {
namespace {

Scenario Nominal() {
  Scenario scenario;
  scenario.name = "test nominal";
  scenario.mission.destination_NE = Eigen::Vector2d(400, 300);
  scenario.wind.mean_speed = 2.0;
  scenario.wind.direction_rad = 1.0;
  scenario.wind.turbulence = models::TurbulenceCategory::kLowLight;
  scenario.seed = 7;
  return scenario;
}

TEST(SimulatorTest, NominalFlightCompletes) {
  const Simulator simulator(Nominal());
  NoOpPolicy policy;
  const SimResult result = simulator.Run(policy);
  for (const auto& e : result.events) std::printf("%8.2f %s\n", e.time_s, e.what.c_str());
  std::printf("sim %.1f s wall %.4f s rtf %.0f, max err %.2f m, tilt %.1f deg, min cell %.3f V, energy %.1f Wh\n",
              result.sim_time_s, result.wall_time_s, result.realtime_factor(), result.max_tracking_error,
              result.max_tilt * kDegreesPerRadian, result.min_cell_voltage_v, result.energy_wh);
  EXPECT_EQ(result.outcome, Outcome::kCompleted) << result.reason;
}

}  // namespace
}  // namespace uascma::sim
