#pragma once
// Noisy sensing: what the CMA reads instead of the simulator's truth when SimOptions::noisy_sensing
// is on. Off (the default), every reading is the truth and no random number is drawn, so every result is the same
// bit for bit as without this file.
//
//   power module   the pack current and the bus voltage through a digital shunt monitor: a gain error and an offset
//                  drawn once per flight, white noise per sample (every GNC step). The CMA counts coulombs with the
//                  measured current and starts from the pack's rest voltage read before take-off, so its state of
//                  charge is the truth's plus an error common to every cell (CalcSocEstimateSigma: its 1σ);
//   vibration      white noise added to the IMM's gyro and accelerometer samples beyond what the IMM assumes
//                  (gnc/imm.h ImmParams::gyro_noise, accel_noise): false isolations become possible;
//   spall          a 1 Hz spall indicator (today's MH = SF at the true onset is a perfect one) that reads "spall" with
//                  a false-positive probability per epoch when there is none and misses a present spall with a miss
//                  probability per epoch, independently at every epoch.
//
// Magnitudes (SensingParams's defaults) are cited beside each; "ours" marks a documented choice. The random draws use
// their own streams (sim/flight_internal.h: DeriveSeed with stream ids 5, 6 and 7), so switching the noise on changes
// no other draw of a flight.
#include <array>
#include <string>

#include "uascma/common/random.h"

namespace uascma::sim {

struct SensingParams {
  // ---- power module: a TI INA226-class shunt monitor (datasheet SBOS547B, §5.5 Electrical Characteristics) ----
  // Ours, derived: the shunt that puts I_max = 105 A (Table 4.1) at the INA226's 81.92 mV full scale, 0.78 mΩ.
  double shunt_resistance_ohm = 0.08192 / 105.0;
  // Shunt voltage gain error 0.1 % max (SBOS547B) and a ±1 % current-sense resistor (ours: the common tolerance);
  // a datasheet maximum is read as 3σ (ours). 1σ, fraction, per flight.
  double current_gain_sigma = 0.0033;
  // Shunt offset voltage ±10 µV max (SBOS547B) over the shunt, read as 3σ: V per flight, 1σ.
  double shunt_offset_sigma_v = 10e-6 / 3.0;
  // V, 1σ per sample: one LSB of the shunt voltage, 2.5 µV (SBOS547B). Ours: the ADC's input noise taken as one LSB,
  // above the quantisation's LSB / √12.
  double shunt_noise_v = 2.5e-6;
  // Bus voltage: offset ±7.5 mV max, gain error 0.1 % max (SBOS547B), each read as 3σ, per flight; noise one LSB of
  // 1.25 mV per sample.
  double bus_offset_sigma_v = 7.5e-3 / 3.0;
  double bus_gain_sigma = 0.001 / 3.0;
  double bus_noise_v = 1.25e-3;
  // ---- vibration (IMU) ----
  // m/s², 1σ per 200 Hz sample of the specific force along z_B: ArduPilot's "normal" vibration, the standard
  // deviation of the raw accelerometer below 15 m/s² ("Measuring Vibration", ardupilot.org/copter/docs/
  // common-measuring-vibration.html), through PX4's default accelerometer low-pass IMU_ACCEL_CUTOFF = 30 Hz
  // (second order) at the rotors' once-per-revolution frequency in hover (the imbalance line, CalcVibrationNoise).
  double vibration_raw_accel_sigma = 15.0;  // m/s², raw (ArduPilot, above)
  double accel_cutoff_hz = 30.0;            // PX4 IMU_ACCEL_CUTOFF default
  double gyro_cutoff_hz = 40.0;             // PX4 IMU_GYRO_CUTOFF default
  // The gyro's vibration (ours, derived): the imbalance force F = m σ_a that shakes the body at σ_a acts at the arm
  // length L (models/mixer.h), a torque F L whose angular acceleration m σ_a L / I_xx at the rotor frequency f is
  // an angular rate of 1σ m σ_a L / (I_xx 2π f), through PX4's gyro low-pass IMU_GYRO_CUTOFF = 40 Hz.
  // ---- spall indicator (1 Hz) ----
  // Ours: one false alarm per hour of flight (P per 1 Hz epoch) and a spall at its initial size seen at one epoch in
  // two (a weak signature, §3.4.1's 0.1 mm² initial area).
  double spall_false_positive = 1.0 / 3600.0;
  double spall_miss = 0.5;
  bool IsValid(std::string* error) const;
  bool operator==(const SensingParams&) const = default;
};

// 1σ of a second-order Butterworth low-pass's output for white input of 1σ `raw_sigma` concentrated at `frequency_hz`:
// raw_sigma / sqrt(1 + (f / f_c)^4).
double CalcLowPassedSigma(double raw_sigma, double frequency_hz, double cutoff_hz);

// The vibration noise the IMM sees per sample at a hover rotor speed (rad/s): {gyro rad/s, accelerometer m/s²}.
struct VibrationNoise {
  double gyro_sigma = 0.0;   // rad/s
  double accel_sigma = 0.0;  // m/s²
};
// `mass_kg`, `inertia_xx` (kg m²) and `arm_length_m` of the airframe.
VibrationNoise CalcVibrationNoise(const SensingParams& params, double hover_rotor_speed, double mass_kg,
                                  double inertia_xx, double arm_length_m);

// The power module's per-flight errors, drawn once at take-off.
struct PowerSensorErrors {
  double current_gain = 0.0;      // fraction
  double current_offset_a = 0.0;  // A
  double bus_gain = 0.0;          // fraction
  double bus_offset_v = 0.0;      // V
  bool operator==(const PowerSensorErrors&) const = default;
};
PowerSensorErrors DrawPowerSensorErrors(const SensingParams& params, RandomStream& random);

// One reading of the current (A) and the bus voltage (V): truth × (1 + gain) + offset + noise.
double ReadCurrent(const SensingParams& params, const PowerSensorErrors& errors, double current_a,
                   RandomStream& random);
double ReadBusVoltage(const SensingParams& params, const PowerSensorErrors& errors, double bus_voltage_v,
                      RandomStream& random);

// What the CMA has read of the power system (a part of PowerState): the errors, the coulomb count's error and the
// energy and load it reads. Only used with noisy sensing.
struct PowerSensing {
  RandomStream random;
  PowerSensorErrors errors;
  double initial_soc_error = 0.0;    // the SOC from the rest voltage read before take-off, less the truth
  double charge_error_as = 0.0;      // ∫ (I_read − I) dt since take-off, A·s
  double energy_wh = 0.0;            // ∫ V_read I_read dt
  double load_current_a = 0.0;       // I_read low-passed (the filter of docs/modelling-choices.md#pack-eod)
  double bus_voltage_v = 0.0;        // the last reading
  double charge_read_as = 0.0;       // ∫ I_read dt since take-off
  double rest_voltage_v = 0.0;       // the bus voltage read at rest before take-off
  double ocv_slope_v_per_soc = 0.0;  // dOCV/dz of a cell at the initial SOC (what the reading went through)
  bool operator==(const PowerSensing&) const = default;
};

// The SOC error of the CMA's estimate, common to every cell: the initial error less the counted charge error shared
// by the two branches, each of three cells of capacity `cell_capacity_as` (ours: the split is unknown to a pack-level
// sensor; an even split).
double SocEstimateError(const PowerSensing& sensing, double cell_capacity_as);

// 1σ of that error after `elapsed_s` at a mean pack current `mean_current_a`, from the settings alone: the rest
// voltage's error through the OCV slope `ocv_slope_v_per_soc` (dOCV/dz at the initial SOC), the current's gain and
// offset (correlated over the flight) and its white noise (averaging out as √t), with `sample_dt_s` the reading
// interval. What eoddist's EodUncertainty::soc_sigma takes under noisy sensing.
double CalcSocEstimateSigma(const SensingParams& params, double elapsed_s, double mean_current_a,
                            double cell_capacity_as, double ocv_slope_v_per_soc, double sample_dt_s,
                            double initial_bus_voltage_v);

// The spall indicator's reading at one epoch.
bool ReadSpallIndicator(const SensingParams& params, bool spall_present, RandomStream& random);

// ---- the motor-health belief ----------------------------------------------------------------------------------
// A Bayes filter of P(spall present) from the indicator's readings: predict with the onset hazard of the epoch (the
// probability that a spall starts in it given none before), then update with the reading's likelihood.
double PredictSpallProbability(double p_spall, double onset_hazard);
double UpdateSpallProbability(double p_spall, bool reading, double false_positive, double miss);
// The onset hazard at flight time t (s) of §5.4's fault model: a spall in a flight with probability
// `fault_probability`, its onset uniform over the nominal plan's duration T: h = (p / T) Δt / (1 − p t / T), Δt the
// epoch; 0 after T.
double SpallOnsetHazard(double fault_probability, double plan_duration_s, double time_s, double epoch_s);

// b(NF, SF, JF): JF from the IMM (1 once a rotor is isolated, else 1 − P(nominal mode)), the rest shared between NF
// and SF by the spall filter.
std::array<double, 3> MotorHealthBelief(double p_spall, double p_jammed);

}  // namespace uascma::sim
