#include <gtest/gtest.h>

#include "uascma/common/frames.h"
#include "uascma/sim/scenario.h"
#include "uascma/sim/simulator.h"
#include "uascma/sim/telemetry.h"
#include "uascma/common/error.h"

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

TEST(SimulatorTest, SameSeedGivesBitIdenticalTelemetry) {
  Scenario scenario = Nominal();
  scenario.mission.destination_NE = Eigen::Vector2d(150, 100);
  scenario.wind.turbulence = models::TurbulenceCategory::kMediumModerate;
  scenario.fault.enabled = true;
  scenario.fault.spall_onset_s = 20.0;
  scenario.fault.time_per_growth_step_s = 0.7128;
  const Simulator simulator(scenario);
  NoOpPolicy policy;
  const std::string first = TelemetryCsv(simulator.Run(policy));
  const std::string second = TelemetryCsv(simulator.Run(policy));
  EXPECT_EQ(first, second);  // text of every sample, to the printed digits
  const SimResult a = simulator.Run(policy), b = simulator.Run(policy);
  ASSERT_EQ(a.telemetry.size(), b.telemetry.size());
  for (std::size_t k = 0; k < a.telemetry.size(); ++k) {
    ASSERT_EQ(a.telemetry[k].p_W, b.telemetry[k].p_W);  // bit-identical doubles
    ASSERT_EQ(a.telemetry[k].cell_voltage, b.telemetry[k].cell_voltage);
  }
  scenario.seed += 1;
  const std::string other = TelemetryCsv(Simulator(scenario).Run(policy));
  EXPECT_NE(first, other);
}

TEST(SimulatorTest, HoverIsSteadyInCalmAir) {
  Scenario scenario;
  scenario.mission.destination_NE = Eigen::Vector2d::Zero();  // take off, hover 60 s, land
  scenario.mission.drop_hover_s = 60.0;
  scenario.options.telemetry_rate_hz = 50.0;
  const Simulator simulator(scenario);
  NoOpPolicy policy;
  const SimResult result = simulator.Run(policy);
  EXPECT_EQ(result.outcome, Outcome::kCompleted) << result.reason;
  const double hover_start = simulator.nominal_plan().segments()[1].start_time;
  double max_error = 0.0, max_speed = 0.0, max_tilt = 0.0;
  for (const TelemetryRow& row : result.telemetry) {
    if (row.t < hover_start + 10.0 || row.t > hover_start + 60.0) continue;  // settled hover
    max_error = std::max(max_error, (row.p_W - row.p_ref_W).norm());
    max_speed = std::max(max_speed, row.v_W.norm());
    max_tilt = std::max(max_tilt, std::hypot(row.euler.x(), row.euler.y()));
  }
  EXPECT_LT(max_error, 0.05);   // m: the offset of a controller without integrator stays small
  EXPECT_LT(max_speed, 0.02);   // m/s
  EXPECT_LT(max_tilt, 0.01);    // rad
}

TEST(SimulatorTest, PoorBatteryOnAPlanLongerThanItsEodFailsUnderNoOp) {
  Scenario scenario = Nominal();
  for (auto& pack : scenario.battery.cell_health) pack = PackHealthPreset(models::HealthClass::kP);
  for (auto& pack : scenario.battery.initial_cell_voltage_v) pack.fill(4.05);
  scenario.battery.ambient_temp_degf = 40.0;
  scenario.mission.destination_NE = Eigen::Vector2d(1800, 900);
  const Simulator simulator(scenario);
  NoOpPolicy policy;
  const SimResult result = simulator.Run(policy, {}, {.record_telemetry = false});
  Print(result);
  EXPECT_EQ(result.outcome, Outcome::kFailedBattery) << result.reason;
  EXPECT_EQ(simulator.battery_health(), decision::BatteryHealth::kP);
  // The 1 Hz prognosis saw it coming: the reach margin was negative long before the cut-off.
  int negative_epochs = 0;
  for (const auto& [t, state] : result.states) negative_epochs += (state % 2 == 0) ? 1 : 0;  // RM0
  EXPECT_GT(negative_epochs, 60);
}

TEST(ScenarioFileTest, ParsesTheExampleKeysAndRejectsBadOnesByName) {
  const ScenarioFile file = ParseScenario(
      "name: t\nseed: 4\nbattery: {initial_cell_voltage_v: 4.08, packs: [G, M]}\n"
      "wind: {speed_mps: 2.5, direction_deg: 90, turbulence: medium-light}\n"
      "fault: {motor: 2, spall_onset_s: 30}\n",
      "t.yaml");
  EXPECT_EQ(file.scenario.seed, 4u);
  EXPECT_TRUE(file.scenario.fault.enabled);
  EXPECT_EQ(file.scenario.fault.motor, 2);
  EXPECT_NEAR(file.scenario.wind.direction_rad, std::acos(-1.0) / 2, 1e-12);
  EXPECT_TRUE(file.scenario.battery.cell_health[1][0].power_fade);
  EXPECT_FALSE(file.scenario.battery.cell_health[1][0].capacity_fade);
  EXPECT_FALSE(file.scenario.battery.cell_health[0][2].power_fade);
  auto message = [](const std::string& yaml) {
    try {
      ParseScenario(yaml, "bad.yaml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message("wind: {turbulance: none}\n").find("bad.yaml: wind.turbulance"), std::string::npos);
  EXPECT_NE(message("fault: {motor: 7, spall_onset_s: 3}\n").find("fault.motor"), std::string::npos);
  EXPECT_NE(message("mission: {cruise_altitude_m: abc}\n").find("mission.cruise_altitude_m: a number, got 'abc'"),
            std::string::npos);
  EXPECT_NE(message("battery: {initial_cell_voltage_v: 4.5}\n").find("initial_cell_voltage_v"), std::string::npos);
  EXPECT_NE(message("seed: [1, 2\n").find("bad.yaml: line"), std::string::npos);
}

}  // namespace
}  // namespace uascma::sim
