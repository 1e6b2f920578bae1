#include "uascma/mavlink/sitl_vehicle.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <tuple>

namespace uascma::mavlink {
namespace {

constexpr double kRadPerSecondToRpm = 60.0 / (2.0 * std::numbers::pi);

std::uint32_t TimeMs(double time_s) { return static_cast<std::uint32_t>(std::llround(time_s * 1000.0)); }

template <class T>
T Saturate(double value) {
  const double low = static_cast<double>(std::numeric_limits<T>::lowest());
  const double high = static_cast<double>(std::numeric_limits<T>::max());
  if (!std::isfinite(value)) return value > 0 ? std::numeric_limits<T>::max() : std::numeric_limits<T>::lowest();
  return static_cast<T>(std::llround(std::clamp(value, low, high)));
}

// Roll, pitch, yaw (ZYX, intrinsic: MAVLink's ATTITUDE convention) of R_WB, W = NED, B = FRD.
Eigen::Vector3d Euler(const Eigen::Quaterniond& q_WB) {
  const Eigen::Matrix3d R = q_WB.toRotationMatrix();
  const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  return {std::atan2(R(2, 1), R(2, 2)), pitch, std::atan2(R(1, 0), R(0, 0))};
}

std::uint8_t Severity(const std::string& event) {
  const auto has = [&](const char* word) { return event.find(word) != std::string::npos; };
  if (has("crash") || has("failed") || has("jam") || has("terminat")) return kMavSeverityCritical;
  if (has("LandPract") || has("LandASAP") || has("spall") || has("isolat")) return kMavSeverityWarning;
  return kMavSeverityInfo;
}

}  // namespace

Statustext MakeStatustext(std::uint8_t severity, const std::string& text) {
  Statustext message;
  message.severity = severity;
  std::size_t length = std::min(text.size(), message.text.size());
  // Cut at a character boundary: never inside a UTF-8 sequence (its continuation bytes are 10xxxxxx).
  while (length < text.size() && length > 0 && (static_cast<unsigned char>(text[length]) & 0xC0) == 0x80) --length;
  std::memcpy(message.text.data(), text.data(), length);
  return message;
}

std::vector<Statustext> StatustextChunks(std::uint8_t severity, const std::string& text, std::uint16_t id) {
  std::vector<Statustext> chunks;
  constexpr std::size_t kChunk = std::tuple_size_v<decltype(Statustext::text)>;  // 50 bytes
  // Every chunk but the last is full: a NUL ends the text for the receiver, so a chunk is never cut short.
  for (std::size_t begin = 0; chunks.size() < 255; begin += kChunk) {
    Statustext chunk;
    chunk.severity = severity;
    chunk.id = id;
    chunk.chunk_seq = static_cast<std::uint8_t>(chunks.size());
    const std::size_t length = std::min(kChunk, text.size() - std::min(begin, text.size()));
    std::memcpy(chunk.text.data(), text.data() + begin, length);
    chunks.push_back(chunk);
    if (length < kChunk) break;
  }
  return chunks;
}

void SitlVehicle::Say(std::uint8_t severity, const std::string& text, std::vector<Outgoing>& out) {
  for (const Statustext& chunk : StatustextChunks(severity, text, ++statustext_id_)) out.push_back(MakeOutgoing(chunk));
}

void SitlVehicle::UseModel(const sim::FlightModel& model, std::vector<planning::ItemArrival> arrivals) {
  model_ = &model;
  arrivals_ = std::move(arrivals);
  arrivals_sent_ = 0;
}

void SitlVehicle::ItemsReached(const sim::FlightState& state, std::vector<Outgoing>& out) {
  if (arrivals_.empty() || state.guidance.on_emergency_plan) return;
  // At the mission's end (landed where it ends) every item is reached, whatever the touchdown's instant.
  const bool completed = state.outcome == sim::Outcome::kCompleted;
  const double elapsed_s = state.original_plan_elapsed_s();
  for (; arrivals_sent_ < arrivals_.size() && (completed || arrivals_[arrivals_sent_].time_s <= elapsed_s);
       ++arrivals_sent_) {
    MissionItemReached reached;
    reached.seq = static_cast<std::uint16_t>(arrivals_[arrivals_sent_].item_number - 1);
    out.push_back(MakeOutgoing(reached));
  }
  if (arrivals_sent_ < arrivals_.size()) {
    missions_.set_current(static_cast<std::uint16_t>(arrivals_[arrivals_sent_].item_number - 1));
  }
}

SitlVehicle::SitlVehicle(const sim::FlightModel& model, Address self, planning::GeoPoint origin,
                         std::uint64_t unix_start_us, bool external_cma)
    : model_(&model),
      self_(self),
      projection_(origin),
      unix_start_us_(unix_start_us),
      missions_(self),
      external_cma_(external_cma) {}

std::vector<planning::Waypoint> SitlVehicle::MissionWaypoints() const {
  std::vector<planning::Waypoint> waypoints;
  for (const MissionItemInt& item : missions_.items()) {
    if (item.command != kMavCmdNavWaypoint && item.command != kMavCmdNavLand) continue;
    planning::Waypoint waypoint;
    const Eigen::Vector2d p_NE = projection_.ToLocal({item.x * 1e-7, item.y * 1e-7});
    waypoint.p_W = Eigen::Vector3d(p_NE.x(), p_NE.y(), -static_cast<double>(item.z));
    if (item.command == kMavCmdNavWaypoint) waypoint.hover_after_s = std::max(0.0, static_cast<double>(item.param1));
    waypoints.push_back(waypoint);
  }
  return waypoints;
}

void SitlVehicle::Position(const sim::FlightState& state, std::uint32_t time_ms, std::vector<Outgoing>& out) const {
  const models::RigidBodyState& body = state.vehicle.body;
  const Eigen::Vector3d euler = Euler(body.q_WB);
  const planning::GeoPoint geo = projection_.ToGeodetic(body.p_WB_W.head<2>());
  GlobalPositionInt global;
  global.time_boot_ms = time_ms;
  global.lat = Saturate<std::int32_t>(geo.lat_deg * 1e7);
  global.lon = Saturate<std::int32_t>(geo.lon_deg * 1e7);
  global.alt = Saturate<std::int32_t>(-body.p_WB_W.z() * 1000.0);  // above the origin's ground (W is NED)
  global.relative_alt = global.alt;
  global.vx = Saturate<std::int16_t>(body.v_WB_W.x() * 100.0);
  global.vy = Saturate<std::int16_t>(body.v_WB_W.y() * 100.0);
  global.vz = Saturate<std::int16_t>(body.v_WB_W.z() * 100.0);
  const double heading_deg = std::fmod(euler.z() * 180.0 / std::numbers::pi + 360.0, 360.0);
  global.hdg = Saturate<std::uint16_t>(std::min(heading_deg * 100.0, 35999.0));
  out.push_back(MakeOutgoing(global));
  LocalPositionNed local;
  local.time_boot_ms = time_ms;
  local.x = static_cast<float>(body.p_WB_W.x());
  local.y = static_cast<float>(body.p_WB_W.y());
  local.z = static_cast<float>(body.p_WB_W.z());
  local.vx = static_cast<float>(body.v_WB_W.x());
  local.vy = static_cast<float>(body.v_WB_W.y());
  local.vz = static_cast<float>(body.v_WB_W.z());
  out.push_back(MakeOutgoing(local));
  Attitude attitude;
  attitude.time_boot_ms = time_ms;
  attitude.roll = static_cast<float>(euler.x());
  attitude.pitch = static_cast<float>(euler.y());
  attitude.yaw = static_cast<float>(euler.z());
  attitude.rollspeed = static_cast<float>(body.w_WB_B.x());
  attitude.pitchspeed = static_cast<float>(body.w_WB_B.y());
  attitude.yawspeed = static_cast<float>(body.w_WB_B.z());
  out.push_back(MakeOutgoing(attitude));
}

void SitlVehicle::Batteries(const sim::FlightState& state, const sim::FlightLog& log,
                            std::vector<Outgoing>& out) const {
  const sim::TelemetryRow* row = log.telemetry.empty() ? nullptr : &log.telemetry.back();
  for (int pack = 0; pack < models::kBranchCount; ++pack) {
    BatteryStatus battery;
    battery.id = static_cast<std::uint8_t>(pack);
    battery.battery_function = static_cast<std::uint8_t>(kMavBatteryFunctionAll);
    battery.type = static_cast<std::uint8_t>(kMavBatteryTypeLipo);
    battery.temperature = std::numeric_limits<std::int16_t>::max();  // not modelled as a state: unknown
    battery.voltages.fill(std::numeric_limits<std::uint16_t>::max());
    battery.voltages_ext.fill(0);
    for (int cell = 0; cell < models::kCellsPerBranch; ++cell) {
      const double v = row ? row->cell_voltage[pack * models::kCellsPerBranch + cell] : 0.0;
      battery.voltages[cell] = Saturate<std::uint16_t>(v * 1000.0);
    }
    battery.current_battery = row ? Saturate<std::int16_t>(row->branch_current[pack] * 100.0) : -1;
    // Charge drawn: (z0 − z) Q of the pack's first cell (the cells of a pack are in series, η_discharge = 1,
    // Table 3.1), from a full charge at the state's initial SOC.
    const models::SelfCorrectingCell& cell = model_->pack().cell(pack, 0);
    const double soc = state.power.pack.cells[pack][0].soc_fraction;
    const double initial = initial_soc_[pack];
    battery.current_consumed = Saturate<std::int32_t>((initial - soc) * cell.capacity_as() / 3.6);
    battery.energy_consumed = -1;
    battery.battery_remaining = Saturate<std::int8_t>(std::clamp(soc, 0.0, 1.0) * 100.0);
    battery.time_remaining = Saturate<std::int32_t>(sim::EodAtLeastS(state.decision.inputs.eod));
    const bool cut_off = row && row->cell_voltage[pack * models::kCellsPerBranch] <= models::kCutoffVoltage;
    battery.charge_state = static_cast<std::uint8_t>(cut_off ? kMavBatteryChargeStateFailed
                                                             : kMavBatteryChargeStateOk);
    out.push_back(MakeOutgoing(battery));
  }
}

void SitlVehicle::Escs(const sim::FlightState& state, std::vector<Outgoing>& out) const {
  const std::uint64_t time_us = static_cast<std::uint64_t>(std::llround(state.time_s * 1e6));
  for (int first = 0; first < 6; first += 4) {
    EscStatus status;
    status.index = static_cast<std::uint8_t>(first);
    status.time_usec = time_us;
    EscInfo info;
    info.index = static_cast<std::uint8_t>(first);
    info.time_usec = time_us;
    info.count = 6;
    info.connection_type = static_cast<std::uint8_t>(kEscConnectionTypePpm);
    info.temperature.fill(std::numeric_limits<std::int16_t>::max());
    for (int k = 0; k < 4 && first + k < 6; ++k) {
      status.rpm[k] = Saturate<std::int32_t>(state.vehicle.rotor_speed[first + k] * kRadPerSecondToRpm);
      info.info = static_cast<std::uint8_t>(info.info | (1u << k));
      if (state.faults.allocation_failure == first + k + 1) info.failure_flags[k] = kEscFailureMotorStuck;
    }
    out.push_back(MakeOutgoing(status));
    out.push_back(MakeOutgoing(info));
  }
}

void SitlVehicle::Telemetry(const sim::FlightState& state, const sim::FlightLog& log, bool armed,
                            std::vector<Outgoing>& out) {
  const std::uint32_t time_ms = TimeMs(state.time_s);
  if (!initial_soc_known_) {
    for (int pack = 0; pack < models::kBranchCount; ++pack) initial_soc_[pack] = state.power.pack.cells[pack][0].soc_fraction;
    initial_soc_known_ = true;
  }
  Heartbeat heartbeat;
  heartbeat.type = kMavTypeHexarotor;
  heartbeat.autopilot = kMavAutopilotGeneric;
  heartbeat.base_mode = static_cast<std::uint8_t>((armed ? kMavModeFlagSafetyArmed : 0) | kMavModeFlagAutoEnabled);
  heartbeat.system_status = static_cast<std::uint8_t>(
      state.done() ? kMavStateStandby : (state.faults.spall_onset_s ? kMavStateCritical : kMavStateActive));
  if (state.outcome == sim::Outcome::kTerminated) heartbeat.system_status = kMavStateFlightTermination;
  out.push_back(MakeOutgoing(heartbeat));
  SystemTime time;
  time.time_unix_usec = unix_start_us_ + static_cast<std::uint64_t>(std::llround(state.time_s * 1e6));
  time.time_boot_ms = time_ms;
  out.push_back(MakeOutgoing(time));
  SysStatus status;
  const sim::TelemetryRow* row = log.telemetry.empty() ? nullptr : &log.telemetry.back();
  // The bus voltage and pack current of the state at the epoch (what the CMA's load forecast reads, sim::Observe),
  // not the last GNC step's row: its voltage differs by millivolts, a few hundredths of a second of EOD.
  status.voltage_battery = row ? Saturate<std::uint16_t>(state.power.bus_voltage_v * 1000.0) : 0;
  status.current_battery = row ? Saturate<std::int16_t>(state.power.pack_current_a * 100.0) : -1;
  status.battery_remaining = -1;
  out.push_back(MakeOutgoing(status));
  Batteries(state, log, out);
  Position(state, time_ms, out);
  HomePosition home;
  const Eigen::Vector3d home_W = model_->nominal_plan().start_W();
  const planning::GeoPoint home_geo = projection_.ToGeodetic(home_W.head<2>());
  home.latitude = Saturate<std::int32_t>(home_geo.lat_deg * 1e7);
  home.longitude = Saturate<std::int32_t>(home_geo.lon_deg * 1e7);
  home.x = static_cast<float>(home_W.x());
  home.y = static_cast<float>(home_W.y());
  home.q = {1.0f, 0.0f, 0.0f, 0.0f};
  home.time_usec = static_cast<std::uint64_t>(std::llround(state.time_s * 1e6));
  out.push_back(MakeOutgoing(home));
  ExtendedSysState extended;
  extended.landed_state = static_cast<std::uint8_t>(
      state.vehicle.airborne && !state.done() ? kMavLandedStateInAir : kMavLandedStateOnGround);
  out.push_back(MakeOutgoing(extended));
  Escs(state, out);
  ItemsReached(state, out);
  MissionCurrent current;
  current.seq = missions_.current();
  current.total = static_cast<std::uint16_t>(missions_.items().size());
  current.mission_state = static_cast<std::uint8_t>(missions_.items().empty() ? kMissionStateNoMission
                                                    : state.done()           ? kMissionStateComplete
                                                                             : kMissionStateActive);
  out.push_back(MakeOutgoing(current));
  // The energy drawn from the packs since take-off at float precision (docs/modelling-choices.md#companion-belief:
  // BATTERY_STATUS energy_consumed's hectojoules are a third of one epoch's draw).
  NamedValueFloat energy;
  energy.time_boot_ms = time_ms;
  std::memcpy(energy.name.data(), "energy_wh", 9);
  energy.value = static_cast<float>(state.power.energy_wh);
  out.push_back(MakeOutgoing(energy));
  NamedValueFloat spall;
  spall.time_boot_ms = time_ms;
  std::memcpy(spall.name.data(), "spall_mm2", 9);
  spall.value = row ? static_cast<float>(row->spall_area_mm2) : 0.0f;
  out.push_back(MakeOutgoing(spall));
}

void SitlVehicle::Events(const sim::FlightLog& log, std::vector<Outgoing>& out) {
  for (; events_sent_ < log.events.size(); ++events_sent_) {
    const sim::FlightEvent& event = log.events[events_sent_];
    Statustext text = MakeStatustext(Severity(event.what), event.what);
    text.id = ++statustext_id_;
    out.push_back(MakeOutgoing(text));
  }
}

VehicleRequest SitlVehicle::OnCommand(std::uint16_t command, std::uint8_t target, const std::array<double, 7>& params,
                                      Address sender, bool armed, bool flying, std::vector<Outgoing>& out) {
  if (target != self_.system_id && target != 0) {
    ++counts_.foreign_commands;
    return VehicleRequest::kNone;
  }
  ++counts_.commands;
  VehicleRequest request = VehicleRequest::kNone;
  std::uint8_t result = kMavResultAccepted;
  switch (command) {
    case kMavCmdComponentArmDisarm:
      if (params[0] > 0.5) {
        request = VehicleRequest::kArm;
      } else if (flying && params[1] != 21196.0) {  // 21196: the force-disarm magic of the command's param 2
        result = kMavResultDenied;
      } else {
        request = VehicleRequest::kDisarm;
      }
      break;
    case kMavCmdMissionStart:
    case kMavCmdNavTakeoff:
      if (!armed) {
        result = kMavResultDenied;
        if (mission_required_) Say(kMavSeverityError, "start denied: not armed", out);
      } else if (mission_required_ && !flying && missions_.items().empty()) {
        result = kMavResultDenied;
        Say(kMavSeverityError, "start denied: no mission uploaded (a flyable one is stored at MISSION_ACK)", out);
      } else if (external_cma_ && flying && command == kMavCmdMissionStart && missions_.counts().uploads > 0 &&
                 !MissionWaypoints().empty())
        request = VehicleRequest::kFlyMission;
      else request = VehicleRequest::kMissionStart;
      break;
    case kMavCmdDoReposition:  // params 5-7: latitude, longitude (degrees), altitude (m, relative to home)
      if (!external_cma_) {
        result = kMavResultUnsupported;
        ++counts_.unsupported_commands;
      } else if (!flying || !std::isfinite(params[4]) || !std::isfinite(params[5]) || !std::isfinite(params[6])) {
        result = kMavResultDenied;
      } else {
        const Eigen::Vector2d p_NE = projection_.ToLocal({params[4], params[5]});
        reposition_W_ = Eigen::Vector3d(p_NE.x(), p_NE.y(), -params[6]);
      }
      break;
    case kMavCmdNavLand:
      if (!flying) result = kMavResultDenied;
      else request = VehicleRequest::kLand;
      break;
    case kMavCmdDoFlighttermination:
      if (params[0] <= 0.5 || !flying) result = kMavResultDenied;
      else request = VehicleRequest::kTerminate;
      break;
    default:
      result = kMavResultUnsupported;
      ++counts_.unsupported_commands;
  }
  CommandAck ack;
  ack.command = command;
  ack.result = result;
  ack.target_system = sender.system_id;
  ack.target_component = sender.component_id;
  out.push_back(MakeOutgoing(ack));
  return request;
}

VehicleRequest SitlVehicle::Handle(const Frame& frame, double wall_s, bool armed, bool flying,
                                   std::vector<Outgoing>& out) {
  if (frame.Is<CommandLong>()) {
    const CommandLong c = frame.As<CommandLong>();
    return OnCommand(c.command, c.target_system, {c.param1, c.param2, c.param3, c.param4, c.param5, c.param6, c.param7},
                     frame.sender, armed, flying, out);
  }
  if (frame.Is<CommandInt>()) {
    const CommandInt c = frame.As<CommandInt>();
    return OnCommand(c.command, c.target_system, {c.param1, c.param2, c.param3, c.param4, c.x * 1e-7, c.y * 1e-7, c.z},
                     frame.sender, armed, flying, out);
  }
  missions_.Handle(frame, wall_s, out);
  if (const std::optional<std::string> why = missions_.TakeRefusal())
    Say(kMavSeverityError, "mission refused: " + *why, out);
  return VehicleRequest::kNone;
}

}  // namespace uascma::mavlink
