#include "uascma/mavlink/sitl.h"

#include <chrono>
#include <cmath>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "uascma/common/cpu_time.h"
#include "uascma/common/error.h"
#include "uascma/planning/mission_write.h"
#include "uascma/sim/emergency_planner.h"
#include "uascma/sim/epoch.h"
#include "uascma/sim/initial_state.h"

namespace uascma::mavlink {
namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The scenario's policy (with the CMA external: NoOp), except at an epoch where a received command asked for an
// action: that action instead, planned by the command's planner (empty: the model's map planner). With the CMA
// external the executor falls back only on NoOp when the commanded plan cannot be carried out (Act's ranking): the
// vehicle never picks an action of its own.
class CommandedPolicy final : public sim::DecisionPolicy {
 public:
  CommandedPolicy(sim::DecisionPolicy& inner, bool external) : inner_(inner), external_(external) {}
  decision::CmaAction Decide(const sim::DecisionInputs& inputs) override {
    if (commanded_) {
      ranking_[0] = static_cast<decision::ActionIndex>(*commanded_);
      commanded_.reset();
      return static_cast<decision::CmaAction>(ranking_[0]);
    }
    planner_ = nullptr;
    return external_ ? decision::CmaAction::kNoOp : inner_.Decide(inputs);
  }
  std::string name() const override { return external_ ? "external" : inner_.name(); }
  sim::ActionRanking Ranking(const sim::DecisionInputs& inputs) const override {
    return external_ ? sim::ActionRanking(ranking_) : inner_.Ranking(inputs);
  }
  bool ReadsEodDistribution() const override { return !external_ && inner_.ReadsEodDistribution(); }
  bool ReadsOnlyCmaState() const override { return false; }  // a command may ask for an action at any epoch
  void Command(decision::CmaAction action, sim::EmergencyPlanner planner = nullptr) {
    commanded_ = action;
    planner_ = std::move(planner);
  }
  // The planner of the epoch's command: the command's own, else the model's map planner.
  sim::EmergencyPlan Plan(const sim::FlightModel& model, const sim::EmergencyRequest& request) const {
    if (planner_) return planner_(request);
    if (model.map_planner()) return model.map_planner()(request);
    sim::EmergencyPlan none;
    none.message = "the map has no landing sites";
    return none;
  }

 private:
  sim::DecisionPolicy& inner_;
  bool external_;
  std::optional<decision::CmaAction> commanded_;
  sim::EmergencyPlanner planner_;
  std::array<decision::ActionIndex, 2> ranking_{0, static_cast<decision::ActionIndex>(decision::CmaAction::kNoOp)};
};

// The planner of a commanded landing with the CMA external: NAV_LAND after a DO_REPOSITION lands at the map site
// nearest the repositioned point (the map's path to it); MISSION_START flies the uploaded waypoints from where the
// vehicle comes to rest, labelled with the map site nearest their last point.
sim::EmergencyPlanner RepositionPlanner(const sim::FlightModel& model, const Eigen::Vector3d& target_W) {
  return [&model, target_W](const sim::EmergencyRequest& request) {
    if (model.map_point_planner()) return model.map_point_planner()(request, target_W);
    sim::EmergencyPlan none;
    none.message = "the map has no landing sites";
    return none;
  };
}
sim::EmergencyPlanner MissionPlanner(const sim::FlightModel& model, std::vector<planning::Waypoint> waypoints) {
  return [&model, waypoints = std::move(waypoints)](const sim::EmergencyRequest& request) {
    sim::EmergencyPlan plan;
    plan.status = planning::LandingStatus::kOk;
    plan.plan = planning::FlightPlan::Through(request.p_WB_W, waypoints, model.scenario().limits);
    const int site = sim::NearestLandingSite(model.map(), waypoints.back().p_W);
    plan.site = site >= 0 ? model.map().sites()[site].id : "the uploaded mission's end";
    plan.site_radius = site >= 0 ? model.map().sites()[site].radius : 0.0;
    return plan;
  };
}

constexpr const char* kUploadedSource = "the uploaded mission";

// The scenario flying the uploaded items, read as a mission file's items are (planning::MissionFromItems) from where
// the vehicle stands, in the scenario's frame and over its map. InputError naming the item when it cannot be flown.
sim::Scenario UploadedFlight(const sim::Scenario& scenario, const sim::FlightModel& ground,
                             const std::vector<MissionItemInt>& uploaded) {
  const planning::GeoPoint origin = VehicleGeoOrigin(scenario);
  std::vector<planning::MissionItem> items;
  for (const MissionItemInt& item : uploaded) items.push_back(ToMissionItem(item));
  planning::MissionImportOptions import;
  import.origin = origin;
  import.map = scenario.map.get();
  const planning::GeoPoint home =
      planning::LocalProjection(origin).ToGeodetic(ground.nominal_plan().start_W().head<2>());
  sim::Scenario flight = scenario;
  sim::FlyMissionRoute(flight,
                       planning::MissionFromItems(items, home, kUploadedSource, planning::MissionFirmware::kUnknown,
                                                  "uploaded to a MAV_AUTOPILOT_GENERIC vehicle", import),
                       kUploadedSource);
  return flight;
}

// The plan as the items a .plan export writes (planning::PlanMissionItems), for the vehicle to hold.
std::vector<MissionItemInt> PlanAsMission(const sim::FlightModel& model, Address self) {
  planning::QgcPlanExportOptions options;
  options.origin = VehicleGeoOrigin(model.scenario());
  options.cruise_speed = model.scenario().limits.cruise_speed;
  std::vector<MissionItemInt> items;
  for (const planning::MissionItem& item : planning::PlanMissionItems(model.nominal_plan(), options)) {
    items.push_back(ToMissionItemInt(item, self, static_cast<std::uint16_t>(items.size())));
  }
  return items;
}

struct LoopState {
  bool armed = true;    // flies the scenario as `simulate` does from the start
  bool started = true;  // SitlOptions::wait_for_start: false until MISSION_START
  bool stop = false;    // a DISARM on the ground
};

// Serves the link until `deadline` (wall, from the run's start): frames handled in arrival order, mission timeouts.
void Serve(const sim::FlightModel& model, SitlVehicle& vehicle, UdpLink& link, FrameSender& sender,
           CommandedPolicy& policy, LoopState& loop, bool flying, Clock::time_point start, double deadline_s) {
  std::vector<Outgoing> out;
  for (;;) {
    const double now = SecondsSince(start);
    const double wait = deadline_s - now;
    for (const ReceivedFrame& received : link.Receive(std::max(0.0, std::min(wait, 0.05)))) {
      switch (vehicle.Handle(received.frame, SecondsSince(start), loop.armed, flying, out)) {
        case VehicleRequest::kLand:
          if (const std::optional<Eigen::Vector3d> site_W = vehicle.TakeReposition())
            policy.Command(decision::CmaAction::kLandAsap, RepositionPlanner(model, *site_W));
          else
            policy.Command(decision::CmaAction::kLandAsap);
          break;
        case VehicleRequest::kFlyMission:
          policy.Command(decision::CmaAction::kLandPract, MissionPlanner(model, vehicle.MissionWaypoints()));
          break;
        case VehicleRequest::kTerminate:
          policy.Command(decision::CmaAction::kTerminate);
          break;
        case VehicleRequest::kArm:
          loop.armed = true;
          break;
        case VehicleRequest::kMissionStart:
          loop.started = true;
          break;
        case VehicleRequest::kDisarm:
          loop.armed = false;
          loop.stop = !flying;
          break;
        default:
          break;
      }
    }
    sender.Flush(out);  // the replies to one batch of datagrams, in order, packed
    vehicle.Tick(SecondsSince(start), out);
    sender.Flush(out);
    if (wait <= 0.0) return;
  }
}

}  // namespace

bool SitlOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (links.empty()) return fail("--mavlink: at least one address (udp:HOST:PORT or udpout:HOST:PORT)");
  return CheckWithin(speed, kSpeedBounds, "--speed", error) &&
         CheckWithin(system_id, kSystemIdBounds, "--system-id", error) &&
         CheckWithin(linger_s, kLingerBounds, "--linger", error);
}

std::string SitlSummary::BriefReport() const {
  return fmt::format(
      "{} ({}) at {:.1f} s simulated in {:.1f} s wall ({:.1f}x, {:.1f} s CPU); {} epochs, {} late; link: {} frames, "
      "{} bad checksum, {} unknown id, {} truncated; {} commands ({} unsupported, {} for another system); "
      "{} mission uploads ({} refused), {} downloads",
      sim::OutcomeName(outcome), reason, sim_time_s, wall_time_s, wall_time_s > 0 ? sim_time_s / wall_time_s : 0.0,
      cpu_time_s, epochs, late_epochs, link.frames, link.bad_checksum, link.unknown_message, link.truncated,
      commands.commands, commands.unsupported_commands, commands.foreign_commands, missions.uploads, missions.refused,
      missions.downloads);
}

namespace {

// On the ground, disarmed, streaming once a wall second, until ARM and MISSION_START (or a DISARM ends the run).
void WaitOnGround(const sim::FlightModel& ground, SitlVehicle& vehicle, UdpLink& link, FrameSender& sender,
                  CommandedPolicy& commanded, LoopState& loop) {
  loop.armed = false;
  loop.started = false;
  const sim::FlightState state = sim::MakeInitialState(ground, ground.scenario().seed);
  const sim::FlightLog log;
  std::vector<Outgoing> out;
  const Clock::time_point waiting = Clock::now();
  for (int second = 1; !loop.started && !loop.stop; ++second) {
    vehicle.Telemetry(state, log, loop.armed, out);
    sender.Flush(out);
    Serve(ground, vehicle, link, sender, commanded, loop, false, waiting, second);
  }
}

// The flight, epoch by epoch, paced to wall time, then `linger_s` of serving the final state.
void Fly(const sim::FlightModel& model, SitlVehicle& vehicle, UdpLink& link, FrameSender& sender,
         CommandedPolicy& commanded, LoopState& loop, const SitlOptions& options, SitlSummary& summary) {
  const sim::Controllers controllers{
      &commanded, nullptr, [&](const sim::EmergencyRequest& request) { return commanded.Plan(model, request); }};
  sim::FlightState state = sim::MakeInitialState(model, model.scenario().seed);
  sim::FlightLog log;
  log.record_telemetry = true;  // the pack's outputs for BATTERY_STATUS, as `simulate --out` records them
  std::vector<Outgoing> out;
  const double cpu_start = ProcessCpuSeconds();
  const Clock::time_point start = Clock::now();
  vehicle.Telemetry(state, log, loop.armed, out);
  sender.Flush(out);
  while (!state.done() && !loop.stop) {
    sim::DecideEpoch(model, state, controllers, &log);
    sim::StepToNextEpoch(model, state, &log);
    ++summary.epochs;
    const double deadline = state.time_s / options.speed;
    if (SecondsSince(start) > deadline) ++summary.late_epochs;
    // Only the last telemetry row is read: keep the log's memory to one row.
    if (log.telemetry.size() > 1) log.telemetry.erase(log.telemetry.begin(), log.telemetry.end() - 1);
    // The epoch's telemetry goes out as soon as it is stepped, and the link is served until the epoch's wall
    // deadline: a command answering this telemetry (an external CMA's) is carried out at this epoch's decision.
    vehicle.Telemetry(state, log, loop.armed, out);
    vehicle.Events(log, out);
    sender.Flush(out);
    if (state.done()) break;
    Serve(model, vehicle, link, sender, commanded, loop, true, start, deadline);
  }
  if (state.done()) {  // how it ended, as MakeSimResult writes it (sim/simulator.cc)
    log.events.push_back({state.time_s, fmt::format("{}: {}", sim::OutcomeName(state.outcome), state.reason)});
    vehicle.Events(log, out);
    sender.Flush(out);
  }
  loop.armed = false;
  const double end = SecondsSince(start);
  for (double t = end; t < end + options.linger_s; t += 1.0) {  // the final state, once a second
    Serve(model, vehicle, link, sender, commanded, loop, false, start, std::min(t + 1.0, end + options.linger_s));
    vehicle.Telemetry(state, log, loop.armed, out);
    sender.Flush(out);
  }
  summary.outcome = state.outcome;
  summary.reason = state.reason;
  summary.sim_time_s = state.time_s;
  summary.wall_time_s = end;
  summary.cpu_time_s = ProcessCpuSeconds() - cpu_start;
  summary.events = log.events;
}

}  // namespace

SitlSummary RunSitl(const sim::Scenario& scenario, sim::DecisionPolicy& policy, const SitlOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError(error);
  const sim::FlightModel ground(scenario);
  UdpLink link(options.links);
  if (options.on_ready) options.on_ready(link);
  const Address self{options.system_id, static_cast<std::uint8_t>(kMavCompIdAutopilot1)};
  const auto unix_now = std::chrono::system_clock::now().time_since_epoch();
  SitlVehicle vehicle(
      ground, self, VehicleGeoOrigin(scenario),
      static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::microseconds>(unix_now).count()),
      options.external_cma);
  FrameSender sender(link, self);
  CommandedPolicy commanded(policy, options.external_cma);
  if (options.wait_for_mission) {
    vehicle.RequireMission([&](const std::vector<MissionItemInt>& items) -> std::optional<std::string> {
      try {
        UploadedFlight(scenario, ground, items);
        return std::nullopt;
      } catch (const InputError& refused) {
        return std::string(refused.what());
      }
    });
  } else {
    vehicle.HoldMission(PlanAsMission(ground, self));
  }
  LoopState loop;
  if (options.wait_for_start || options.wait_for_mission) WaitOnGround(ground, vehicle, link, sender, commanded, loop);
  std::unique_ptr<const sim::FlightModel> uploaded;  // the uploaded mission's flight (wait_for_mission)
  if (options.wait_for_mission && loop.started) {
    const sim::Scenario flight = UploadedFlight(scenario, ground, vehicle.missions().items());
    uploaded = std::make_unique<const sim::FlightModel>(flight);
    vehicle.UseModel(*uploaded, planning::MissionItemArrivals(*flight.route, flight.limits));
  }
  SitlSummary summary;
  Fly(uploaded ? *uploaded : ground, vehicle, link, sender, commanded, loop, options, summary);
  summary.link = link.counts();
  summary.missions = vehicle.missions().counts();
  summary.commands = vehicle.counts();
  return summary;
}

}  // namespace uascma::mavlink
