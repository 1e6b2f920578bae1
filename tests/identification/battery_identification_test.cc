// Identification and validation of the cell model (identification/battery_identification.h,
// battery_validation.h): a round trip from known parameters, and the NASA B0005 cell (Saha & Goebel 2007).
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "uascma/common/error.h"
#include "uascma/identification/battery_identification.h"
#include "uascma/identification/battery_validation.h"
#include "uascma/prognostics/eod.h"

namespace uascma::identification {
namespace {

std::string DataPath(const std::string& relative) { return std::string(UASCMA_SOURCE_DIR) + "/data/bench/" + relative; }

// A pulsed discharge (Fig. 3.5's kind) of a known cell, sampled at 1 s: 60 s rest, then 240 s at 1C and 60 s rest
// repeated until the terminal voltage reaches 3.2 V, then 600 s rest. Noise 2 mV; five samples 150 mV off.
BatteryRecord MakePulsedDischarge(const models::CellParams& params, std::uint64_t seed) {
  const models::SelfCorrectingCell cell(params, models::DefaultOcvTable());
  std::mt19937_64 generator(seed);
  std::normal_distribution<double> noise(0.0, 2e-3);
  BatteryRecord record;
  record.source = "synthetic";
  record.layout = "ours";
  models::CellState state;  // full, rested
  const double one_c_a = params.capacity_ah;
  double time_s = 0.0, rest_until_s = 60.0, end_s = -1.0;
  bool discharged = false;
  while (end_s < 0.0 || time_s <= end_s) {
    double current = 0.0;
    if (!discharged && time_s >= rest_until_s) current = std::fmod(time_s - rest_until_s, 300.0) < 240.0 ? one_c_a : 0.0;
    const double voltage = cell.CalcTerminalVoltage(state, current);
    if (!discharged && current > 0.0 && voltage <= 3.2) discharged = true, end_s = time_s + 600.0, current = 0.0;
    record.time_s.push_back(time_s);
    record.current_a.push_back(current);
    record.voltage_v.push_back(cell.CalcTerminalVoltage(state, current) + noise(generator));
    record.line.push_back(static_cast<int>(record.line.size()) + 2);
    state = cell.Step(state, current, 1.0);
    time_s += 1.0;
  }
  for (int k : {500, 1500, 2500, 3500, 4500}) record.voltage_v[k] += (k % 1000 == 500 ? 0.15 : -0.15);
  return record;
}

models::CellParams KnownCell() {
  models::CellParams params = models::Table31Cell(1);
  params.capacity_ah = 2.5;
  params.r0_ohm = 12e-3;
  params.rc[0] = {18e-3, 2.0e3};  // τ1 = 36 s
  params.hysteresis_m_v = 0.0;
  params.hysteresis_m0_v = 0.0;
  return params;
}

TEST(BatteryIdentificationTest, RecoversKnownParametersFromANoisyPulsedDischarge) {
  const models::CellParams truth = KnownCell();
  const BatteryRecord record = MakePulsedDischarge(truth, 44);
  const CellIdentification result = IdentifyCell(record);
  constexpr double kCapacityTolerance = 0.02;    // 2 %: the discharge ends within 0.5 % SOC of empty (OCV knee)
  constexpr double kResistanceTolerance = 0.10;  // 10 %
  EXPECT_NEAR(result.params.capacity_ah, truth.capacity_ah, kCapacityTolerance * truth.capacity_ah);
  EXPECT_NEAR(result.params.r0_ohm, truth.r0_ohm, kResistanceTolerance * truth.r0_ohm);
  EXPECT_NEAR(result.params.rc[0].resistance_ohm, truth.rc[0].resistance_ohm, 0.2 * truth.rc[0].resistance_ohm);
  ASSERT_TRUE(result.r0_standard_error_ohm.has_value());
  // The fit leaves about the noise (2 mV) plus the five outliers' share of the RMS: sqrt(5/n) · 150 mV.
  const double outlier_rms_mv = 150.0 * std::sqrt(5.0 / result.fitted_samples);
  EXPECT_LT(result.fit_rms_mv, std::hypot(2.0, outlier_rms_mv) + 1.0);
  // Hysteresis is not identified from a discharge, and says so.
  bool hysteresis_reported = false;
  for (const NotIdentified& item : result.not_identified) hysteresis_reported |= item.parameter == "hysteresis_m_v";
  EXPECT_TRUE(hysteresis_reported);
}

// The OCV derived is monotone and the model reproduces its own fitting record from its start.
TEST(BatteryIdentificationTest, TheIdentifiedCellReproducesTheRecordItCameFrom) {
  const BatteryRecord record = MakePulsedDischarge(KnownCell(), 7);
  const CellIdentification result = IdentifyCell(record);
  for (std::size_t k = 1; k < result.ocv_voltage_v.size(); ++k) EXPECT_GT(result.ocv_voltage_v[k], result.ocv_voltage_v[k - 1]);
  CellValidationOptions options;
  options.cutoff_v = 3.3;
  const CellValidation validation = ValidateCell(result.MakeCell(), record, options);
  constexpr double kSelfRmsMv = 15.0;  // noise + outliers + the OCV table's 2.5 % node spacing
  EXPECT_LT(validation.voltage_rms_mv, kSelfRmsMv);
}

// The model voltage the fit reports (and its figure draws) is the identified cell itself simulated through the record
// from full and rested: the fit's own bookkeeping (Coulomb-counted z, the RC lag of eq. 3.1 in closed form) against
// SelfCorrectingCell::Step, two computations of eqs. 3.1-3.3. Its errors over the fitted samples are the fit's RMS.
TEST(BatteryIdentificationTest, TheFitsModelVoltageIsTheIdentifiedCellSimulated) {
  const BatteryRecord record = MakePulsedDischarge(KnownCell(), 44);
  const CellIdentification result = IdentifyCell(record);
  ASSERT_EQ(static_cast<int>(result.model_v.size()), record.size());
  const std::vector<double> simulated = SimulateTerminalVoltage(result.MakeCell(), models::CellState{}, record);
  constexpr double kRoundOffV = 1e-9;  // V: the two sums of ~5,000 steps differ by round-off only
  double largest_v = 0.0, sum_v2 = 0.0;
  for (int k = 0; k < record.size(); ++k) largest_v = std::max(largest_v, std::abs(simulated[k] - result.model_v[k]));
  for (int k = 0; k < result.fitted_samples; ++k) sum_v2 += std::pow(record.voltage_v[k] - result.model_v[k], 2);
  EXPECT_LT(largest_v, kRoundOffV);
  constexpr double kRmsRoundOffMv = 1e-9;
  EXPECT_NEAR(1e3 * std::sqrt(sum_v2 / result.fitted_samples), result.fit_rms_mv, kRmsRoundOffMv);
}

// NASA B0005 (2 A, 24 °C): fit on cycle 1, validate on cycle 2.
TEST(BatteryIdentificationTest, NasaB0005FitOnOneCycleValidatesOnTheNext) {
  BatteryReadOptions read;
  read.cycle = 1;
  const CellIdentification model = IdentifyCell(ReadBatteryRecord(DataPath("battery-nasa/B0005.csv"), read));
  EXPECT_NEAR(model.params.capacity_ah, 1.86, 0.01);  // the data set's published first-cycle capacity, ~1.86 Ah
  read.cycle = 2;
  const BatteryRecord next = ReadBatteryRecord(DataPath("battery-nasa/B0005.csv"), read);
  CellValidationOptions options;
  options.window_low_v = 3.0;
  options.window_high_v = 4.1;
  const CellValidation validation = ValidateCell(model.MakeCell(), next, options);
  constexpr double kRmsLimitMv = 30.0;
  EXPECT_LE(validation.voltage_rms_mv, kRmsLimitMv);
  // The window reported (and shaded by the figure) is the one summarised: it starts at the first sample at or below
  // 4.1 V, ends before the first below 3.0 V, and its errors give the RMS.
  const int begin = validation.window_begin_sample, end = validation.window_end_sample;
  ASSERT_GT(begin, 0);
  ASSERT_LT(end, next.size());
  EXPECT_EQ(end - begin, validation.window_samples);
  EXPECT_LE(next.voltage_v[begin], 4.1);
  EXPECT_GT(next.voltage_v[begin - 1], 4.1);
  EXPECT_LT(next.voltage_v[end], 3.0);
  double sum_v2 = 0.0;
  for (int k = begin; k < end; ++k) sum_v2 += std::pow(validation.model_v[k] - validation.measured_v[k], 2);
  constexpr double kRmsRoundOffMv = 1e-9;
  EXPECT_NEAR(1e3 * std::sqrt(sum_v2 / (end - begin)), validation.voltage_rms_mv, kRmsRoundOffMv);
  ASSERT_EQ(validation.eod.size(), 3u);
  EXPECT_DOUBLE_EQ(validation.eod[1].at_fraction, 0.5);
  constexpr double kEodTolerance = 0.05;
  EXPECT_LE(std::abs(validation.eod[1].relative_error), kEodTolerance);
  // The same at the test's own 2.7 V cut-off.
  options.cutoff_v = 2.7;
  EXPECT_LE(std::abs(ValidateCell(model.MakeCell(), next, options).eod[1].relative_error), kEodTolerance);
}

// A larger capacity in the model lengthens the EOD the prognosis reads from the same state (eqs. 3.1, 3.3).
TEST(BatteryIdentificationTest, CapacityChangesThePredictedEod) {
  const CellIdentification result = IdentifyCell(MakePulsedDischarge(KnownCell(), 3));
  models::CellParams larger = result.params;
  larger.capacity_ah *= 1.2;
  const models::SelfCorrectingCell base = result.MakeCell();
  const models::SelfCorrectingCell bigger(larger, result.MakeOcvTable());
  models::CellState state;
  state.soc_fraction = 0.8;
  const double eod_s = prognostics::CalcCellEod(base, state, 2.5).eod_s;
  const double bigger_eod_s = prognostics::CalcCellEod(bigger, state, 2.5).eod_s;
  EXPECT_GT(bigger_eod_s, 1.15 * eod_s);
}

// Bad input names the file, the line and the column.
TEST(BatteryIdentificationTest, BadInputNamesFileLineAndColumn) {
  BatteryReadOptions read;
  read.min_samples = 3;
  auto message = [&](const std::string& text) {
    try {
      ParseBatteryRecord(text, "cell.csv", read);
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("time_s,current_a\n0,1\n").find("cell.csv:1: voltage_v"), std::string::npos);
  EXPECT_NE(message("time_s,current_a,voltage_v\n0,1,4\n2,1,4\n1,1,4\n").find("cell.csv:4: time_s"), std::string::npos);
  EXPECT_NE(message("time_s,current_a,voltage_v\n0,1,4\n1,nan,4\n2,1,4\n").find("cell.csv:3: current_a"), std::string::npos);
  EXPECT_NE(message("time_s,current_a,voltage_v\n0,0,4\n1,-2,4\n2,-2,3.9\n").find("cell.csv:3: current_a"), std::string::npos);
  read.min_samples = 20;
  EXPECT_NE(message("time_s,current_a,voltage_v\n0,0,4\n1,2,4\n2,2,3.9\n").find("at least 20 samples"), std::string::npos);
}

TEST(BatteryIdentificationTest, TheNasaLayoutIsRecognisedAndItsSignNegated) {
  const std::string text =
      "Voltage_measured,Current_measured,Temperature_measured,Current_load,Voltage_load,Time,cycle_idx\r\n"
      "4.19,-0.001,24,0,0,0,1\r\n3.97,-2.01,24,-2,3,19,1\r\n3.95,-2.01,24,-2,3,38,1\r\n4.0,-2.0,24,-2,3,0,2\r\n";
  BatteryReadOptions read;
  read.min_samples = 3;
  const BatteryRecord record = ParseBatteryRecord(text, "nasa.csv", read);
  EXPECT_EQ(record.layout, "nasa");
  ASSERT_EQ(record.size(), 3);
  EXPECT_DOUBLE_EQ(record.current_a[1], 2.01);
  EXPECT_EQ(record.cycle, 1);
}

}  // namespace
}  // namespace uascma::identification
