// The pack stepped at a lower rate than its load (models/battery_pack.h PackLinearisation) against the pack stepped
// at the GNC rate: a full discharge under a varying current, both packs degraded differently and cold, compared
// step by step (voltages, branch currents), at every slow step (states of charge, RC currents, hysteresis), at every
// 1 Hz epoch (EOD) and at the cut-off.
#include <algorithm>
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "uascma/models/battery.h"
#include "uascma/prognostics/eod.h"

namespace uascma::models {
namespace {

constexpr double kGncStep = 0.005;  // s, 200 Hz
constexpr int kEpochSteps = 200;    // GNC steps per 1 Hz epoch

// A = the load of a flight's power system: a 20 A cruise with a slow 5 A swing, a 7 Hz ripple of 3 A (rotor
// commands in gusts), 30 A climbs for 30 s every 300 s and 2 A hovers on the ground at the start.
double LoadCurrent(double t) {
  if (t < 10.0) return 2.0;
  const double climb = std::fmod(t, 300.0) < 30.0 ? 10.0 : 0.0;
  return 20.0 + climb + 5.0 * std::sin(2.0 * std::numbers::pi * 0.3 * t) +
         3.0 * std::sin(2.0 * std::numbers::pi * 7.0 * t);
}

struct Deviations {
  double voltage_v = 0.0;         // any cell's terminal voltage, and the bus voltage, V
  double branch_current_a = 0.0;  // A
  double soc_fraction = 0.0;      // at the slow steps
  double rc_current_a = 0.0;      // A, at the slow steps
  double hysteresis = 0.0;        // dimensionless, at the slow steps
  double eod_s = 0.0;             // s, at the 1 Hz epochs
  double cutoff_s = 0.0;          // s, when the lowest cell first reads ≤ 3.3 V
};

void Track(double& worst, double a, double b) { worst = std::max(worst, std::abs(a - b)); }

Deviations CompareRates(const BatteryPack& pack, int substeps, double initial_cell_voltage_v) {
  const BatteryPack::FixedStep fast = pack.MakeFixedStep(kGncStep);
  const BatteryPack::FixedStep slow = pack.MakeFixedStep(substeps * kGncStep);
  PackState reference = pack.MakeRestingState(initial_cell_voltage_v);
  PackState state = reference;
  PackLinearisation at = pack.Linearise(state);
  PerBranch<double> charge_as = {0.0, 0.0};
  Deviations d;
  double cutoff_reference = -1.0, cutoff = -1.0;
  for (int k = 0; k < 400'000 && (cutoff_reference < 0.0 || cutoff < 0.0); ++k) {
    const double t = k * kGncStep;
    const double current_a = LoadCurrent(t);
    if (k % kEpochSteps == 0) {  // an epoch is a slow step's boundary: the slow state is the present state
      const double eod_reference = prognostics::CalcPackEod(pack, reference, current_a).eod_s;
      Track(d.eod_s, eod_reference, prognostics::CalcPackEod(pack, state, current_a).eod_s);
    }
    const PackStepResult r = pack.StepWithOutputs(reference, current_a, fast);
    const PackOutputs out = pack.CalcLinearisedOutputs(state, at, charge_as, (k % substeps) * kGncStep, current_a);
    Track(d.voltage_v, r.outputs.split.bus_voltage_v, out.split.bus_voltage_v);
    for (int b = 0; b < kBranchCount; ++b) {
      Track(d.branch_current_a, r.outputs.split.current_a[b], out.split.current_a[b]);
      for (int c = 0; c < kCellsPerBranch; ++c)
        Track(d.voltage_v, r.outputs.cell_voltage_v[b][c], out.cell_voltage_v[b][c]);
      charge_as[b] += out.split.current_a[b] * kGncStep;
    }
    if (cutoff_reference < 0.0 && r.outputs.min_cell_voltage_v <= kCutoffVoltage) cutoff_reference = t;
    if (cutoff < 0.0 && out.min_cell_voltage_v <= kCutoffVoltage) cutoff = t;
    reference = r.next;
    if ((k + 1) % substeps == 0) {
      state = pack.Advance(state, charge_as, substeps * kGncStep, &slow);
      at = pack.Linearise(state);
      charge_as = {0.0, 0.0};
      for (int b = 0; b < kBranchCount; ++b) {
        for (int c = 0; c < kCellsPerBranch; ++c) {
          const CellState& x = reference.cells[b][c];
          const CellState& y = state.cells[b][c];
          Track(d.soc_fraction, x.soc_fraction, y.soc_fraction);
          Track(d.rc_current_a, x.rc_current_a[0], y.rc_current_a[0]);
          Track(d.hysteresis, x.hysteresis, y.hysteresis);
        }
      }
    }
  }
  EXPECT_GT(cutoff_reference, 0.0) << "the reference pack reaches the cut-off";
  EXPECT_GT(cutoff, 0.0) << "the slow pack reaches the cut-off";
  d.cutoff_s = std::abs(cutoff - cutoff_reference);
  return d;
}

// Two packs that discharge out of step (one with power fade in a cell, one with capacity fade in two), cold.
BatteryPack DegradedPack() {
  PerCell<CellHealth> health{};
  health[0][1].power_fade = true;
  health[1][0].capacity_fade = true;
  health[1][2].capacity_fade = true;
  return BatteryPack(MakePackParams(health, 40.0));
}

// Bounds (ours), from the slow step's error analysis (battery_pack.h) at T = 0.1 s and a branch current ≤ 20 A:
// - SOC: Coulomb counting is exact; the only difference is the split, whose branch OCVs differ by the held i_R and
//   h terms (≤ 0.1 mV over T) through R0 ≈ 20-40 mΩ: a few mA, 1e-7 of the charge; bound 1e-6.
// - i_R: the mean current of T instead of the varying one: |ΔI| T / (R1 C1) ≈ 10 A · 0.1 s / 500 s = 2 mA per step,
//   relaxing with R1 C1; bound 5 mA. h: exact in the charge; bound 1e-6.
// - Voltages: the held i_R (R1 · |Δi_R| ≤ 0.05 mV) and the first-order h (M γ q / Q)² ≤ 0.1 mV at the start;
//   bound 0.5 mV. Branch currents: 0.5 mV / R0 ≤ 50 mA; bound 50 mA.
// - EOD at the epochs and the cut-off instant: the 0.1 s.
constexpr double kSocBound = 1e-6;            // fraction of capacity
constexpr double kRcCurrentBound = 5e-3;      // A
constexpr double kHysteresisBound = 1e-6;     // dimensionless
constexpr double kVoltageBound = 0.5e-3;      // V
constexpr double kBranchCurrentBound = 0.05;  // A
constexpr double kEodBound = 0.1;             // s

void ExpectWithinBounds(const Deviations& d) {
  EXPECT_LT(d.soc_fraction, kSocBound);
  EXPECT_LT(d.rc_current_a, kRcCurrentBound);
  EXPECT_LT(d.hysteresis, kHysteresisBound);
  EXPECT_LT(d.voltage_v, kVoltageBound);
  EXPECT_LT(d.branch_current_a, kBranchCurrentBound);
  EXPECT_LT(d.eod_s, kEodBound);
  EXPECT_LT(d.cutoff_s, kEodBound);
  std::printf(
      "max deviations: SOC %.3g, i_R %.3g A, h %.3g, voltage %.3g V, branch current %.3g A, EOD %.3g s, "
      "cut-off %.3g s\n",
      d.soc_fraction, d.rc_current_a, d.hysteresis, d.voltage_v, d.branch_current_a, d.eod_s, d.cutoff_s);
}

TEST(PackRateTest, TenHertzPackMatchesTheGncRatePackOverAFullDischarge) {
  ExpectWithinBounds(CompareRates(BatteryPack(), 20, 4.1));
}

TEST(PackRateTest, TenHertzPackMatchesTheGncRatePackWhenThePacksDischargeOutOfStep) {
  ExpectWithinBounds(CompareRates(DegradedPack(), 20, 4.05));
}

// One GNC step per slow step: the linearisation at zero charge is the model itself (eq. 3.3 term by term).
TEST(PackRateTest, OneSubstepIsTheGncRatePackToRounding) {
  const Deviations d = CompareRates(DegradedPack(), 1, 4.12);
  EXPECT_LT(d.soc_fraction, 1e-12);
  EXPECT_LT(d.voltage_v, 1e-12);
  EXPECT_LT(d.branch_current_a, 1e-9);
  EXPECT_EQ(d.cutoff_s, 0.0);
}

// Coulomb counting with the mean current is exact: one slow step of any length moves z by η q / Q.
TEST(PackRateTest, AdvanceMovesEachCellsChargeByItsBranchCharge) {
  const BatteryPack pack = DegradedPack();
  const PackState start = pack.MakeRestingState(4.1);
  const PerBranch<double> charge_as = {123.0, 45.0};
  const PackState next = pack.Advance(start, charge_as, 7.0);
  for (int b = 0; b < kBranchCount; ++b) {
    for (int c = 0; c < kCellsPerBranch; ++c) {
      const double expected = start.cells[b][c].soc_fraction - charge_as[b] / pack.cell(b, c).capacity_as();
      EXPECT_NEAR(next.cells[b][c].soc_fraction, expected, 1e-14);
      EXPECT_EQ(next.cells[b][c].hysteresis_sign, -1.0);
    }
  }
}

}  // namespace
}  // namespace uascma::models
