// uascma simulate — fly one scenario in the high-fidelity simulator (§5.4, Fig. 5.15).
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "bounded_option.h"
#include "commands.h"
#include "output.h"
#include "uascma/campaign/battery_flights.h"
#include "uascma/campaign/policies.h"
#include "uascma/campaign/replay.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/planning/mission_file.h"
#include "uascma/planning/mission_write.h"
#include "uascma/sim/act.h"
#include "uascma/sim/flight_summary.h"
#include "uascma/sim/policy.h"
#include "uascma/sim/scenario.h"
#include "uascma/sim/simulator.h"
#include "uascma/sim/telemetry.h"
#include "uascma/sim/vehicle_file.h"

namespace uascma::cli {
namespace {

struct SimulateOptions {
  std::vector<std::string> replay;  // DB RUN_ID
  std::string scenario;
  std::string out;
  std::string policy;
  std::string mission;
  std::string battery_policy;
  std::string vehicle;
  std::optional<std::uint64_t> seed;
  bool json = false;
};

// The QGroundControl export of a plan in the scenario's frame (origin known).
planning::QgcPlanExportOptions ExportOptions(const sim::Scenario& scenario, const planning::FlightPlan& nominal) {
  planning::QgcPlanExportOptions options;
  options.origin = *scenario.geo_origin;
  options.cruise_speed = scenario.limits.cruise_speed;
  if (scenario.route) {
    options.home_amsl = scenario.route->home_amsl.value_or(0.0);
    options.firmware_type = scenario.route->firmware_type.value_or(options.firmware_type);  // kept on export
    options.vehicle_type = scenario.route->vehicle_type.value_or(options.vehicle_type);
    options.home_W = scenario.route->home_W;
  } else {
    options.home_W = Eigen::Vector3d(nominal.start_W().x(), nominal.start_W().y(), 0.0);
  }
  return options;
}

}  // namespace

void AddSimulateCommand(CLI::App& app) {
  auto options = std::make_shared<SimulateOptions>();
  CLI::App* command = app.add_subcommand(
      "simulate",
      "Fly one scenario: 6-DOF dynamics with drag and Dryden wind, LQR at 200 Hz, rotor faults isolated by\n"
      "an IMM, the battery pack coupled to the rotors, and the decision module at 1 Hz. Prints the outcome;\n"
      "--out writes telemetry.csv, plan.csv and summary.json (draw them with 'uascma plot DIR') and, when\n"
      "the scenario has a geodetic frame (a mission file, an imported map, mission.origin), nominal.plan and\n"
      "emergency.plan for QGroundControl, nominal.waypoints and emergency.waypoints for Mission Planner;\n"
      "--mission flies a .plan/.waypoints mission; --battery-policy runs the battery executor (Ch. IV) alongside\n"
      "the CMA policy; --replay DB RUN_ID flies one run of a campaign again, bit for bit");
  command->add_option("scenario", options->scenario, "Scenario YAML (see examples/)");
  command
      ->add_option("--replay", options->replay,
                   "Fly one run of a campaign again from its database: DB RUN_ID (a flight id, or INDEX:POLICY)")
      ->expected(2);
  command->add_option("--out", options->out,
                      "Folder for telemetry.csv, plan.csv, summary.json (+ nominal/emergency .plan and .waypoints); "
                      "replaced whole");
  command->add_option("--mission", options->mission,
                      "Mission file (.plan or .waypoints, relative to the current folder) flown instead of the "
                      "scenario's mission");
  command->add_option("--vehicle", options->vehicle,
                      "Vehicle file (YAML: mass, inertia, arm length, rotor directions, cells, CELL.json, PROP.json,\n"
                      "DRAG.csv; docs/identification.md#vehicle-file) flown instead of the scenario's vehicle");
  command->add_option("--battery-policy", options->battery_policy,
                      "Battery policy JSON ('uascma battery solve'): the 1 Hz pack-switch executor");
  command->add_option("--policy", options->policy,
                      "noop | cma | cma-vehicle | cma-risk[@P] | cma-qmdp | cma-vehicle-risk[@P] | cma-vehicle-qmdp |\n"
                      "policy.json (overrides the scenario's)");
  AddSeedOption(command, "--seed", options->seed, "Random seed (overrides the scenario's)");
  command->add_flag("--json", options->json, "Print the summary as JSON");
  command->callback([options] {
    sim::ScenarioFile file;
    std::unique_ptr<sim::DecisionPolicy> policy;
    if (!options->replay.empty()) {
      if (!options->scenario.empty())
        throw InputError("--replay", "scenario", "either a scenario file or --replay, not both");
      if (!options->mission.empty())
        throw InputError("--replay", "--mission", "either --mission or --replay, not both");
      if (!options->vehicle.empty())
        throw InputError("--replay", "--vehicle", "either --vehicle or --replay, not both (the campaign's vehicle)");
      // The run's scenario is resampled from the stored campaign and its seed (bit-identical flight).
      const campaign::ReplayFlight flight = campaign::LoadReplay(options->replay[0], options->replay[1]);
      file.scenario = flight.run.scenario;
      policy = campaign::MakeDecisionPolicy(flight.policy);
    } else {
      if (options->scenario.empty())
        throw InputError("simulate", "scenario", "a scenario YAML file (or --replay DB RUN_ID)");
      sim::ScenarioLoadOptions load;
      if (!options->mission.empty()) load.mission_file = options->mission;
      if (!options->vehicle.empty()) load.vehicle_file = options->vehicle;
      file = sim::LoadScenarioFile(options->scenario, load);
    }
    // The vehicle file's parts left at the dissertation's values: one line.
    if (file.scenario.vehicle && !file.scenario.vehicle->defaulted.empty()) {
      std::fprintf(stderr, "note: %s\n", file.scenario.vehicle->DefaultedLine().c_str());
    }
    // The importer's notes on the mission (items read but not modelled, our choices): one line each.
    if (file.scenario.route) {
      // Which autopilot's reading of the altitudes was applied (planning/mission_file.h, MissionFirmware).
      std::fprintf(stderr, "note: %s\n", file.scenario.route->FirmwareNote().c_str());
      for (const std::string& warning : file.scenario.route->warnings)
        std::fprintf(stderr, "warning: %s\n", warning.c_str());
    }
    if (options->seed) file.scenario.seed = *options->seed;
    if (!policy || !options->policy.empty()) {
      const std::string policy_spec = options->policy.empty() ? file.policy : options->policy;
      policy = sim::MakePolicy(policy_spec, options->policy.empty() ? options->scenario : "--policy");
    }
    const sim::Simulator simulator(file.scenario);
    std::unique_ptr<sim::BatterySwitchPolicy> battery;
    if (!options->battery_policy.empty()) {
      battery = campaign::LoadBatterySwitchPolicy(options->battery_policy, file.scenario);
    }
    // Checked (and staged) before the flight, so a refused folder costs no flight.
    std::optional<OutputDirectory> out;
    if (!options->out.empty()) out.emplace("--out", options->out);
    sim::RunOptions run;
    run.record_telemetry = out.has_value();
    run.battery_policy = battery.get();
    const sim::SimResult result = simulator.Run(*policy, {}, run);
    const bool geodetic = file.scenario.geo_origin.has_value();
    std::vector<std::string> written = {"telemetry.csv", "plan.csv", "summary.json"};
    const sim::FlightSummary flight{file.scenario, simulator.nominal_plan(), result, battery != nullptr};
    nlohmann::json summary = flight.Json();
    if (file.scenario.vehicle) {
      summary["vehicle"] = {{"file", file.scenario.vehicle->source},
                            {"content_hash", file.scenario.vehicle->content_hash},
                            {"defaulted", file.scenario.vehicle->defaulted}};
    }
    if (out) {
      if (geodetic) {
        const planning::QgcPlanExportOptions qgc = ExportOptions(file.scenario, simulator.nominal_plan());
        // Each plan for QGroundControl (.plan) and Mission Planner (.waypoints, QGC WPL 110).
        auto write_plan = [&](const std::string& stem, const planning::FlightPlan& plan) {
          for (const char* extension : {".plan", ".waypoints"}) {
            planning::WriteMissionFile(out->staging() / (stem + extension), plan, qgc);
            written.push_back(stem + extension);
          }
        };
        write_plan("nominal", simulator.nominal_plan());
        if (result.emergency_plan) write_plan("emergency", *result.emergency_plan);
      }
      summary["files"] = written;
      if (!geodetic) {
        summary["qgc_plans"] =
            "not written: the scenario has no geodetic frame (no mission file, imported map or mission.origin)";
      }
      sim::WriteFlightRecord(out->staging(), file.scenario, simulator.nominal_plan(), result, simulator.checkpoints());
      // The summary with this command's additions (the files written) replaces the record's.
      WriteFileAtomically(out->staging() / "summary.json", summary.dump(2) + "\n");
      out->Commit();
    }
    if (options->json) {
      PrintJson(summary);
      return;
    }
    std::fputs(flight.Text().c_str(), stdout);
    if (out) {
      std::string list;
      for (const auto& name : written) list += (list.empty() ? "" : ",") + name;
      std::printf("wrote %s/{%s}\n", options->out.c_str(), list.c_str());
      if (!geodetic)
        std::printf(
            "no .plan files: the scenario has no geodetic frame (no mission file, imported map or mission.origin)\n");
    }
  });
}

}  // namespace uascma::cli
