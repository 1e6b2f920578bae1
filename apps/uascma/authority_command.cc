// uascma authority — the control authority of dissertation §4.4.2 (Figs. 4.14–4.16): the largest
// square of roll and pitch angles within which the hexacopter still holds altitude, healthy or
// reconfigured as a quadcopter after one motor failure (§4.4.1, docs/modelling-choices.md#mixing-after-motor-failure).
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "bounded_option.h"
#include "commands.h"
#include "output.h"
#include "uascma/common/error.h"
#include "uascma/common/frames.h"
#include "uascma/models/mixer.h"

namespace uascma::cli {
namespace {
constexpr Bounds kFailedMotorsBounds{0.0, 1.0, "motors"};
}  // namespace

void AddAuthorityCommand(CLI::App& app) {
  struct Options {
    int failed_motors = 0;
    double total_thrust_n = 0.0;
    double mass_kg = 0.0;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = app.add_subcommand(
      "authority",
      "Largest roll/pitch square (|roll| = |pitch| <= a, degrees) within which the vehicle holds altitude:\n"
      "m g / (cos(roll) cos(pitch)) must be deliverable with zero torque by the rotors left after the\n"
      "failure rule (a failed motor and its opposite off, §4.4.1). Dissertation §4.4.2, Figs. 4.14-4.16");
  AddBoundedOption(command, "--failed-motors", options->failed_motors,
                   "Number of failed motors: 0 (hexacopter) or 1 (quadcopter on the 4 remaining rotors;\n"
                   "the reconfiguration of §4.4 handles a single failure)",
                   kFailedMotorsBounds)
      ->required();
  AddBoundedOption(command, "--total-thrust-n", options->total_thrust_n,
                   "Total thrust of the healthy hexacopter, all six rotors at maximum (N); each rotor\n"
                   "gives a sixth (Fig. 4.14: 24 N)",
                   kVehicleThrustBounds)
      ->required();
  AddBoundedOption(command, "--mass-kg", options->mass_kg, "Vehicle mass (kg)", kVehicleMassBounds)->required();
  command->add_flag("--json", options->json, "Print {\"max_angle_deg\", \"failed_motors\", ...} as JSON");
  command->callback([options] {
    if (options->failed_motors < 0 || options->failed_motors > 1) {
      throw InputError("--failed-motors", "value",
                       fmt::format("0 (no failure) or 1 (one failed motor; §4.4 reconfigures a single "
                                   "failure only), got {}",
                                   options->failed_motors));
    }
    RequireWithin(options->total_thrust_n, kVehicleThrustBounds, "--total-thrust-n", "value");
    RequireWithin(options->mass_kg, kVehicleMassBounds, "--mass-kg", "value");
    models::MixerParams params;
    params.max_rotor_thrust = options->total_thrust_n / models::kRotorCount;
    const models::Mixer mixer(params);
    // With one failure, the worst case over which motor failed (by symmetry all six agree).
    models::ControlAuthority authority = models::CalcControlAuthority(mixer, models::kNoFailedMotor, options->mass_kg);
    if (options->failed_motors == 1) {
      authority = models::CalcControlAuthority(mixer, 1, options->mass_kg);
      for (int motor = 2; motor <= models::kRotorCount; ++motor) {
        const models::ControlAuthority candidate = models::CalcControlAuthority(mixer, motor, options->mass_kg);
        if (candidate.max_tilt < authority.max_tilt) authority = candidate;
      }
    }
    const bool can_hover = authority.status == models::AuthorityStatus::kCanHover;
    const double max_angle_deg = authority.max_tilt * kDegreesPerRadian;
    if (options->json) {
      PrintJson({{"failed_motors", options->failed_motors},
                 {"active_rotors", authority.active_rotors},
                 {"total_thrust_n", options->total_thrust_n},
                 {"available_thrust_n", authority.max_hover_thrust},
                 {"mass_kg", options->mass_kg},
                 {"weight_n", authority.weight},
                 {"status", can_hover ? "can_hover" : "cannot_hover"},
                 {"max_angle_deg", can_hover ? nlohmann::json(max_angle_deg) : nlohmann::json(nullptr)}});
      return;
    }
    const std::string vehicle =
        options->failed_motors == 0 ? "hexacopter (6 rotors)" : "quadcopter after one motor failure (4 rotors)";
    if (!can_hover) {
      WriteOutput("", fmt::format("{}: cannot hold altitude even level: weight {:.3f} N exceeds the {:.3f} N "
                                  "the rotors give\n",
                                  vehicle, authority.weight, authority.max_hover_thrust));
      return;
    }
    WriteOutput("", fmt::format("{}: holds altitude for |roll|, |pitch| <= {:.2f} deg (weight {:.3f} N, "
                                "available thrust {:.3f} N)\n",
                                vehicle, max_angle_deg, authority.weight, authority.max_hover_thrust));
  });
}

}  // namespace uascma::cli
