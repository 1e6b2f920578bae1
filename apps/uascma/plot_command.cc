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
      "Draw a simulated flight to PNG files in its folder: path.png (3-D path against the plan; over a city with\n"
      "the LandPract checkpoints and the buildings near the route), states.png (position, velocity, attitude and\n"
      "the motor fault flag, Fig. 5.19), forces.png, rotors.png (thrusts and currents), battery.png (cell\n"
      "voltages), eod.png (EOD against the remaining flight time, RM, MM), decisions.png (CMA state, action and\n"
      "IMM mode) and, over a city, map.png (buildings, landing sites, route, checkpoints, footprint and the\n"
      "emergency path)");
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
    std::printf("wrote %s/{path,states,forces,rotors,battery,eod,decisions%s}.png\n", folder->c_str(),
                city ? ",map" : "");
  });
}

}  // namespace uascma::cli
