// `uascma companion --mavlink udpout:HOST:PORT --scenario S.yaml`: the CMA as an onboard companion on an autopilot's
// MAVLink link (mavlink/companion.h).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "bounded_option.h"
#include "commands.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/mavlink/companion.h"
#include "uascma/mavlink/companion_log.h"
#include "uascma/planning/map_import.h"
#include "uascma/sim/policy.h"
#include "uascma/sim/scenario.h"

namespace uascma::cli {
namespace {

struct CompanionCommandOptions {
  std::vector<std::string> links;
  std::string scenario;
  std::string policy;
  std::string log;
  std::vector<std::string> map_files;
  std::string sites;
  planning::MapImportOptions import;  // the --map fall-backs for buildings without a height
  double wait_s = 30.0;
  bool allow_termination = false;
};

// The companion's own map and landing sites in place of the scenario's, read by the importer of `map:` keys and
// `uascma map` (planning::ImportCityMap: building files, a landing-site CSV), in the scenario's frame when it has one.
// --sites alone keeps the scenario's buildings.
void UseOwnMap(sim::Scenario& scenario, const std::vector<std::string>& map_files, const std::string& sites,
               planning::MapImportOptions import) {
  if (map_files.empty() && sites.empty()) return;
  import.origin = scenario.geo_origin;
  const std::vector<std::filesystem::path> files(map_files.begin(), map_files.end());
  planning::ImportedMap imported = planning::ImportCityMap(files, sites, import);
  if (files.empty() && scenario.map) {
    imported.map = planning::CityMap(scenario.map->buildings(), imported.map.sites());
  }
  scenario.geo_origin = imported.summary.origin;
  scenario.map = std::make_shared<const planning::CityMap>(std::move(imported.map));
  scenario.map_obstacles.reset();  // the emergency planners inflate the new map's buildings
}

}  // namespace

void AddCompanionCommand(CLI::App& app) {
  auto options = std::make_shared<CompanionCommandOptions>();
  CLI::App* command = app.add_subcommand(
      "companion",
      "The CMA as an onboard companion on an autopilot's MAVLink v2 link. Reads HEARTBEAT, SYSTEM_TIME, SYS_STATUS,\n"
      "BATTERY_STATUS per pack, LOCAL_POSITION_NED, ATTITUDE, EXTENDED_SYS_STATE, ESC_INFO and NAMED_VALUE_FLOAT\n"
      "spall_mm2; at each epoch runs the CMA (EOD, RUL, margins, the policy, the emergency planners) on its belief\n"
      "of the flight and acts: LandASAP as DO_REPOSITION + NAV_LAND at its site, LandPract as an uploaded mission\n"
      "and MISSION_START, Terminate as DO_FLIGHTTERMINATION (only with --allow-termination). The plan it reasons\n"
      "about is the vehicle's mission, downloaded before take-off (HOME_POSITION, MISSION_CURRENT). Each command\n"
      "waits for its COMMAND_ACK (sent again after 1.5 s, at most 5 times); a denied one is a STATUSTEXT and a log\n"
      "note, and a failed LandPract becomes LandASAP at the next epoch. Each action is a STATUSTEXT; every epoch a\n"
      "row of --log. Ends when the vehicle has landed. See docs/mavlink.md.");
  command
      ->add_option("--mavlink", options->links,
                   "udpout:HOST:PORT (an autopilot listening there, e.g. `uascma sitl --mavlink udp:...`) or "
                   "udp:HOST:PORT (listen for an autopilot that sends here); may be given more than once")
      ->required();
  command
      ->add_option("--scenario", options->scenario,
                   "Scenario YAML: the vehicle, battery and options the CMA knows, its map and landing sites unless\n"
                   "--map/--sites, and the plan used only when the vehicle holds no mission (it is downloaded)")
      ->required();
  command->add_option("--policy", options->policy,
                      "CMA policy: cma | cma-vehicle | noop | … | policy.json (as `uascma simulate --policy`; "
                      "default: the scenario's)");
  command->add_option(
      "--log", options->log,
      "Decision log CSV, one row per epoch (written when the run ends; `uascma plot companion` draws it)");
  command->add_option("--map", options->map_files,
                      "Building files (.geojson, .json, .osm, .osm.pbf) of the companion's own map, in place of the "
                      "scenario's (may be given more than once)");
  command->add_flag("--height-from-levels", options->import.height_from_levels,
                    "--map: a building without a height takes building:levels x 3 m (as `uascma map info`)");
  command->add_flag("--skip-missing-height", options->import.skip_missing_height,
                    "--map: skip (and count) a building still without a height instead of stopping");
  command->add_option("--sites", options->sites,
                      "Landing-site CSV of the companion's own, in place of the scenario's sites (as `uascma map "
                      "--sites`)");
  AddBoundedOption(command, "--wait", options->wait_s, "Wall seconds to wait for the vehicle's HEARTBEAT (0: forever)",
                   mavlink::kCompanionWaitBounds);
  command->add_flag("--allow-termination", options->allow_termination,
                    "Send DO_FLIGHTTERMINATION when the CMA's Terminate is taken (withheld otherwise)");
  command->callback([options] {
    sim::ScenarioFile file = sim::LoadScenarioFile(options->scenario, {});
    UseOwnMap(file.scenario, options->map_files, options->sites, options->import);
    const std::string policy_spec = options->policy.empty() ? file.policy : options->policy;
    auto policy = sim::MakePolicy(policy_spec, options->policy.empty() ? options->scenario : "--policy");
    mavlink::CompanionOptions companion;
    for (const std::string& text : options->links) {
      companion.links.push_back(mavlink::ParseLinkAddress(text, "--mavlink"));
    }
    companion.allow_termination = options->allow_termination;
    companion.wait_s = options->wait_s;
    companion.on_ready = [&](const mavlink::UdpLink& link) {
      for (const std::string& address : mavlink::ListeningAddresses(companion.links, link)) {
        std::printf("listening on %s\n", address.c_str());
      }
      std::fflush(stdout);
    };
    const mavlink::CompanionSummary summary = mavlink::RunCompanion(file.scenario, *policy, companion);
    for (const mavlink::CompanionDecision& row : summary.log) {
      if (row.taken != "NoOp" || !row.note.empty()) {
        std::printf("%8.1f s  %s -> %s (%s) %s\n", row.time_s, row.state.c_str(), row.taken.c_str(),
                    row.decided.c_str(), row.note.c_str());
      }
    }
    std::printf("%s\n", summary.BriefReport().c_str());
    if (!options->log.empty()) WriteFileAtomically(options->log, mavlink::CompanionLogCsv(summary.log));
  });
}

}  // namespace uascma::cli
