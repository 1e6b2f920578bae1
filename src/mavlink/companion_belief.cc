#include "uascma/mavlink/companion_belief.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "uascma/common/frames.h"
#include "uascma/sim/initial_state.h"

namespace uascma::mavlink {
namespace {

constexpr double kAmpSecondsPerMah = 3.6;

}  // namespace

double TelemetrySample::OldestS() const {
  return std::min({position_s, attitude_s, landed_s, power_s, esc_s, spall_s, battery_s[0], battery_s[1]});
}

bool TelemetryReader::Read(const Frame& frame) {
  if (frame.sender.system_id != vehicle_ || frame.sender.component_id != kMavCompIdAutopilot1) return false;
  TelemetrySample& s = sample_;
  if (frame.Is<SystemTime>()) {
    s.time_s = frame.As<SystemTime>().time_boot_ms * 1e-3;
  } else if (frame.Is<LocalPositionNed>()) {
    const LocalPositionNed m = frame.As<LocalPositionNed>();
    s.p_W = Eigen::Vector3d(m.x, m.y, m.z);
    s.v_W = Eigen::Vector3d(m.vx, m.vy, m.vz);
    s.position_s = m.time_boot_ms * 1e-3;
  } else if (frame.Is<Attitude>()) {
    const Attitude m = frame.As<Attitude>();
    s.euler = Eigen::Vector3d(m.roll, m.pitch, m.yaw);
    s.attitude_s = m.time_boot_ms * 1e-3;
  } else if (frame.Is<ExtendedSysState>()) {
    s.in_air = frame.As<ExtendedSysState>().landed_state == kMavLandedStateInAir;
    s.landed_s = s.time_s;
  } else if (frame.Is<SysStatus>()) {
    const SysStatus m = frame.As<SysStatus>();
    // 0 or UINT16_MAX volts and −1 amperes: not measured (the message's own convention); the group stays old.
    if (m.voltage_battery == 0 || m.voltage_battery == UINT16_MAX || m.current_battery < 0) return true;
    s.bus_voltage_v = m.voltage_battery * 1e-3;
    s.pack_current_a = m.current_battery * 1e-2;
    s.power_s = s.time_s;
  } else if (frame.Is<BatteryStatus>()) {
    const BatteryStatus m = frame.As<BatteryStatus>();
    if (m.id >= s.consumed_mah.size()) return true;
    s.consumed_mah[m.id] = m.current_consumed;
    s.battery_s[m.id] = s.time_s;
  } else if (frame.Is<EscInfo>()) {
    const EscInfo m = frame.As<EscInfo>();
    if (m.index == 0)
      s.failed_rotor = 0;  // the first of the two messages (rotors 1-4, then 5-6) starts the epoch's flags
    for (int k = 0; k < 4 && m.index + k < 6; ++k) {
      if (m.failure_flags[k] != 0) s.failed_rotor = m.index + k + 1;
    }
    if (m.index + 4 >= m.count) s.esc_s = s.time_s;  // every rotor's flags read
  } else if (frame.Is<NamedValueFloat>()) {
    const NamedValueFloat m = frame.As<NamedValueFloat>();
    if (std::strncmp(m.name.data(), "energy_wh", m.name.size()) == 0) {
      s.energy_wh = m.value;
      s.energy_s = m.time_boot_ms * 1e-3;
      return true;
    }
    if (std::strncmp(m.name.data(), "spall_mm2", m.name.size()) != 0) return true;
    s.spall_mm2 = m.value;
    s.spall_s = m.time_boot_ms * 1e-3;
  } else {
    return false;
  }
  return true;
}

VehicleBelief::VehicleBelief(const sim::FlightModel& model)
    : model_(&model), state_(sim::MakeInitialState(model, model.scenario().seed)) {
  for (int branch = 0; branch < models::kBranchCount; ++branch) {
    for (int cell = 0; cell < models::kCellsPerBranch; ++cell) {
      initial_soc_[branch][cell] = state_.power.pack.cells[branch][cell].soc_fraction;
    }
  }
}

void VehicleBelief::Update(const TelemetrySample& sample) {
  sim::FlightState& s = state_;
  const double dt = last_ ? sample.time_s - last_->time_s : 0.0;
  s.time_s = sample.time_s;
  s.step = std::llround(sample.time_s / model_->dt());
  s.vehicle.body.p_WB_W = sample.p_W;
  s.vehicle.body.v_WB_W = sample.v_W;
  s.vehicle.body.q_WB = Eigen::Quaterniond(RotationFromEuler(sample.euler.x(), sample.euler.y(), sample.euler.z()));
  s.vehicle.airborne = s.vehicle.airborne || sample.in_air;
  // Power: the pack model stepped with the measured current (held as the trapezoid of the two epochs' readings),
  // then each cell's SOC from the coulomb counter.
  sim::PowerState& power = s.power;
  if (dt > 0.0) {
    const double current_a = 0.5 * (last_->pack_current_a + sample.pack_current_a);
    const double step_s = model_->pack_step().dt_s;
    const int steps = std::max(1, static_cast<int>(std::ceil(dt / step_s - 1e-9)));
    for (int k = 0; k < steps; ++k) power.pack = model_->pack().Step(power.pack, current_a, dt / steps);
    power.energy_wh += 0.5 *
                       (last_->bus_voltage_v * last_->pack_current_a + sample.bus_voltage_v * sample.pack_current_a) *
                       dt / 3600.0;
  }
  if (sample.energy_s == sample.time_s) power.energy_wh = sample.energy_wh;  // the autopilot's own count, when sent
  // The charge each branch has delivered: the pack model's (fine-grained, but integrated from 1 Hz readings) kept
  // within the coulomb counter's rounding, ±0.5 mAh of its reading (docs/modelling-choices.md#companion-belief).
  for (int branch = 0; branch < models::kBranchCount; ++branch) {
    const double counted_as = sample.consumed_mah[branch] * kAmpSecondsPerMah;
    const double capacity_as = model_->pack().cell(branch, 0).capacity_as();
    const double integrated_as = (initial_soc_[branch][0] - power.pack.cells[branch][0].soc_fraction) * capacity_as;
    const double drawn_as =
        std::clamp(integrated_as, counted_as - 0.5 * kAmpSecondsPerMah, counted_as + 0.5 * kAmpSecondsPerMah);
    power.branch_charge_as[branch] = drawn_as;
    for (int cell = 0; cell < models::kCellsPerBranch; ++cell) {
      power.pack.cells[branch][cell].soc_fraction =
          std::clamp(initial_soc_[branch][cell] - drawn_as / model_->pack().cell(branch, cell).capacity_as(), 0.0, 1.0);
    }
  }
  power.bus_voltage_v = sample.bus_voltage_v;
  power.pack_current_a = power.load_current_a = sample.pack_current_a;
  // Faults: the spall indicator latched; the flagged rotor as the isolated one.
  if (sample.spall_mm2 > 0.0 && !s.faults.spall) {
    s.faults.spall.emplace(model_->rul_model(), sample.time_s, 0);
    s.faults.spall_onset_s = sample.time_s;
  }
  if (sample.failed_rotor != 0 && s.faults.allocation_failure == 0) {
    s.faults.allocation_failure = sample.failed_rotor;
    s.faults.isolation_time_s = sample.time_s;
  }
  last_ = sample;
}

}  // namespace uascma::mavlink
