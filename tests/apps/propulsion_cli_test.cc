// End-to-end checks of `uascma thrust` and `uascma authority`: exit codes 0/2, one-line errors naming
// the option, JSON fields.
#include "cli_runner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

namespace uascma {
namespace {

using testing_support::ExpectBadInput;
using testing_support::RunCli;
using testing_support::RunResult;

// --- uascma thrust ----------------------------------------------------------------------------------
TEST(ThrustCliTest, JsonAtTheFullThrottleRowOfTable22) {
  const auto result = RunCli("thrust --config tractor --throttle-us 1900 --power-w 578 --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const auto json = nlohmann::json::parse(result.out);
  // 578 W / 6 = 96.33 W per motor → 16057 RPM (eq. 2.12) → 4.036 N per rotor, 24.21 N in all: within
  // the 10 % of §2.5.2 of the measured 26.85 N.
  EXPECT_NEAR(json.at("rpm").get<double>(), 16057.2, 0.1);
  EXPECT_NEAR(json.at("thrust_n").get<double>(), 24.214, 0.001);
  EXPECT_LT(std::abs(json.at("thrust_n").get<double>() - 26.85) / 26.85, 0.10);
  EXPECT_NEAR(json.at("motor_power_w").get<double>(), 578.0 / 6.0, 1e-9);
  EXPECT_EQ(json.at("configuration"), "tractor");
}

TEST(ThrustCliTest, PusherMakesMoreThrustThanTractorAtTheSamePower) {
  const auto tractor = RunCli("thrust --config tractor --throttle-us 1700 --power-w 400 --json");
  const auto pusher = RunCli("thrust --config pusher --throttle-us 1700 --power-w 400 --json");
  ASSERT_EQ(tractor.exit_code, 0) << tractor.err;
  ASSERT_EQ(pusher.exit_code, 0) << pusher.err;
  const auto t = nlohmann::json::parse(tractor.out);
  const auto p = nlohmann::json::parse(pusher.out);
  EXPECT_NEAR(t.at("rpm").get<double>(), p.at("rpm").get<double>(), 1e-9);    // one estimator for both
  EXPECT_GT(p.at("thrust_n").get<double>(), t.at("thrust_n").get<double>());  // Table 2.1: C_T larger
}

TEST(ThrustCliTest, TextOutputNamesTheThrust) {
  const auto result = RunCli("thrust --config pusher --throttle-us 1500 --power-w 291");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("13.642 N"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("RPM"), std::string::npos) << result.out;
}

TEST(ThrustCliTest, BadInputIsExitTwoNamingTheOption) {
  ExpectBadInput(RunCli("thrust --config puller --throttle-us 1500 --power-w 291"), "--config");
  ExpectBadInput(RunCli("thrust --config tractor --throttle-us 1000 --power-w 291"), "--throttle-us");
  ExpectBadInput(RunCli("thrust --config tractor --throttle-us 1950 --power-w 291"), "--throttle-us");
  ExpectBadInput(RunCli("thrust --config tractor --throttle-us 1500 --power-w -1"), "--power-w");
  ExpectBadInput(RunCli("thrust --config tractor --throttle-us 1500 --power-w nan"), "--power-w");
  ExpectBadInput(RunCli("thrust --config tractor --throttle-us 1500 --power-w inf"), "--power-w");
  ExpectBadInput(RunCli("thrust --config tractor --throttle-us abc --power-w 1"), "--throttle-us");
  EXPECT_EQ(RunCli("thrust --config tractor --throttle-us 1500").exit_code, 2);  // --power-w missing
}

// --- uascma authority -------------------------------------------------------------------------------
TEST(AuthorityCliTest, JsonMatchesTheClosedFormOfFigs414And415) {
  // 24 N hexacopter, 1 kg: arccos(sqrt(9.80665/24)) = 50.27°; after one failure 16 N: 38.47°.
  const auto healthy = RunCli("authority --failed-motors 0 --total-thrust-n 24 --mass-kg 1 --json");
  ASSERT_EQ(healthy.exit_code, 0) << healthy.err;
  const auto h = nlohmann::json::parse(healthy.out);
  EXPECT_NEAR(h.at("max_angle_deg").get<double>(), 50.2658402, 1e-6);
  EXPECT_EQ(h.at("failed_motors").get<int>(), 0);
  EXPECT_EQ(h.at("active_rotors").get<int>(), 6);
  EXPECT_EQ(h.at("status"), "can_hover");

  const auto failed = RunCli("authority --failed-motors 1 --total-thrust-n 24 --mass-kg 1 --json");
  ASSERT_EQ(failed.exit_code, 0) << failed.err;
  const auto f = nlohmann::json::parse(failed.out);
  EXPECT_NEAR(f.at("max_angle_deg").get<double>(), 38.4741183, 1e-6);
  EXPECT_EQ(f.at("failed_motors").get<int>(), 1);
  EXPECT_EQ(f.at("active_rotors").get<int>(), 4);
  EXPECT_NEAR(f.at("available_thrust_n").get<double>(), 16.0, 1e-12);
}

TEST(AuthorityCliTest, TooHeavyIsAnAnswerNotAnError) {
  const auto result = RunCli("authority --failed-motors 1 --total-thrust-n 18 --mass-kg 1.3 --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const auto json = nlohmann::json::parse(result.out);
  EXPECT_EQ(json.at("status"), "cannot_hover");
  EXPECT_TRUE(json.at("max_angle_deg").is_null());
  const auto text = RunCli("authority --failed-motors 1 --total-thrust-n 18 --mass-kg 1.3");
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("cannot hold altitude"), std::string::npos) << text.out;
}

TEST(AuthorityCliTest, TextOutputGivesTheAngle) {
  const auto result = RunCli("authority --failed-motors 0 --total-thrust-n 24 --mass-kg 1");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("50.27 deg"), std::string::npos) << result.out;
}

TEST(AuthorityCliTest, BadInputIsExitTwoNamingTheOption) {
  ExpectBadInput(RunCli("authority --failed-motors 2 --total-thrust-n 24 --mass-kg 1"), "--failed-motors");
  ExpectBadInput(RunCli("authority --failed-motors -1 --total-thrust-n 24 --mass-kg 1"), "--failed-motors");
  ExpectBadInput(RunCli("authority --failed-motors 0 --total-thrust-n 0 --mass-kg 1"), "--total-thrust-n");
  ExpectBadInput(RunCli("authority --failed-motors 0 --total-thrust-n nan --mass-kg 1"), "--total-thrust-n");
  ExpectBadInput(RunCli("authority --failed-motors 0 --total-thrust-n 24 --mass-kg -1"), "--mass-kg");
  ExpectBadInput(RunCli("authority --failed-motors one --total-thrust-n 24 --mass-kg 1"), "--failed-motors");
}

}  // namespace
}  // namespace uascma
