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

void Print(const SimResult& result) {
  for (const auto& e : result.events) std::printf("%8.2f %s\n", e.time_s, e.what.c_str());
  std::printf("sim %.1f s wall %.4f s rtf %.0f, max err %.2f m, tilt %.1f deg, min cell %.3f V, energy %.1f Wh\n",
              result.sim_time_s, result.wall_time_s, result.realtime_factor(), result.max_tracking_error,
              result.max_tilt * kDegreesPerRadian, result.min_cell_voltage_v, result.energy_wh);
}

TEST(SimulatorTest, NominalFlightCompletes) {
  const Simulator simulator(Nominal());
  NoOpPolicy policy;
  const SimResult result = simulator.Run(policy);
  Print(result);
  EXPECT_EQ(result.outcome, Outcome::kCompleted) << result.reason;
}

class JamTest : public ::testing::TestWithParam<int> {};

TEST_P(JamTest, JamIsIsolatedAndTheQuadcopterStaysControlled) {
  Scenario scenario = Nominal();
  scenario.fault.enabled = true;
  scenario.fault.motor = GetParam();
  scenario.fault.spall_onset_s = 60.0;
  scenario.fault.time_per_growth_step_s = 0.7128;  // jam ~17 s after the spall, as in scenario I
  const Simulator simulator(scenario);
  NoOpPolicy policy;
  const SimResult result = simulator.Run(policy);
  Print(result);
  ASSERT_TRUE(result.jam_time_s.has_value());
  ASSERT_TRUE(result.isolation_time_s.has_value());
  EXPECT_EQ(result.isolated_rotor, GetParam());
  EXPECT_LT(*result.isolation_time_s - *result.jam_time_s, 0.2);
  EXPECT_EQ(result.outcome, Outcome::kCompleted) << result.reason;
}

INSTANTIATE_TEST_SUITE_P(Rotors, JamTest, ::testing::Values(1, 2, 3, 4, 5, 6));

TEST(SimulatorTest, WithoutReconfigurationTheJamLosesControl) {
  Scenario scenario = Nominal();
  scenario.fault.enabled = true;
  scenario.fault.motor = 3;
  scenario.fault.spall_onset_s = 60.0;
  scenario.fault.time_per_growth_step_s = 0.7128;
  scenario.options.reconfiguration = false;
  const Simulator simulator(scenario);
  NoOpPolicy policy;
  const SimResult result = simulator.Run(policy);
  Print(result);
  EXPECT_TRUE(IsFailure(result.outcome)) << OutcomeName(result.outcome);
}

}  // namespace
}  // namespace uascma::sim
