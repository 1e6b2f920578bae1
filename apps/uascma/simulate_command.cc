// uascma simulate — fly one scenario in the high-fidelity simulator (§5.4, Fig. 5.15).
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "commands.h"
#include "output.h"
#include "uascma/campaign/policies.h"
#include "uascma/campaign/replay.h"
#include "uascma/common/error.h"
#include "uascma/sim/policy.h"
#include "uascma/sim/scenario.h"
#include "uascma/sim/simulator.h"
#include "uascma/sim/telemetry.h"

namespace uascma::cli {
namespace {

struct SimulateOptions {
  std::vector<std::string> replay;  // DB RUN_ID
  std::string scenario;
  std::string out;
  std::string policy;
  std::optional<std::uint64_t> seed;
  bool json = false;
};

}  // namespace

void AddSimulateCommand(CLI::App& app) {
  auto options = std::make_shared<SimulateOptions>();
  CLI::App* command = app.add_subcommand(
      "simulate",
      "Fly one scenario: 6-DOF dynamics with drag and Dryden wind, LQR at 200 Hz, rotor faults isolated by\n"
      "an IMM, the battery pack coupled to the rotors, and the decision module at 1 Hz. Prints the outcome;\n"
      "--out writes telemetry.csv, plan.csv and summary.json (draw them with 'uascma plot DIR');\n"
      "--replay DB RUN_ID flies one run of a campaign again, bit for bit");
  command->add_option("scenario", options->scenario, "Scenario YAML (see examples/)");
  command->add_option("--replay", options->replay,
                      "Fly one run of a campaign again from its database: DB RUN_ID (a flight id, or INDEX:POLICY)")
      ->expected(2);
  command->add_option("--out", options->out, "Folder for telemetry.csv, plan.csv, summary.json");
  command->add_option("--policy", options->policy, "noop | cma | policy.json (overrides the scenario's)");
  command->add_option("--seed", options->seed, "Random seed (overrides the scenario's)");
  command->add_flag("--json", options->json, "Print the summary as JSON");
  command->callback([options] {
    sim::ScenarioFile file;
    std::unique_ptr<sim::DecisionPolicy> policy;
    if (!options->replay.empty()) {
      if (!options->scenario.empty()) throw InputError("--replay", "scenario", "either a scenario file or --replay, not both");
      // The run's scenario is resampled from the stored campaign and its seed (bit-identical flight).
      const campaign::ReplayFlight flight = campaign::LoadReplay(options->replay[0], options->replay[1]);
      file.scenario = flight.run.scenario;
      policy = campaign::MakeDecisionPolicy(flight.policy);
    } else {
      if (options->scenario.empty()) throw InputError("simulate", "scenario", "a scenario YAML file (or --replay DB RUN_ID)");
      file = sim::LoadScenarioFile(options->scenario);
    }
    if (options->seed) file.scenario.seed = *options->seed;
    if (!policy || !options->policy.empty()) {
      const std::string policy_spec = options->policy.empty() ? file.policy : options->policy;
      policy = sim::MakePolicy(policy_spec, options->policy.empty() ? options->scenario : "--policy");
    }
    const sim::Simulator simulator(file.scenario);
    sim::RunOptions run;
    run.record_telemetry = !options->out.empty();
    const sim::SimResult result = simulator.Run(*policy, {}, run);
    if (!options->out.empty()) {
      sim::WriteFlightRecord(options->out, file.scenario, simulator.nominal_plan(), result, simulator.checkpoints());
    }
    const nlohmann::json summary = sim::SummaryJson(file.scenario, simulator.nominal_plan(), result);
    if (options->json) {
      PrintJson(summary);
      return;
    }
    std::printf("%s: %s (%s)\n", file.scenario.name.c_str(), sim::OutcomeName(result.outcome), result.reason.c_str());
    for (const auto& e : result.events) std::printf("  %8.2f s  %s\n", e.time_s, e.what.c_str());
    std::printf("flew %.1f s of simulated time in %.1f ms (%.0fx real time); min cell %.3f V, energy %.1f Wh\n",
                result.sim_time_s, result.wall_time_s * 1e3, result.realtime_factor(), result.min_cell_voltage_v,
                result.energy_wh);
    if (!options->out.empty()) std::printf("wrote %s/{telemetry.csv,plan.csv,summary.json}\n", options->out.c_str());
  });
}

}  // namespace uascma::cli
