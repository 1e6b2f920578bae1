// The battery models: OCV table, Enhanced Self-Correcting cell (eqs. 3.1–3.3), packs (eqs. 3.4–3.7),
// degradation (Table 3.2) and health classes (docs/modelling-choices.md#battery-health-label).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../support/input_error.h"

#include "uascma/common/error.h"
#include "uascma/models/battery.h"

namespace uascma::models {
namespace {

using testing_support::InputErrorMessage;

// Volts: the OCV table is piecewise linear, so interpolation and its inverse are exact up to rounding.
constexpr double kVoltageTolerance = 1e-12;
// SOC fraction: the same arithmetic, one level removed.
constexpr double kSocTolerance = 1e-12;
// Amperes: closed forms vs the exact discretisation differ only by rounding over many steps.
constexpr double kCurrentTolerance = 1e-9;
// Amperes: branch currents sum to the total; the split computes one from the other, so only rounding.
constexpr double kCurrentSumTolerance = 1e-12;

// --- OCV table -------------------------------------------------------------------------------------
TEST(OcvTableTest, DefaultTableIsTheSpecTableWithLinearInterpolation) {
  const OcvTable& ocv = DefaultOcvTable();
  ASSERT_EQ(ocv.point_count(), 21);
  EXPECT_NEAR(ocv.CalcVoltage(0.0), 3.27, kVoltageTolerance);   // docs/defaults.md#battery, 0 %
  EXPECT_NEAR(ocv.CalcVoltage(0.5), 3.84, kVoltageTolerance);   // 50 %
  EXPECT_NEAR(ocv.CalcVoltage(0.85), 4.08, kVoltageTolerance);  // 85 %
  EXPECT_NEAR(ocv.CalcVoltage(1.0), 4.20, kVoltageTolerance);   // 100 %
  EXPECT_NEAR(ocv.CalcVoltage(0.025), 0.5 * (3.27 + 3.61), kVoltageTolerance);
  EXPECT_NEAR(ocv.CalcVoltage(0.875), 0.5 * (4.08 + 4.11), kVoltageTolerance);
  // Linear extension beyond the ends, still increasing.
  EXPECT_NEAR(ocv.CalcVoltage(-0.01), 3.27 - 0.01 * (3.61 - 3.27) / 0.05, kVoltageTolerance);
  EXPECT_NEAR(ocv.CalcVoltage(1.01), 4.20 + 0.01 * (4.20 - 4.15) / 0.05, kVoltageTolerance);
}

TEST(OcvTableTest, InversionRoundTrips) {
  const OcvTable& ocv = DefaultOcvTable();
  for (int k = 0; k <= 1000; ++k) {
    const double soc = k / 1000.0;
    const auto back = ocv.CalcSoc(ocv.CalcVoltage(soc));
    ASSERT_TRUE(back.has_value()) << soc;
    EXPECT_NEAR(*back, soc, kSocTolerance) << soc;
  }
  for (double v = 3.27; v <= 4.20; v += 0.0037) {
    const auto soc = ocv.CalcSoc(v);
    ASSERT_TRUE(soc.has_value()) << v;
    EXPECT_NEAR(ocv.CalcVoltage(*soc), v, kVoltageTolerance) << v;
  }
  EXPECT_FALSE(ocv.CalcSoc(3.2699).has_value());
  EXPECT_FALSE(ocv.CalcSoc(4.2001).has_value());
  EXPECT_FALSE(ocv.CalcSoc(std::nan("")).has_value());
}

TEST(OcvTableTest, SegmentForDischargeIsTheSegmentAFallingSocIsIn) {
  const OcvTable& ocv = DefaultOcvTable();
  EXPECT_EQ(ocv.SegmentForDischarge(0.10), 1);  // exactly on a breakpoint: the segment below it
  EXPECT_EQ(ocv.SegmentForDischarge(0.1000001), 2);
  EXPECT_EQ(ocv.SegmentForDischarge(1.0), 19);
  EXPECT_EQ(ocv.SegmentForDischarge(1.2), 19);
  EXPECT_EQ(ocv.SegmentForDischarge(0.0), 0);
  EXPECT_EQ(ocv.SegmentForDischarge(-0.3), 0);
  // An unevenly spaced table (binary search) with an extra point on the 10–15 % line is the same
  // function as the evenly spaced one (O(1) look-up).
  std::vector<double> soc = ocv.soc_fraction(), voltage = ocv.voltage_v();
  soc.insert(soc.begin() + 3, 0.125);
  voltage.insert(voltage.begin() + 3, 0.5 * (3.69 + 3.71));
  const OcvTable uneven(soc, voltage);
  for (double z = -0.05; z <= 1.05; z += 0.0007) {
    EXPECT_NEAR(uneven.CalcVoltage(z), ocv.CalcVoltage(z), kVoltageTolerance) << z;
  }
  EXPECT_EQ(uneven.SegmentForDischarge(0.125), 2);
  EXPECT_EQ(uneven.SegmentForDischarge(0.126), 3);
}

TEST(OcvTableTest, RejectsTablesThatBreakTheContract) {
  EXPECT_NE(InputErrorMessage([] { OcvTable({0.0, 1.0}, {3.3}); }).find("as many voltages"), std::string::npos);
  EXPECT_NE(InputErrorMessage([] { OcvTable({0.5}, {3.7}); }).find("at least 2 points"), std::string::npos);
  EXPECT_NE(InputErrorMessage([] {
              OcvTable({0.0, 0.0, 1.0}, {3.3, 3.5, 4.2});
            }).find("SOC strictly increasing"),
            std::string::npos);
  EXPECT_NE(InputErrorMessage([] {
              OcvTable({0.0, 0.5, 1.0}, {3.3, 3.8, 3.8});
            }).find("voltage strictly increasing"),
            std::string::npos);
  EXPECT_NE(InputErrorMessage([] { OcvTable({0.0, 1.5}, {3.3, 4.2}); }).find("[0, 1]"), std::string::npos);
  EXPECT_NE(InputErrorMessage([] {
              OcvTable({0.0, 1.0}, {3.3, std::nan("")}, "my.csv");
            }).find("my.csv"),
            std::string::npos);
}

TEST(OcvTableTest, CsvLoaderReadsPercentOrFractionAndSkipsComments) {
  std::string percent = "# a resting-voltage chart\nsoc_percent,ocv_v\n";
  std::string fraction = "soc_fraction,voltage_v\n\n";
  const OcvTable& reference = DefaultOcvTable();
  for (int k = 0; k < reference.point_count(); ++k) {
    percent += std::to_string(5 * k) + ", " + std::to_string(reference.voltage_v()[k]) + "\r\n";
    fraction += std::to_string(reference.soc_fraction()[k]) + "," + std::to_string(reference.voltage_v()[k]) + "\n";
  }
  for (const std::string& text : {percent, fraction}) {
    const OcvTable table = ParseOcvTableCsv(text, "ocv.csv");
    ASSERT_EQ(table.point_count(), reference.point_count());
    for (double soc = 0.0; soc <= 1.0; soc += 0.01) {
      EXPECT_NEAR(table.CalcVoltage(soc), reference.CalcVoltage(soc), 1e-9) << soc;
    }
  }
  const auto dir = std::filesystem::temp_directory_path() / "uascma_battery_test_csv";
  std::filesystem::create_directories(dir);
  const auto path = dir / "ocv.csv";
  std::ofstream(path) << percent;
  EXPECT_NEAR(LoadOcvTableCsv(path).CalcVoltage(0.5), 3.84, 1e-9);
  std::filesystem::remove_all(dir);
}

TEST(OcvTableTest, BadCsvIsInputErrorNamingFileAndLine) {
  const std::string bad_number =
      InputErrorMessage([] { ParseOcvTableCsv("soc_percent,ocv_v\n0,3.27\n5,abc\n", "t.csv"); });
  EXPECT_NE(bad_number.find("t.csv"), std::string::npos) << bad_number;
  EXPECT_NE(bad_number.find("line 3"), std::string::npos) << bad_number;
  EXPECT_NE(bad_number.find("5,abc"), std::string::npos) << bad_number;
  EXPECT_NE(InputErrorMessage([] { ParseOcvTableCsv("soc,volts\n0,3.3\n", "t.csv"); }).find("header"),
            std::string::npos);
  EXPECT_NE(InputErrorMessage([] { ParseOcvTableCsv("", "t.csv"); }).find("empty"), std::string::npos);
  EXPECT_NE(InputErrorMessage([] { ParseOcvTableCsv("soc_percent,ocv_v\n0,3.27,1\n", "t.csv"); }).find("line 2"),
            std::string::npos);
  EXPECT_NE(InputErrorMessage([] {
              ParseOcvTableCsv("soc_percent,ocv_v\n0,3.5\n50,3.4\n", "t.csv");
            }).find("voltage strictly increasing"),
            std::string::npos);
  EXPECT_NE(InputErrorMessage([] { LoadOcvTableCsv("/nonexistent/ocv.csv"); }).find("/nonexistent/ocv.csv"),
            std::string::npos);
}

// --- Cell parameters and degradation ------------------------------------------------------------------
TEST(CellParamsTest, Table31Values) {
  const CellParams c1 = Table31Cell(1), c2 = Table31Cell(2), c3 = Table31Cell(3);
  EXPECT_DOUBLE_EQ(c1.r0_ohm, 6.0e-3);
  EXPECT_DOUBLE_EQ(c2.r0_ohm, 5.5e-3);
  EXPECT_DOUBLE_EQ(c3.r0_ohm, 5.5e-3);
  EXPECT_DOUBLE_EQ(c1.rc[0].resistance_ohm, 9.9e-3);
  EXPECT_DOUBLE_EQ(c2.rc[0].resistance_ohm, 8.8e-3);
  EXPECT_DOUBLE_EQ(c3.rc[0].resistance_ohm, 8.7e-3);
  EXPECT_DOUBLE_EQ(c1.rc[0].capacitance_f, 51.5e3);
  EXPECT_DOUBLE_EQ(c2.rc[0].capacitance_f, 52.5e3);
  EXPECT_DOUBLE_EQ(c3.rc[0].capacitance_f, 60.5e3);
  EXPECT_DOUBLE_EQ(c2.capacity_ah, 3.0271);
  EXPECT_DOUBLE_EQ(c1.hysteresis_gamma, 300.0);
  EXPECT_DOUBLE_EQ(c2.hysteresis_gamma, 200.0);
  EXPECT_DOUBLE_EQ(c2.hysteresis_m_v, 31.2e-3);
  EXPECT_DOUBLE_EQ(c3.hysteresis_m0_v, 5.2e-3);
  EXPECT_DOUBLE_EQ(c3.eta_charge, 0.973);
  EXPECT_DOUBLE_EQ(c3.eta_discharge, 1.0);
  // The struct defaults are cell 1.
  const CellParams defaults;
  EXPECT_DOUBLE_EQ(defaults.r0_ohm, c1.r0_ohm);
  EXPECT_DOUBLE_EQ(defaults.rc[0].capacitance_f, c1.rc[0].capacitance_f);
  EXPECT_DOUBLE_EQ(defaults.hysteresis_m_v, c1.hysteresis_m_v);
}

TEST(CellParamsTest, InvalidParametersAreInputErrorsNamingTheField) {
  CellParams params;
  params.rc[0].capacitance_f = -1.0;
  std::string error;
  EXPECT_FALSE(params.IsValid(&error));
  EXPECT_NE(error.find("rc[0].capacitance_f"), std::string::npos) << error;
  const std::string message =
      InputErrorMessage([&] { SelfCorrectingCell(params, DefaultOcvTable(), "pack 1 cell 2"); });
  EXPECT_NE(message.find("pack 1 cell 2"), std::string::npos) << message;
  EXPECT_NE(message.find("capacitance"), std::string::npos) << message;
  params = CellParams{};
  params.eta_charge = 1.2;
  EXPECT_FALSE(params.IsValid(nullptr));
  params = CellParams{};
  params.rc_pair_count = 0;
  EXPECT_FALSE(params.IsValid(nullptr));
  EXPECT_TRUE(CellParams{}.IsValid(nullptr));
}

TEST(CellConditionsTest, Table32FactorsAndTheirCombination) {
  const CellParams nominal = Table31Cell(2);
  const CellParams capacity = ApplyCellConditions(nominal, {.capacity_fade = true}, 77.0);
  EXPECT_DOUBLE_EQ(capacity.capacity_ah, 0.8 * nominal.capacity_ah);
  EXPECT_DOUBLE_EQ(capacity.r0_ohm, nominal.r0_ohm);
  const CellParams power = ApplyCellConditions(nominal, {.power_fade = true}, 77.0);
  EXPECT_DOUBLE_EQ(power.r0_ohm, 2.0 * nominal.r0_ohm);
  EXPECT_DOUBLE_EQ(power.capacity_ah, nominal.capacity_ah);
  const CellParams cold = ApplyCellConditions(nominal, {}, 49.9);
  EXPECT_DOUBLE_EQ(cold.r0_ohm, 1.5 * nominal.r0_ohm);
  EXPECT_DOUBLE_EQ(ApplyCellConditions(nominal, {}, 50.0).r0_ohm, nominal.r0_ohm);  // "T < 50F" is strict
  const CellParams both = ApplyCellConditions(nominal, {.capacity_fade = true, .power_fade = true}, 20.0);
  EXPECT_DOUBLE_EQ(both.r0_ohm, 3.0 * nominal.r0_ohm);  // power fade × cold multiply
  EXPECT_DOUBLE_EQ(both.capacity_ah, 0.8 * nominal.capacity_ah);
  // Nothing else changes.
  EXPECT_DOUBLE_EQ(both.rc[0].resistance_ohm, nominal.rc[0].resistance_ohm);
  EXPECT_DOUBLE_EQ(both.hysteresis_gamma, nominal.hysteresis_gamma);
}

TEST(HealthClassTest, StatedHealthLabelClasses) {
  std::array<CellHealth, 3> pack{};
  EXPECT_EQ(ClassifyHealth(pack), HealthClass::kG);
  pack[1].power_fade = true;
  EXPECT_EQ(ClassifyHealth(pack), HealthClass::kM);
  pack[2].capacity_fade = true;  // two cells with one fade each: still M
  EXPECT_EQ(ClassifyHealth(pack), HealthClass::kM);
  pack[2].power_fade = true;  // one cell with both: P
  EXPECT_EQ(ClassifyHealth(pack), HealthClass::kP);
  PerCell<CellHealth> battery{};
  EXPECT_EQ(ClassifyHealth(battery), HealthClass::kG);
  battery[1][0].capacity_fade = true;
  EXPECT_EQ(ClassifyHealth(battery), HealthClass::kM);
  battery[0][2] = {.capacity_fade = true, .power_fade = true};
  EXPECT_EQ(ClassifyHealth(battery), HealthClass::kP);
  EXPECT_EQ(ParseHealthClass("M", "--health"), HealthClass::kM);
  EXPECT_STREQ(HealthClassName(HealthClass::kP), "P");
  const std::string message = InputErrorMessage([] { ParseHealthClass("Q", "--health"); });
  EXPECT_NE(message.find("--health"), std::string::npos) << message;
  EXPECT_NE(message.find("'Q'"), std::string::npos) << message;
}

// --- Cell dynamics ---------------------------------------------------------------------------------------
TEST(SelfCorrectingCellTest, RestingStateHasTheRestVoltageAndBadVoltagesAreInputErrors) {
  const SelfCorrectingCell cell;
  const CellState state = cell.MakeRestingState(4.1);
  EXPECT_NEAR(state.soc_fraction, 0.85 + 0.05 * (4.10 - 4.08) / (4.11 - 4.08), kSocTolerance);
  EXPECT_NEAR(cell.CalcTerminalVoltage(state, 0.0), 4.1, kVoltageTolerance);
  const std::string message = InputErrorMessage([&] { cell.MakeRestingState(4.5, "--initial-cell-voltage"); });
  EXPECT_NE(message.find("--initial-cell-voltage"), std::string::npos) << message;
  EXPECT_NE(message.find("3.27 to 4.2 V"), std::string::npos) << message;
  EXPECT_THROW(cell.MakeRestingState(3.0), InputError);
}

TEST(SelfCorrectingCellTest, SocAfterConstantCurrentIsCoulombCounting) {
  const SelfCorrectingCell cell(Table31Cell(3), DefaultOcvTable());
  const double q_as = 3.0271 * 3600.0;
  const CellState start = cell.MakeRestingState(4.0);
  // Discharge, η_discharge = 1: z = z0 − i t / Q, whether in one step or many.
  const CellState one_step = cell.Step(start, 12.0, 300.0);
  EXPECT_NEAR(one_step.soc_fraction, start.soc_fraction - 12.0 * 300.0 / q_as, kSocTolerance);
  CellState many = start;
  for (int k = 0; k < 30000; ++k) many = cell.Step(many, 12.0, 0.01);
  EXPECT_NEAR(many.soc_fraction, one_step.soc_fraction, 1e-10);
  // Charge, η_charge = 0.973: z = z0 + 0.973 |i| t / Q.
  const CellState charged = cell.Step(start, -3.0, 600.0);
  EXPECT_NEAR(charged.soc_fraction, start.soc_fraction + 0.973 * 3.0 * 600.0 / q_as, kSocTolerance);
}

TEST(SelfCorrectingCellTest, RcBranchFollowsTheAnalyticStepResponse) {
  const SelfCorrectingCell cell(Table31Cell(1), DefaultOcvTable());
  const double tau_s = 9.9e-3 * 51.5e3;  // R1 C1, Table 3.1
  const double current_a = 20.0;
  CellState state = cell.MakeRestingState(4.1);
  for (int k = 1; k <= 1000; ++k) {
    state = cell.Step(state, current_a, 0.5);
    const double t = 0.5 * k;
    ASSERT_NEAR(state.rc_current_a[0], current_a * (1.0 - std::exp(-t / tau_s)), kCurrentTolerance) << t;
  }
  // Rest afterwards: the RC current relaxes as i_R(t0) e^{−t/τ}.
  const double i_r0 = state.rc_current_a[0];
  const CellState rested = cell.Step(state, 0.0, 250.0);
  EXPECT_NEAR(rested.rc_current_a[0], i_r0 * std::exp(-250.0 / tau_s), kCurrentTolerance);
  EXPECT_DOUBLE_EQ(rested.soc_fraction, state.soc_fraction);
  EXPECT_DOUBLE_EQ(rested.hysteresis, state.hysteresis);
}

TEST(SelfCorrectingCellTest, HysteresisRelaxesWithChargeMovedAndSignFollowsTheCurrent) {
  const SelfCorrectingCell cell(Table31Cell(2), DefaultOcvTable());
  const double q_as = 3.0271 * 3600.0;
  CellState state = cell.MakeRestingState(3.9);
  EXPECT_DOUBLE_EQ(state.hysteresis_sign, 0.0);
  // Discharge: h → −1 as h + 1 = (h0 + 1) exp(−η γ i t / Q).
  const CellState discharged = cell.Step(state, 5.0, 20.0);
  EXPECT_NEAR(discharged.hysteresis, -1.0 + std::exp(-200.0 * 5.0 * 20.0 / q_as), 1e-14);
  EXPECT_DOUBLE_EQ(discharged.hysteresis_sign, -1.0);
  // Charge: h → +1 with η_charge.
  const CellState charged = cell.Step(discharged, -2.0, 30.0);
  const double a_h = std::exp(-0.973 * 2.0 * 200.0 * 30.0 / q_as);
  EXPECT_NEAR(charged.hysteresis, a_h * discharged.hysteresis + (1.0 - a_h), 1e-14);
  EXPECT_DOUBLE_EQ(charged.hysteresis_sign, 1.0);
  // Rest keeps both.
  const CellState rested = cell.Step(charged, 0.0, 100.0);
  EXPECT_DOUBLE_EQ(rested.hysteresis, charged.hysteresis);
  EXPECT_DOUBLE_EQ(rested.hysteresis_sign, 1.0);
}

TEST(SelfCorrectingCellTest, TerminalVoltageIsThePlettForm) {
  const CellParams p = Table31Cell(1);
  const SelfCorrectingCell cell(p, DefaultOcvTable());
  CellState state = cell.MakeRestingState(3.9);
  state.rc_current_a[0] = 4.0;
  state.hysteresis = -0.5;
  state.hysteresis_sign = 1.0;
  const double ocv = DefaultOcvTable().CalcVoltage(state.soc_fraction);
  // Discharging at 10 A: s = −1, the RC drop −R1 i_R and the ohmic drop −R0 i both lower the voltage.
  EXPECT_NEAR(cell.CalcTerminalVoltage(state, 10.0),
              ocv - p.hysteresis_m0_v + p.hysteresis_m_v * (-0.5) - p.rc[0].resistance_ohm * 4.0 - p.r0_ohm * 10.0,
              kVoltageTolerance);
  // At rest: the stored s.
  EXPECT_NEAR(cell.CalcTerminalVoltage(state, 0.0),
              ocv + p.hysteresis_m0_v + p.hysteresis_m_v * (-0.5) - p.rc[0].resistance_ohm * 4.0, kVoltageTolerance);
}

TEST(SelfCorrectingCellTest, DiscretisationIsExactForAnyStepLength) {
  const SelfCorrectingCell cell(Table31Cell(3), DefaultOcvTable());
  CellState start = cell.MakeRestingState(4.05);
  start.rc_current_a[0] = 7.0;
  start.hysteresis = 0.3;
  const CellState big = cell.Step(start, 25.0, 120.0);
  CellState small = start;
  for (int k = 0; k < 12000; ++k) small = cell.Step(small, 25.0, 0.01);
  EXPECT_NEAR(small.soc_fraction, big.soc_fraction, 1e-10);
  EXPECT_NEAR(small.rc_current_a[0], big.rc_current_a[0], kCurrentTolerance);
  EXPECT_NEAR(small.hysteresis, big.hysteresis, 1e-10);
}

TEST(SelfCorrectingCellTest, SocNeverRisesDuringDischarge) {
  const SelfCorrectingCell cell(Table31Cell(2), DefaultOcvTable());
  CellState state = cell.MakeRestingState(4.12);
  for (int k = 0; k < 5000; ++k) {
    const double current_a = 5.0 + 40.0 * std::abs(std::sin(0.01 * k));  // a varying discharge
    const CellState next = cell.Step(state, current_a, 0.1);
    ASSERT_LE(next.soc_fraction, state.soc_fraction) << k;
    state = next;
  }
}

// --- Packs -----------------------------------------------------------------------------------------------
TEST(BranchSplitTest, Eqs34To35WithSwitchesAndDiodes) {
  // Identical branches share evenly.
  BranchSplit split = CalcBranchSplit({12.3, 12.3}, {0.017, 0.017}, {true, true}, 30.0);
  EXPECT_NEAR(split.current_a[0], 15.0, kCurrentSumTolerance);
  EXPECT_NEAR(split.current_a[1], 15.0, kCurrentSumTolerance);
  EXPECT_NEAR(split.bus_voltage_v, 12.3 - 0.017 * 15.0, kVoltageTolerance);
  // Eq. 3.4 against its direct form, and eq. 3.5 for both branches.
  split = CalcBranchSplit({12.4, 12.2}, {0.017, 0.034}, {true, true}, 40.0);
  const double bus_v = (12.4 / 0.017 + 12.2 / 0.034 - 40.0) / (1.0 / 0.017 + 1.0 / 0.034);
  EXPECT_NEAR(split.bus_voltage_v, bus_v, kVoltageTolerance);
  EXPECT_NEAR(split.current_a[0], (12.4 - bus_v) / 0.017, 1e-10);
  EXPECT_NEAR(split.current_a[1], (12.2 - bus_v) / 0.034, 1e-10);
  EXPECT_NEAR(split.current_a[0] + split.current_a[1], 40.0, kCurrentSumTolerance);
  // A degraded branch (higher R0) carries less at equal OCV.
  split = CalcBranchSplit({12.3, 12.3}, {0.017, 0.034}, {true, true}, 30.0);
  EXPECT_GT(split.current_a[0], split.current_a[1]);
  EXPECT_NEAR(split.current_a[1], 10.0, 1e-10);
  // One switch off: everything through the other.
  split = CalcBranchSplit({12.3, 12.0}, {0.017, 0.017}, {false, true}, 30.0);
  EXPECT_DOUBLE_EQ(split.current_a[0], 0.0);
  EXPECT_DOUBLE_EQ(split.current_a[1], 30.0);
  EXPECT_NEAR(split.bus_voltage_v, 12.0 - 0.017 * 30.0, kVoltageTolerance);
  // Both off: no current, dead bus.
  split = CalcBranchSplit({12.3, 12.0}, {0.017, 0.017}, {false, false}, 30.0);
  EXPECT_DOUBLE_EQ(split.current_a[0] + split.current_a[1], 0.0);
  EXPECT_DOUBLE_EQ(split.bus_voltage_v, 0.0);
  // Diode: a much lower branch would be charged by eq. 3.5; it carries nothing instead.
  split = CalcBranchSplit({12.6, 11.5}, {0.017, 0.017}, {true, true}, 10.0);
  EXPECT_DOUBLE_EQ(split.current_a[1], 0.0);
  EXPECT_DOUBLE_EQ(split.current_a[0], 10.0);
  EXPECT_FALSE(split.conducting[1]);
  EXPECT_NEAR(split.bus_voltage_v, 12.6 - 0.017 * 10.0, kVoltageTolerance);
  // No load and unequal packs: no circulating current.
  split = CalcBranchSplit({12.6, 12.5}, {0.017, 0.017}, {true, true}, 0.0);
  EXPECT_DOUBLE_EQ(split.current_a[0], 0.0);
  EXPECT_DOUBLE_EQ(split.current_a[1], 0.0);
}

TEST(BatteryPackTest, BranchSumsAreEqs36And37) {
  const BatteryPack pack;
  EXPECT_NEAR(pack.branch_r0_ohm(0), 6e-3 + 5.5e-3 + 5.5e-3, 1e-15);
  PerCell<double> voltages = {{{4.1, 4.0, 3.9}, {4.05, 4.05, 4.05}}};
  const PackState state = pack.MakeRestingState(voltages);
  EXPECT_NEAR(pack.CalcBranchOcv(state, 0), 4.1 + 4.0 + 3.9, 1e-12);
  EXPECT_NEAR(pack.CalcBranchOcv(state, 1), 3 * 4.05, 1e-12);
  const PackOutputs out = pack.CalcOutputs(state, 0.0);
  EXPECT_NEAR(out.branch_voltage_v[0], 12.0, 1e-12);
  EXPECT_NEAR(out.min_cell_voltage_v, 3.9, 1e-12);
  EXPECT_EQ(out.min_cell_branch, 0);
  EXPECT_EQ(out.min_cell_index, 2);
}

TEST(BatteryPackTest, IdenticalBranchesSplitEvenlyAndStayIdentical) {
  const BatteryPack pack;
  PackState state = pack.MakeRestingState(4.1);
  for (int k = 0; k < 2000; ++k) {
    const PackStepResult step = pack.StepWithOutputs(state, 35.0, 0.5);
    ASSERT_NEAR(step.outputs.split.current_a[0], 17.5, 1e-9) << k;
    ASSERT_NEAR(step.outputs.split.current_a[0] + step.outputs.split.current_a[1], 35.0, kCurrentSumTolerance);
    state = step.next;
  }
  for (int c = 0; c < kCellsPerBranch; ++c) {
    EXPECT_NEAR(state.cells[0][c].soc_fraction, state.cells[1][c].soc_fraction, 1e-12);
    EXPECT_NEAR(state.cells[0][c].rc_current_a[0], state.cells[1][c].rc_current_a[0], 1e-9);
  }
}

TEST(BatteryPackTest, DegradedBranchCarriesLessAndCurrentsSumToTheTotal) {
  PerCell<CellHealth> health{};
  for (auto& cell : health[1]) cell.power_fade = true;
  const BatteryPack pack(MakePackParams(health));
  EXPECT_NEAR(pack.branch_r0_ohm(1), 2.0 * pack.branch_r0_ohm(0), 1e-15);
  PackState state = pack.MakeRestingState(4.1);
  for (int k = 0; k < 1500; ++k) {
    const PackStepResult step = pack.StepWithOutputs(state, 30.0, 0.5);
    const auto& current = step.outputs.split.current_a;
    ASSERT_NEAR(current[0] + current[1], 30.0, kCurrentSumTolerance) << k;
    // At equal state the degraded branch carries less (its R0 is twice the other's). Later the healthy
    // branch's lower OCV (eq. 3.5's circulating term) evens the split out and may turn it round.
    if (k < 240) {
      ASSERT_GT(current[0], current[1]) << k;
    }
    for (int b = 0; b < kBranchCount; ++b) {
      for (int c = 0; c < kCellsPerBranch; ++c) {
        ASSERT_LE(step.next.cells[b][c].soc_fraction, state.cells[b][c].soc_fraction);  // SOC never rises
      }
    }
    state = step.next;
  }
  // The fuller branch's OCV falls faster, so the split moves towards even.
  const BranchSplit start = pack.CalcSplit(pack.MakeRestingState(4.1), 30.0);
  const BranchSplit later = pack.CalcSplit(state, 30.0);
  EXPECT_NEAR(start.current_a[1], 10.0, 1e-10);
  EXPECT_GT(later.current_a[1], start.current_a[1]);
}

TEST(BatteryPackTest, StepIsEachCellsExactStepAtItsBranchCurrent) {
  PerCell<CellHealth> health{};
  health[0][1].capacity_fade = true;
  const BatteryPack pack(MakePackParams(health, 40.0));
  PerCell<double> voltages = {{{4.1, 4.1, 4.1}, {4.0, 4.05, 4.0}}};
  const PackState state = pack.MakeRestingState(voltages);
  const PackStepResult step = pack.StepWithOutputs(state, 22.0, 0.005);
  for (int b = 0; b < kBranchCount; ++b) {
    for (int c = 0; c < kCellsPerBranch; ++c) {
      const double current = step.outputs.split.current_a[b];
      const CellState expected = pack.cell(b, c).Step(state.cells[b][c], current, 0.005);
      EXPECT_DOUBLE_EQ(step.next.cells[b][c].soc_fraction, expected.soc_fraction);
      EXPECT_DOUBLE_EQ(step.next.cells[b][c].rc_current_a[0], expected.rc_current_a[0]);
      EXPECT_DOUBLE_EQ(step.outputs.cell_voltage_v[b][c],
                       pack.cell(b, c).CalcTerminalVoltage(state.cells[b][c], current));
    }
  }
  // The same next state without outputs.
  const PackState next = pack.Step(state, 22.0, 0.005);
  EXPECT_DOUBLE_EQ(next.cells[1][2].soc_fraction, step.next.cells[1][2].soc_fraction);
  // Cold and power-faded cells use the Table 3.2 resistance.
  EXPECT_DOUBLE_EQ(pack.cell(1, 0).params().r0_ohm, 1.5 * 6e-3);
}

TEST(BatteryPackTest, SwitchedOffPackRestsAndCarriesNothing) {
  const BatteryPack pack;
  PackState state = pack.MakeRestingState(4.1, PackAction::kUseBatt1);
  EXPECT_TRUE(state.branch_on[0]);
  EXPECT_FALSE(state.branch_on[1]);
  const PackStepResult step = pack.StepWithOutputs(state, 30.0, 10.0);
  EXPECT_DOUBLE_EQ(step.outputs.split.current_a[0], 30.0);
  EXPECT_DOUBLE_EQ(step.outputs.split.current_a[1], 0.0);
  EXPECT_DOUBLE_EQ(step.next.cells[1][0].soc_fraction, state.cells[1][0].soc_fraction);
  EXPECT_LT(step.next.cells[0][0].soc_fraction, state.cells[0][0].soc_fraction);
  EXPECT_EQ(ParsePackAction("UseBatt2", "--use"), PackAction::kUseBatt2);
  EXPECT_NE(InputErrorMessage([] { ParsePackAction("UseAll", "--use"); }).find("UseBoth"), std::string::npos);
  EXPECT_EQ(CellLabel(1, 0), "pack 2 cell 1");
}

}  // namespace
}  // namespace uascma::models
