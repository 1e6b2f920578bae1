#pragma once
// Propulsion model of one rotor of the hexacopter — a Multistar Elite 2204 2300Kv motor, its speed
// controller and a 6040 two-blade propeller (dissertation Ch. II §2.3, §2.4.1, §2.5).
//
// What is modelled, per rotor:
//   thrust       T = C_T n²                        eq. 2.1
//   torque       Q = C_Q n²                        eq. 2.2 (magnitude of the reaction torque on the
//                                                  body about the rotor axis)
//   mech. power  P_mech = Q ω                       eqs. 2.3 and 2.9 (C_P ω³ with C_P ≡ C_Q when
//                                                  n and ω are the same speed in consistent units)
//   elec. power  P_elec = k (T / 1 N)^b             docs/defaults.md#vehicle: a power law fitted to
//                                                  Table 2.2 (see FitElectricalPowerLaw)
//   current      I = P_elec / V_bus                eq. 2.10
//   speed lag    dω/dt = (ω_cmd − ω) / τ_m          docs/defaults.md#vehicle (τ_m = 0.03 s)
//   saturation   0 ≤ T ≤ T_max                     docs/defaults.md#vehicle (Table 2.2 at 1900 µs / 6)
// and the RPM estimator of eq. 2.12 (§2.5.2), the cubic-in-throttle, quadratic-in-power surface fitted
// on the dynamometer; its power input is ONE motor's electrical power (docs/modelling-choices.md#rpm-per-motor).
//
// Units. SI inside: a double without a suffix is SI (N, N·m, W, A, V, s, rad/s). The rotor speed ω is
// in rad/s everywhere in uascma. RPM appears only at the edges, in names that say so: Table 2.1's
// coefficients are per RPM² (`_per_rpm2`), and eq. 2.12 returns RPM. The conversion is the one pair of
// functions RpmToRadPerSecond / RadPerSecondToRpm below.
//
// Thread safety: every function is pure; parameters are plain values.
#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

namespace uascma::models {

// --- unit conversion at the edges ----------------------------------------------------------------
inline constexpr double kRadPerSecondPerRpm = 2.0 * std::numbers::pi / 60.0;
constexpr double RpmToRadPerSecond(double rpm) { return rpm * kRadPerSecondPerRpm; }
inline constexpr double kRpmPerRadPerSecond = 60.0 / (2.0 * std::numbers::pi);
constexpr double RadPerSecondToRpm(double rotor_speed) { return rotor_speed * kRpmPerRadPerSecond; }

// --- configuration ------------------------------------------------------------------------------
// Propeller mounting (§2.4, Fig. 2.4): tractor (propeller above the arm, pulling) or pusher
// (propeller below the arm, pushing). Identical motors, propellers and airframe otherwise.
enum class PropellerConfiguration { kTractor, kPusher };

// "tractor" / "pusher".
std::string_view PropellerConfigurationName(PropellerConfiguration configuration);
// Parses "tractor" or "pusher"; throws InputError naming `source` (e.g. "--config") otherwise.
PropellerConfiguration ParsePropellerConfiguration(std::string_view text, const std::string& source);

// One row pair of Table 2.2: the whole hexacopter on the load-cell stand, level, all six motors at
// one throttle (§2.5.3.1). The "Est Thrust" column is not used (and is withheld from our copy).
struct StaticThrustMeasurement {
  double throttle_us;   // δ_t, µs
  double total_thrust;  // N, measured by the load cell, all six rotors
  double total_power;   // W, electrical, the whole hexacopter
};
// Table 2.2 for one configuration: {1500 µs, 1900 µs}.
std::array<StaticThrustMeasurement, 2> StaticThrustTable(PropellerConfiguration configuration);

// --- parameters ---------------------------------------------------------------------------------
// The RPM estimator of eq. 2.12 (§2.5.2): with x = (δ_t − 1550 µs) / 201.9 µs and
// y = (P_elec − 71.11 W) / 55.75 W (P_elec of ONE motor, docs/modelling-choices.md#rpm-per-motor),
//   RPM = p00 + p10 x + p01 y + p20 x² + p11 x y + p02 y² + p30 x³ + p21 x² y + p12 x y².
// The coefficient names are the dissertation's (p_ij multiplies x^i y^j). Fitted on throttle
// commands of 1100–1900 µs (§2.4.1, §2.5.2); outside that range it is not defined here.
struct RpmEstimatorParams {
  double p00 = 1.239e+04;
  double p10 = -803.8;
  double p01 = 4125.0;
  double p20 = 979.3;
  double p11 = -2757.0;
  double p02 = 334.4;
  double p30 = 450.0;
  double p21 = -17.38;
  double p12 = 69.46;
  double throttle_mean_us = 1550.0;  // normalisation of δ_t, §2.5.2
  double throttle_std_us = 201.9;
  double power_mean = 71.11;        // W, normalisation of P_elec, §2.5.2
  double power_std = 55.75;         // W
  double min_throttle_us = 1100.0;  // the fitted throttle range, §2.4.1 and §2.5.2
  double max_throttle_us = 1900.0;
};

// Electrical power of one rotor as a function of its thrust: P_elec = power_at_one_newton·(T/1 N)^exponent.
struct ElectricalPowerLaw {
  double power_at_one_newton;  // W, k
  double exponent;             // b, dimensionless
};

// The power law through two (thrust, power) points, solved exactly in log-log coordinates:
//   b = ln(P2/P1) / ln(T2/T1),   k = P1 / T1^b.
// Throws InputError unless both points are positive and T1 ≠ T2.
ElectricalPowerLaw FitPowerLaw(double thrust_1, double power_1, double thrust_2, double power_2);

// The motor power law of docs/defaults.md#vehicle for one configuration: FitPowerLaw through Table 2.2's two rows, each
// divided by six (one rotor of six). Evaluated, the fit gives
//   tractor: (2.5 N, 47.67 W), (4.475 N, 96.33 W)   → b = 1.2085, k = 15.751 W
//   pusher:  (2.593 N, 48.50 W), (5.167 N, 96.83 W) → b = 1.0031, k = 18.646 W
// (momentum theory would give b = 1.5; two measured points are what the dissertation offers).
ElectricalPowerLaw FitElectricalPowerLaw(PropellerConfiguration configuration);

struct PropulsionParams {
  PropellerConfiguration configuration = PropellerConfiguration::kTractor;
  // Table 2.1, 6040 propeller, tractor row (pusher: ForConfiguration(kPusher)).
  double thrust_coefficient_n_per_rpm2 = 1.5652e-08;   // C_T
  double torque_coefficient_nm_per_rpm2 = 2.0862e-10;  // C_Q
  // N per rotor: Table 2.2 total thrust at 1900 µs divided by six (docs/defaults.md#vehicle).
  double max_thrust = 26.85 / 6.0;
  // s: the rotor-speed lag, typical for 2204-class motors (docs/defaults.md#vehicle).
  double motor_time_constant = 0.03;
  // Fitted in code to Table 2.2 divided by six (docs/defaults.md#vehicle); see FitElectricalPowerLaw.
  ElectricalPowerLaw electrical_power = FitElectricalPowerLaw(PropellerConfiguration::kTractor);
  RpmEstimatorParams rpm_estimator;

  // The defaults above for the tractor, or Table 2.1's pusher row, the pusher's 31/6 N and the power
  // law fitted to the pusher's Table 2.2 rows.
  static PropulsionParams ForConfiguration(PropellerConfiguration configuration);
  // True when every coefficient is positive and finite; otherwise false with a one-line reason.
  bool IsValid(std::string* error) const;
};

// --- the rotor equations (pure kernels) ----------------------------------------------------------
// Thrust (N) of one rotor turning at `rotor_speed` rad/s, eq. 2.1.
inline double CalcRotorThrust(const PropulsionParams& params, double rotor_speed) {
  // Eq. 2.1 with Table 2.1's C_T, which is per RPM².
  const double rpm = RadPerSecondToRpm(rotor_speed);
  return params.thrust_coefficient_n_per_rpm2 * rpm * rpm;
}
// Reaction-torque magnitude (N·m) on the body about the rotor axis, eq. 2.2.
double CalcRotorTorque(const PropulsionParams& params, double rotor_speed);
// Shaft (mechanical) power (W), eqs. 2.3 and 2.9: Q ω.
double CalcMechanicalPower(const PropulsionParams& params, double rotor_speed);
// Inverse of eq. 2.1: the rotor speed (rad/s) giving `thrust` N (thrust ≤ 0 gives 0).
inline double CalcRotorSpeedForThrust(const PropulsionParams& params, double thrust) {
  if (thrust <= 0.0) return 0.0;
  // Invert eq. 2.1 in RPM, where C_T is given, then convert.
  return RpmToRadPerSecond(std::sqrt(thrust / params.thrust_coefficient_n_per_rpm2));
}
// The yaw-torque-to-thrust ratio γ = C_Q / C_T (m) of eqs. 2.7 and 4.11.
double CalcYawTorquePerThrust(const PropulsionParams& params);
// Electrical power (W) one rotor draws at `thrust` N (the power law of docs/defaults.md#vehicle; thrust ≤ 0 gives 0).
double CalcElectricalPower(const PropulsionParams& params, double thrust);
// The power law P = k T^b tabulated on a uniform thrust grid, for the simulator's 200 Hz loop (a table
// read instead of a pow per rotor and step). Linear interpolation; beyond the grid the exact law. With the
// default 4096 intervals up to 1.5 × T_max the relative error is below 1e-4 for T ≥ 0.05 N (3.4e-5 at
// 0.05 N, ~1e-7 near the hover thrust of ~2 N)
// (tests/models/propulsion_test.cc).
class ElectricalPowerTable {
 public:
  explicit ElectricalPowerTable(const PropulsionParams& params, int intervals = 4096);
  double Power(double thrust) const {
    if (thrust <= 0.0) return 0.0;
    const double x = thrust * inverse_step_;
    // Beyond the grid (or NaN) before the index is formed: a thrust past 2^31 cells or NaN has no int (the cast would
    // give INT_MIN, a read far before the table). The same cells as comparing the index: floor(x) < n ⟺ x < n.
    if (!(x < static_cast<double>(intervals_))) return CalcElectricalPower(params_, thrust);
    const int i = static_cast<int>(x);
    const double f = x - i;
    return power_[i] + f * (power_[i + 1] - power_[i]);
  }
  // The grid, for a caller that reads it for several rotors at once with Power's arithmetic (sim/rotor_lanes.h):
  // grid()[i] is the power at thrust i / inverse_step(), i in [0, intervals()].
  const double* grid() const { return power_.data(); }
  double inverse_step() const { return inverse_step_; }
  int intervals() const { return intervals_; }

 private:
  PropulsionParams params_;
  int intervals_;
  double inverse_step_;
  std::vector<double> power_;  // [intervals + 1], W at thrust i · step
};

// Motor current (A) at `electrical_power` W from a bus at `bus_voltage` V, eq. 2.10: I = P / V.
// Throws InputError unless bus_voltage > 0.
double CalcMotorCurrent(double electrical_power, double bus_voltage);
// The thrust clamped to [0, max_thrust] (the rotor cannot push, nor exceed Table 2.2's maximum).
double SaturateThrust(const PropulsionParams& params, double thrust);

// Eq. 2.12: the RPM of one motor at throttle `throttle_us` drawing `motor_power` W (one motor's
// electrical power, docs/modelling-choices.md#rpm-per-motor). A (never observed in the fitted range) negative
// polynomial value is returned as 0. Throws InputError if the throttle is outside [min_throttle_us,
// max_throttle_us] or the power is negative or not finite.
double EstimateRpm(const RpmEstimatorParams& params, double throttle_us, double motor_power);

// The static test of §2.5.3.1 as the dissertation estimated it: the hexacopter at throttle δ_t
// drawing `vehicle_power` W in total. Each motor draws vehicle_power / 6 (docs/modelling-choices.md#rpm-per-motor); eq.
// 2.12 gives its RPM, eq. 2.1 its thrust, and the total is six times the rotor's.
struct StaticThrustEstimate {
  double total_thrust;  // N, six rotors
  double rotor_thrust;  // N, one rotor
  double rpm;           // RPM of each motor (eq. 2.12)
  double motor_power;   // W, vehicle_power / 6
};
StaticThrustEstimate EstimateStaticThrust(const PropulsionParams& params, double throttle_us, double vehicle_power);

// --- rotor-speed dynamics -------------------------------------------------------------------------
// The first-order lag of the rotor speed behind its command, dω/dt = (ω_cmd − ω) / τ_m, discretised
// exactly for a command held over the step (zero-order hold):
//   ω[k+1] = ω_cmd + (ω[k] − ω_cmd) · exp(−Δt / τ_m).
// The decay factor is computed once for a fixed step; Step() is a multiply-add.
class RotorSpeedLag {
 public:
  // Throws InputError unless time_constant > 0 and step > 0 (both s, finite).
  RotorSpeedLag(double time_constant, double step);
  // The rotor speed (rad/s) one step later, from `rotor_speed` under `commanded_rotor_speed`.
  double Step(double rotor_speed, double commanded_rotor_speed) const {
    return commanded_rotor_speed + (rotor_speed - commanded_rotor_speed) * decay_;
  }
  double decay() const { return decay_; }  // exp(−Δt / τ_m)
  double step() const { return step_; }    // Δt, s

 private:
  double step_;
  double decay_;
};

}  // namespace uascma::models
