#include "uascma/sim/sensing.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

namespace uascma::sim {
namespace {

bool SensingFail(std::string* error, const char* field, const char* expected) {
  if (error) *error = fmt::format("{}: expected {}", field, expected);
  return false;
}

bool NonNegativeFinite(double value) { return std::isfinite(value) && value >= 0.0; }

}  // namespace

bool SensingParams::IsValid(std::string* error) const {
  if (!(std::isfinite(shunt_resistance_ohm) && shunt_resistance_ohm > 0.0)) {
    return SensingFail(error, "shunt_resistance_ohm", "a positive resistance");
  }
  for (const double sigma : {current_gain_sigma, shunt_offset_sigma_v, shunt_noise_v, bus_offset_sigma_v,
                             bus_gain_sigma, bus_noise_v, vibration_raw_accel_sigma}) {
    if (!NonNegativeFinite(sigma)) return SensingFail(error, "sensing", "every 1σ finite and >= 0");
  }
  if (!(accel_cutoff_hz > 0.0 && gyro_cutoff_hz > 0.0 && std::isfinite(accel_cutoff_hz) &&
        std::isfinite(gyro_cutoff_hz))) {
    return SensingFail(error, "cutoff_hz", "positive cut-off frequencies");
  }
  if (!(spall_false_positive >= 0.0 && spall_false_positive < 1.0 && spall_miss >= 0.0 && spall_miss < 1.0)) {
    return SensingFail(error, "spall indicator", "probabilities in [0, 1)");
  }
  return true;
}

double CalcLowPassedSigma(double raw_sigma, double frequency_hz, double cutoff_hz) {
  const double ratio = frequency_hz / cutoff_hz;
  return raw_sigma / std::sqrt(1.0 + ratio * ratio * ratio * ratio);
}

VibrationNoise CalcVibrationNoise(const SensingParams& params, double hover_rotor_speed, double mass_kg,
                                  double inertia_xx, double arm_length_m) {
  const double frequency_hz = hover_rotor_speed / (2.0 * std::numbers::pi);  // once per revolution
  VibrationNoise noise;
  noise.accel_sigma = CalcLowPassedSigma(params.vibration_raw_accel_sigma, frequency_hz, params.accel_cutoff_hz);
  // The imbalance force's torque at the arm, as an angular rate at the rotor frequency.
  const double raw_gyro =
      mass_kg * params.vibration_raw_accel_sigma * arm_length_m / (inertia_xx * 2.0 * std::numbers::pi * frequency_hz);
  noise.gyro_sigma = CalcLowPassedSigma(raw_gyro, frequency_hz, params.gyro_cutoff_hz);
  return noise;
}

PowerSensorErrors DrawPowerSensorErrors(const SensingParams& params, RandomStream& random) {
  PowerSensorErrors errors;
  errors.current_gain = params.current_gain_sigma * random.Normal();
  errors.current_offset_a = params.shunt_offset_sigma_v / params.shunt_resistance_ohm * random.Normal();
  errors.bus_gain = params.bus_gain_sigma * random.Normal();
  errors.bus_offset_v = params.bus_offset_sigma_v * random.Normal();
  return errors;
}

double ReadCurrent(const SensingParams& params, const PowerSensorErrors& errors, double current_a,
                   RandomStream& random) {
  const double noise_a = params.shunt_noise_v / params.shunt_resistance_ohm;
  return current_a * (1.0 + errors.current_gain) + errors.current_offset_a + noise_a * random.Normal();
}

double ReadBusVoltage(const SensingParams& params, const PowerSensorErrors& errors, double bus_voltage_v,
                      RandomStream& random) {
  return bus_voltage_v * (1.0 + errors.bus_gain) + errors.bus_offset_v + params.bus_noise_v * random.Normal();
}

double SocEstimateError(const PowerSensing& sensing, double cell_capacity_as) {
  // Reading more current than flows counts more charge out: the estimate is low.
  return sensing.initial_soc_error - sensing.charge_error_as / (2.0 * cell_capacity_as);
}

double CalcSocEstimateSigma(const SensingParams& params, double elapsed_s, double mean_current_a,
                            double cell_capacity_as, double ocv_slope_v_per_soc, double sample_dt_s,
                            double initial_bus_voltage_v) {
  // The rest voltage: one bus reading over three cells in series.
  const double gain_v = params.bus_gain_sigma * initial_bus_voltage_v;
  const double cell_v = std::sqrt(params.bus_offset_sigma_v * params.bus_offset_sigma_v + gain_v * gain_v +
                                  params.bus_noise_v * params.bus_noise_v) /
                        3.0;
  const double initial = cell_v / ocv_slope_v_per_soc;
  // The counted charge: gain and offset grow with t, the white noise as √(dt t).
  const double t = std::max(elapsed_s, 0.0);
  const double gain_as = params.current_gain_sigma * mean_current_a * t;
  const double offset_as = params.shunt_offset_sigma_v / params.shunt_resistance_ohm * t;
  const double noise_as = params.shunt_noise_v / params.shunt_resistance_ohm * std::sqrt(sample_dt_s * t);
  const double counted =
      std::sqrt(gain_as * gain_as + offset_as * offset_as + noise_as * noise_as) / (2.0 * cell_capacity_as);
  return std::sqrt(initial * initial + counted * counted);
}

bool ReadSpallIndicator(const SensingParams& params, bool spall_present, RandomStream& random) {
  const double u = random.Uniform();
  return spall_present ? u >= params.spall_miss : u < params.spall_false_positive;
}

double PredictSpallProbability(double p_spall, double onset_hazard) { return p_spall + (1.0 - p_spall) * onset_hazard; }

double UpdateSpallProbability(double p_spall, bool reading, double false_positive, double miss) {
  const double if_spall = reading ? 1.0 - miss : miss;
  const double if_none = reading ? false_positive : 1.0 - false_positive;
  const double evidence = p_spall * if_spall + (1.0 - p_spall) * if_none;
  return evidence > 0.0 ? p_spall * if_spall / evidence : p_spall;
}

double SpallOnsetHazard(double fault_probability, double plan_duration_s, double time_s, double epoch_s) {
  if (!(plan_duration_s > 0.0) || time_s >= plan_duration_s) return 0.0;
  const double density = fault_probability / plan_duration_s;
  const double survival = 1.0 - fault_probability * std::max(time_s, 0.0) / plan_duration_s;
  return survival > 0.0 ? std::min(1.0, density * epoch_s / survival) : 1.0;
}

std::array<double, 3> MotorHealthBelief(double p_spall, double p_jammed) {
  const double free = 1.0 - p_jammed;
  return {free * (1.0 - p_spall), free * p_spall, p_jammed};
}

}  // namespace uascma::sim
