#include "uascma/models/propulsion.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "uascma/common/error.h"

namespace uascma::models {
namespace {

// The hexacopter has six identical propulsion units (§2.4.2); Table 2.2 is the sum of the six.
constexpr double kRotorsPerVehicle = 6.0;

bool PositiveFinitePropulsionInput(double value) { return std::isfinite(value) && value > 0.0; }

}  // namespace

std::string_view PropellerConfigurationName(PropellerConfiguration configuration) {
  return configuration == PropellerConfiguration::kTractor ? "tractor" : "pusher";
}

PropellerConfiguration ParsePropellerConfiguration(std::string_view text, const std::string& source) {
  if (text == "tractor") return PropellerConfiguration::kTractor;
  if (text == "pusher") return PropellerConfiguration::kPusher;
  throw InputError(source, "configuration", fmt::format("'tractor' or 'pusher', got '{}'", text));
}

std::array<StaticThrustMeasurement, 2> StaticThrustTable(PropellerConfiguration configuration) {
  // Table 2.2: throttle (µs), load-cell thrust (N), electrical power (W).
  if (configuration == PropellerConfiguration::kTractor) {
    return {{{1500.0, 15.0, 286.0}, {1900.0, 26.85, 578.0}}};
  }
  return {{{1500.0, 15.56, 291.0}, {1900.0, 31.0, 581.0}}};
}

ElectricalPowerLaw FitPowerLaw(double thrust_1, double power_1, double thrust_2, double power_2) {
  if (!(PositiveFinitePropulsionInput(thrust_1) && PositiveFinitePropulsionInput(power_1) &&
        PositiveFinitePropulsionInput(thrust_2) && PositiveFinitePropulsionInput(power_2)) ||
      thrust_1 == thrust_2) {
    throw InputError("FitPowerLaw", "points",
                     fmt::format("two points of positive thrust and power with distinct thrusts, got "
                                 "({} N, {} W) and ({} N, {} W)",
                                 thrust_1, power_1, thrust_2, power_2));
  }
  // ln P = ln k + b ln T through both points: the slope is b, the intercept ln k.
  const double exponent = std::log(power_2 / power_1) / std::log(thrust_2 / thrust_1);
  return {power_1 / std::pow(thrust_1, exponent), exponent};
}

ElectricalPowerLaw FitElectricalPowerLaw(PropellerConfiguration configuration) {
  // docs/defaults.md#vehicle: one rotor draws a sixth of the vehicle's power and makes a sixth of its thrust.
  const auto table = StaticThrustTable(configuration);
  return FitPowerLaw(table[0].total_thrust / kRotorsPerVehicle, table[0].total_power / kRotorsPerVehicle,
                     table[1].total_thrust / kRotorsPerVehicle, table[1].total_power / kRotorsPerVehicle);
}

PropulsionParams PropulsionParams::ForConfiguration(PropellerConfiguration configuration) {
  PropulsionParams params;  // tractor defaults
  if (configuration == PropellerConfiguration::kPusher) {
    params.configuration = PropellerConfiguration::kPusher;
    params.thrust_coefficient_n_per_rpm2 = 1.9693e-08;   // Table 2.1, pusher
    params.torque_coefficient_nm_per_rpm2 = 2.1374e-10;  // Table 2.1, pusher
    params.max_thrust = 31.0 / 6.0;                      // docs/defaults.md#vehicle: Table 2.2 at 1900 µs / 6
    params.electrical_power = FitElectricalPowerLaw(PropellerConfiguration::kPusher);
  }
  return params;
}

bool PropulsionParams::IsValid(std::string* error) const {
  const auto fail = [error](const std::string& reason) {
    if (error != nullptr) *error = reason;
    return false;
  };
  if (!PositiveFinitePropulsionInput(thrust_coefficient_n_per_rpm2))
    return fail("thrust_coefficient_n_per_rpm2 must be > 0");
  if (!PositiveFinitePropulsionInput(torque_coefficient_nm_per_rpm2))
    return fail("torque_coefficient_nm_per_rpm2 must be > 0");
  if (!PositiveFinitePropulsionInput(max_thrust)) return fail("max_thrust must be > 0 N");
  if (!PositiveFinitePropulsionInput(motor_time_constant)) return fail("motor_time_constant must be > 0 s");
  if (!PositiveFinitePropulsionInput(electrical_power.power_at_one_newton) ||
      !PositiveFinitePropulsionInput(electrical_power.exponent)) {
    return fail("electrical_power: power_at_one_newton and exponent must be > 0");
  }
  const RpmEstimatorParams& rpm = rpm_estimator;
  if (!PositiveFinitePropulsionInput(rpm.throttle_std_us) || !PositiveFinitePropulsionInput(rpm.power_std)) {
    return fail("rpm_estimator: the normalising standard deviations must be > 0");
  }
  if (!(rpm.min_throttle_us < rpm.max_throttle_us)) {
    return fail("rpm_estimator: min_throttle_us must be below max_throttle_us");
  }
  return true;
}

double CalcRotorTorque(const PropulsionParams& params, double rotor_speed) {
  // Eq. 2.2 with Table 2.1's C_Q, which is per RPM².
  const double rpm = RadPerSecondToRpm(rotor_speed);
  return params.torque_coefficient_nm_per_rpm2 * rpm * rpm;
}

double CalcMechanicalPower(const PropulsionParams& params, double rotor_speed) {
  // Eq. 2.9: P_mech = Q ω, with ω in rad/s (this is eq. 2.3's C_P ω³).
  return CalcRotorTorque(params, rotor_speed) * rotor_speed;
}

double CalcYawTorquePerThrust(const PropulsionParams& params) {
  // Q / T = C_Q n² / (C_T n²): the per-RPM² units cancel.
  return params.torque_coefficient_nm_per_rpm2 / params.thrust_coefficient_n_per_rpm2;
}

double CalcElectricalPower(const PropulsionParams& params, double thrust) {
  if (thrust <= 0.0) return 0.0;
  return params.electrical_power.power_at_one_newton * std::pow(thrust, params.electrical_power.exponent);
}

ElectricalPowerTable::ElectricalPowerTable(const PropulsionParams& params, int intervals)
    : params_(params), intervals_(intervals) {
  if (intervals < 2) throw InputError("ElectricalPowerTable", "intervals", "at least 2");
  const double top = 1.5 * params.max_thrust;  // covers any commanded thrust (the cap is T_max)
  const double step = top / intervals;
  inverse_step_ = 1.0 / step;
  power_.resize(static_cast<std::size_t>(intervals) + 1);
  for (int i = 0; i <= intervals; ++i) power_[i] = CalcElectricalPower(params, i * step);
}

double CalcMotorCurrent(double electrical_power, double bus_voltage) {
  if (!PositiveFinitePropulsionInput(bus_voltage)) {
    throw InputError("CalcMotorCurrent", "bus_voltage", fmt::format("a voltage > 0 V, got {}", bus_voltage));
  }
  return electrical_power / bus_voltage;  // eq. 2.10
}

double SaturateThrust(const PropulsionParams& params, double thrust) {
  return std::clamp(thrust, 0.0, params.max_thrust);
}

double EstimateRpm(const RpmEstimatorParams& params, double throttle_us, double motor_power) {
  if (!(std::isfinite(throttle_us) && throttle_us >= params.min_throttle_us && throttle_us <= params.max_throttle_us)) {
    throw InputError("RPM estimator (eq. 2.12)", "throttle_us",
                     fmt::format("a throttle command within the fitted {}-{} us, got {}", params.min_throttle_us,
                                 params.max_throttle_us, throttle_us));
  }
  if (!(std::isfinite(motor_power) && motor_power >= 0.0)) {
    throw InputError("RPM estimator (eq. 2.12)", "motor_power",
                     fmt::format("one motor's electrical power, finite and >= 0 W, got {}", motor_power));
  }
  // The normalised inputs of §2.5.2.
  const double x = (throttle_us - params.throttle_mean_us) / params.throttle_std_us;
  const double y = (motor_power - params.power_mean) / params.power_std;
  // Eq. 2.12, grouped by powers of x (Horner in x with y-polynomial coefficients).
  const double rpm =
      (params.p00 + params.p01 * y + params.p02 * y * y) +
      x * ((params.p10 + params.p11 * y + params.p12 * y * y) + x * ((params.p20 + params.p21 * y) + x * params.p30));
  return std::max(rpm, 0.0);
}

StaticThrustEstimate EstimateStaticThrust(const PropulsionParams& params, double throttle_us, double vehicle_power) {
  StaticThrustEstimate estimate;
  // docs/modelling-choices.md#rpm-per-motor: eq. 2.12 is a per-motor fit, so each motor gets a sixth of the vehicle's
  // power (the six motors share one bus and receive the same throttle on the stand, §2.5.3.1).
  estimate.motor_power = vehicle_power / kRotorsPerVehicle;
  estimate.rpm = EstimateRpm(params.rpm_estimator, throttle_us, estimate.motor_power);
  estimate.rotor_thrust = CalcRotorThrust(params, RpmToRadPerSecond(estimate.rpm));  // eq. 2.1
  estimate.total_thrust = kRotorsPerVehicle * estimate.rotor_thrust;
  return estimate;
}

RotorSpeedLag::RotorSpeedLag(double time_constant, double step) : step_(step), decay_(0.0) {
  if (!PositiveFinitePropulsionInput(time_constant)) {
    throw InputError("RotorSpeedLag", "time_constant", fmt::format("a time constant > 0 s, got {}", time_constant));
  }
  if (!PositiveFinitePropulsionInput(step)) {
    throw InputError("RotorSpeedLag", "step", fmt::format("a time step > 0 s, got {}", step));
  }
  // The exact solution of dω/dt = (ω_cmd − ω)/τ over Δt with ω_cmd constant:
  //   ω(Δt) − ω_cmd = (ω(0) − ω_cmd) e^{−Δt/τ}.
  decay_ = std::exp(-step / time_constant);
}

}  // namespace uascma::models
