// The pooled voltage errors of several validations (identification/battery_validation_report.h) against their closed
// form, and the report's shape for one record and for several.
#include "uascma/identification/battery_validation_report.h"

#include <cmath>

#include <gtest/gtest.h>

namespace uascma::identification {
namespace {

CellValidation Validation(double rms_mv, double max_mv, int samples, std::vector<EodCheck> eod = {}) {
  CellValidation v;
  v.voltage_rms_mv = rms_mv;
  v.voltage_max_mv = max_mv;
  v.window_samples = samples;
  v.eod = std::move(eod);
  return v;
}

BatteryRecord Record(const std::string& source, int cycle) {
  BatteryRecord r;
  r.source = source;
  r.cycle = cycle;
  return r;
}

// Two windows of 100 samples at 3 mV RMS and 300 at 5 mV RMS: sqrt((100·9 + 300·25) / 400) = sqrt(21) mV; the
// largest error is the larger of the two maxima (1e-12 mV).
TEST(BatteryValidationReportTest, PooledErrorIsTheRmsOverEverySampleOfEveryWindow) {
  const PooledValidationError pooled = PoolValidationErrors({Validation(3.0, 8.0, 100), Validation(5.0, 12.5, 300)});
  EXPECT_EQ(pooled.samples, 400);
  EXPECT_NEAR(pooled.rms_mv, std::sqrt(21.0), 1e-12);
  EXPECT_EQ(pooled.max_mv, 12.5);
  const PooledValidationError none = PoolValidationErrors({});
  EXPECT_EQ(none.samples, 0);
  EXPECT_EQ(none.rms_mv, 0.0);
}

TEST(BatteryValidationReportTest, SeveralRecordsListEveryEodCheckWithItsFileAndAPooledLine) {
  EodCheck check;
  check.at_fraction = 0.5;
  check.relative_error = 0.01;
  const std::vector<CellValidation> results = {Validation(3.0, 8.0, 100, {check}), Validation(5.0, 12.5, 300, {})};
  const std::vector<BatteryRecord> records = {Record("a.csv", 1), Record("b.csv", 2)};
  const CellValidationOptions options;
  const nlohmann::json one = CellValidationsJson({results[0]}, {records[0]}, options);
  EXPECT_EQ(one["file"], "a.csv");
  ASSERT_EQ(one["records"].size(), 1u);
  const nlohmann::json both = CellValidationsJson(results, records, options);
  EXPECT_EQ(both["window_samples"], 400);
  EXPECT_NEAR(both["voltage_rms_mv"].get<double>(), std::sqrt(21.0), 1e-12);
  ASSERT_EQ(both["eod"].size(), 1u);
  EXPECT_EQ(both["eod"][0]["file"], "a.csv");
  EXPECT_EQ(both["eod"][0]["cycle"], 1);
  EXPECT_EQ(both["records"].size(), 2u);
  const std::string text = CellValidationsText(results, records, options);
  EXPECT_NE(text.find("b.csv cycle 2: voltage error RMS 5.00 mV"), std::string::npos);
  EXPECT_NE(text.find("no EOD check"), std::string::npos);  // b.csv never reaches the cut-off
  EXPECT_NE(text.find("all 2 records: voltage error RMS 4.58 mV, max 12.50 mV over 400 samples"), std::string::npos);
  EXPECT_EQ(CellValidationsText({results[0]}, {records[0]}, options).find("all "), std::string::npos);
}

}  // namespace
}  // namespace uascma::identification
