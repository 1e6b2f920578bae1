// Identification of motor-propeller pairs (identification/propulsion_identification.h) on the thrust-stand data of
// data/bench/dyno-strawson (RCbenchmark 1520 step tests, MIT licence) and on surfaces made from known coefficients.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "uascma/common/error.h"
#include "uascma/identification/propulsion_identification.h"
#include "uascma/identification/thrust_stand_data.h"

namespace uascma::identification {
namespace {

const std::filesystem::path kDynoFolder = std::filesystem::path(UASCMA_SOURCE_DIR) / "data/bench/dyno-strawson";
// The files' speed column is already the shaft speed: with 7 pole pairs the dimensionless C_T of these 5-inch
// propellers would be ~8, with 1 it is 0.075-0.196 (docs/identification.md).
constexpr int kPolePairsOfTheFiles = 1;

PropulsionIdentificationOptions FiveInch() {
  PropulsionIdentificationOptions options;
  options.pole_pairs = kPolePairsOfTheFiles;
  options.diameter_in = 5.0;
  return options;
}

// Every pair, its 2S and 3S files together.
TEST(PropulsionIdentificationTest, EveryPairCrossValidatesWithinFivePercent) {
  int pairs = 0;
  for (char motor = 'a'; motor <= 'g'; ++motor) {
    for (int propeller = 1; propeller <= 8; ++propeller) {
      const std::string stem = std::string(1, motor) + std::to_string(propeller);
      const std::filesystem::path two_cell = kDynoFolder / (stem + "_7.csv"), three_cell = kDynoFolder / (stem + "_11.csv");
      if (!std::filesystem::exists(two_cell) || !std::filesystem::exists(three_cell)) continue;
      ++pairs;
      const PropulsionIdentification result = IdentifyPropulsion(
          {ReadThrustStandRecord(two_cell.string(), kPolePairsOfTheFiles),
           ReadThrustStandRecord(three_cell.string(), kPolePairsOfTheFiles)}, FiveInch());
      constexpr double kRpmTolerance = 0.05;     // leave-one-step-out median relative RPM error
      constexpr double kThrustTolerance = 0.10;  // median relative thrust error of C_T n² above 1300 µs
      EXPECT_LE(result.loo_rpm_median_relative_error, kRpmTolerance) << stem;
      EXPECT_LE(result.thrust_median_relative_error, kThrustTolerance) << stem;
      EXPECT_GT(result.thrust_check_points, 10) << stem;
      EXPECT_TRUE(result.warnings.empty() || result.surface.order != 3) << stem << ": " << result.warnings.front();
    }
  }
  EXPECT_EQ(pairs, 56);
}

// The left-out predictions kept for the figure are the ones the cross-validation scored: their median error and their
// share within the bounds are the reported ones (g8, its 2S and 3S files; docs/identification.md).
TEST(PropulsionIdentificationTest, TheLeftOutPredictionsAreTheOnesScored) {
  const std::vector<ThrustStandRecord> records = {
      ReadThrustStandRecord((kDynoFolder / "g8_7.csv").string(), kPolePairsOfTheFiles),
      ReadThrustStandRecord((kDynoFolder / "g8_11.csv").string(), kPolePairsOfTheFiles)};
  const PropulsionIdentification result = IdentifyPropulsion(records, FiveInch());
  ASSERT_EQ(static_cast<int>(result.loo_predictions.size()), result.points);
  std::vector<double> errors;
  int within = 0;
  std::size_t k = 0;
  for (const ThrustStandRecord& record : records) {
    for (int i = 0; i < record.size(); ++i, ++k) {
      const LeftOutPrediction& left_out = result.loo_predictions[k];
      errors.push_back(std::abs(left_out.predicted_rpm - record.rpm[i]) / record.rpm[i]);
      within += std::abs(left_out.predicted_rpm - record.rpm[i]) <= left_out.bound_rpm ? 1 : 0;
      // A prediction interval has a positive width (s > 0 on measured data).
      EXPECT_GT(left_out.bound_rpm, 0.0);
    }
  }
  std::sort(errors.begin(), errors.end());
  const double median = errors.size() % 2 == 1 ? errors[errors.size() / 2]
                                               : 0.5 * (errors[errors.size() / 2 - 1] + errors[errors.size() / 2]);
  constexpr double kExact = 1e-12;  // relative: the same numbers
  EXPECT_NEAR(median, result.loo_rpm_median_relative_error, kExact);
  EXPECT_NEAR(errors.back(), result.loo_rpm_max_relative_error, kExact);
  EXPECT_NEAR(static_cast<double>(within) / static_cast<double>(errors.size()), result.loo_share_within_95_bounds,
              kExact);
}

// Points on an exact surface of eq. 2.12's form and an exact square law give back C_T and the RPM everywhere.
TEST(PropulsionIdentificationTest, ExactDataGivesItsCoefficientsBack) {
  ThrustStandRecord record;
  record.source = "exact";
  constexpr double kThrustCoefficient = 1.5652e-8;  // Table 2.1, N/RPM²
  for (int step = 0; step < 12; ++step) {
    for (double voltage : {7.4, 11.1}) {
      const double throttle = 1100.0 + 80.0 * step;
      const double power = 5.0 + 0.1 * (throttle - 1100.0) * voltage / 7.4 + 0.002 * step * step;
      const double rpm = 3000.0 + 9.0 * (throttle - 1100.0) + 20.0 * power - 0.004 * (throttle - 1100.0) * power;
      record.throttle_us.push_back(throttle);
      record.power_w.push_back(power);
      record.rpm.push_back(rpm);
      record.thrust_n.push_back(kThrustCoefficient * rpm * rpm);
      record.line.push_back(step + 2);
    }
  }
  const PropulsionIdentification result = IdentifyPropulsion({record}, FiveInch());
  EXPECT_NEAR(result.thrust_coefficient_n_per_rpm2, kThrustCoefficient, 1e-12 * kThrustCoefficient + 1e-20);
  constexpr double kRpmTolerance = 1e-6;  // relative: an exact surface inside the model's span
  EXPECT_LT(result.loo_rpm_median_relative_error, kRpmTolerance);
  EXPECT_NEAR(result.surface.CalcRpm(1500.0, 30.0), 3000.0 + 9.0 * 400.0 + 20.0 * 30.0 - 0.004 * 400.0 * 30.0, 1e-3);
}

TEST(PropulsionIdentificationTest, TheRcBenchmarkLayoutIsRecognisedAndScaled) {
  const std::string text =
      "\xEF\xBB\xBFTime (s),ESC signal (\xC2\xB5s),Thrust (gf),Voltage (V),Current (A),Motor Electrical Speed (RPM),"
      "Electrical Power (W),\r\n0,1050,5,7.4,0.3,0,2.2,\r\n1,1150,100,7.4,1,7000,7.4,\r\n2,1250,200,7.3,2,14000,14.6,\r\n"
      "3,1350,300,7.3,3,21000,21.9,\r\n";
  const ThrustStandRecord record = ParseThrustStandRecord(text, "stand.csv", 7);
  EXPECT_EQ(record.layout, "rcbenchmark");
  ASSERT_EQ(record.size(), 3);  // the stopped motor's row is dropped
  EXPECT_DOUBLE_EQ(record.rpm[0], 1000.0);
  EXPECT_NEAR(record.thrust_n[0], 0.980665, 1e-12);
  EXPECT_EQ(record.line[0], 3);
}

TEST(PropulsionIdentificationTest, BadInputNamesFileLineAndColumn) {
  auto message = [](const std::string& text) {
    try {
      ParseThrustStandRecord(text, "stand.csv", 1);
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("throttle_us,rpm,thrust_n\n1100,1,1\n").find("stand.csv:1: power_w"), std::string::npos);
  EXPECT_NE(message("throttle_us,rpm,thrust_n,power_w\n1100,1,1,1\n1200,x,1,1\n").find("stand.csv:3: rpm"), std::string::npos);
  EXPECT_NE(message("throttle_us,rpm,thrust_n,power_w\n1100,1,1,1\n1200,2,1,-1\n").find("stand.csv:3: power_w"),
            std::string::npos);
  EXPECT_NE(message("throttle_us,rpm,thrust_n,power_w\n1100,1,1,1\n").find("at least 3 rows"), std::string::npos);
}

}  // namespace
}  // namespace uascma::identification
