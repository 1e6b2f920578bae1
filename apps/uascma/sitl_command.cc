// `uascma sitl SCENARIO.yaml --mavlink udp:HOST:PORT`: the simulator as a MAVLink v2 vehicle (mavlink/sitl.h).
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bounded_option.h"
#include "commands.h"
#include "uascma/common/error.h"
#include "uascma/mavlink/sitl.h"
#include "uascma/sim/policy.h"
#include "uascma/sim/scenario.h"

namespace uascma::cli {
namespace {

struct SitlCommandOptions {
  std::string scenario;
  std::vector<std::string> links;
  std::string policy;
  std::string cma = "onboard";
  double speed = 1.0;
  int system_id = 1;
  double linger_s = 2.0;
  bool wait_for_start = false;
  bool wait_for_mission = false;
  std::optional<std::uint64_t> seed;
};

}  // namespace

void AddSitlCommand(CLI::App& app) {
  auto options = std::make_shared<SitlCommandOptions>();
  CLI::App* command = app.add_subcommand(
      "sitl",
      "Fly a scenario as a MAVLink v2 vehicle (a hexarotor) on UDP, for ground stations and companions.\n"
      "Streams HEARTBEAT, SYSTEM_TIME, SYS_STATUS, BATTERY_STATUS per pack (time_remaining = the EOD), positions,\n"
      "ATTITUDE, HOME_POSITION, EXTENDED_SYS_STATE, ESC_STATUS/ESC_INFO, MISSION_CURRENT, NAMED_VALUE_FLOAT spall_mm2\n"
      "once per simulated second, and STATUSTEXT for each event; takes the mission protocol and COMMAND_LONG/INT\n"
      "(ARM/DISARM, MISSION_START, NAV_LAND = LandASAP, DO_FLIGHTTERMINATION = Terminate) with COMMAND_ACK.\n"
      "Without commands it flies what `uascma simulate` flies, and holds that plan as its mission (downloadable);\n"
      "--wait-for-mission flies an uploaded mission instead. Prints the ports it listens on, then a summary.\n"
      "--cma external: the CMA is a companion on the link (`uascma companion`); the vehicle flies its plan and\n"
      "carries out NAV_LAND (after DO_REPOSITION: at that site), MISSION_START in flight (the uploaded mission as\n"
      "the emergency plan) and DO_FLIGHTTERMINATION.\n"
      "See docs/mavlink.md.");
  command->add_option("scenario", options->scenario, "Scenario YAML file")->required();
  command->add_option("--mavlink", options->links,
                      "udp:HOST:PORT (listen; answer every peer) or udpout:HOST:PORT (send to a ground station); "
                      "may be given more than once; PORT 0 lets the system choose")
      ->required();
  command->add_option("--policy", options->policy, "CMA policy (as `uascma simulate --policy`; default: the scenario's)");
  command->add_option("--cma", options->cma,
                      "onboard (the policy decides in the simulator) or external (only the link's commands act)")
      ->check(CLI::IsMember({"onboard", "external"}));
  AddBoundedOption(command, "--speed", options->speed, "Simulated seconds per wall second", mavlink::kSpeedBounds);
  AddBoundedOption(command, "--system-id", options->system_id, "MAVLink system id of the vehicle",
                   mavlink::kSystemIdBounds);
  AddBoundedOption(command, "--linger", options->linger_s, "Wall seconds the link is served after the flight",
                   mavlink::kLingerBounds);
  command->add_flag("--wait-for-start", options->wait_for_start,
                    "Stay on the ground, disarmed, until ARM and MISSION_START; then fly the scenario's plan");
  command
      ->add_flag("--wait-for-mission", options->wait_for_mission,
                 "Stay on the ground, disarmed, until a mission upload, ARM and MISSION_START; then fly the\n"
                 "uploaded mission (read as a mission file's items are, over the scenario's map; an upload it\n"
                 "cannot fly is refused at MISSION_ACK with a STATUSTEXT naming why)")
      ->excludes("--wait-for-start");
  AddSeedOption(command, "--seed", options->seed, "Random seed (overrides the scenario's)");
  command->callback([options] {
    sim::ScenarioFile file = sim::LoadScenarioFile(options->scenario, {});
    if (options->seed) file.scenario.seed = *options->seed;
    const std::string policy_spec = options->policy.empty() ? file.policy : options->policy;
    auto policy = sim::MakePolicy(policy_spec, options->policy.empty() ? options->scenario : "--policy");
    mavlink::SitlOptions sitl;
    for (const std::string& text : options->links) sitl.links.push_back(mavlink::ParseLinkAddress(text, "--mavlink"));
    sitl.speed = options->speed;
    sitl.system_id = static_cast<std::uint8_t>(options->system_id);
    sitl.linger_s = options->linger_s;
    sitl.wait_for_start = options->wait_for_start;
    sitl.wait_for_mission = options->wait_for_mission;
    sitl.external_cma = options->cma == "external";
    if (sitl.external_cma && !options->policy.empty())
      throw InputError("--policy", "value", "no policy with --cma external (the companion's --policy decides)");
    sitl.on_ready = [&](const mavlink::UdpLink& link) {
      for (const std::string& address : mavlink::ListeningAddresses(sitl.links, link)) {
        std::printf("listening on %s\n", address.c_str());
      }
      std::fflush(stdout);
    };
    const mavlink::SitlSummary summary = mavlink::RunSitl(file.scenario, *policy, sitl);
    for (const sim::FlightEvent& event : summary.events) std::printf("%8.1f s  %s\n", event.time_s, event.what.c_str());
    std::printf("%s\n", summary.BriefReport().c_str());
  });
}

}  // namespace uascma::cli
