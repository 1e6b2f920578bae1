// uascma plot — draw a flight written by `uascma simulate --out DIR`.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "commands.h"
#include "plotting.h"
#include "uascma/common/error.h"

namespace uascma::cli {

void AddPlotCommand(CLI::App& app) {
  auto folder = std::make_shared<std::string>();
  CLI::App* command = app.add_subcommand(
      "plot",
      "Draw a simulated flight to PNG files in its folder: path.png (3-D path against the plan), forces.png,\n"
      "rotors.png (thrusts and currents), battery.png (cell voltages), eod.png (EOD against the remaining\n"
      "flight time, RM, MM), decisions.png (CMA state, action and IMM mode) and, over a city, map.png\n"
      "(buildings, landing sites, route, checkpoints, footprint and the emergency path)");
  command->add_option("dir", *folder, "Folder written by 'uascma simulate --out'")->required();
  command->callback([folder] {
    for (const char* name : {"telemetry.csv", "plan.csv", "summary.json"}) {
      std::error_code ec;
      if (!std::filesystem::is_regular_file(std::filesystem::path(*folder) / name, ec)) {
        throw InputError(*folder, name, "a flight folder written by 'uascma simulate --out' (missing file)");
      }
    }
    RunPlotScript("flight.py", {*folder});
    const bool city = std::filesystem::exists(std::filesystem::path(*folder) / "map.json");
    std::printf("wrote %s/{path,forces,rotors,battery,eod,decisions%s}.png\n", folder->c_str(), city ? ",map" : "");
  });
}

}  // namespace uascma::cli
