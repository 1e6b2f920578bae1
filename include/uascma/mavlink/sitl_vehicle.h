#pragma once
// The simulated hexarotor as a MAVLink v2 vehicle (`uascma sitl`): what it streams of a flight state, and what it
// does with the commands and mission messages it receives. The flight itself is the simulator's (sim/flight.h),
// stepped epoch by epoch by the caller; this class only reads the state and turns commands into requests.
//
// Telemetry, one of each message per call (the caller calls at every decision epoch, 1 Hz of simulated time):
//   HEARTBEAT (MAV_TYPE_HEXAROTOR, MAV_AUTOPILOT_GENERIC, armed flag, MAV_STATE), SYSTEM_TIME, SYS_STATUS,
//   BATTERY_STATUS per pack (id 0, 1: the three cells' voltages, the pack's current, consumed charge,
//   time_remaining = the epoch's EOD, §3.4), GLOBAL_POSITION_INT, LOCAL_POSITION_NED, ATTITUDE, HOME_POSITION,
//   EXTENDED_SYS_STATE, ESC_STATUS and ESC_INFO for rotors 1-4 and 5-6 (rpm; a jammed rotor's flag
//   ESC_FAILURE_MOTOR_STUCK once the fault detector has isolated it), MISSION_CURRENT, and NAMED_VALUE_FLOAT
//   "spall_mm2" (the spall indicator, §2.3) and "energy_wh" (the energy drawn since take-off, for a companion's load
//   forecast).
// Every timestamp is the simulated clock (time_boot_ms = simulated ms since take-off).
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "uascma/mavlink/mission_server.h"
#include "uascma/planning/map_projection.h"
#include "uascma/planning/mission_file.h"
#include "uascma/sim/flight.h"

namespace uascma::mavlink {

// What a received command asks of the flight loop. kFlyMission: MISSION_START in flight with an uploaded mission, with
// the CMA external (SitlVehicle's `external_cma`): fly the mission as the emergency plan (LandPract).
enum class VehicleRequest { kNone, kArm, kDisarm, kMissionStart, kLand, kTerminate, kFlyMission };

struct SitlCounts {
  int commands = 0;              // commands for this system, acknowledged
  int unsupported_commands = 0;  // acknowledged MAV_RESULT_UNSUPPORTED
  int foreign_commands = 0;      // commands addressed to another system: ignored, not acknowledged
};

class SitlVehicle {
 public:
  // `origin`: where W's origin is on the globe (the scenario's geo_origin; see docs/mavlink.md for the default).
  // `external_cma`: the CMA runs elsewhere (`uascma companion`) and acts through commands: DO_REPOSITION (the
  // landing site of a NAV_LAND that follows) and MISSION_START in flight (fly the uploaded mission) are then taken.
  SitlVehicle(const sim::FlightModel& model, Address self, planning::GeoPoint origin, std::uint64_t unix_start_us,
              bool external_cma = false);

  // One of each telemetry message for `state` (the log's last telemetry row gives the pack's outputs).
  void Telemetry(const sim::FlightState& state, const sim::FlightLog& log, bool armed, std::vector<Outgoing>& out);
  // STATUSTEXT for each event of the log not yet sent (severity: failures critical, the CMA's actions warning,
  // the rest info).
  void Events(const sim::FlightLog& log, std::vector<Outgoing>& out);
  // A received frame: mission protocol, COMMAND_LONG/COMMAND_INT (acknowledged). `armed` and `flying` decide
  // whether a command can be carried out now.
  VehicleRequest Handle(const Frame& frame, double wall_s, bool armed, bool flying, std::vector<Outgoing>& out);
  void Tick(double wall_s, std::vector<Outgoing>& out) { missions_.Tick(wall_s, out); }

  // The flight's model from now on (the uploaded mission's, SitlOptions::wait_for_mission); `model` must outlive the
  // vehicle. With `arrivals` (planning::MissionItemArrivals of the mission it flies) each item's MISSION_ITEM_REACHED
  // is sent with the first telemetry at or after its arrival on the plan, and MISSION_CURRENT follows.
  void UseModel(const sim::FlightModel& model, std::vector<planning::ItemArrival> arrivals = {});
  // Holds `items` as its mission (the plan it flies, for a ground station to download).
  void HoldMission(std::vector<MissionItemInt> items) { missions_.Load(std::move(items)); }
  // Waiting on the ground for a mission (SitlOptions::wait_for_mission): `check` refuses an upload the vehicle cannot
  // fly (MISSION_ACK MAV_MISSION_INVALID and a STATUSTEXT naming why), and MISSION_START / NAV_TAKEOFF without a
  // stored mission is denied (COMMAND_ACK MAV_RESULT_DENIED and a STATUSTEXT).
  void RequireMission(MissionServer::Check check) {
    missions_.set_check(std::move(check));
    mission_required_ = true;
  }
  // A STATUSTEXT of any length, in chunks of 50 bytes (MAVLink 2's id and chunk_seq), severity `severity`.
  void Say(std::uint8_t severity, const std::string& text, std::vector<Outgoing>& out);

  const MissionServer& missions() const { return missions_; }
  // The last DO_REPOSITION's point in W (NED, m), taken by the NAV_LAND that lands there: empty afterwards, and
  // without one.
  std::optional<Eigen::Vector3d> TakeReposition() { return std::exchange(reposition_W_, std::nullopt); }
  // The uploaded mission's NAV_WAYPOINT and NAV_LAND items as waypoints in W (hold time param1 as the hover);
  // items of other commands are skipped.
  std::vector<planning::Waypoint> MissionWaypoints() const;
  const SitlCounts& counts() const { return counts_; }
  Address self() const { return self_; }

 private:
  // params 5 and 6 of a positional command are degrees (COMMAND_INT's x and y scaled by 1e-7).
  VehicleRequest OnCommand(std::uint16_t command, std::uint8_t target, const std::array<double, 7>& params,
                           Address sender, bool armed, bool flying, std::vector<Outgoing>& out);
  void Position(const sim::FlightState& state, std::uint32_t time_ms, std::vector<Outgoing>& out) const;
  void Batteries(const sim::FlightState& state, const sim::FlightLog& log, std::vector<Outgoing>& out) const;
  void Escs(const sim::FlightState& state, std::vector<Outgoing>& out) const;
  void ItemsReached(const sim::FlightState& state, std::vector<Outgoing>& out);

  const sim::FlightModel* model_;
  Address self_;
  planning::LocalProjection projection_;
  std::uint64_t unix_start_us_;
  MissionServer missions_;
  std::size_t events_sent_ = 0;
  std::uint16_t statustext_id_ = 0;
  SitlCounts counts_;
  models::PerBranch<double> initial_soc_{};  // each pack's first cell at the first Telemetry call
  bool initial_soc_known_ = false;
  bool external_cma_ = false;
  std::optional<Eigen::Vector3d> reposition_W_;
  bool mission_required_ = false;                // RequireMission
  std::vector<planning::ItemArrival> arrivals_;  // UseModel: the mission's items, in flying order
  std::size_t arrivals_sent_ = 0;
};

// Where W's origin is on the globe: the scenario's geo_origin (an imported map or mission), else 1° N, 1° E
// (docs/modelling-choices.md#mavlink-geodetic-origin: not 0°, 0°, which a mission item reserves for "where the vehicle
// is"). The vehicle and a companion given the same scenario share it.
inline planning::GeoPoint VehicleGeoOrigin(const sim::Scenario& scenario) {
  return scenario.geo_origin.value_or(planning::GeoPoint{1.0, 1.0});
}

// STATUSTEXT of at most 50 bytes (longer texts are cut at a UTF-8 character boundary: the chunked form is not used).
Statustext MakeStatustext(std::uint8_t severity, const std::string& text);
// A text of any length as STATUSTEXT chunks of `id` (chunk_seq 0, 1, …): every chunk but the last a full 50 bytes
// (a UTF-8 character may straddle two: the receiver joins the bytes), the last holding a NUL, empty when the text
// fills the one before (the common set's rule for reassembly); at most 255 chunks.
std::vector<Statustext> StatustextChunks(std::uint8_t severity, const std::string& text, std::uint16_t id);

}  // namespace uascma::mavlink
