#include "uascma/sim/flight_summary.h"

#include <cmath>
#include <cstdarg>
#include <cstdio>

#include "uascma/sim/outcome.h"
#include "uascma/sim/telemetry.h"

namespace uascma::sim {
namespace {

// printf's formatting (the text `uascma simulate` has always printed, its rounding included).
std::string Printf(const char* format, ...) {
  va_list args;
  va_start(args, format);
  va_list again;
  va_copy(again, args);
  const int size = std::vsnprintf(nullptr, 0, format, args);
  va_end(args);
  std::string out(static_cast<std::size_t>(size > 0 ? size : 0), '\0');
  std::vsnprintf(out.data(), out.size() + 1, format, again);
  va_end(again);
  return out;
}

}  // namespace

std::string FlightSummary::Text() const {
  std::string out = Printf("%s: %s (%s)\n", scenario.name.c_str(), OutcomeName(result.outcome), result.reason.c_str());
  out += Printf("EOD load: %s (docs/modelling-choices.md#%s)\n", result.eod_load.c_str(),
                result.eod_load == "forecast" ? "eod-load-forecast" : "pack-eod");
  for (const auto& e : result.events) out += Printf("  %8.2f s  %s\n", e.time_s, e.what.c_str());
  if (std::isfinite(result.min_cell_voltage_v) && result.sim_time_s > 0.0) {
    out += Printf("flew %.1f s of simulated time in %.1f ms (%.0fx real time); min cell %.3f V, energy %.1f Wh\n",
                  result.sim_time_s, result.wall_time_s * 1e3, result.realtime_factor(), result.min_cell_voltage_v,
                  result.energy_wh);
  } else {
    // Grounded before take-off: no step was flown, so there is no cell minimum nor a speed to report.
    out += Printf("flew no simulated time (%.1f s): the vehicle stayed on the ground, no cell was loaded\n",
                  result.sim_time_s);
  }
  if (battery_executor) {
    out += "battery executor:";
    for (const auto& [time_s, action] : result.battery_switches) {
      out += Printf(" %.0f s %s;", time_s, models::PackActionName(action));
    }
    out += "\n";
  }
  return out;
}

nlohmann::json FlightSummary::Json() const { return SummaryJson(scenario, nominal_plan, result); }

}  // namespace uascma::sim
