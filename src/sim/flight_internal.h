#pragma once
// What the GNC step (flight.cc), the initial state (initial_state.cc), the decision epoch (epoch.cc), the executor
// (act.cc) and the result (simulator.cc) of the kernel share; not part of the API.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include "uascma/prognostics/eod.h"
#include "uascma/sim/flight.h"

namespace uascma::sim::internal {

// Independent random streams of one flight (common/random.h DeriveSeed), so that e.g. the wind does not
// change when the sensor noise is switched off.
// Streams 5-7 are drawn only with SimOptions::noisy_sensing (sim/sensing.h), stream 8 only when the vehicle-level
// prognosis is read (sim/epoch.cc), stream 9 only by a connector pack fault (models/pack_fault.h, from the scenario's
// seed).
enum Stream : std::uint64_t {
  kWindStream = 1,
  kSensorStream = 2,
  kSpallStream = 3,
  kPrognosisStream = 4,
  kVibrationStream = 5,
  kPowerSensingStream = 6,
  kSpallIndicatorStream = 7,
  kVehiclePrognosisStream = 8,
  kPackFaultSeedStream = 9
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

// N: what the active rotors can give together at the present bus voltage (the LQR's thrust priority, gnc/lqr.h).
inline double MaxCollectiveThrust(const FlightModel& model, const FlightState& state) {
  return ActiveRotors(state) * ThrustCap(model, state.power.bus_voltage_v);
}

// ---- what the decision epoch (epoch.cc) and the executor (act.cc) share; defined in epoch.cc ------------------------
// The executed action into the state (and the log's actions).
void AddAction(FlightState& state, FlightLog* log, decision::CmaAction action);
// A new executing plan: the forecast's profile is rebuilt at the next epoch (its bias ratio carries on).
void StartPlan(FlightState& state);

// Where a plan made now starts (as an emergency plan does): a moving vehicle first brakes to rest at the plan's
// horizontal acceleration limit (FlightPlan::AfterBraking), and the plan starts where it stops, when the braking line
// is clear of buildings; otherwise from where it is.
struct PlanStart {
  Eigen::Vector3d p_W, v_horizontal_W, stop_W;
  double accel = 0.0;
  bool brake = false;
  Eigen::Vector3d from_W() const { return brake ? stop_W : p_W; }
  planning::FlightPlan Then(planning::FlightPlan plan) const {
    return brake ? planning::FlightPlan::AfterBraking(p_W, v_horizontal_W, accel, plan) : plan;
  }
};

PlanStart StartFromHere(const FlightModel& model, const FlightState& state);

// Re-plans the executing plan's rest at the capped speed, starting as an emergency plan does (StartFromHere). True
// when a plan was made.
bool ReplanCapped(const FlightModel& model, FlightState& state, planning::FlightPlan& out);

// The pack state the CMA's EOD starts from: the truth, or under noisy sensing the truth with every cell's SOC moved by
// the estimate's error (sim/sensing.h).
models::PackState SensedPack(const FlightModel& model, const FlightState& state);

// The options of every EOD the CMA reads at this epoch (the state's, an emergency plan's, the quadcopter's): the
// cut-off raised by the sag of the flight's current peaks, ΔI_peak of the load forecast
// (prognostics/eod_peak.h, docs/modelling-choices.md#eod-peak-sag), at the EOD's constant current `current_a` from
// `pack`. Under SimOptions::eod_load present (the dissertation's constant-current EOD), the plain cut-off.
prognostics::EodOptions EpochEodOptions(const FlightModel& model, const FlightState& state,
                                        const models::PackState& pack, double current_a);

// ---- the epoch's EOD as a value or a bound (sim/eod_precision.h); defined in eod_precision.cc -----------------------
// t_remaining + t_sf: what the EOD must cover for RM ≥ 0 (docs/modelling-choices.md#margins).
double NeededS(const FlightModel& model, const DecisionInputs& inputs);
// The epoch's EOD into DecisionState::eod and DecisionInputs::eod: an EodValue, or, empty (no crossing before
// t_remaining + t_sf, prognostics::CalcPackEodBefore), an EodLowerBound at t_remaining + t_sf (RM 0: RM1).
void StoreEod(const FlightModel& model, FlightState& state, const std::optional<prognostics::EodResult>& eod);

}  // namespace uascma::sim::internal
