// Battery end of discharge (§3.3.2.1, docs/modelling-choices.md#pack-eod): the exact segment propagation against a
// fine fixed-step integration of the same model, closed-form checks, orderings and statuses.
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "uascma/common/error.h"
#include "uascma/models/battery.h"
#include "uascma/prognostics/eod.h"
#include "uascma/prognostics/eod_reference.h"

namespace uascma::prognostics {
namespace {

using namespace uascma::models;

// The EOD must agree with a fine-step (Δt = 0.01 s) reference within 0.5 %.
constexpr double kRequiredRelativeTolerance = 0.005;
constexpr double kReferenceStepS = 0.01;
// The method solves the same model exactly; what is left against the 10 ms reference is the reference's
// zero-order hold of the branch split and its linear interpolation of the crossing: 1e-4 is generous
// (measured ≤ 1.1e-5 over the cases below).
constexpr double kExactRelativeTolerance = 1e-4;
// Seconds: two propagations of the same exact solution that differ only in where they start.
constexpr double kConsistencyToleranceS = 1e-6;

PerCell<CellHealth> UniformHealth(HealthClass health) {
  PerCell<CellHealth> cells{};
  for (auto& branch : cells) {
    for (auto& cell : branch) {
      cell.power_fade = health != HealthClass::kG;
      cell.capacity_fade = health == HealthClass::kP;
    }
  }
  return cells;
}

void ExpectMatchesReference(const EodResult& fast, const EodResult& reference, const std::string& what) {
  ASSERT_EQ(fast.status, EodStatus::kReached) << what << ": " << fast.BriefReport();
  ASSERT_EQ(reference.status, EodStatus::kReached) << what << ": " << reference.BriefReport();
  const double relative = std::abs(fast.eod_s - reference.eod_s) / reference.eod_s;
  EXPECT_LT(relative, kRequiredRelativeTolerance)
      << what << ": " << fast.BriefReport() << " vs " << reference.BriefReport();
  EXPECT_LT(relative, kExactRelativeTolerance)
      << what << ": " << fast.BriefReport() << " vs " << reference.BriefReport();
}

TEST(CellEodTest, MatchesFineStepReferenceForCellsCurrentsAndHealth) {
  for (int number = 1; number <= 3; ++number) {
    for (const CellHealth health :
         {CellHealth{}, CellHealth{.power_fade = true}, CellHealth{.capacity_fade = true, .power_fade = true}}) {
      const SelfCorrectingCell cell(ApplyCellConditions(Table31Cell(number), health, kRoomTemperatureDegf),
                                    DefaultOcvTable());
      const CellState state = cell.MakeRestingState(4.08);
      for (const double current_a : {2.0, 10.0, 30.0}) {
        ExpectMatchesReference(CalcCellEod(cell, state, current_a),
                               SimulateCellEod(cell, state, current_a, kReferenceStepS),
                               "cell " + std::to_string(number) + " at " + std::to_string(current_a) + " A");
      }
    }
  }
}

TEST(CellEodTest, MatchesReferenceAfterChargingAndAfterAHeavyLoad) {
  const SelfCorrectingCell cell(Table31Cell(2), DefaultOcvTable());
  // After a charge: h near +1, s = +1, negative RC current.
  const CellState charged = cell.Step(cell.MakeRestingState(3.9), -3.0, 600.0);
  ExpectMatchesReference(CalcCellEod(cell, charged, 15.0), SimulateCellEod(cell, charged, 15.0, kReferenceStepS),
                         "after charging");
  // After 200 s at 40 A: the RC voltage recovers during a 10 A prediction (v(t) is not monotone).
  const CellState loaded = cell.Step(cell.MakeRestingState(4.1), 40.0, 200.0);
  ExpectMatchesReference(CalcCellEod(cell, loaded, 10.0), SimulateCellEod(cell, loaded, 10.0, kReferenceStepS),
                         "recovering");
}

TEST(CellEodTest, FindsTheFirstCrossingInsideAVoltageDip) {
  // A heavy load left i_R = 30 A, a charge pulse left h = +1; at 3 A the hysteresis falls within seconds
  // while the RC voltage recovers over minutes, so v(t) dips and comes back before OCV takes over. With
  // the cut-off just above the bottom of the dip the EOD is inside the dip, not at the final decline.
  const SelfCorrectingCell cell;
  CellState state;
  state.soc_fraction = 0.12;
  state.rc_current_a[0] = 30.0;
  state.hysteresis = 1.0;
  state.hysteresis_sign = 1.0;
  const double current_a = 3.0;
  double dip_v = std::numeric_limits<double>::infinity();
  double dip_s = 0.0;
  double after_dip_v = 0.0;
  CellState probe = state;
  for (int k = 0; k <= 10000; ++k) {  // 100 s
    const double v = cell.CalcTerminalVoltage(probe, current_a);
    if (v < dip_v) {
      dip_v = v;
      dip_s = 0.01 * k;
    }
    after_dip_v = v;
    probe = cell.Step(probe, current_a, 0.01);
  }
  ASSERT_GT(dip_s, 5.0);
  ASSERT_LT(dip_s, 60.0);
  ASSERT_GT(after_dip_v, dip_v + 0.005);  // recovered by 100 s: a genuine dip
  EodOptions options;
  options.cutoff_v = dip_v + 0.002;
  const EodResult fast = CalcCellEod(cell, state, current_a, options);
  const EodResult reference = SimulateCellEod(cell, state, current_a, kReferenceStepS, options);
  ExpectMatchesReference(fast, reference, "dip");
  EXPECT_LT(fast.eod_s, dip_s);
}

TEST(PackEodTest, MatchesFineStepReferenceForHealthLevelsAndCurrents) {
  for (const HealthClass health : {HealthClass::kG, HealthClass::kM, HealthClass::kP}) {
    const BatteryPack pack(MakePackParams(UniformHealth(health)));
    const PackState state = pack.MakeRestingState(4.1);
    for (const double current_a : {5.0, 30.0, 80.0}) {
      ExpectMatchesReference(CalcPackEod(pack, state, current_a),
                             SimulatePackEod(pack, state, current_a, kReferenceStepS),
                             std::string(HealthClassName(health)) + " at " + std::to_string(current_a) + " A");
    }
  }
}

TEST(PackEodTest, MatchesReferenceWhenTheBranchesSplitUnevenly) {
  // Pack 2 power-faded, its cell 1 also capacity-faded, 40 °F: the split moves during the discharge and
  // pack 2's cells cross their OCV breakpoints out of step.
  PerCell<CellHealth> health{};
  for (int c = 0; c < kCellsPerBranch; ++c) health[1][c] = {.capacity_fade = c == 0, .power_fade = true};
  const BatteryPack pack(MakePackParams(health, 40.0));
  const PackState state = pack.MakeRestingState(4.1);
  for (const double current_a : {10.0, 40.0}) {
    const EodResult fast = CalcPackEod(pack, state, current_a);
    const EodResult reference = SimulatePackEod(pack, state, current_a, kReferenceStepS);
    ExpectMatchesReference(fast, reference, "uneven at " + std::to_string(current_a) + " A");
    EXPECT_EQ(fast.limiting_branch, reference.limiting_branch);
    EXPECT_EQ(fast.limiting_cell, reference.limiting_cell);
  }
}

TEST(PackEodTest, MatchesReferenceWithADiodeBlockedPack) {
  // Pack 2 starts lower: at first its diode blocks, pack 1 carries everything until its bus voltage falls
  // to pack 2's OCV, then both share.
  const BatteryPack pack;
  const PerCell<double> voltages = {{{4.1, 4.1, 4.1}, {3.95, 3.95, 3.95}}};
  const PackState state = pack.MakeRestingState(voltages);
  EXPECT_DOUBLE_EQ(pack.CalcSplit(state, 10.0).current_a[1], 0.0);
  for (const double current_a : {10.0, 60.0}) {
    ExpectMatchesReference(CalcPackEod(pack, state, current_a),
                           SimulatePackEod(pack, state, current_a, kReferenceStepS),
                           "blocked at " + std::to_string(current_a) + " A");
  }
}

TEST(PackEodTest, MatchesReferenceMidFlight) {
  PerCell<CellHealth> health{};
  for (auto& cell : health[0]) cell = {.capacity_fade = true, .power_fade = true};
  const BatteryPack pack(MakePackParams(health, 40.0));
  PackState state = pack.MakeRestingState(4.12);
  for (int k = 0; k < 200; ++k) state = pack.Step(state, k < 100 ? 70.0 : 20.0, 1.0);
  for (const double current_a : {5.0, 20.0, 50.0}) {
    ExpectMatchesReference(CalcPackEod(pack, state, current_a),
                           SimulatePackEod(pack, state, current_a, kReferenceStepS),
                           "mid-flight at " + std::to_string(current_a) + " A");
  }
}

TEST(PackEodTest, IdenticalBranchesAreOneBranchAtHalfTheCurrent) {
  // The even split of identical branches is exact (eqs. 3.4–3.5), so the pack EOD at I is the EOD of one
  // pack at I/2, and that is the minimum of its cells' EODs at I/2.
  const BatteryPack pack;
  const PackState both = pack.MakeRestingState(4.1);
  const PackState one = pack.MakeRestingState(4.1, PackAction::kUseBatt1);
  const EodResult pack_eod = CalcPackEod(pack, both, 40.0);
  const EodResult single = CalcPackEod(pack, one, 20.0);
  EXPECT_NEAR(pack_eod.eod_s, single.eod_s, kConsistencyToleranceS);
  double min_cell_s = std::numeric_limits<double>::infinity();
  int min_cell = -1;
  for (int c = 0; c < kCellsPerBranch; ++c) {
    const EodResult cell_eod = CalcCellEod(pack.cell(0, c), one.cells[0][c], 20.0);
    if (cell_eod.eod_s < min_cell_s) {
      min_cell_s = cell_eod.eod_s;
      min_cell = c;
    }
  }
  EXPECT_NEAR(single.eod_s, min_cell_s, kConsistencyToleranceS);
  EXPECT_EQ(single.limiting_cell, min_cell);
  EXPECT_EQ(single.limiting_branch, 0);
}

TEST(PackEodTest, SwitchedOffPackDoesNotCount) {
  PerCell<CellHealth> health{};
  for (auto& cell : health[0]) cell = {.capacity_fade = true, .power_fade = true};
  const BatteryPack pack(MakePackParams(health));
  const EodResult second_only = CalcPackEod(pack, pack.MakeRestingState(4.1, PackAction::kUseBatt2), 30.0);
  ExpectMatchesReference(
      second_only, SimulatePackEod(pack, pack.MakeRestingState(4.1, PackAction::kUseBatt2), 30.0, kReferenceStepS),
      "UseBatt2");
  EXPECT_EQ(second_only.limiting_branch, 1);
  // Pack 1 alone (poor) runs out sooner than pack 2 alone (good), both together last longest.
  const EodResult first_only = CalcPackEod(pack, pack.MakeRestingState(4.1, PackAction::kUseBatt1), 30.0);
  const EodResult both = CalcPackEod(pack, pack.MakeRestingState(4.1), 30.0);
  EXPECT_LT(first_only.eod_s, second_only.eod_s);
  EXPECT_GT(both.eod_s, second_only.eod_s);
}

TEST(PackEodTest, EodFallsWithCurrentDegradationAndCold) {
  const BatteryPack good(MakePackParams(UniformHealth(HealthClass::kG)));
  const BatteryPack medium(MakePackParams(UniformHealth(HealthClass::kM)));
  const BatteryPack poor(MakePackParams(UniformHealth(HealthClass::kP)));
  const BatteryPack cold(MakePackParams(UniformHealth(HealthClass::kG), 30.0));
  double previous_s = std::numeric_limits<double>::infinity();
  for (const double current_a : {5.0, 10.0, 20.0, 40.0, 80.0}) {
    const double good_s = CalcPackEod(good, good.MakeRestingState(4.1), current_a).eod_s;
    const double medium_s = CalcPackEod(medium, medium.MakeRestingState(4.1), current_a).eod_s;
    const double poor_s = CalcPackEod(poor, poor.MakeRestingState(4.1), current_a).eod_s;
    const double cold_s = CalcPackEod(cold, cold.MakeRestingState(4.1), current_a).eod_s;
    EXPECT_LT(good_s, previous_s) << current_a;
    EXPECT_LT(medium_s, good_s) << current_a;
    EXPECT_LT(poor_s, medium_s) << current_a;
    EXPECT_LT(cold_s, good_s) << current_a;
    previous_s = good_s;
  }
}

TEST(PackEodTest, PredictionIsConsistentAlongTheDischarge) {
  // The simulator calls the EOD at 1 Hz: after stepping the model t seconds at the same current, the new
  // EOD is the old one minus t (exact stepping, exact prediction).
  PerCell<CellHealth> health{};
  for (auto& cell : health[1]) cell.power_fade = true;
  const BatteryPack pack(MakePackParams(health));
  PackState state = pack.MakeRestingState(4.1);
  const double current_a = 35.0;
  const double eod0_s = CalcPackEod(pack, state, current_a).eod_s;
  // One exact step per second (the split is held over each second, so allow the 1 s zero-order hold).
  for (int k = 0; k < 100; ++k) state = pack.Step(state, current_a, 1.0);
  const double eod100_s = CalcPackEod(pack, state, current_a).eod_s;
  EXPECT_NEAR(eod100_s, eod0_s - 100.0, 1e-3 * eod0_s);
  // With identical branches the split is constant and stepping is exact: consistency to rounding.
  const BatteryPack even;
  PackState even_state = even.MakeRestingState(4.1);
  const double even0_s = CalcPackEod(even, even_state, current_a).eod_s;
  even_state = even.Step(even_state, current_a, 100.0);
  EXPECT_NEAR(CalcPackEod(even, even_state, current_a).eod_s, even0_s - 100.0, kConsistencyToleranceS);
}

TEST(PackEodTest, Statuses) {
  const BatteryPack pack;
  // Already below: a nearly empty pack under a large load.
  const PackState low = pack.MakeRestingState(3.45);
  const EodResult below = CalcPackEod(pack, low, 100.0);
  EXPECT_EQ(below.status, EodStatus::kAlreadyBelowCutoff);
  EXPECT_DOUBLE_EQ(below.eod_s, 0.0);
  EXPECT_GE(below.limiting_branch, 0);
  EXPECT_GE(below.limiting_cell, 0);
  // No current: never reached; eod_s is the horizon, a lower bound.
  const EodResult idle = CalcPackEod(pack, pack.MakeRestingState(4.1), 0.0);
  EXPECT_EQ(idle.status, EodStatus::kNotReachedWithinHorizon);
  EXPECT_DOUBLE_EQ(idle.eod_s, EodOptions{}.horizon_s);
  EXPECT_EQ(idle.limiting_branch, -1);
  // A tiny current with a short horizon.
  EodOptions short_horizon;
  short_horizon.horizon_s = 600.0;
  const EodResult tiny = CalcPackEod(pack, pack.MakeRestingState(4.1), 0.5, short_horizon);
  EXPECT_EQ(tiny.status, EodStatus::kNotReachedWithinHorizon);
  EXPECT_DOUBLE_EQ(tiny.eod_s, 600.0);
  // Both switches off.
  PackState off = pack.MakeRestingState(4.1);
  off.branch_on = {false, false};
  EXPECT_EQ(CalcPackEod(pack, off, 10.0).status, EodStatus::kNoBranchConnected);
  EXPECT_STREQ(EodStatusName(EodStatus::kReached), "reached");
  // Cell EOD under charge: never reached.
  EXPECT_EQ(CalcCellEod(pack.cell(0, 0), pack.MakeRestingState(4.0).cells[0][0], -2.0).status,
            EodStatus::kNotReachedWithinHorizon);
}

TEST(PackEodTest, BadInputIsInputError) {
  const BatteryPack pack;
  const PackState state = pack.MakeRestingState(4.1);
  EXPECT_THROW(CalcPackEod(pack, state, -1.0), InputError);
  EXPECT_THROW(CalcPackEod(pack, state, std::nan("")), InputError);
  EodOptions options;
  options.horizon_s = -5.0;
  EXPECT_THROW(CalcPackEod(pack, state, 10.0, options), InputError);
  options = EodOptions{};
  options.time_tolerance_s = 0.0;
  std::string error;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("time_tolerance_s"), std::string::npos) << error;
  EXPECT_THROW(SimulatePackEod(pack, state, 10.0, 0.0), InputError);
}

// CalcPackEodBefore (the reach margin's class, sim/epoch.cc): a result is CalcPackEod's bit for bit; none only when
// CalcPackEod's EOD is at least the bound. Over healths, temperatures, diode-blocked and mid-flight states, currents
// and bounds from 0 to past the EOD, including the EOD itself and its neighbours.
TEST(PackEodTest, TheEodBeforeABoundIsTheEodOrSaysItIsAtLeastTheBound) {
  int stopped = 0, returned = 0;
  for (const HealthClass health : {HealthClass::kG, HealthClass::kM, HealthClass::kP}) {
    for (const double temp_degf : {40.0, 77.0}) {
      const BatteryPack pack(MakePackParams(UniformHealth(health), temp_degf));
      std::vector<PackState> states = {pack.MakeRestingState(4.12),
                                       pack.MakeRestingState(PerCell<double>{{{4.1, 4.1, 4.1}, {3.95, 3.95, 3.95}}})};
      PackState flown = states[0];
      for (int k = 0; k < 300; ++k) flown = pack.Step(flown, k < 150 ? 60.0 : 15.0, 1.0);
      states.push_back(flown);
      for (const PackState& state : states) {
        for (const double current_a : {0.0, 8.0, 25.0, 70.0}) {
          const EodResult full = CalcPackEod(pack, state, current_a);
          const double eod = full.eod_s;
          for (const double bound_s : {0.0, 1.0, 0.3 * eod, 0.9 * eod, std::nextafter(eod, 0.0), eod,
                                       std::nextafter(eod, 1e9), 1.5 * eod + 1.0, 1e6}) {
            const std::optional<EodResult> before = CalcPackEodBefore(pack, state, current_a, bound_s);
            if (before) {
              ++returned;
              EXPECT_EQ(*before, full) << "bound " << bound_s << " s: " << before->BriefReport();
              EXPECT_EQ(std::bit_cast<std::uint64_t>(before->eod_s), std::bit_cast<std::uint64_t>(eod));
            } else {
              ++stopped;
              EXPECT_GE(eod, bound_s) << full.BriefReport();
            }
          }
        }
      }
    }
  }
  // Both answers occur (the bounds straddle the EOD).
  EXPECT_GT(stopped, 50);
  EXPECT_GT(returned, 50);
  // A healthy pack at 25 A bounded at half its EOD stops there.
  const BatteryPack pack;
  const PackState state = pack.MakeRestingState(4.12);
  const EodResult full = CalcPackEod(pack, state, 25.0);
  EXPECT_FALSE(CalcPackEodBefore(pack, state, 25.0, 0.5 * full.eod_s).has_value());
  EXPECT_THROW(CalcPackEodBefore(pack, state, -1.0, 10.0), InputError);
}

TEST(ReachMarginTest, FollowsTheStatedMarginDefinition) {
  EodResult eod;
  eod.status = EodStatus::kReached;
  eod.eod_s = 600.0;
  EXPECT_DOUBLE_EQ(CalcReachMargin(eod, 150.0), 0.75);  // RM = 1 − t_flight / t_EOD
  EXPECT_DOUBLE_EQ(CalcReachMargin(eod, 600.0), 0.0);
  EXPECT_LT(CalcReachMargin(eod, 601.0), 0.0);
  EXPECT_TRUE(IsFlightTimeReachable(eod, 600.0));
  EXPECT_FALSE(IsFlightTimeReachable(eod, 600.5));
  EXPECT_DOUBLE_EQ(CalcReachMargin(eod, 0.0), 1.0);
  eod.eod_s = 0.0;  // already below the cut-off
  EXPECT_TRUE(std::isinf(CalcReachMargin(eod, 1.0)));
  EXPECT_FALSE(IsFlightTimeReachable(eod, 1.0));
  // Reachability agrees with the sign of RM over a sweep.
  eod.eod_s = 321.0;
  for (double t = 0.0; t < 700.0; t += 3.7) {
    EXPECT_EQ(IsFlightTimeReachable(eod, t), CalcReachMargin(eod, t) >= 0.0) << t;
  }
}

// An open cell (R_f of 1 MΩ) in pack 2 with both switches on: its branch carries ~3e-5 A of 20 A, so the packs' EOD
// is pack 1's alone (pack 2 switched off, no fault), two computations of eqs. 3.1-3.7 within 0.5 s; read across R_f,
// the open cell would have ended it at once.
TEST(PackEodTest, AnOpenCellLeavesTheEodOfItsSiblingAlone) {
  const double total_a = 20.0;
  models::PackParams params = models::MakePackParams();
  params.fault = models::PackFault{.kind = models::PackFaultKind::kFailedCell,
                                   .branch = 1,
                                   .cell = 0,
                                   .resistance_ohm = 1e6,
                                   .onset_s = 0.0,
                                   .seed = 0};
  const models::BatteryPack pack(params);
  models::PackState state = pack.MakeRestingState(3.9);
  state.fault_on = true;
  const EodResult with_open_cell = SimulatePackEod(pack, state, total_a, 0.1);
  const models::BatteryPack healthy;
  models::PackState alone = healthy.MakeRestingState(3.9);
  alone.branch_on = {true, false};
  const EodResult sibling_alone = SimulatePackEod(healthy, alone, total_a, 0.1);
  ASSERT_EQ(sibling_alone.status, EodStatus::kReached);
  ASSERT_EQ(with_open_cell.status, EodStatus::kReached);
  EXPECT_GT(sibling_alone.eod_s, 100.0);
  EXPECT_NEAR(with_open_cell.eod_s, sibling_alone.eod_s, 0.5);
  EXPECT_EQ(with_open_cell.limiting_branch, 0);
}

}  // namespace
}  // namespace uascma::prognostics
