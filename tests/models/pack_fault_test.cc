// Sudden pack faults (models/pack_fault.h, docs/modelling-choices.md#pack-faults): closed forms of the internal short,
// the failed cell and the connector against the pack model, the linearised slow step against the exact outputs,
// and the connector's contact draws.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "uascma/common/error.h"
#include "uascma/models/battery.h"

namespace uascma::models {
namespace {

// Volts and amperes of closed forms against the model: the same arithmetic in another order, rounding only.
constexpr double kFaultVoltageTolerance = 1e-12;
constexpr double kFaultCurrentTolerance = 1e-12;
constexpr double kFaultSocTolerance = 1e-15;
// Volts: the slow step's linearisation against the exact outputs 0.1 s on. Second-order terms: the short's own
// drain moves OCV by ~1e-5 V in 0.1 s (i_s ~ 2 A, a 3 A·h cell, OCV slope ~1 V per unit SOC), so its change of i_s
// and of the OCV segment are far below a microvolt; the RC term's (T/(R1 C1))² is ~4e-8 of the branch current's.
constexpr double kLinearisationTolerance = 1e-6;

BatteryPack FaultedPack(PackFaultKind kind, double resistance_ohm, int branch = 0, int cell = 1) {
  PackParams params = MakePackParams();
  params.fault = PackFault{
      .kind = kind, .branch = branch, .cell = cell, .resistance_ohm = resistance_ohm, .onset_s = 0.0, .seed = 7};
  return BatteryPack(params);
}

TEST(PackFaultTest, ShortAtRestDrainsItsCellAtOcvOverRs) {
  const double r_s = 2.0;  // Ω, a soft short (docs/modelling-choices.md#pack-faults)
  const BatteryPack pack = FaultedPack(PackFaultKind::kInternalShort, r_s);
  PackState state = pack.MakeRestingState(4.0);
  state.fault_on = true;
  const double ocv_v = pack.ocv().CalcVoltage(state.cells[0][1].soc_fraction);
  const double i_s = ocv_v / r_s;
  EXPECT_NEAR(pack.CalcShortCurrent(state), i_s, kFaultCurrentTolerance);
  EXPECT_NEAR(pack.CalcFaultHeat(state, 0.0), ocv_v * ocv_v / r_s, 1e-12 * ocv_v * ocv_v / r_s);
  // At rest (no load) the shorted cell still discharges: z' = z − i_s Δt / Q (eq. 3.1, η_discharge = 1), exact.
  const double dt_s = 10.0;
  const PackState next = pack.Step(state, 0.0, dt_s);
  const double q_as = pack.cell(0, 1).capacity_as();
  EXPECT_NEAR(next.cells[0][1].soc_fraction, state.cells[0][1].soc_fraction - i_s * dt_s / q_as, kFaultSocTolerance);
  for (int b = 0; b < kBranchCount; ++b) {
    for (int c = 0; c < kCellsPerBranch; ++c) {
      if (b == 0 && c == 1) continue;
      EXPECT_EQ(next.cells[b][c], state.cells[b][c]) << CellLabel(b, c);  // nothing else moves
    }
  }
  // Its terminal voltage at rest (eq. 3.3 at i = i_s, a fresh cell: h = 0, i_R = 0, s = −1): OCV − M0 − R0 i_s.
  const CellParams& p = pack.cell(0, 1).params();
  const PackOutputs out = pack.CalcOutputs(state, 0.0);
  EXPECT_NEAR(out.cell_voltage_v[0][1], ocv_v - p.hysteresis_m0_v - p.r0_ohm * i_s, kFaultVoltageTolerance);
  // The fault off: the same pack is the healthy one, bit for bit.
  state.fault_on = false;
  const BatteryPack healthy;
  EXPECT_EQ(pack.Step(state, 20.0, dt_s), healthy.Step(state, 20.0, dt_s));
  EXPECT_EQ(pack.CalcOutputs(state, 20.0).cell_voltage_v, healthy.CalcOutputs(state, 20.0).cell_voltage_v);
}

TEST(PackFaultTest, SiblingFeedsTheLoadNotTheShortedPack) {
  const double r_s = 0.5;
  const BatteryPack pack = FaultedPack(PackFaultKind::kInternalShort, r_s);
  PackState state = pack.MakeRestingState(3.9);
  state.fault_on = true;
  const double i_s = pack.CalcShortCurrent(state);
  // Eqs. 3.4-3.7 with the shorted branch's OCV lowered by R0 i_s.
  const double e1 = pack.CalcBranchOcv(state, 0) - pack.cell(0, 1).params().r0_ohm * i_s;
  const double e2 = pack.CalcBranchOcv(state, 1);
  const double r1 = pack.branch_r0_ohm(0), r2 = pack.branch_r0_ohm(1);
  const double total_a = 20.0;
  const double bus_v = (e1 / r1 + e2 / r2 - total_a) / (1.0 / r1 + 1.0 / r2);  // eq. 3.4
  const BranchSplit split = pack.CalcSplit(state, total_a);
  EXPECT_NEAR(split.bus_voltage_v, bus_v, kFaultVoltageTolerance);
  EXPECT_NEAR(split.current_a[0], (e1 - bus_v) / r1, 1e-9);  // eq. 3.5
  EXPECT_LT(split.current_a[0], 0.5 * total_a);              // the faulted pack carries less than its half
  // Without load eq. 3.5 would send (E2 − E1)/(R1 + R2) from the sibling into the faulted pack; the diodes of
  // §4.3.1.2 block it: neither branch carries anything.
  ASSERT_GT((e2 - e1) / (r1 + r2), 0.0);
  const BranchSplit idle = pack.CalcSplit(state, 0.0);
  EXPECT_EQ(idle.current_a[0], 0.0);
  EXPECT_EQ(idle.current_a[1], 0.0);
}

TEST(PackFaultTest, FailedCellTakesItsBranchCurrentTowardsZero) {
  const double total_a = 20.0;
  for (const double r_f : {0.2, 1e4}) {
    const BatteryPack pack = FaultedPack(PackFaultKind::kFailedCell, r_f, 1, 2);
    PackState state = pack.MakeRestingState(4.0);
    state.fault_on = true;
    const double e1 = pack.CalcBranchOcv(state, 0), e2 = pack.CalcBranchOcv(state, 1);
    const double r1 = pack.branch_r0_ohm(0), r2 = pack.branch_r0_ohm(1) + r_f;  // eq. 3.7 with R_f in series
    const double bus_v = (e1 / r1 + e2 / r2 - total_a) / (1.0 / r1 + 1.0 / r2);
    const PackOutputs out = pack.CalcOutputs(state, total_a);
    const double i2 = (e2 - bus_v) / r2;
    EXPECT_NEAR(out.split.current_a[1], i2, 1e-9) << r_f;
    const CellParams& p = pack.cell(1, 2).params();
    const double ocv_v = pack.ocv().CalcVoltage(state.cells[1][2].soc_fraction);
    EXPECT_NEAR(out.cell_voltage_v[1][2], ocv_v - p.hysteresis_m0_v - (p.r0_ohm + r_f) * i2, 1e-9) << r_f;
    if (r_f > 1e3) {
      EXPECT_LT(out.split.current_a[1], 1e-4 * total_a);  // an open cell: the sibling carries it all
    }
  }
}

// The monitor reads the failed cell across its R_f; the cut-off of §3.3.2.1 reads the cell's own voltage, which R_f
// does not discharge: min_cell_voltage_v is the lowest own voltage (linearised slow step and exact outputs alike).
TEST(PackFaultTest, FailedCellIsReadAcrossItsResistanceButCutsOffOnItsOwnVoltage) {
  const double total_a = 20.0, r_f = 2.0;
  const BatteryPack pack = FaultedPack(PackFaultKind::kFailedCell, r_f, 1, 0);
  PackState state = pack.MakeRestingState(3.6);
  state.fault_on = true;
  const PackOutputs out = pack.CalcOutputs(state, total_a);
  const double drop_v = r_f * out.split.current_a[1];
  ASSERT_GT(drop_v, 0.05);  // the residual the monitor flags (30 mV, docs/modelling-choices.md#pack-fault-detection)
  const double own_v = pack.CalcCellOwnVoltage(state, out, 1, 0);
  EXPECT_NEAR(own_v, out.cell_voltage_v[1][0] + drop_v, 1e-12);
  double lowest_own_v = std::numeric_limits<double>::infinity();
  for (int b = 0; b < kBranchCount; ++b) {
    double branch_reading_v = 0.0;
    for (int c = 0; c < kCellsPerBranch; ++c) {
      lowest_own_v = std::min(lowest_own_v, pack.CalcCellOwnVoltage(state, out, b, c));
      branch_reading_v += out.cell_voltage_v[b][c];
      if (b != 1 || c != 0) EXPECT_EQ(pack.CalcCellOwnVoltage(state, out, b, c), out.cell_voltage_v[b][c]);
    }
    EXPECT_NEAR(out.branch_voltage_v[b], branch_reading_v, 1e-12);  // the readings sum to the branch's voltage
  }
  EXPECT_EQ(out.min_cell_voltage_v, lowest_own_v);
  EXPECT_GT(out.min_cell_voltage_v, out.cell_voltage_v[1][0]);  // the reading alone is not the cut-off's voltage
  const PackOutputs slow = pack.CalcLinearisedOutputs(state, pack.Linearise(state), {0.0, 0.0}, 0.0, total_a);
  EXPECT_NEAR(slow.min_cell_voltage_v, out.min_cell_voltage_v, kFaultVoltageTolerance);
  EXPECT_NEAR(slow.cell_voltage_v[1][0], out.cell_voltage_v[1][0], kFaultVoltageTolerance);
}

TEST(PackFaultTest, ConnectorAddsContactResistanceAndLeavesTheCells) {
  const double r_c = 0.1;
  const BatteryPack pack = FaultedPack(PackFaultKind::kConnector, r_c, 0, 0);
  const BatteryPack healthy;
  PackState state = pack.MakeRestingState(4.0);
  state.fault_on = true;
  const PackOutputs out = pack.CalcOutputs(state, 20.0);
  const BranchSplit expected =
      CalcBranchSplit({pack.CalcBranchOcv(state, 0), pack.CalcBranchOcv(state, 1)},
                      {pack.branch_r0_ohm(0) + r_c, pack.branch_r0_ohm(1)}, {true, true}, 20.0);
  EXPECT_NEAR(out.split.current_a[0], expected.current_a[0], kFaultCurrentTolerance);
  EXPECT_NEAR(out.split.bus_voltage_v, expected.bus_voltage_v, kFaultVoltageTolerance);
  // Each cell's voltage is the healthy cell's at the branch current it carries (the contact is outside the cells).
  PackState alone = state;
  alone.branch_on = {true, false};
  const PackOutputs at_branch = healthy.CalcOutputs(alone, out.split.current_a[0]);
  for (int c = 0; c < kCellsPerBranch; ++c) {
    EXPECT_NEAR(out.cell_voltage_v[0][c], at_branch.cell_voltage_v[0][c], kFaultVoltageTolerance);
  }
}

TEST(PackFaultTest, ConnectorContactIsIntermittentAndReplays) {
  PackFault fault{
      .kind = PackFaultKind::kConnector, .branch = 1, .cell = 0, .resistance_ohm = 0.1, .onset_s = 100.0, .seed = 42};
  EXPECT_FALSE(IsPackFaultOn(fault, 99.99));
  const int periods = 4000;
  int poor = 0;
  for (int k = 0; k < periods; ++k) {
    const double t = fault.onset_s + (k + 0.5) * kConnectorPeriodS;
    const bool on = IsPackFaultOn(fault, t);
    EXPECT_EQ(on, IsPackFaultOn(fault, t + 0.2 * kConnectorPeriodS)) << k;  // one draw per period
    poor += on ? 1 : 0;
  }
  // Binomial(4000, 0.5): σ = 31.6; 5 σ.
  EXPECT_NEAR(poor, periods * kConnectorPoorProbability, 5.0 * std::sqrt(periods * 0.25));
  PackFault other = fault;
  other.seed = 43;
  int differ = 0;
  for (int k = 0; k < 200; ++k) {
    const double t = fault.onset_s + (k + 0.5) * kConnectorPeriodS;
    differ += IsPackFaultOn(fault, t) != IsPackFaultOn(other, t) ? 1 : 0;
  }
  EXPECT_GT(differ, 50);  // another seed, other draws (expected 100 of 200)
  fault.kind = PackFaultKind::kInternalShort;
  EXPECT_TRUE(IsPackFaultOn(fault, 100.0));
  EXPECT_TRUE(IsPackFaultOn(fault, 5000.0));
}

TEST(PackFaultTest, LinearisedSlowStepMatchesTheExactOutputs) {
  for (const PackFaultKind kind :
       {PackFaultKind::kInternalShort, PackFaultKind::kFailedCell, PackFaultKind::kConnector}) {
    const BatteryPack pack = FaultedPack(kind, kind == PackFaultKind::kInternalShort ? 2.0 : 0.3);
    PackState state = pack.MakeRestingState(3.95);
    state.fault_on = true;
    state = pack.Step(state, 22.0, 30.0);  // some RC current and hysteresis
    const double total_a = 21.0;
    const PackLinearisation at = pack.Linearise(state);
    // At the linearisation point: the exact outputs.
    const PackOutputs exact0 = pack.CalcOutputs(state, total_a);
    const PackOutputs lin0 = pack.CalcLinearisedOutputs(state, at, {0.0, 0.0}, 0.0, total_a);
    for (int b = 0; b < kBranchCount; ++b) {
      EXPECT_NEAR(lin0.split.current_a[b], exact0.split.current_a[b], 1e-9) << PackFaultKindName(kind);
      for (int c = 0; c < kCellsPerBranch; ++c) {
        EXPECT_NEAR(lin0.cell_voltage_v[b][c], exact0.cell_voltage_v[b][c], 1e-12) << PackFaultKindName(kind);
      }
    }
    // 0.1 s on, each branch having drawn its share: the advanced state's exact outputs.
    const double t_s = 0.1;
    const PerBranch<double> charge_as = {exact0.split.current_a[0] * t_s, exact0.split.current_a[1] * t_s};
    const PackState later = pack.Advance(state, charge_as, t_s);
    const PackOutputs exact1 = pack.CalcOutputs(later, total_a);
    const PackOutputs lin1 = pack.CalcLinearisedOutputs(state, at, charge_as, t_s, total_a);
    for (int b = 0; b < kBranchCount; ++b) {
      for (int c = 0; c < kCellsPerBranch; ++c) {
        EXPECT_NEAR(lin1.cell_voltage_v[b][c], exact1.cell_voltage_v[b][c], kLinearisationTolerance)
            << PackFaultKindName(kind) << " " << CellLabel(b, c);
      }
    }
  }
}

TEST(PackFaultTest, InvalidFaultsAreInputErrors) {
  PackParams params = MakePackParams();
  params.fault = PackFault{.kind = PackFaultKind::kInternalShort, .branch = 2};
  EXPECT_THROW(BatteryPack{params}, InputError);
  params.fault = PackFault{.kind = PackFaultKind::kInternalShort, .resistance_ohm = 0.0};
  EXPECT_THROW(BatteryPack{params}, InputError);
  EXPECT_THROW(ParsePackFaultKind("short", "test", "kind"), InputError);
  EXPECT_EQ(ParsePackFaultKind("failed_cell", "test", "kind"), PackFaultKind::kFailedCell);
}

}  // namespace
}  // namespace uascma::models
