#pragma once
// `uascma companion`: the CMA as an onboard companion on an autopilot's MAVLink link (the dissertation's future work,
// §5.6, §6.2: the CMA beside PX4 or ArduPilot). At each epoch of the autopilot's telemetry (once its messages of one
// SYSTEM_TIME are all in, companion_belief.h) it updates its belief of the flight, runs the kernel's 1 Hz CMA on it
// (sim::Observe: EOD, RUL, margins, the abstract state; the policy's Decide; sim::Act: the emergency planners and the
// executor's checks) and acts through MAVLink:
//   LandASAP   COMMAND_INT DO_REPOSITION to the chosen site (latitude, longitude, the site's altitude), then
//              COMMAND_LONG NAV_LAND;
//   LandPract  the planner's path uploaded as a mission (MISSION_ITEM_INT NAV_WAYPOINT … NAV_LAND at the site,
//              MAV_FRAME_GLOBAL_RELATIVE_ALT_INT), then COMMAND_LONG MISSION_START;
//   Terminate  COMMAND_LONG DO_FLIGHTTERMINATION, only with CompanionOptions::allow_termination (else withheld and
//              logged).
// Each decision that is not NoOp is a STATUSTEXT ("CMA: LandPract to <site> (RM0 …)"); every epoch is a row of the
// decision log (CompanionSummary::log, written as CSV by the CLI; docs/mavlink.md#the-cma-as-a-companion).
//
// The plan it reasons about is the vehicle's mission, downloaded before take-off (MissionDownload) and read as an
// uploaded mission is (planning::MissionFromItems from HOME_POSITION, sim::FlyMissionRoute); no mission: the
// scenario's (docs/mavlink.md#what-the-companion-takes-from-where). Commands go through CommandClient (an ACK awaited,
// repeats after the timeout); one that fails, or a refused emergency mission, is said and logged, the belief returns
// to the plan the vehicle flies, and LandPract falls back to LandASAP at the next epoch
// (docs/mavlink.md#companion-commands).
//
// Staleness (docs/modelling-choices.md#companion-staleness): an epoch whose telemetry is not all in when the next
// SYSTEM_TIME arrives is decided on what is there when no group is older than kMaxStaleEpochs decision periods, and
// not decided at all otherwise (logged "stale"); with no frame from the vehicle for kLinkLostS wall seconds the
// companion ends.
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "uascma/common/bounds.h"
#include "uascma/mavlink/udp_link.h"
#include "uascma/sim/policy.h"
#include "uascma/sim/scenario.h"

namespace uascma::mavlink {

// Decision periods a telemetry group may lag the epoch it is used at (ours: the battery's coulomb counter or the
// position a second late moves the EOD by a second's draw, within one epoch; three seconds is a link in trouble).
inline constexpr int kMaxStaleEpochs = 2;
// Wall seconds without a frame from the vehicle after which the companion ends (ours: five missed HEARTBEATs).
inline constexpr double kLinkLostS = 5.0;
inline constexpr Bounds kCompanionWaitBounds{0.0, 3600.0, "s"};

struct CompanionOptions {
  std::vector<LinkAddress> links;  // udpout:HOST:PORT to reach an autopilot that listens; udp:HOST:PORT to be reached
  bool allow_termination = false;
  // Wall seconds to wait for the vehicle's first frame (0: forever).
  double wait_s = 30.0;
  // Called once the sockets are bound: e.g. to print the ports of port-0 endpoints.
  std::function<void(const UdpLink&)> on_ready;
  bool IsValid(std::string* error) const;
};

// One row of the decision log: one epoch of the vehicle's telemetry.
struct CompanionDecision {
  double time_s = 0.0;         // the autopilot's clock (SYSTEM_TIME time_boot_ms)
  std::string state;           // the abstract CMA state's label, e.g. "N,SF,M,RM1,MM1" ("" when not decided)
  std::string decided, taken;  // the policy's action and the executor's (they differ after a substitution)
  double eod_s = 0.0, rul_s = 0.0, flight_time_remaining_s = 0.0, reach_margin = 0.0, motor_margin = 0.0;
  double decision_ms = 0.0;  // wall time from the epoch's last frame to the commands sent
  std::string note;          // why not decided (stale), what was sent, or a withheld Terminate
};

struct CompanionSummary {
  std::vector<CompanionDecision> log;
  int epochs = 0, decided = 0, stale = 0, commands = 0, missions_uploaded = 0;
  int resent_commands = 0;  // sends again after a timeout (CommandClient)
  int failed_commands = 0;  // commands denied, failed or not acknowledged, and emergency missions refused
  double max_decision_ms = 0.0, mean_decision_ms = 0.0;
  std::string BriefReport() const;
};

// Runs until the vehicle lands (EXTENDED_SYS_STATE on the ground after in air), its HEARTBEAT reports the flight
// terminated, or the link is lost. `scenario`: the vehicle, battery, map and options the companion's belief and
// planners use, and the plan when the vehicle holds no mission; `policy`: the CMA policy (sim::MakePolicy's names).
CompanionSummary RunCompanion(const sim::Scenario& scenario, sim::DecisionPolicy& policy,
                              const CompanionOptions& options);

}  // namespace uascma::mavlink
