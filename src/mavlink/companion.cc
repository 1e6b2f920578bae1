#include "uascma/mavlink/companion.h"

#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <utility>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/decision/cma_abstraction.h"
#include "uascma/mavlink/command_client.h"
#include "uascma/mavlink/companion_belief.h"
#include "uascma/mavlink/mission_client.h"
#include "uascma/mavlink/sitl_vehicle.h"
#include "uascma/planning/map_projection.h"
#include "uascma/sim/act.h"
#include "uascma/sim/emergency_planner.h"
#include "uascma/sim/epoch.h"

namespace uascma::mavlink {
namespace {

using Clock = std::chrono::steady_clock;
using decision::CmaAction;

double WallSecondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

CommandLong MakeCommand(Address vehicle, std::uint32_t command, std::array<float, 7> params = {}) {
  CommandLong c;
  c.target_system = vehicle.system_id;
  c.target_component = vehicle.component_id;
  c.command = static_cast<std::uint16_t>(command);
  c.param1 = params[0], c.param2 = params[1], c.param3 = params[2], c.param4 = params[3];
  c.param5 = params[4], c.param6 = params[5], c.param7 = params[6];
  return c;
}

// The planner's path as a mission: each move's end a NAV_WAYPOINT (a hover after it its hold time), the last one a
// NAV_LAND at the site; global frame, altitude relative to home (W's origin on the ground).
std::vector<MissionItemInt> PlanItems(const planning::FlightPlan& plan, const planning::LocalProjection& projection,
                                      Address vehicle) {
  std::vector<MissionItemInt> items;
  for (const planning::PlanSegment& segment : plan.segments()) {
    if (segment.kind == planning::PlanSegment::Kind::kHover) {
      if (!items.empty()) items.back().param1 += static_cast<float>(segment.duration);
      continue;
    }
    MissionItemInt item;
    item.target_system = vehicle.system_id;
    item.target_component = vehicle.component_id;
    item.seq = static_cast<std::uint16_t>(items.size());
    item.frame = static_cast<std::uint8_t>(kMavFrameGlobalRelativeAltInt);
    item.command = static_cast<std::uint16_t>(kMavCmdNavWaypoint);
    item.autocontinue = 1;
    const planning::GeoPoint geo = projection.ToGeodetic(segment.end_W.head<2>());
    item.x = static_cast<std::int32_t>(std::llround(geo.lat_deg * 1e7));
    item.y = static_cast<std::int32_t>(std::llround(geo.lon_deg * 1e7));
    item.z = static_cast<float>(-segment.end_W.z());
    item.mission_type = static_cast<std::uint8_t>(kMavMissionTypeMission);
    items.push_back(item);
  }
  if (!items.empty()) items.back().command = static_cast<std::uint16_t>(kMavCmdNavLand);
  if (!items.empty()) items.front().current = 1;
  return items;
}

// One companion run: the link, the belief, the policy, what was sent.
class Companion {
 public:
  Companion(const sim::Scenario& scenario, sim::DecisionPolicy& policy, const CompanionOptions& options)
      : scenario_(scenario),
        model_(std::make_unique<const sim::FlightModel>(scenario)),
        policy_(policy),
        options_(options),
        projection_(VehicleGeoOrigin(scenario)),
        link_(options.links),
        self_{1, static_cast<std::uint8_t>(kMavCompIdOnboardComputer)},
        sender_(link_, self_),
        belief_(*model_) {}
  CompanionSummary Run();

 private:
  // The action whose commands (or emergency mission) are under way, and the guidance the belief had before it.
  struct Acting {
    CmaAction action = CmaAction::kNoOp;
    sim::GuidanceState guidance_before;
  };
  void OnFrame(const Frame& frame, double now_s, Clock::time_point received);
  void OnTransfers(const Frame& frame, double now_s);
  void Tick(double now_s);
  void AdoptMission(const std::vector<MissionItemInt>& items);
  void OnCommandOutcome(const CommandOutcome& outcome);
  void Failed(const std::string& what);
  void DecideEpoch(Clock::time_point received);
  CmaAction Act(CmaAction action, const sim::DecisionInputs& inputs, CompanionDecision& row);
  void Send(CmaAction taken, const sim::EmergencyPlan& plan, double now_s, CompanionDecision& row);
  void Say(std::uint8_t severity, const std::string& text);
  void SayDecision(const CompanionDecision& row);

  sim::Scenario scenario_;
  std::unique_ptr<const sim::FlightModel> model_;
  std::vector<std::unique_ptr<const sim::FlightModel>> retired_;  // models replaced by the vehicle's mission's
  sim::DecisionPolicy& policy_;
  CompanionOptions options_;
  planning::LocalProjection projection_;
  UdpLink link_;
  Address self_;
  FrameSender sender_;
  std::optional<Address> vehicle_;
  std::optional<TelemetryReader> reader_;
  VehicleBelief belief_;
  sim::FlightLog flight_log_;
  MissionUpload upload_;
  MissionDownload download_;
  CommandClient commands_;
  std::optional<planning::GeoPoint> home_;         // HOME_POSITION
  std::optional<std::uint16_t> downloaded_total_;  // MISSION_CURRENT's total the last download was started at
  bool plan_known_ = false;                        // the vehicle's mission read (or found absent)
  bool airborne_seen_ = false;
  std::optional<Acting> acting_;
  std::optional<CmaAction> fallback_;  // taken at the next epoch: an action's commands failed
  std::string pending_note_;           // for the next row of the log: what happened on the link since
  std::vector<Outgoing> out_;
  double decided_time_s_ = -1.0;  // the last epoch decided (or skipped as stale)
  bool landed_ = false, terminated_ = false;
  std::uint16_t statustext_id_ = 0;
  CompanionSummary summary_;
  Clock::time_point start_ = Clock::now();
};

void Companion::Say(std::uint8_t severity, const std::string& text) {
  for (const Statustext& chunk : StatustextChunks(severity, text, ++statustext_id_))
    out_.push_back(MakeOutgoing(chunk));
}

// The vehicle's mission as the plan the companion reasons about: read as a mission file's items are
// (planning::MissionFromItems, from the vehicle's HOME_POSITION, over the companion's map), the scenario flying it
// (sim::FlyMissionRoute). No mission, or one it cannot read: the scenario's plan, said in a STATUSTEXT and the log.
void Companion::AdoptMission(const std::vector<MissionItemInt>& items) {
  plan_known_ = true;
  std::string note;
  if (items.empty()) {
    note = "the vehicle holds no mission: planning on the scenario's plan";
  } else {
    try {
      std::vector<planning::MissionItem> read;
      for (const MissionItemInt& item : items) read.push_back(ToMissionItem(item));
      planning::MissionImportOptions import;
      import.origin = projection_.origin();
      import.map = scenario_.map.get();
      sim::Scenario flight = scenario_;
      sim::FlyMissionRoute(flight,
                           planning::MissionFromItems(read, *home_, "the vehicle's mission",
                                                      planning::MissionFirmware::kUnknown, "downloaded", import),
                           "the vehicle's mission");
      const double scenario_plan_s = model_->nominal_plan().duration();
      retired_.push_back(std::move(model_));
      model_ = std::make_unique<const sim::FlightModel>(flight);
      belief_.UseModel(*model_);
      note = fmt::format("the vehicle's mission, {} items: a plan of {:.1f} s (the scenario's: {:.1f} s)", items.size(),
                         model_->nominal_plan().duration(), scenario_plan_s);
    } catch (const InputError& error) {
      note = fmt::format("the vehicle's mission cannot be flown ({}): planning on the scenario's plan", error.what());
    }
  }
  Say(kMavSeverityInfo, "CMA: " + note);
  pending_note_ += note;
}

// A command or the emergency mission failed: said, logged, the belief back on the plan the vehicle still flies, and
// the fallback of docs/mavlink.md#companion-commands at the next epoch (LandPract → LandASAP).
void Companion::Failed(const std::string& what) {
  ++summary_.failed_commands;
  std::string note = what;
  if (acting_) {
    belief_.state().guidance = acting_->guidance_before;
    if (acting_->action == CmaAction::kLandPract) {
      fallback_ = CmaAction::kLandAsap;
      note += ": LandASAP at the next epoch";
    } else {
      note += fmt::format(": {} not carried out", decision::CmaActionName(acting_->action));
    }
    acting_.reset();
  }
  Say(kMavSeverityError, "CMA: " + note);
  pending_note_ += (pending_note_.empty() ? "" : "; ") + note;
}

void Companion::OnCommandOutcome(const CommandOutcome& outcome) {
  if (!outcome.accepted()) {
    Failed(outcome.Describe());
  } else if (commands_.idle() && !upload_.active()) {
    acting_.reset();  // every command of the action accepted
  }
}

void Companion::SayDecision(const CompanionDecision& row) {
  Statustext text = MakeStatustext(kMavSeverityWarning, fmt::format("CMA: {} ({}) {}", row.taken, row.state, row.note));
  text.id = ++statustext_id_;
  out_.push_back(MakeOutgoing(text));
}

void Companion::Send(CmaAction taken, const sim::EmergencyPlan& plan, double now_s, CompanionDecision& row) {
  const Address vehicle = *vehicle_;
  if (taken == CmaAction::kLandPract) {
    upload_.Start(PlanItems(plan.plan, projection_, vehicle), vehicle, now_s, out_);
    row.note = fmt::format("to {}: mission of the plan uploaded, MISSION_START", plan.site);
  } else if (taken == CmaAction::kLandAsap) {
    const Eigen::Vector3d site_W = plan.plan.end_W();
    const planning::GeoPoint geo = projection_.ToGeodetic(site_W.head<2>());
    CommandInt reposition;
    reposition.target_system = vehicle.system_id;
    reposition.target_component = vehicle.component_id;
    reposition.frame = static_cast<std::uint8_t>(kMavFrameGlobalRelativeAltInt);
    reposition.command = static_cast<std::uint16_t>(kMavCmdDoReposition);
    reposition.param1 = -1.0f;  // the default ground speed
    reposition.x = static_cast<std::int32_t>(std::llround(geo.lat_deg * 1e7));
    reposition.y = static_cast<std::int32_t>(std::llround(geo.lon_deg * 1e7));
    reposition.z = static_cast<float>(-site_W.z());
    commands_.Send(reposition, now_s, out_);
    commands_.Send(MakeCommand(vehicle, kMavCmdNavLand,
                               {0, 0, 0, NAN, static_cast<float>(geo.lat_deg), static_cast<float>(geo.lon_deg),
                                static_cast<float>(-site_W.z())}),
                   now_s, out_);
    row.note = fmt::format("to {}: DO_REPOSITION, NAV_LAND", plan.site);
  } else if (taken == CmaAction::kTerminate) {
    commands_.Send(MakeCommand(vehicle, kMavCmdDoFlighttermination, {1}), now_s, out_);
    row.note = "DO_FLIGHTTERMINATION";
  }
  ++summary_.commands;
}

// The executor's action on the belief (sim::Act, with the companion's map planner), and its commands sent.
CmaAction Companion::Act(CmaAction action, const sim::DecisionInputs& inputs, CompanionDecision& row) {
  sim::FlightState& state = belief_.state();
  const sim::FlightState before = state;
  const std::size_t actions_before = flight_log_.actions.size();
  sim::EmergencyPlan planned;  // the last plan the planners found (the taken action's when one is taken)
  const sim::EmergencyPlanner planner = [&](const sim::EmergencyRequest& request) {
    sim::EmergencyPlan plan = model_->map_planner()(request);
    if (plan.ok()) planned = plan;
    return plan;
  };
  const CmaAction taken = sim::Act(*model_, state, action, model_->map_planner() ? planner : sim::EmergencyPlanner{},
                                   &flight_log_, policy_.Ranking(inputs));
  row.taken = decision::CmaActionName(taken);
  if (taken == CmaAction::kTerminate && !options_.allow_termination) {
    state = before;  // the vehicle flies on: the belief too
    row.note = "Terminate withheld (no --allow-termination)";
    SayDecision(row);
  } else if (flight_log_.actions.size() > actions_before) {
    if (taken == CmaAction::kTerminate || planned.ok()) {
      acting_ = Acting{taken, before.guidance};
      Send(taken, planned, WallSecondsSince(start_), row);
    } else {  // before take-off (sim::Act: the vehicle stays on the ground): nothing to fly
      row.note = "chosen before take-off: nothing sent";
    }
    SayDecision(row);
  }
  return taken;
}

void Companion::DecideEpoch(Clock::time_point received) {
  const TelemetrySample& sample = reader_->sample();
  decided_time_s_ = sample.time_s;
  ++summary_.epochs;
  CompanionDecision row;
  row.time_s = sample.time_s;
  const double period_s = 1.0 / model_->options().decision_rate_hz;
  if (sample.OldestS() < 0.0) {
    row.note = "incomplete: a telemetry group not yet received, no decision";
    ++summary_.stale;
    summary_.log.push_back(row);
    return;
  }
  if (sample.time_s - sample.OldestS() > kMaxStaleEpochs * period_s + 1e-6) {
    row.note = fmt::format("stale: telemetry {:.1f} s old, no decision", sample.time_s - sample.OldestS());
    ++summary_.stale;
    summary_.log.push_back(row);
    return;
  }
  belief_.Update(sample);
  sim::FlightState& state = belief_.state();
  if (state.vehicle.airborne && !sample.in_air) landed_ = true;
  if (landed_ || state.done()) return;
  const sim::DecisionInputs& inputs =
      sim::Observe(*model_, state, &flight_log_, sim::NeedsEodDistribution(&policy_, nullptr));
  row.state = decision::CmaStateLabel(inputs.state);
  const sim::EodValue& eod = inputs.eod_value();
  row.eod_s = eod.eod_s, row.rul_s = inputs.rul_s, row.reach_margin = eod.reach_margin;
  row.motor_margin = inputs.motor_margin, row.flight_time_remaining_s = inputs.flight_time_remaining_s;
  CmaAction action = policy_.Decide(inputs);
  row.decided = row.taken = decision::CmaActionName(action);
  if (fallback_ && action != CmaAction::kTerminate) {  // an action whose commands failed: its fallback now
    action = *std::exchange(fallback_, std::nullopt);
    row.taken = decision::CmaActionName(action);
  }
  if (action != CmaAction::kNoOp && !plan_known_) {
    row.note = "not acted: the vehicle's mission not yet downloaded";
  } else if (action != CmaAction::kNoOp) {
    Act(action, inputs, row);
  }
  if (!pending_note_.empty()) {
    row.note = row.note.empty() ? pending_note_ : pending_note_ + "; " + row.note;
    pending_note_.clear();
  }
  sender_.Flush(out_);
  row.decision_ms = std::chrono::duration<double, std::milli>(Clock::now() - received).count();
  ++summary_.decided;
  summary_.log.push_back(row);
}

// The mission download, the emergency mission's upload and the commands' ACKs.
void Companion::OnTransfers(const Frame& frame, double now_s) {
  if (frame.Is<HomePosition>()) {
    const HomePosition home = frame.As<HomePosition>();
    home_ = planning::GeoPoint{home.latitude * 1e-7, home.longitude * 1e-7};
  }
  // The vehicle's mission, downloaded before take-off and again while it changes on the ground (an upload there).
  if (frame.Is<MissionCurrent>() && home_ && !airborne_seen_ && !download_.active() &&
      frame.As<MissionCurrent>().total != downloaded_total_) {
    downloaded_total_ = frame.As<MissionCurrent>().total;
    download_.Start(*vehicle_, now_s, out_);
  }
  if (const std::optional<std::vector<MissionItemInt>> items = download_.Handle(frame, now_s, out_)) {
    AdoptMission(*items);
  }
  switch (upload_.Handle(frame, now_s, out_)) {
    case TransferStatus::kDone:
      ++summary_.missions_uploaded;
      commands_.Send(MakeCommand(*vehicle_, kMavCmdMissionStart), now_s, out_);
      break;
    case TransferStatus::kRefused:
      Failed("the emergency mission refused (MISSION_ACK)");
      break;
    default:
      break;
  }
  if (const std::optional<CommandOutcome> outcome = commands_.Handle(frame, *vehicle_, now_s, out_)) {
    OnCommandOutcome(*outcome);
  }
}

void Companion::Tick(double now_s) {
  if (upload_.Tick(now_s, out_) == TransferStatus::kNoAnswer) Failed("the emergency mission's upload not answered");
  if (download_.Tick(now_s, out_) == TransferStatus::kNoAnswer) {
    pending_note_ += "the vehicle's mission not downloaded (no answer); ";
    AdoptMission({});
  }
  if (const std::optional<CommandOutcome> outcome = commands_.Tick(now_s, out_)) OnCommandOutcome(*outcome);
}

void Companion::OnFrame(const Frame& frame, double now_s, Clock::time_point received) {
  if (!vehicle_ && frame.Is<Heartbeat>() && frame.sender.component_id == kMavCompIdAutopilot1) {
    vehicle_ = frame.sender;
    reader_.emplace(frame.sender.system_id);
  }
  if (!vehicle_ || frame.sender != *vehicle_) return;
  if (frame.Is<Heartbeat>() && frame.As<Heartbeat>().system_status == kMavStateFlightTermination) terminated_ = true;
  OnTransfers(frame, now_s);
  // A new epoch's SYSTEM_TIME while the last is undecided: decide the last on what came (the staleness rule).
  const bool new_epoch =
      frame.Is<SystemTime>() && frame.As<SystemTime>().time_boot_ms * 1e-3 > reader_->sample().time_s;
  if (new_epoch && reader_->sample().time_s > decided_time_s_) DecideEpoch(received);
  const bool telemetry = reader_->Read(frame);
  if (telemetry && reader_->sample().in_air) airborne_seen_ = true;
  if (telemetry && reader_->Complete() && reader_->sample().time_s > decided_time_s_) DecideEpoch(received);
}

CompanionSummary Companion::Run() {
  if (options_.on_ready) options_.on_ready(link_);
  double last_frame_s = 0.0, last_heartbeat_s = -1.0;
  while (!landed_ && !terminated_) {
    const double now_s = WallSecondsSince(start_);
    if (now_s - last_heartbeat_s >= 1.0) {  // a companion's HEARTBEAT once a second: the vehicle learns where we are
      Heartbeat heartbeat;
      heartbeat.type = kMavTypeOnboardController;
      heartbeat.autopilot = kMavAutopilotInvalid;
      heartbeat.system_status = kMavStateActive;
      out_.push_back(MakeOutgoing(heartbeat));
      last_heartbeat_s = now_s;
    }
    const std::vector<ReceivedFrame> frames = link_.Receive(0.02);
    const Clock::time_point received = Clock::now();
    for (const ReceivedFrame& frame : frames) {
      last_frame_s = WallSecondsSince(start_);
      OnFrame(frame.frame, last_frame_s, received);
    }
    Tick(WallSecondsSince(start_));
    sender_.Flush(out_);
    if (!vehicle_ && options_.wait_s > 0.0 && WallSecondsSince(start_) > options_.wait_s) {
      throw InputError("--mavlink", "vehicle", fmt::format("a vehicle's HEARTBEAT within {:.0f} s", options_.wait_s));
    }
    if (vehicle_ && WallSecondsSince(start_) - last_frame_s > kLinkLostS) break;
  }
  double total_ms = 0.0;
  for (const CompanionDecision& row : summary_.log) {
    summary_.max_decision_ms = std::max(summary_.max_decision_ms, row.decision_ms);
    total_ms += row.decision_ms;
  }
  summary_.resent_commands = commands_.resent();
  summary_.mean_decision_ms = summary_.decided > 0 ? total_ms / summary_.decided : 0.0;
  return summary_;
}

}  // namespace

bool CompanionOptions::IsValid(std::string* error) const {
  if (links.empty()) {
    if (error) *error = "--mavlink: at least one address (udpout:HOST:PORT or udp:HOST:PORT)";
    return false;
  }
  return CheckWithin(wait_s, kCompanionWaitBounds, "--wait", error);
}

std::string CompanionSummary::BriefReport() const {
  return fmt::format(
      "{} epochs: {} decided, {} stale; {} commands ({} sent again, {} failed), {} missions uploaded; decision time "
      "{:.2f} ms mean, {:.2f} ms max",
      epochs, decided, stale, commands, resent_commands, failed_commands, missions_uploaded, mean_decision_ms,
      max_decision_ms);
}

CompanionSummary RunCompanion(const sim::Scenario& scenario, sim::DecisionPolicy& policy,
                              const CompanionOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError(error);
  Companion companion(scenario, policy, options);
  return companion.Run();
}

}  // namespace uascma::mavlink
