// uascma thrust — the static thrust of the hexacopter estimated as in the load-cell test of
// dissertation §2.5.3.1: per-motor power P/6 into the RPM estimator (eq. 2.12), thrust per rotor by
// eq. 2.1 with Table 2.1's C_T, times six.
#include <cmath>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "commands.h"
#include "output.h"
#include "uascma/common/error.h"
#include "uascma/models/propulsion.h"

namespace uascma::cli {

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
  command->add_option("--throttle-us", options->throttle_us,
                      "Throttle command in microseconds, within the fitted 1100-1900 us")
      ->required();
  command->add_option("--power-w", options->power_w, "Electrical power of the WHOLE hexacopter in watts, >= 0")
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
    if (!(std::isfinite(options->power_w) && options->power_w >= 0.0)) {
      throw InputError("--power-w", "value",
                       fmt::format("the hexacopter's electrical power, finite and >= 0 W, got {}", options->power_w));
    }
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
    WriteOutput("", fmt::format("{} hexacopter at {:g} us drawing {:g} W ({:.2f} W per motor):\n"
                                "  estimated static thrust {:.3f} N ({:.3f} N per rotor at {:.0f} RPM; eqs. 2.12, 2.1)\n",
                                models::PropellerConfigurationName(configuration), options->throttle_us,
                                options->power_w, estimate.motor_power, estimate.total_thrust,
                                estimate.rotor_thrust, estimate.rpm));
  });
}

}  // namespace uascma::cli
