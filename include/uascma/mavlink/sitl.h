#pragma once
// `uascma sitl`: a scenario flown by the simulator, epoch by epoch, as a MAVLink v2 vehicle on UDP (udp_link.h),
// paced to wall time. Without commands it flies exactly what `uascma simulate` flies (the same DecideEpoch and
// StepToNextEpoch, the scenario's CMA policy deciding at each epoch): a ground station can watch. Commands that map
// onto the CMA's actions are carried out at the next decision epoch in place of the policy's choice:
// NAV_LAND → LandASAP (§5.3.2.2: land at once within the footprint), DO_FLIGHTTERMINATION → Terminate;
// DISARM on the ground ends the run. Everything the vehicle streams is in sitl_vehicle.h. With
// SitlOptions::wait_for_start the simulated clock starts at MISSION_START, so a client sees the whole flight; with
// SitlOptions::wait_for_mission the flight is the uploaded mission's. Otherwise the vehicle holds its plan as its
// mission (the items a .plan export writes), for a ground station or a companion to download. With
// SitlOptions::external_cma the CMA is a companion on the link: only its commands act.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "uascma/common/bounds.h"
#include "uascma/mavlink/sitl_vehicle.h"
#include "uascma/mavlink/udp_link.h"
#include "uascma/sim/policy.h"
#include "uascma/sim/scenario.h"

namespace uascma::mavlink {

// Plausibility bounds (ours): a pace from a hundredth of real time to 1000 times it, MAVLink's system ids
// 1-255 (0 is the broadcast address), at most an hour of serving after the flight.
inline constexpr Bounds kSpeedBounds{0.01, 1000.0, "x real time"};
inline constexpr Bounds kSystemIdBounds{1.0, 255.0, ""};
inline constexpr Bounds kLingerBounds{0.0, 3600.0, "s"};

struct SitlOptions {
  std::vector<LinkAddress> links;
  double speed = 1.0;          // simulated seconds per wall second
  std::uint8_t system_id = 1;  // MAVLink system id (component MAV_COMP_ID_AUTOPILOT1)
  double linger_s = 2.0;       // wall seconds the link is still served after the flight ended (final telemetry)
  // Stay on the ground, disarmed, streaming once a wall second, until ARM and then MISSION_START (or NAV_TAKEOFF)
  // arrive; then fly the scenario's plan (an uploaded mission is stored and can be downloaded, not flown).
  bool wait_for_start = false;
  // As wait_for_start, and then fly the uploaded mission instead of the scenario's plan: the items read as a mission
  // file's are (planning::MissionFromItems, from where the vehicle stands; the scenario's map checks them), the flight
  // the scenario's with that route (sim::FlyMissionRoute). An upload that cannot be flown is refused at its
  // MISSION_ACK (MAV_MISSION_INVALID, a STATUSTEXT naming why); MISSION_START without a stored mission is denied.
  bool wait_for_mission = false;
  // The CMA runs elsewhere (`uascma companion`, docs/mavlink.md#the-cma-as-a-companion): the in-process policy does
  // not decide; the vehicle flies its plan and carries out the commands: NAV_LAND (LandASAP; at the site of a
  // preceding DO_REPOSITION), MISSION_START in flight (the uploaded mission as the emergency plan: LandPract),
  // DO_FLIGHTTERMINATION (Terminate).
  bool external_cma = false;
  // Called once the sockets are bound (before the first epoch): e.g. to print the ports of port-0 endpoints.
  std::function<void(const UdpLink&)> on_ready;
  bool IsValid(std::string* error) const;
};

struct SitlSummary {
  sim::Outcome outcome = sim::Outcome::kInProgress;
  std::string reason;
  double sim_time_s = 0.0;
  double wall_time_s = 0.0;
  double cpu_time_s = 0.0;  // this process's CPU time over the run
  int epochs = 0;
  int late_epochs = 0;             // epochs whose stepping ended after their wall deadline (the pace not held)
  std::vector<sim::FlightEvent> events;
  ParserCounts link;
  MissionServerCounts missions;
  SitlCounts commands;
  std::string BriefReport() const;
};

SitlSummary RunSitl(const sim::Scenario& scenario, sim::DecisionPolicy& policy, const SitlOptions& options);

}  // namespace uascma::mavlink
