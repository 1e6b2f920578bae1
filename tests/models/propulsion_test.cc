// The rotor model of dissertation §2.3 and §2.5: eqs. 2.1–2.3, 2.10, 2.12, Tables 2.1–2.2, and the
// defaults of docs/defaults.md#vehicle (power law, speed lag, saturation).
#include "uascma/models/propulsion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "uascma/common/error.h"

namespace uascma::models {
namespace {

constexpr double kRoundOff = 1e-12;         // relative, for closed forms evaluated in double
constexpr double kRpmTolerance = 0.01;      // RPM, for the hand evaluations of eq. 2.12 below
constexpr double kThrustTolerance = 1e-12;  // N

double RelativeError(double estimate, double measured) { return (estimate - measured) / measured; }

// --- Table 2.2 against the dissertation's stated accuracy ---------------------------------------
// The accuracy the dissertation states for thrust estimated by eq. 2.1 from the eq. 2.12 RPM:
//  §2.5.2:  "the relative error with this approach was less than 10%, except at lower throttle inputs"
//  §2.6.1:  "Table 2.2 shows that the average relative error in thrust estimates for appreciable throttle
//            commands was approximately 5%. However, this error was as high as 20% for low throttle
//            commands."
// So: at 1900 µs (full throttle) each estimate within 10%; at 1500 µs (the low command of Table 2.2)
// within 20%.
constexpr double kHighThrottleBound = 0.10;  // §2.5.2
constexpr double kLowThrottleBound = 0.20;   // §2.6.1

TEST(StaticThrustTest, FullThrottleRowsOfTable22AreWithinTenPercent) {
  for (const auto configuration : {PropellerConfiguration::kTractor, PropellerConfiguration::kPusher}) {
    const PropulsionParams params = PropulsionParams::ForConfiguration(configuration);
    const StaticThrustMeasurement row = StaticThrustTable(configuration)[1];
    ASSERT_DOUBLE_EQ(row.throttle_us, 1900.0);
    const StaticThrustEstimate estimate = EstimateStaticThrust(params, row.throttle_us, row.total_power);
    EXPECT_LT(std::abs(RelativeError(estimate.total_thrust, row.total_thrust)), kHighThrottleBound)
        << PropellerConfigurationName(configuration) << ": " << estimate.total_thrust << " N vs " << row.total_thrust
        << " N";
  }
  // Values for the record (computed by this model): tractor 24.21 N vs 26.85 N (−9.8 %), pusher
  // 30.46 N vs 31 N (−1.8 %); their mean |error|, 5.8 %, is the "approximately 5%" of §2.6.1.
}

TEST(StaticThrustTest, PusherAt1500UsIsWithinTheLowThrottleBound) {
  const auto configuration = PropellerConfiguration::kPusher;
  const StaticThrustMeasurement row = StaticThrustTable(configuration)[0];
  ASSERT_DOUBLE_EQ(row.throttle_us, 1500.0);
  const StaticThrustEstimate estimate =
      EstimateStaticThrust(PropulsionParams::ForConfiguration(configuration), row.throttle_us, row.total_power);
  EXPECT_LT(std::abs(RelativeError(estimate.total_thrust, row.total_thrust)), kLowThrottleBound)
      << estimate.total_thrust << " N vs " << row.total_thrust << " N";  // 13.64 N vs 15.56 N: −12.3 %
}

// A known shortfall, kept visible rather than tuned away: for the tractor at 1500 µs and 286 W the
// published eq. 2.12 and Table 2.1 give 10677 RPM and 10.71 N against the measured 15 N, −28.6 %,
// beyond even the 20 % §2.6.1 admits for low throttle. (The withheld "Est Thrust" column may have used
// inputs we do not have.) This test pins the value so that any change to the model is noticed.
TEST(StaticThrustTest, TractorAt1500UsFallsShortOfTheStatedBound) {
  const auto configuration = PropellerConfiguration::kTractor;
  const StaticThrustMeasurement row = StaticThrustTable(configuration)[0];
  const StaticThrustEstimate estimate =
      EstimateStaticThrust(PropulsionParams::ForConfiguration(configuration), row.throttle_us, row.total_power);
  const double error = RelativeError(estimate.total_thrust, row.total_thrust);
  EXPECT_GT(std::abs(error), kLowThrottleBound);
  EXPECT_NEAR(error, -0.2863, 0.001);
  EXPECT_NEAR(estimate.rpm, 10677.1, 0.1);
}

TEST(StaticThrustTest, UsesOneSixthOfTheVehiclePowerPerMotor) {
  const PropulsionParams params;
  const StaticThrustEstimate estimate = EstimateStaticThrust(params, 1700.0, 420.0);
  EXPECT_DOUBLE_EQ(estimate.motor_power, 70.0);
  EXPECT_NEAR(estimate.rpm, EstimateRpm(params.rpm_estimator, 1700.0, 70.0), kRpmTolerance);
  EXPECT_NEAR(estimate.total_thrust, 6.0 * estimate.rotor_thrust, kThrustTolerance);
  EXPECT_NEAR(estimate.rotor_thrust, params.thrust_coefficient_n_per_rpm2 * estimate.rpm * estimate.rpm,
              kThrustTolerance);
}

// --- eq. 2.12 by hand ----------------------------------------------------------------------------
// At δ_t = 1550 + 201.9 = 1751.9 µs and P = 71.11 + 55.75 = 126.86 W the normalised inputs are x = y = 1,
// so every monomial is 1 and the RPM is the sum of the nine coefficients:
//   12390 − 803.8 + 4125 + 979.3 − 2757 + 334.4 + 450 − 17.38 + 69.46 = 14769.98 RPM.
// At δ_t = 1550 − 201.9 = 1348.1 µs, same power (x = −1, y = 1), the odd powers of x change sign:
//   12390 + 803.8 + 4125 + 979.3 + 2757 + 334.4 − 450 − 17.38 − 69.46 = 20852.66 RPM.
// At the means (x = y = 0) only p00 remains: 12390 RPM.
TEST(RpmEstimatorTest, ReproducesHandEvaluatedPoints) {
  const RpmEstimatorParams params;
  EXPECT_NEAR(EstimateRpm(params, 1751.9, 126.86), 14769.98, kRpmTolerance);
  EXPECT_NEAR(EstimateRpm(params, 1348.1, 126.86), 20852.66, kRpmTolerance);
  EXPECT_NEAR(EstimateRpm(params, 1550.0, 71.11), 12390.0, kRpmTolerance);
}

TEST(RpmEstimatorTest, RejectsInputsOutsideTheFit) {
  const RpmEstimatorParams params;
  EXPECT_NO_THROW(EstimateRpm(params, 1100.0, 0.0));
  EXPECT_NO_THROW(EstimateRpm(params, 1900.0, 200.0));
  EXPECT_THROW(EstimateRpm(params, 1099.9, 50.0), InputError);
  EXPECT_THROW(EstimateRpm(params, 1900.1, 50.0), InputError);
  EXPECT_THROW(EstimateRpm(params, 1500.0, -0.1), InputError);
  EXPECT_THROW(EstimateRpm(params, 1500.0, std::numeric_limits<double>::quiet_NaN()), InputError);
  EXPECT_THROW(EstimateRpm(params, 1500.0, std::numeric_limits<double>::infinity()), InputError);
  EXPECT_THROW(EstimateRpm(params, std::numeric_limits<double>::quiet_NaN(), 50.0), InputError);
}

// --- eqs. 2.1–2.3 with Table 2.1 ------------------------------------------------------------------
// At 10000 RPM (ω = 10000·2π/60 = 1047.198 rad/s), tractor:
//   T = 1.5652e-8 · 1e8 = 1.5652 N;  Q = 2.0862e-10 · 1e8 = 0.020862 N·m;
//   P_mech = Q ω = 0.020862 · 1047.1976 = 21.8467 W.
TEST(RotorEquationsTest, Table21CoefficientsArePerRpmSquared) {
  const PropulsionParams tractor;
  const double rotor_speed = RpmToRadPerSecond(10000.0);
  EXPECT_NEAR(rotor_speed, 1047.1975511965977, 1e-9);
  EXPECT_NEAR(CalcRotorThrust(tractor, rotor_speed), 1.5652, 1.5652 * kRoundOff);
  EXPECT_NEAR(CalcRotorTorque(tractor, rotor_speed), 0.020862, 0.020862 * kRoundOff);
  EXPECT_NEAR(CalcMechanicalPower(tractor, rotor_speed), 0.020862 * 1047.1975511965977, 1e-9);
  const PropulsionParams pusher = PropulsionParams::ForConfiguration(PropellerConfiguration::kPusher);
  EXPECT_NEAR(CalcRotorThrust(pusher, rotor_speed), 1.9693, 1.9693 * kRoundOff);
  EXPECT_NEAR(CalcRotorTorque(pusher, rotor_speed), 0.021374, 0.021374 * kRoundOff);
}

TEST(RotorEquationsTest, SpeedForThrustInvertsEq21) {
  const PropulsionParams params;
  for (const double thrust : {0.1, 1.0, 2.125, params.max_thrust}) {
    EXPECT_NEAR(CalcRotorThrust(params, CalcRotorSpeedForThrust(params, thrust)), thrust, thrust * kRoundOff);
  }
  EXPECT_EQ(CalcRotorSpeedForThrust(params, 0.0), 0.0);
  EXPECT_EQ(CalcRotorSpeedForThrust(params, -1.0), 0.0);
}

TEST(RotorEquationsTest, YawTorquePerThrustIsTheCoefficientRatio) {
  // γ = C_Q / C_T = 2.0862e-10 / 1.5652e-08 = 0.0133286 m (tractor).
  EXPECT_NEAR(CalcYawTorquePerThrust(PropulsionParams{}), 0.013328648096, 1e-12);
}

TEST(RotorEquationsTest, SaturationClampsToZeroAndTable22Maximum) {
  const PropulsionParams tractor;
  EXPECT_DOUBLE_EQ(tractor.max_thrust, 4.475);  // 26.85 / 6
  EXPECT_DOUBLE_EQ(SaturateThrust(tractor, 9.0), 4.475);
  EXPECT_DOUBLE_EQ(SaturateThrust(tractor, -0.3), 0.0);
  EXPECT_DOUBLE_EQ(SaturateThrust(tractor, 2.0), 2.0);
  const auto pusher = PropulsionParams::ForConfiguration(PropellerConfiguration::kPusher);
  EXPECT_DOUBLE_EQ(SaturateThrust(pusher, 9.0), 31.0 / 6.0);
}

// --- electrical power and current ------------------------------------------------------------------
TEST(ElectricalPowerTest, PowerLawPassesThroughTable22PerRotor) {
  for (const auto configuration : {PropellerConfiguration::kTractor, PropellerConfiguration::kPusher}) {
    const PropulsionParams params = PropulsionParams::ForConfiguration(configuration);
    for (const StaticThrustMeasurement& row : StaticThrustTable(configuration)) {
      EXPECT_NEAR(CalcElectricalPower(params, row.total_thrust / 6.0), row.total_power / 6.0, 1e-9)
          << PropellerConfigurationName(configuration) << " at " << row.throttle_us << " us";
    }
  }
}

TEST(ElectricalPowerTest, FittedConstantsMatchTheDocumentedDerivation) {
  // Tractor: b = ln(96.333/47.667) / ln(4.475/2.5) = ln 2.02098 / ln 1.79 = 0.70359 / 0.58222 = 1.20846,
  //          k = 47.667 / 2.5^1.20846 = 15.7515 W.
  const ElectricalPowerLaw tractor = FitElectricalPowerLaw(PropellerConfiguration::kTractor);
  EXPECT_NEAR(tractor.exponent, 1.20846, 5e-5);
  EXPECT_NEAR(tractor.power_at_one_newton, 15.7515, 5e-4);
  // Pusher: b = ln(96.833/48.5) / ln(5.16667/2.59333) = 1.00311, k = 48.5 / 2.59333^1.00311 = 18.6465 W.
  const ElectricalPowerLaw pusher = FitElectricalPowerLaw(PropellerConfiguration::kPusher);
  EXPECT_NEAR(pusher.exponent, 1.00311, 5e-5);
  EXPECT_NEAR(pusher.power_at_one_newton, 18.6465, 5e-4);
  EXPECT_THROW(FitPowerLaw(1.0, 10.0, 1.0, 20.0), InputError);
  EXPECT_THROW(FitPowerLaw(-1.0, 10.0, 2.0, 20.0), InputError);
}

TEST(ElectricalPowerTest, PowerGrowsWithThrustAndCurrentIsPowerOverVoltage) {
  const PropulsionParams params;
  EXPECT_EQ(CalcElectricalPower(params, 0.0), 0.0);
  double previous = 0.0;
  for (double thrust = 0.25; thrust <= params.max_thrust; thrust += 0.25) {
    const double power = CalcElectricalPower(params, thrust);
    EXPECT_GT(power, previous);
    previous = power;
  }
  // Eq. 2.10 at the tractor's full-throttle rotor: 578/6 W from an 11.1 V bus is 8.6787 A.
  EXPECT_NEAR(CalcMotorCurrent(CalcElectricalPower(params, params.max_thrust), 11.1), 578.0 / 6.0 / 11.1, 1e-9);
  EXPECT_THROW(CalcMotorCurrent(50.0, 0.0), InputError);
}

// --- rotor-speed lag ----------------------------------------------------------------------------
TEST(RotorSpeedLagTest, DecayIsExpOfMinusStepOverTimeConstant) {
  const RotorSpeedLag lag(0.03, 0.005);                    // τ_m of docs/defaults.md#vehicle, the 200 Hz GNC step
  EXPECT_NEAR(lag.decay(), 0.846481724890614, kRoundOff);  // e^{−1/6}
}

TEST(RotorSpeedLagTest, MatchesTheAnalyticResponseAndAFineEulerIntegration) {
  const double time_constant = 0.03;
  const double start = 200.0;     // rad/s
  const double command = 1500.0;  // rad/s
  const double duration = 0.1;    // s
  // Exact discretisation in 20 steps of 5 ms.
  const RotorSpeedLag lag(time_constant, 0.005);
  double speed = start;
  for (int k = 0; k < 20; ++k) speed = lag.Step(speed, command);
  const double analytic = command + (start - command) * std::exp(-duration / time_constant);
  EXPECT_NEAR(speed, analytic, 1e-9);
  // An independent computation: forward Euler with 10^6 steps converges to the same value (error O(dt)).
  double euler = start;
  const int fine_steps = 1000000;
  const double dt = duration / fine_steps;
  for (int k = 0; k < fine_steps; ++k) euler += dt * (command - euler) / time_constant;
  EXPECT_NEAR(speed, euler, 1e-3);
}

TEST(RotorSpeedLagTest, RejectsNonPositiveArguments) {
  EXPECT_THROW(RotorSpeedLag(0.0, 0.005), InputError);
  EXPECT_THROW(RotorSpeedLag(0.03, -0.005), InputError);
  EXPECT_THROW(RotorSpeedLag(0.03, std::numeric_limits<double>::infinity()), InputError);
}

// --- parameters ---------------------------------------------------------------------------------
TEST(PropulsionParamsTest, FactoryGivesTable21RowsAndValidates) {
  const auto tractor = PropulsionParams::ForConfiguration(PropellerConfiguration::kTractor);
  EXPECT_EQ(tractor.configuration, PropellerConfiguration::kTractor);
  EXPECT_DOUBLE_EQ(tractor.thrust_coefficient_n_per_rpm2, 1.5652e-08);
  EXPECT_DOUBLE_EQ(tractor.torque_coefficient_nm_per_rpm2, 2.0862e-10);
  const auto pusher = PropulsionParams::ForConfiguration(PropellerConfiguration::kPusher);
  EXPECT_EQ(pusher.configuration, PropellerConfiguration::kPusher);
  EXPECT_DOUBLE_EQ(pusher.thrust_coefficient_n_per_rpm2, 1.9693e-08);
  EXPECT_DOUBLE_EQ(pusher.torque_coefficient_nm_per_rpm2, 2.1374e-10);
  std::string error;
  EXPECT_TRUE(tractor.IsValid(&error)) << error;
  EXPECT_TRUE(pusher.IsValid(&error)) << error;
  PropulsionParams broken;
  broken.max_thrust = -1.0;
  EXPECT_FALSE(broken.IsValid(&error));
  EXPECT_NE(error.find("max_thrust"), std::string::npos);
}

TEST(PropulsionParamsTest, ParsesConfigurationNames) {
  EXPECT_EQ(ParsePropellerConfiguration("tractor", "--config"), PropellerConfiguration::kTractor);
  EXPECT_EQ(ParsePropellerConfiguration("pusher", "--config"), PropellerConfiguration::kPusher);
  try {
    ParsePropellerConfiguration("puller", "--config");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--config"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("puller"), std::string::npos);
  }
}

TEST(ElectricalPowerTableTest, MatchesThePowerLawWithinItsStatedError) {
  for (auto configuration : {PropellerConfiguration::kTractor, PropellerConfiguration::kPusher}) {
    const PropulsionParams params = PropulsionParams::ForConfiguration(configuration);
    const ElectricalPowerTable table(params);
    double worst = 0.0;
    for (double thrust = 0.05; thrust <= 1.6 * params.max_thrust; thrust += 0.0137) {
      const double exact = CalcElectricalPower(params, thrust);
      worst = std::max(worst, std::abs(table.Power(thrust) - exact) / exact);
    }
    EXPECT_LT(worst, 1e-4);  // relative, the bound the header states
    EXPECT_DOUBLE_EQ(table.Power(0.0), 0.0);
    // Off the grid by far (past 2^31 cells, where an int index would wrap) and NaN: the exact law, no read outside.
    EXPECT_EQ(table.Power(1e12), CalcElectricalPower(params, 1e12));
    EXPECT_TRUE(std::isnan(table.Power(std::numeric_limits<double>::quiet_NaN())));
  }
}

}  // namespace
}  // namespace uascma::models
