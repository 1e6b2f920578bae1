// uascma plot — draw a flight written by `uascma simulate --out DIR`; `uascma plot companion LOG.csv` draws the
// decision log of `uascma companion --log`.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "commands.h"
#include "output.h"
#include "plotting.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/mavlink/companion.h"
#include "uascma/mavlink/companion_log.h"

namespace uascma::cli {
namespace {

// The decision log as the drawing script reads it (python/plots/companion.py), and as --json prints it.
nlohmann::json CompanionLogJson(const std::vector<mavlink::CompanionDecision>& log, const std::string& source) {
  nlohmann::json rows = nlohmann::json::array();
  nlohmann::json actions = nlohmann::json::array();
  for (const mavlink::CompanionDecision& row : log) {
    const bool decided = !row.state.empty();
    // A number of a decided epoch; null when the epoch was not decided or the value is infinite (the RUL before a
    // spall): JSON has no infinity.
    const auto value = [decided](double x) {
      return decided && std::isfinite(x) ? nlohmann::json(x) : nlohmann::json();
    };
    rows.push_back({{"time_s", row.time_s},
                    {"cma_state", row.state},
                    {"decided", row.decided},
                    {"taken", row.taken},
                    {"eod_s", value(row.eod_s)},
                    {"rul_s", value(row.rul_s)},
                    {"flight_time_remaining_s", value(row.flight_time_remaining_s)},
                    {"reach_margin", value(row.reach_margin)},
                    {"motor_margin", value(row.motor_margin)},
                    {"decision_ms", row.decision_ms},
                    {"note", row.note}});
    if (decided && row.taken != "NoOp")
      actions.push_back({{"time_s", row.time_s}, {"action", row.taken}, {"note", row.note}});
  }
  return {{"source", source}, {"epochs", log.size()}, {"actions", actions}, {"rows", rows}};
}

void AddPlotCompanionCommand(CLI::App& plot) {
  struct Options {
    std::string log;
    std::string png;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = plot.add_subcommand(
      "companion",
      "Draw the decision log of `uascma companion --log` (docs/mavlink.md#the-cma-as-a-companion): the EOD against\n"
      "the remaining flight time, the reach and motor margins, the CMA state and the actions taken over the\n"
      "vehicle's clock, and the decision time per epoch");
  command->add_option("log", options->log, "Decision log CSV written by 'uascma companion --log'")->required();
  command->add_option("--png", options->png, "The picture (default: the log's name with .png)");
  command->add_flag("--json", options->json, "Print the log's timeline (rows and actions taken) as JSON");
  command->callback([options] {
    const std::vector<mavlink::CompanionDecision> log =
        mavlink::ParseCompanionLogCsv(ReadFile(options->log), options->log);
    if (log.empty()) throw InputError(options->log, "rows", "at least one epoch after the header");
    const std::string png =
        options->png.empty() ? std::filesystem::path(options->log).replace_extension(".png").string() : options->png;
    CheckOutputFile(png, "--png");
    const nlohmann::json data = CompanionLogJson(log, options->log);
    PlotJsonWhole("companion.py", data, png);
    if (options->json) {
      PrintJson(data);
      return;
    }
    std::printf("wrote %s (%zu epochs, %zu actions taken)\n", png.c_str(), log.size(), data["actions"].size());
  });
}

}  // namespace

void AddPlotCommand(CLI::App& app) {
  auto folder = std::make_shared<std::string>();
  CLI::App* command = app.add_subcommand(
      "plot",
      "Draw a simulated flight to PNG files in its folder: path.png (3-D path against the plan; over a city with\n"
      "the LandPract checkpoints and the buildings near the route), states.png (position, velocity, attitude and\n"
      "the motor fault flag, Fig. 5.19), forces.png, rotors.png (thrusts and currents), battery.png (cell\n"
      "voltages), eod.png (EOD against the remaining flight time, RM, MM), decisions.png (CMA state, action and\n"
      "IMM mode) and, over a city, map.png (buildings, landing sites, route, checkpoints, footprint and the\n"
      "emergency path)");
  command->add_option("dir", *folder, "Folder written by 'uascma simulate --out'");
  AddPlotCompanionCommand(*command);
  command->require_subcommand(0, 1);
  command->callback([folder, command] {
    if (command->got_subcommand("companion")) return;
    if (folder->empty())
      throw InputError("plot", "dir", "a folder written by 'uascma simulate --out' (or: plot companion LOG.csv)");
    for (const char* name : {"telemetry.csv", "plan.csv", "summary.json"}) {
      std::error_code ec;
      if (!std::filesystem::is_regular_file(std::filesystem::path(*folder) / name, ec)) {
        throw InputError(*folder, name, "a flight folder written by 'uascma simulate --out' (missing file)");
      }
    }
    RunPlotScript("flight.py", {*folder});
    const bool city = std::filesystem::exists(std::filesystem::path(*folder) / "map.json");
    std::printf("wrote %s/{path,states,forces,rotors,battery,eod,decisions%s}.png\n", folder->c_str(),
                city ? ",map" : "");
  });
}

}  // namespace uascma::cli
