// The pack-fault indicator (prognostics/pack_fault_monitor.h) against faults injected into the pack model
// (models/pack_fault.h): no alarm without a fault, detection after the onset and never before, within the delay
// the residual's closed form gives.
#include "uascma/prognostics/pack_fault_monitor.h"

#include <cmath>

#include <gtest/gtest.h>

namespace uascma::models {
namespace {

using prognostics::PackFaultMonitor;
using prognostics::ReadPackMonitor;

// Without a fault the residuals are the difference between the truth stepped at 0.1 s and the monitor's 1 s step of
// the same charge: the RC term's (Δt/(R1 C1))² ~ 4e-6 of the current's change, and hysteresis exact in the charge.
// Volts and amperes; 1e-4 is 300 times below the thresholds.
constexpr double kFaultFreeResidualBound = 1e-4;

struct Flown {
  PackFaultMonitor monitor;
  double max_voltage_residual_v = 0.0;
  double max_current_residual_a = 0.0;
};

// The pack stepped at 0.1 s under a load that swings between 14 and 26 A with a 20 s period (hover and cruise),
// read by the monitor once a second, for `duration_s` or until a switched-in cell reaches the cut-off.
Flown Fly(const BatteryPack& pack, double duration_s, const PackFault* fault) {
  PackState state = pack.MakeRestingState(4.1);
  Flown flown{PackFaultMonitor(pack, state), 0.0, 0.0};
  PerBranch<double> charge_as{};
  const double dt_s = 0.1;
  for (int k = 0; k * dt_s < duration_s; ++k) {
    const double t = k * dt_s;
    state.fault_on = fault != nullptr && IsPackFaultOn(*fault, t);
    const double current_a = 20.0 + 6.0 * std::sin(2.0 * 3.141592653589793 * t / 20.0);
    if (k % 10 == 0) {
      flown.monitor.Update(ReadPackMonitor(pack, state, current_a, charge_as, t));
      for (int b = 0; b < kBranchCount; ++b) {
        flown.max_voltage_residual_v = std::max(flown.max_voltage_residual_v, -flown.monitor.voltage_residual_v()[b]);
        flown.max_current_residual_a =
            std::max(flown.max_current_residual_a, std::abs(flown.monitor.current_residual_a()[b]));
      }
    }
    const PackStepResult step = pack.StepWithOutputs(state, current_a, dt_s);
    if (step.outputs.min_cell_voltage_v <= kCutoffVoltage) break;
    for (int b = 0; b < kBranchCount; ++b) charge_as[b] += step.outputs.split.current_a[b] * dt_s;
    state = step.next;
  }
  return flown;
}

BatteryPack PackWith(const PackFault& fault, const PerCell<CellHealth>& health = {}, double temp_degf = 77.0) {
  PackParams params = MakePackParams(health, temp_degf);
  params.fault = fault;
  return BatteryPack(params);
}

TEST(PackFaultMonitorTest, NoAlarmWithoutAFaultAtAnyHealthOrTemperature) {
  PerCell<CellHealth> poor{};
  poor[0][1] = {.capacity_fade = true, .power_fade = true};
  poor[1][0] = {.capacity_fade = true, .power_fade = false};
  for (const double temp_degf : {40.0, 77.0}) {
    for (const PerCell<CellHealth>& health : {PerCell<CellHealth>{}, poor}) {
      const BatteryPack pack(MakePackParams(health, temp_degf));
      const Flown flown = Fly(pack, 1500.0, nullptr);  // to the cut-off
      EXPECT_FALSE(flown.monitor.any_faulted()) << temp_degf;
      EXPECT_LT(flown.max_voltage_residual_v, kFaultFreeResidualBound) << temp_degf;
      EXPECT_LT(flown.max_current_residual_a, kFaultFreeResidualBound) << temp_degf;
    }
  }
}

TEST(PackFaultMonitorTest, ShortIsDetectedAfterItsOnsetWithinTheResidualsDelay) {
  // A 2 Ω short in pack 2 cell 1 from 100 s: the cell's residual is −R0 i_s at once and then falls by the OCV the
  // extra charge i_s (t − t0) removes, slope · i_s (t − t0) / Q. The default OCV table's flattest segment above 3.6 V
  // is 0.2 V per unit SOC (3.84 → 3.85 V over 50-55 %, docs/defaults.md#battery), i_s ≥ 3.6 V / 2 Ω = 1.8 A there and
  // Q = 3.0271 A·h: the 30 mV threshold is crossed within 0.03 · Q / (0.2 · 1.8 A) = 908 s of the onset at the latest
  // (the branch current's residual may fire first), then held 3 epochs.
  const PackFault fault{
      .kind = PackFaultKind::kInternalShort, .branch = 1, .cell = 0, .resistance_ohm = 2.0, .onset_s = 100.0};
  const Flown flown = Fly(PackWith(fault), 1100.0, &fault);
  ASSERT_TRUE(flown.monitor.faulted()[1]);
  EXPECT_FALSE(flown.monitor.faulted()[0]);
  const double detected_s = *flown.monitor.detection_time_s()[1];
  EXPECT_GT(detected_s, fault.onset_s);
  EXPECT_LE(detected_s, fault.onset_s + 0.03 * 3.0271 * 3600.0 / (0.2 * 1.8) + 3.0);
}

TEST(PackFaultMonitorTest, FailedCellAndConnectorAreDetectedWithinSeconds) {
  // A failed cell of 0.5 Ω sags by R_f i ≈ 0.5 Ω · 1.5 A at once (its branch keeps ~7 % of 20 A): three epochs. A
  // 0.2 Ω connector takes the branch from half the load to a tenth while the contact is poor: the first three
  // epochs in a row that find it poor (probability ½ each, models/pack_fault.h).
  const PackFault failed{
      .kind = PackFaultKind::kFailedCell, .branch = 0, .cell = 2, .resistance_ohm = 0.5, .onset_s = 50.0};
  const Flown a = Fly(PackWith(failed), 120.0, &failed);
  ASSERT_TRUE(a.monitor.faulted()[0]);
  EXPECT_FALSE(a.monitor.faulted()[1]);
  EXPECT_GT(*a.monitor.detection_time_s()[0], failed.onset_s);
  EXPECT_LE(*a.monitor.detection_time_s()[0], failed.onset_s + 3.0);

  const PackFault connector{
      .kind = PackFaultKind::kConnector, .branch = 1, .cell = 0, .resistance_ohm = 0.2, .onset_s = 50.0, .seed = 11};
  const Flown b = Fly(PackWith(connector), 400.0, &connector);
  ASSERT_TRUE(b.monitor.faulted()[1]);
  EXPECT_FALSE(b.monitor.faulted()[0]);
  EXPECT_GT(*b.monitor.detection_time_s()[1], connector.onset_s);
}

}  // namespace
}  // namespace uascma::models
