#include "uascma/mavlink/sitl.h"

#include <chrono>
#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "uascma/common/cpu_time.h"
#include "uascma/common/error.h"

namespace uascma::mavlink {
namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The scenario's policy, except at an epoch where a received command asked for an action: that action instead.
class CommandedPolicy final : public sim::DecisionPolicy {
 public:
  explicit CommandedPolicy(sim::DecisionPolicy& inner) : inner_(inner) {}
  decision::CmaAction Decide(const sim::DecisionInputs& inputs) override {
    if (commanded_) {
      const decision::CmaAction action = *commanded_;
      commanded_.reset();
      return action;
    }
    return inner_.Decide(inputs);
  }
  std::string name() const override { return inner_.name(); }
  sim::ActionRanking Ranking(const sim::DecisionInputs& inputs) const override { return inner_.Ranking(inputs); }
  bool ReadsEodDistribution() const override { return inner_.ReadsEodDistribution(); }
  bool ReadsOnlyCmaState() const override { return false; }  // a command may ask for an action at any epoch
  void Command(decision::CmaAction action) { commanded_ = action; }

 private:
  sim::DecisionPolicy& inner_;
  std::optional<decision::CmaAction> commanded_;
};

// Sends every queued message, each in its own frame with the next sequence number, packed into datagrams of at most
// kDatagramBytes (several frames a datagram, as MAVLink over UDP allows: one datagram per epoch instead of twenty).
class Sender {
 public:
  static constexpr std::size_t kDatagramBytes = 1400;  // ours: below a 1500-byte Ethernet MTU with the IP/UDP headers
  Sender(UdpLink& link, Address self) : link_(link), self_(self) {}
  void Flush(std::vector<Outgoing>& out) {
    std::vector<std::uint8_t> datagram;
    for (const Outgoing& message : out) {
      const std::vector<std::uint8_t> frame = EncodeFrame(message.info, message.payload, self_, sequence_++);
      if (datagram.size() + frame.size() > kDatagramBytes) {
        link_.Send(datagram);
        datagram.clear();
      }
      datagram.insert(datagram.end(), frame.begin(), frame.end());
    }
    if (!datagram.empty()) link_.Send(datagram);
    out.clear();
  }

 private:
  UdpLink& link_;
  Address self_;
  std::uint8_t sequence_ = 0;
};

struct LoopState {
  bool armed = true;    // flies the scenario as `simulate` does from the start
  bool started = true;  // SitlOptions::wait_for_start: false until MISSION_START
  bool stop = false;    // a DISARM on the ground
};

// Serves the link until `deadline` (wall, from the run's start): frames handled in arrival order, mission timeouts.
void Serve(SitlVehicle& vehicle, UdpLink& link, Sender& sender, CommandedPolicy& policy, LoopState& loop,
           bool flying, Clock::time_point start, double deadline_s) {
  std::vector<Outgoing> out;
  for (;;) {
    const double now = SecondsSince(start);
    const double wait = deadline_s - now;
    for (const ReceivedFrame& received : link.Receive(std::max(0.0, std::min(wait, 0.05)))) {
      switch (vehicle.Handle(received.frame, SecondsSince(start), loop.armed, flying, out)) {
        case VehicleRequest::kLand: policy.Command(decision::CmaAction::kLandAsap); break;
        case VehicleRequest::kTerminate: policy.Command(decision::CmaAction::kTerminate); break;
        case VehicleRequest::kArm: loop.armed = true; break;
        case VehicleRequest::kMissionStart: loop.started = true; break;
        case VehicleRequest::kDisarm: loop.armed = false; loop.stop = !flying; break;
        default: break;
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
      "{} mission uploads, {} downloads",
      sim::OutcomeName(outcome), reason, sim_time_s, wall_time_s, wall_time_s > 0 ? sim_time_s / wall_time_s : 0.0,
      cpu_time_s, epochs, late_epochs, link.frames, link.bad_checksum, link.unknown_message, link.truncated,
      commands.commands, commands.unsupported_commands, commands.foreign_commands, missions.uploads,
      missions.downloads);
}

SitlSummary RunSitl(const sim::Scenario& scenario, sim::DecisionPolicy& policy, const SitlOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError(error);
  const sim::FlightModel model(scenario);
  UdpLink link(options.links);
  if (options.on_ready) options.on_ready(link);
  const Address self{options.system_id, static_cast<std::uint8_t>(kMavCompIdAutopilot1)};
  const auto unix_now = std::chrono::system_clock::now().time_since_epoch();
  SitlVehicle vehicle(model, self, scenario.geo_origin.value_or(planning::GeoPoint{}),
                      static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::microseconds>(unix_now).count()));
  Sender sender(link, self);
  CommandedPolicy commanded(policy);
  const sim::Controllers controllers{&commanded, nullptr, {}};
  sim::FlightState state = sim::MakeInitialState(model, scenario.seed);
  sim::FlightLog log;
  log.record_telemetry = true;  // the pack's outputs for BATTERY_STATUS, as `simulate --out` records them
  LoopState loop;
  SitlSummary summary;
  std::vector<Outgoing> out;
  if (options.wait_for_start) {  // on the ground, once a wall second, until ARM and MISSION_START
    loop.armed = false;
    loop.started = false;
    const Clock::time_point waiting = Clock::now();
    for (int second = 1; !loop.started && !loop.stop; ++second) {
      vehicle.Telemetry(state, log, loop.armed, out);
      sender.Flush(out);
      Serve(vehicle, link, sender, commanded, loop, false, waiting, second);
    }
  }
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
    Serve(vehicle, link, sender, commanded, loop, true, start, deadline);
    vehicle.Telemetry(state, log, loop.armed, out);
    vehicle.Events(log, out);
    sender.Flush(out);
  }
  if (state.done()) {  // how it ended, as MakeSimResult writes it (sim/simulator.cc)
    log.events.push_back({state.time_s, fmt::format("{}: {}", sim::OutcomeName(state.outcome), state.reason)});
    vehicle.Events(log, out);
    sender.Flush(out);
  }
  loop.armed = false;
  const double end = SecondsSince(start);
  for (double t = end; t < end + options.linger_s; t += 1.0) {  // the final state, once a second
    Serve(vehicle, link, sender, commanded, loop, false, start, std::min(t + 1.0, end + options.linger_s));
    vehicle.Telemetry(state, log, loop.armed, out);
    sender.Flush(out);
  }
  summary.outcome = state.outcome;
  summary.reason = state.reason;
  summary.sim_time_s = state.time_s;
  summary.wall_time_s = end;
  summary.cpu_time_s = ProcessCpuSeconds() - cpu_start;
  summary.events = log.events;
  summary.link = link.counts();
  summary.missions = vehicle.missions().counts();
  summary.commands = vehicle.counts();
  return summary;
}

}  // namespace uascma::mavlink
