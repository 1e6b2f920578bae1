#pragma once
// What the GNC step (flight.cc), the initial state (initial_state.cc), the decision epoch (epoch.cc) and the result
// (simulator.cc) of the kernel share; not part of the API.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <string>
#include <utility>

#include "uascma/sim/flight.h"

namespace uascma::sim::internal {

// Independent random streams of one flight (common/random.h DeriveSeed), so that e.g. the wind does not
// change when the sensor noise is switched off.
// Streams 5-7 are drawn only with SimOptions::noisy_sensing (sim/sensing.h).
enum Stream : std::uint64_t {
  kWindStream = 1,
  kSensorStream = 2,
  kSpallStream = 3,
  kPrognosisStream = 4,
  kVibrationStream = 5,
  kPowerSensingStream = 6,
  kSpallIndicatorStream = 7
};

// Wall-clock seconds since `start` (steady clock): the results' wall_time_s and their shares between flights.
inline double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

inline void AddEvent(FlightLog* log, double time_s, std::string what) {
  if (log) log->events.push_back({time_s, std::move(what)});
}

// N per rotor: the bus voltage caps each rotor's thrust, capacity ∝ (V_bus / V_ref)² below V_ref.
inline double ThrustCap(const FlightModel& model, double bus_voltage_v) {
  const double voltage_ratio = std::min(1.0, bus_voltage_v / model.options().reference_bus_voltage_v);
  return model.propulsion().max_thrust * voltage_ratio * voltage_ratio;
}

// Rotors the allocation flies: six, or four after the failure rule
// (docs/modelling-choices.md#mixing-after-motor-failure).
inline int ActiveRotors(const FlightState& state) {
  return state.faults.allocation_failure != models::kNoFailedMotor ? models::kRotorCount - 2 : models::kRotorCount;
}

}  // namespace uascma::sim::internal
