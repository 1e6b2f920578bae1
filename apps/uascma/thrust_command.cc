// uascma thrust — the static thrust of the hexacopter estimated as in the load-cell test of
// dissertation §2.5.3.1: per-motor power P/6 into the RPM estimator (eq. 2.12), thrust per rotor by
// eq. 2.1 with Table 2.1's C_T, times six.
#include <cmath>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "bounded_option.h"
#include "commands.h"
#include "output.h"
#include "uascma/common/error.h"
#include "uascma/models/propulsion.h"

namespace uascma::cli {
namespace {
// The whole vehicle's electrical power: 0 to 1300 W, the battery's I_max of 105 A (Table 4.1) at a full
// 3S pack's 12.6 V; Table 2.2 measures 578-581 W at full throttle.
constexpr Bounds kVehiclePowerBounds{0.0, 1300.0, "W"};
}  // namespace

void AddThrustCommand(CLI::App& app) {
  struct Options {
    std::string config;
    double throttle_us = 0.0;
    double power_w = 0.0;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = app.add_subcommand(
      "thrust",
      "Estimated total static thrust of the hexacopter at a throttle command when the whole vehicle\n"
      "draws the given electrical power (dissertation §2.5.3.1: each motor gets P/6, eq. 2.12 gives its\n"
      "RPM, eq. 2.1 its thrust, times six)");
  command->add_option("--config", options->config, "tractor | pusher (Table 2.1 coefficients)")->required();
  const models::RpmEstimatorParams fit = models::PropulsionParams{}.rpm_estimator;
  AddBoundedOption(command, "--throttle-us", options->throttle_us,
                   "Throttle command in microseconds, within the fitted range (§2.5.2)",
                   Bounds{fit.min_throttle_us, fit.max_throttle_us, "us"})
      ->required();
  AddBoundedOption(command, "--power-w", options->power_w, "Electrical power of the WHOLE hexacopter in watts",
                   kVehiclePowerBounds)
      ->required();
  command->add_flag("--json", options->json, "Print {\"thrust_n\", \"rpm\", ...} as JSON");
  command->callback([options] {
    const models::PropellerConfiguration configuration =
        models::ParsePropellerConfiguration(options->config, "--config");
    const models::PropulsionParams params = models::PropulsionParams::ForConfiguration(configuration);
    const models::RpmEstimatorParams& fit = params.rpm_estimator;
    if (!(std::isfinite(options->throttle_us) && options->throttle_us >= fit.min_throttle_us &&
          options->throttle_us <= fit.max_throttle_us)) {
      throw InputError("--throttle-us", "value",
                       fmt::format("a throttle command within the fitted {}-{} us (§2.5.2), got {}",
                                   fit.min_throttle_us, fit.max_throttle_us, options->throttle_us));
    }
    RequireWithin(options->power_w, kVehiclePowerBounds, "--power-w", "value");
    const models::StaticThrustEstimate estimate =
        models::EstimateStaticThrust(params, options->throttle_us, options->power_w);
    if (options->json) {
      PrintJson({{"configuration", std::string(models::PropellerConfigurationName(configuration))},
                 {"throttle_us", options->throttle_us},
                 {"power_w", options->power_w},
                 {"motor_power_w", estimate.motor_power},
                 {"rpm", estimate.rpm},
                 {"rotor_thrust_n", estimate.rotor_thrust},
                 {"thrust_n", estimate.total_thrust}});
      return;
    }
    WriteOutput("",
                fmt::format("{} hexacopter at {:g} us drawing {:g} W ({:.2f} W per motor):\n"
                            "  estimated static thrust {:.3f} N ({:.3f} N per rotor at {:.0f} RPM; eqs. 2.12, 2.1)\n",
                            models::PropellerConfigurationName(configuration), options->throttle_us, options->power_w,
                            estimate.motor_power, estimate.total_thrust, estimate.rotor_thrust, estimate.rpm));
  });
}

}  // namespace uascma::cli
