// The initial state of a flight (initial_state.h MakeInitialState): its random streams, the vehicle on the plan's start
// with its rotors at hover speed, the packs at rest, the IMM, and noisy sensing's errors and first readings.
#include "uascma/sim/initial_state.h"

#include <algorithm>
#include <cstdint>
#include <limits>

#include "flight_internal.h"
#include "uascma/common/frames.h"
#include "uascma/common/random.h"
#include "uascma/sim/flight.h"
#include "uascma/sim/sensing.h"

namespace uascma::sim {

using internal::kPowerSensingStream;
using internal::kPrognosisStream;
using internal::kSensorStream;
using internal::kSpallIndicatorStream;
using internal::kVibrationStream;
using internal::kWindStream;

namespace {

constexpr double kRulBeforePrognosis = std::numeric_limits<double>::infinity();

// dOCV/dz (V per unit SOC) at `soc`, by a central difference of ±0.005 (ours; the table is piecewise linear).
double OcvSlope(const models::OcvTable& ocv, double soc) {
  constexpr double kHalfStep = 0.005;
  const double lo = std::max(soc - kHalfStep, 0.0);
  const double hi = std::min(soc + kHalfStep, 1.0);
  return (ocv.CalcVoltage(hi) - ocv.CalcVoltage(lo)) / (hi - lo);
}

// Noisy sensing's streams and per-flight errors, and the SOC the CMA reads from the rest voltage before take-off
// (one bus reading over three cells, through the OCV slope at the first cell's SOC). Nothing is drawn without it.
void InitialiseSensing(const FlightModel& model, FlightState& state) {
  const std::uint64_t seed = state.vehicle.seed;
  state.vehicle.vibration_random = RandomStream(DeriveSeed(seed, kVibrationStream));
  state.power.sensing.random = RandomStream(DeriveSeed(seed, kPowerSensingStream));
  state.decision.indicator_random = RandomStream(DeriveSeed(seed, kSpallIndicatorStream));
  if (!model.options().noisy_sensing) return;
  PowerSensing& sensing = state.power.sensing;
  const SensingParams& params = model.options().sensing;
  sensing.errors = DrawPowerSensorErrors(params, sensing.random);
  const double rest_v = state.power.bus_voltage_v;
  const double read_v = ReadBusVoltage(params, sensing.errors, rest_v, sensing.random);
  const models::SelfCorrectingCell& cell = model.pack().cell(0, 0);
  const double soc = state.power.pack.cells[0][0].soc_fraction;
  sensing.ocv_slope_v_per_soc = OcvSlope(cell.ocv(), soc);
  sensing.initial_soc_error = (read_v - rest_v) / models::kCellsPerBranch / sensing.ocv_slope_v_per_soc;
  sensing.bus_voltage_v = read_v;
  sensing.rest_voltage_v = read_v;
  sensing.load_current_a = state.power.load_current_a;
}

}  // namespace

double CalcSocEstimateSigma(const FlightModel& model, const FlightState& state) {
  if (!model.options().noisy_sensing) return 0.0;
  const PowerSensing& sensing = state.power.sensing;
  const double mean_current_a = state.time_s > 0.0 ? sensing.charge_read_as / state.time_s : 0.0;
  return CalcSocEstimateSigma(model.options().sensing, state.time_s, mean_current_a,
                              model.pack().cell(0, 0).capacity_as(), sensing.ocv_slope_v_per_soc, model.dt(),
                              sensing.rest_voltage_v);
}

FlightState MakeInitialState(const FlightModel& model, std::uint64_t seed) {
  const Scenario& sc = model.scenario();
  FlightState state;
  state.vehicle.seed = seed;
  state.vehicle.wind_random = RandomStream(DeriveSeed(seed, kWindStream));
  state.vehicle.sensor_random = RandomStream(DeriveSeed(seed, kSensorStream));
  state.vehicle.prognosis_random = RandomStream(DeriveSeed(seed, kPrognosisStream));
  state.vehicle.body.p_WB_W = model.nominal_plan().start_W();
  state.vehicle.wind = model.wind().InitialState(0.0, state.vehicle.wind_random);
  state.power.pack = model.pack().MakeRestingState(sc.battery.initial_cell_voltage_v);
  state.power.pack_linear = model.pack().Linearise(state.power.pack);
  const double hover_thrust = sc.body.mass * kGravity / 6.0;
  const double hover_speed = models::CalcRotorSpeedForThrust(model.propulsion(), hover_thrust);
  state.vehicle.rotor_speed.fill(hover_speed);
  state.vehicle.believed_speed.fill(hover_speed);
  state.faults.imm = gnc::ImmFilter(sc.imm, sc.body, model.mixer().mixing_matrix(models::kNoFailedMotor));
  state.power.bus_voltage_v = model.pack().CalcOutputs(state.power.pack, 0.0).split.bus_voltage_v;
  // Until the first step has drawn real current, the 1 Hz prognosis sees the hover draw.
  state.power.pack_current_a =
      sc.options.hotel_current_a +
      6.0 * models::CalcElectricalPower(model.propulsion(), hover_thrust) / state.power.bus_voltage_v;
  state.power.load_current_a = state.power.pack_current_a;
  state.decision.inputs.rul_s = kRulBeforePrognosis;
  InitialiseSensing(model, state);
  // The lowest cell voltage starts at the pack at rest (a flight that never takes off reports it; any step under
  // load reads lower).
  state.power.min_cell_voltage_v = model.pack().CalcOutputs(state.power.pack, 0.0).min_cell_voltage_v;
  return state;
}

}  // namespace uascma::sim
