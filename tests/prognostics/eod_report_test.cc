// What `uascma eod` reports (prognostics/eod_report.h): the report's EOD against CalcPackEod, a distribution without
// uncertainty against its point, the fixed-step reference within the propagation's tolerance, and the JSON and text
// against the report.
#include "uascma/prognostics/eod_report.h"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "uascma/models/battery.h"

namespace uascma::prognostics {
namespace {

using models::BatteryPack;
using models::PackAction;
using models::PackState;

constexpr double kCurrentA = 20.0;                    // A: a hover-like load of the default battery (ours)
constexpr double kRestVoltageV = 4.1;                 // V, inside Table 4.4's 4.05-4.12 V
constexpr double kReferenceStepS = 0.01;              // s: the step the EOD's 0.5 % tolerance was stated for (eod.h)
constexpr double kReferenceRelativeTolerance = 5e-3;  // dimensionless, eod.h: 0.5 % against Δt = 0.01 s
constexpr double kQuantileRelativeTolerance = 1e-9;   // dimensionless: a point mass's quantile is its EOD

TEST(EodReportTest, TheReportHoldsTheEodTheSplitAndTheReference) {
  const BatteryPack pack(models::MakePackParams());
  const PackState state = pack.MakeRestingState(kRestVoltageV, PackAction::kUseBoth);
  EodReportOptions options;
  options.current_a = kCurrentA;
  options.reference_dt_s = kReferenceStepS;
  const EodReport report = ReportPackEod(pack, state, options);
  EXPECT_EQ(report.result, CalcPackEod(pack, state, kCurrentA, options.eod));  // bit for bit: the same call
  EXPECT_FALSE(report.distribution.has_value());
  ASSERT_TRUE(report.reference.has_value());
  EXPECT_NEAR(report.reference->eod_s, report.result.eod_s, kReferenceRelativeTolerance * report.result.eod_s);
  // Both branches of equal packs carry half the current (eq. 3.4 with equal OCVs and resistances).
  EXPECT_NEAR(report.now.split.current_a[0], kCurrentA / 2.0, 1e-9 * kCurrentA);
  EXPECT_NEAR(report.now.split.current_a[1], kCurrentA / 2.0, 1e-9 * kCurrentA);

  EodBatteryLabel battery;
  battery.initial_cell_voltage_v = kRestVoltageV;
  const nlohmann::json json = EodReportJson(report, options, battery);
  EXPECT_EQ(json.at("status"), "reached");
  EXPECT_EQ(json.at("limiting_cell").at("pack"), report.result.limiting_branch + 1);
  EXPECT_EQ(json.at("limiting_cell").at("cell"), report.result.limiting_cell + 1);
  const double difference = json.at("reference").at("relative_difference").get<double>();
  EXPECT_DOUBLE_EQ(difference, (report.result.eod_s - report.reference->eod_s) / report.reference->eod_s);
  EXPECT_EQ(json.count("distribution"), 0u);

  const std::string text = EodReportText(report, options, battery);
  EXPECT_EQ(text.rfind("EOD ", 0), 0u) << text;
  EXPECT_NE(text.find(models::CellLabel(report.result.limiting_branch, report.result.limiting_cell) + " reaches"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("fixed-step reference (dt 0.01 s)"), std::string::npos) << text;
}

TEST(EodReportTest, ADistributionWithoutUncertaintyIsItsPoint) {
  const BatteryPack pack(models::MakePackParams());
  const PackState state = pack.MakeRestingState(kRestVoltageV, PackAction::kUseBoth);
  EodReportOptions options;
  options.current_a = kCurrentA;
  options.probability_before_s = 0.0;
  const EodReport report = ReportPackEod(pack, state, options);
  ASSERT_TRUE(report.distribution.has_value());  // asked for by the probability alone
  const nlohmann::json json = EodReportJson(report, options, EodBatteryLabel{});
  const nlohmann::json& quantiles = json.at("distribution").at("quantiles_s");
  ASSERT_EQ(quantiles.size(), std::size(kEodReportLevels));
  for (const nlohmann::json& quantile : quantiles) {
    EXPECT_NEAR(quantile.get<double>(), report.result.eod_s, kQuantileRelativeTolerance * report.result.eod_s);
  }
  EXPECT_EQ(json.at("distribution").at("probability_before").at("probability").get<double>(), 0.0);
  EXPECT_NE(EodReportText(report, options, EodBatteryLabel{}).find("P(EOD < 0 s) = 0.0000\n"), std::string::npos);
}

TEST(EodReportTest, NoPackSwitchedOnIsSaidSo) {
  const BatteryPack pack(models::MakePackParams());
  PackState state = pack.MakeRestingState(kRestVoltageV, PackAction::kUseBoth);
  state.branch_on = {false, false};
  EodReportOptions options;
  options.current_a = kCurrentA;
  const EodReport report = ReportPackEod(pack, state, options);
  EXPECT_EQ(report.result.status, EodStatus::kNoBranchConnected);
  EXPECT_EQ(EodReportText(report, options, EodBatteryLabel{}).rfind("EOD 0 s: no pack is switched on\n", 0), 0u);
  EXPECT_TRUE(EodReportJson(report, options, EodBatteryLabel{}).at("limiting_cell").is_null());
}

}  // namespace
}  // namespace uascma::prognostics
