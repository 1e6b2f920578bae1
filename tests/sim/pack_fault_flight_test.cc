// Sudden pack faults in flight (models/pack_fault.h, scenario key pack_fault): the keys, a short that drains its
// cell, the pack stepped slowly against the pack at every GNC step, and a flight replayed from its seed.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "uascma/common/error.h"
#include "uascma/sim/policy.h"
#include "uascma/sim/simulator.h"

namespace uascma::sim {
namespace {

// Volts: the pack's 10 Hz slow step against its state at the 200 Hz GNC rate over a whole flight (README "Subsystem
// rates" measures ~1 mV on fault-free flights; a 0.5 Ω short adds a drain the linearisation holds constant for 0.1 s).
constexpr double kSlowStepVoltageTolerance = 5e-3;

Scenario Hover(double hover_s) {
  Scenario scenario;
  scenario.name = "pack fault hover";
  scenario.mission.destination_NE = Eigen::Vector2d::Zero();
  scenario.mission.drop_hover_s = hover_s;
  scenario.wind.mean_speed = 2.0;
  scenario.wind.turbulence = models::TurbulenceCategory::kLowLight;
  scenario.seed = 3;
  return scenario;
}

SimResult Fly(const Scenario& scenario) {
  const Simulator simulator(scenario);
  NoOpPolicy policy;
  return simulator.Run(policy, {}, {.record_telemetry = false});
}

std::string ParseMessage(const std::string& yaml) {
  try {
    ParseScenario(yaml, "bad.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return {};
}

TEST(PackFaultFlightTest, ScenarioKeysInjectOneFault) {
  const ScenarioFile file = ParseScenario(
      "pack_fault: {kind: internal_short, pack: 2, cell: 3, onset_s: 120, resistance_ohm: 4.5}\n", "t.yaml");
  ASSERT_TRUE(file.scenario.pack_fault.has_value());
  EXPECT_EQ(file.scenario.pack_fault->kind, models::PackFaultKind::kInternalShort);
  EXPECT_EQ(file.scenario.pack_fault->branch, 1);
  EXPECT_EQ(file.scenario.pack_fault->cell, 2);
  EXPECT_EQ(file.scenario.pack_fault->onset_s, 120.0);
  EXPECT_EQ(file.scenario.pack_fault->resistance_ohm, 4.5);
  EXPECT_FALSE(ParseScenario("name: x\n", "t.yaml").scenario.pack_fault.has_value());
  EXPECT_NE(ParseMessage("pack_fault: {kind: short, pack: 1, cell: 1, onset_s: 1, resistance_ohm: 1}\n")
                .find("bad.yaml: pack_fault.kind"),
            std::string::npos);
  EXPECT_NE(ParseMessage("pack_fault: {kind: connector, pack: 3, onset_s: 1, resistance_ohm: 1}\n")
                .find("bad.yaml: pack_fault.pack"),
            std::string::npos);
  EXPECT_NE(ParseMessage("pack_fault: {kind: failed_cell, pack: 1, cell: 1, onset_s: 1, resistance_ohm: 0}\n")
                .find("bad.yaml: pack_fault.resistance_ohm"),
            std::string::npos);
  EXPECT_NE(ParseMessage("pack_fault: {kind: failed_cell, pack: 1, onset_s: 1, resistance_ohm: 1}\n")
                .find("bad.yaml: pack_fault.cell"),
            std::string::npos);
}

TEST(PackFaultFlightTest, ShortDrainsItsCellAndTheFlightReplays) {
  const Scenario healthy = Hover(240.0);
  Scenario shorted = healthy;
  shorted.pack_fault = models::PackFault{
      .kind = models::PackFaultKind::kInternalShort, .branch = 0, .cell = 1, .resistance_ohm = 0.5, .onset_s = 20.0};
  const SimResult a = Fly(healthy);
  const SimResult b = Fly(shorted);
  // i_s ≈ 8 A for ~250 s drains ~0.18 of the cell's 3 A·h beyond its branch's share: its cell reads lower.
  EXPECT_LT(b.min_cell_voltage_v, a.min_cell_voltage_v - 0.05);
  const SimResult replay = Fly(shorted);
  EXPECT_EQ(replay.outcome, b.outcome);
  EXPECT_EQ(replay.sim_time_s, b.sim_time_s);
  EXPECT_EQ(replay.min_cell_voltage_v, b.min_cell_voltage_v);
  EXPECT_EQ(replay.energy_wh, b.energy_wh);
  // The pack at every GNC step (no slow step) gives the same lowest cell within the slow step's error.
  Scenario every_step = shorted;
  every_step.options.pack_rate_hz = every_step.options.gnc_rate_hz;
  EXPECT_NEAR(Fly(every_step).min_cell_voltage_v, b.min_cell_voltage_v, kSlowStepVoltageTolerance);
}

TEST(PackFaultFlightTest, AFaultBeforeItsOnsetChangesNothing) {
  // A fault whose onset lies after the flight's end leaves the flight bit-identical to the fault-free one.
  const Scenario healthy = Hover(30.0);
  Scenario late = healthy;
  late.pack_fault = models::PackFault{
      .kind = models::PackFaultKind::kFailedCell, .branch = 1, .cell = 0, .resistance_ohm = 5.0, .onset_s = 5000.0};
  const SimResult a = Fly(healthy);
  const SimResult b = Fly(late);
  EXPECT_EQ(a.sim_time_s, b.sim_time_s);
  EXPECT_EQ(a.energy_wh, b.energy_wh);
  EXPECT_EQ(a.min_cell_voltage_v, b.min_cell_voltage_v);
}

}  // namespace
}  // namespace uascma::sim
