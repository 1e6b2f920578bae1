// The companion's decision log (mavlink/companion.h): what `uascma companion --log` writes, `uascma plot companion`
// reads back, every field and the texts with commas, quotes and line breaks; bad logs named by line and column.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "uascma/common/error.h"
#include "uascma/mavlink/companion.h"
#include "uascma/mavlink/companion_log.h"

namespace uascma::mavlink {
namespace {

// The writer's precision: 3 decimals for times and seconds, 5 for the margins.
constexpr double kSecondsTolerance = 5e-4;  // s
constexpr double kMarginTolerance = 5e-6;

TEST(CompanionLogTest, WhatIsWrittenReadsBack) {
  CompanionDecision quiet;  // an epoch not decided: texts empty, the RUL infinite before a spall
  quiet.time_s = 0.0;
  quiet.rul_s = std::numeric_limits<double>::infinity();
  quiet.note = "incomplete: a telemetry group not yet received, no decision";
  CompanionDecision acted;
  acted.time_s = 202.0;
  acted.state = "N,JF,MM0,M,RM0";
  acted.decided = acted.taken = "LandPract";
  acted.eod_s = 300.123, acted.rul_s = 12.5, acted.flight_time_remaining_s = 54.25;
  acted.reach_margin = -0.00004, acted.motor_margin = 0.8, acted.decision_ms = 0.57;
  acted.note = "to \"roof block 11,2 lot s/6\": MISSION_START DENIED,\nLandASAP at the next epoch";
  const std::vector<CompanionDecision> log = ParseCompanionLogCsv(CompanionLogCsv({quiet, acted}), "log.csv");
  ASSERT_EQ(log.size(), 2u);
  EXPECT_TRUE(std::isinf(log[0].rul_s));
  EXPECT_EQ(log[0].state, "");
  EXPECT_EQ(log[0].note, quiet.note);
  EXPECT_EQ(log[1].state, acted.state);
  EXPECT_EQ(log[1].taken, "LandPract");
  EXPECT_NEAR(log[1].eod_s, acted.eod_s, kSecondsTolerance);
  EXPECT_NEAR(log[1].flight_time_remaining_s, acted.flight_time_remaining_s, kSecondsTolerance);
  EXPECT_NEAR(log[1].reach_margin, acted.reach_margin, kMarginTolerance);
  EXPECT_NEAR(log[1].decision_ms, acted.decision_ms, kSecondsTolerance);
  EXPECT_EQ(log[1].note, acted.note);
}

TEST(CompanionLogTest, ABadLogIsRefusedNamingTheLineAndColumn) {
  CompanionDecision row;
  row.time_s = 1.0;
  std::string csv = CompanionLogCsv({row});
  auto message = [](const std::string& text) {
    try {
      ParseCompanionLogCsv(text, "log.csv");
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message("time,state\n1,x\n").find("log.csv: line 1 (header)"), std::string::npos);
  std::string not_a_number = csv;
  not_a_number.replace(not_a_number.find("\n1.000,") + 1, 5, "later");
  EXPECT_NE(message(not_a_number).find("line 2 time_s"), std::string::npos) << message(not_a_number);
  // Times must rise: the same row twice.
  const std::string twice = csv + csv.substr(csv.find('\n') + 1);
  EXPECT_NE(message(twice).find("line 3 time_s"), std::string::npos) << message(twice);
}

}  // namespace
}  // namespace uascma::mavlink
