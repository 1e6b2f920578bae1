// The EOD under current peaks (prognostics/eod_peak.h, docs/modelling-choices.md#eod-peak-sag): the raised cut-off
// against closed forms, and the EOD it gives against an independent fine-step search for the first instant a peak
// would reach the cut-off.
#include <gtest/gtest.h>

#include <cmath>

#include "uascma/models/battery.h"
#include "uascma/prognostics/eod.h"
#include "uascma/prognostics/eod_peak.h"

namespace uascma::prognostics {
namespace {

using namespace uascma::models;

// V: the sag is a product of two numbers; 1e-12 V is rounding.
constexpr double kSagToleranceV = 1e-12;
// The fine-step reference: 10 ms steps, its crossing interpolated linearly (eod_test's reference); 0.5 % as there.
constexpr double kPeakReferenceStepS = 0.01;
constexpr double kPeakRequiredRelativeTolerance = 0.005;

// Pack 2 cell 1 power-faded (R0 x 2) at 40 °F (R0 x 1.5, Table 3.2): the medium, cold pack of a flight that cut off
// under peaks (docs/modelling-choices.md#eod-peak-sag).
BatteryPack ColdPowerFadedPack() {
  PerCell<CellHealth> health{};
  health[1][0].power_fade = true;
  return BatteryPack(MakePackParams(health, 40.0));
}

double MaxCellR0(const BatteryPack& pack, int branch) {
  double r0 = 0.0;
  for (int c = 0; c < kCellsPerBranch; ++c) r0 = std::max(r0, pack.cell(branch, c).params().r0_ohm);
  return r0;
}

TEST(PeakSagTest, OneBranchTakesTheWholePeak) {
  const BatteryPack pack = ColdPowerFadedPack();
  PackState state = pack.MakeRestingState(3.9);
  state.branch_on = {false, true};
  EXPECT_NEAR(CalcPeakSagV(pack, state, 20.0, 6.0), MaxCellR0(pack, 1) * 6.0, kSagToleranceV);
  state.branch_on = {true, false};
  EXPECT_NEAR(CalcPeakSagV(pack, state, 20.0, 6.0), MaxCellR0(pack, 0) * 6.0, kSagToleranceV);
}

TEST(PeakSagTest, TwoBranchesSplitThePeakByTheirConductances) {
  const BatteryPack pack = ColdPowerFadedPack();
  const PackState state = pack.MakeRestingState(3.9);
  const double g0 = 1.0 / pack.branch_r0_ohm(0), g1 = 1.0 / pack.branch_r0_ohm(1);
  const double expected =
      std::max(MaxCellR0(pack, 0) * 6.0 * g0 / (g0 + g1), MaxCellR0(pack, 1) * 6.0 * g1 / (g0 + g1));
  EXPECT_NEAR(CalcPeakSagV(pack, state, 20.0, 6.0), expected, kSagToleranceV);
  // The same as the bus voltage's response to the step: two splits of eqs. 3.4–3.5 a peak apart.
  const BranchSplit mean = pack.CalcSplit(state, 20.0), peak = pack.CalcSplit(state, 26.0);
  const double from_splits = std::max(MaxCellR0(pack, 0) * (peak.current_a[0] - mean.current_a[0]),
                                      MaxCellR0(pack, 1) * (peak.current_a[1] - mean.current_a[1]));
  EXPECT_NEAR(CalcPeakSagV(pack, state, 20.0, 6.0), from_splits, 1e-9);
  EXPECT_EQ(CalcPeakSagV(pack, state, 20.0, 0.0), 0.0);
  EXPECT_EQ(CalcPeakSagV(pack, state, 20.0, -3.0), 0.0);
}

// The raised cut-off's EOD is the first instant at which a peak of ΔI, drawn for an instant on top of the constant
// current, would take a cell to 3.3 V: searched independently by stepping the pack at the mean current and evaluating
// eq. 3.3 at I + ΔI from each step's state (the RC currents where the mean put them).
TEST(PeakSagTest, TheEodUnderPeaksIsWhenAPeakWouldFirstReachTheCutoff) {
  const BatteryPack pack = ColdPowerFadedPack();
  const PackState start = pack.MakeRestingState(3.85);
  for (const double peak_a : {4.0, 8.0}) {
    const double current_a = 24.0;
    const EodResult plain = CalcPackEod(pack, start, current_a);
    const EodResult under_peaks =
        CalcPackEod(pack, start, current_a, PeakSagEodOptions(pack, start, current_a, peak_a));
    ASSERT_EQ(under_peaks.status, EodStatus::kReached) << under_peaks.BriefReport();
    EXPECT_LT(under_peaks.eod_s, plain.eod_s);
    PackState state = start;
    double previous_v = pack.CalcOutputs(state, current_a + peak_a).min_cell_voltage_v;
    double reference_s = -1.0;
    for (long long k = 1; k < 400000 && reference_s < 0.0; ++k) {
      state = pack.Step(state, current_a, kPeakReferenceStepS);
      const double v = pack.CalcOutputs(state, current_a + peak_a).min_cell_voltage_v;
      if (v <= kCutoffVoltage) {
        reference_s = (k - 1 + (previous_v - kCutoffVoltage) / (previous_v - v)) * kPeakReferenceStepS;
      }
      previous_v = v;
    }
    ASSERT_GT(reference_s, 0.0);
    EXPECT_LT(std::abs(under_peaks.eod_s - reference_s) / reference_s, kPeakRequiredRelativeTolerance)
        << "peak " << peak_a << " A: " << under_peaks.BriefReport() << " vs the reference's " << reference_s << " s";
    // The limiting cell is the power-faded one, the cell of the largest raise.
    EXPECT_EQ(under_peaks.limiting_branch, 1);
    EXPECT_EQ(under_peaks.limiting_cell, 0);
  }
}

TEST(PeakSagTest, NoPeakIsThePlainEodAndTheCutoffStaysWithinItsBound) {
  const BatteryPack pack = ColdPowerFadedPack();
  const PackState state = pack.MakeRestingState(3.9);
  EXPECT_EQ(CalcPackEod(pack, state, 20.0, PeakSagEodOptions(pack, state, 20.0, 0.0)), CalcPackEod(pack, state, 20.0));
  EXPECT_EQ(PeakSagEodOptions(pack, state, 20.0, 1e6).cutoff_v, kCutoffVoltageBounds.high);
}

}  // namespace
}  // namespace uascma::prognostics
