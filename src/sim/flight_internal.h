#pragma once
// What the GNC step (flight.cc) and the decision epoch (epoch.cc) of the kernel share; not part of the API.
#include <algorithm>
#include <string>
#include <utility>

#include "uascma/sim/flight.h"

namespace uascma::sim::internal {

inline void AddEvent(FlightLog* log, double time_s, std::string what) {
  if (log) log->events.push_back({time_s, std::move(what)});
}

// N per rotor: the bus voltage caps each rotor's thrust, capacity ∝ (V_bus / V_ref)² below V_ref.
inline double ThrustCap(const FlightModel& model, double bus_voltage_v) {
  const double voltage_ratio = std::min(1.0, bus_voltage_v / model.options().reference_bus_voltage_v);
  return model.propulsion().max_thrust * voltage_ratio * voltage_ratio;
}

}  // namespace uascma::sim::internal
