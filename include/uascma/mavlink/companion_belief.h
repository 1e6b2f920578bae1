#pragma once
// What `uascma companion` knows of the vehicle: the telemetry of one decision epoch read off the MAVLink link
// (TelemetryReader), and the companion's belief of the flight built from it (VehicleBelief), a sim::FlightState that
// the kernel's own 1 Hz functions read: sim::Observe (EOD at the load forecast, the RUL prognosis, the margins, the
// abstract CMA state, the speed cap after an isolation) and sim::Act (the emergency planners and the executor's
// checks). The CMA is not implemented twice: only the belief's inputs come from the link instead of the simulator
// (docs/mavlink.md#the-cma-as-a-companion).
//
// The belief, part by part (docs/modelling-choices.md#companion-belief):
//   clock      time_boot_ms of SYSTEM_TIME (the autopilot's clock since take-off);
//   vehicle    LOCAL_POSITION_NED (p_WB_W, v_WB_W; W = NED), ATTITUDE (R_WB from roll, pitch, yaw), airborne
//              latched from EXTENDED_SYS_STATE in air; the random streams of sim::MakeInitialState at the scenario's
//              seed, so the prognosis draws its particles as the in-process CMA draws them;
//   power      the pack model of the scenario (its resting state at the scenario's charge) stepped with the
//              measured pack current between epochs (trapezoid), each cell's SOC then set from the pack's coulomb
//              counter (BATTERY_STATUS current_consumed); SYS_STATUS's bus voltage and current; the energy drawn from
//              NAMED_VALUE_FLOAT "energy_wh" when the autopilot sends it, else the trapezoid of V_bus I between epochs;
//   faults     a spall from the first epoch NAMED_VALUE_FLOAT spall_mm2 > 0 (the spall indicator, §2.3); the rotor
//              ESC_INFO flags failed as the isolated one (the allocation flies around it);
//   decision, guidance   the companion's own: the nominal plan of the scenario, then the emergency plan it commanded.
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "uascma/mavlink/codec.h"
#include "uascma/sim/flight.h"

namespace uascma::mavlink {

// One epoch's telemetry, SI units. Each group remembers the autopilot time (s) of its last update: a message with
// its own time stamp gives it; one without (BATTERY_STATUS, SYS_STATUS, EXTENDED_SYS_STATE, ESC_INFO) takes that
// of the SYSTEM_TIME received before it.
struct TelemetrySample {
  double time_s = -1.0;  // SYSTEM_TIME time_boot_ms
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero(), v_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d euler = Eigen::Vector3d::Zero();  // roll, pitch, yaw (rad)
  bool in_air = false;
  double bus_voltage_v = 0.0, pack_current_a = 0.0;
  std::array<double, 2> consumed_mah{};  // per pack, BATTERY_STATUS id 0 and 1
  int failed_rotor = 0;                  // 1..6 from ESC_INFO failure flags, 0: none
  double spall_mm2 = 0.0;
  double energy_wh = 0.0;  // NAMED_VALUE_FLOAT "energy_wh", optional: the energy drawn since take-off
  // Autopilot time (s) of each group's last update; −1: never.
  double position_s = -1, attitude_s = -1, landed_s = -1, power_s = -1, esc_s = -1, spall_s = -1;
  std::array<double, 2> battery_s{-1.0, -1.0};
  double energy_s = -1;  // optional: not among the groups the decision needs
  // The oldest update among the groups the decision needs (all of the above but energy_s); −1 while one was never
  // received.
  double OldestS() const;
};

// Folds frames from one vehicle (`vehicle`: its system id; component 1) into the sample.
class TelemetryReader {
 public:
  explicit TelemetryReader(std::uint8_t vehicle_system_id) : vehicle_(vehicle_system_id) {}
  // True when the frame was the vehicle's telemetry (and so may complete the epoch).
  bool Read(const Frame& frame);
  const TelemetrySample& sample() const { return sample_; }
  // True when every group was updated at the latest SYSTEM_TIME: the epoch is complete.
  bool Complete() const { return sample_.time_s >= 0.0 && sample_.OldestS() >= sample_.time_s; }

 private:
  std::uint8_t vehicle_;
  TelemetrySample sample_;
};

class VehicleBelief {
 public:
  // `model`: the scenario the companion was given (vehicle, battery, map, plan, options); must outlive the belief.
  explicit VehicleBelief(const sim::FlightModel& model);
  // The belief at the sample's epoch (the sample must be later than the last one).
  void Update(const TelemetrySample& sample);
  // The model from now on (the vehicle's downloaded mission's: its plan; the vehicle, battery and options are the
  // same scenario's); the belief's state is kept. `model` must outlive the belief.
  void UseModel(const sim::FlightModel& model) { model_ = &model; }
  sim::FlightState& state() { return state_; }
  const sim::FlightState& state() const { return state_; }

 private:
  const sim::FlightModel* model_;
  sim::FlightState state_;
  models::PerCell<double> initial_soc_{};  // each cell's SOC at take-off (the scenario's charge)
  std::optional<TelemetrySample> last_;
};

}  // namespace uascma::mavlink
