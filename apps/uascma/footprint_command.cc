// uascma footprint — the approximate reachable footprint of dissertation §5.3.1 (Algorithm 1, eqs. 5.1–5.13):
// the forward, backward and lateral limits in the heading frame and the ellipse through them; --plot draws
// the footprints of an EOD sweep like Fig. 5.4.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "bounded_option.h"
#include "commands.h"
#include "output.h"
#include "plotting.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/common/frames.h"
#include "uascma/models/drag.h"
#include "uascma/planning/footprint.h"

namespace uascma::cli {
namespace {

using planning::FootprintParams;
using planning::FootprintResult;
using planning::FootprintStatus;

constexpr int kPlotSweepCount = 10;       // footprints drawn by --plot: [1 s,] EOD/10, 2 EOD/10, …, EOD
constexpr double kPlotShortestEod = 1.0;  // s: Fig. 5.4 starts at 1 s, where the footprint is a cone ahead

// Plausibility bounds of the options. Ours unless cited: speeds up to 30 m/s (Table 4.4 samples
// 1-9 m/s, the drag table spans 0-10 m/s); EOD up to two hours (the packs hover ~15 min); mass and thrust
// as bounded_option.h's vehicle; tilt 1-89 degrees (90 cannot
// hold altitude); a drag slope up to 100 N*s/m (the default table's is ~1 N*s/m at 10 m/s); the series
// order of the existing check, 0 (exact) to 30.
constexpr Bounds kSpeedBounds{0.0, 30.0, "m/s"};
constexpr Bounds kEodBounds{0.0, 7200.0, "s"};
constexpr Bounds kTiltBounds{1.0, 89.0, "deg"};
constexpr Bounds kDragSlopeBounds{0.0, 100.0, "N*s/m"};
constexpr Bounds kMaclaurinBounds{0.0, 30.0, ""};

struct Options {
  double speed_mps = std::nan("");
  double eod_s = std::nan("");
  double mass_kg = FootprintParams{}.mass;
  double thrust_n = FootprintParams{}.available_thrust;
  double max_tilt_deg = FootprintParams{}.max_tilt * kDegreesPerRadian;
  double drag_slope = std::nan("");  // N·s/m; NaN: the default table's slope at the cruise speed
  int maclaurin = 0;
  bool json = false;
  std::string plot;
};

void Require(bool condition, const char* option, const std::string& expected, double value) {
  if (!condition) throw InputError(option, "value", fmt::format("{}, got {}", expected, value));
}

FootprintParams ResolveParams(const Options& o) {
  RequireWithin(o.speed_mps, kSpeedBounds, "--speed-mps", "value");
  RequireWithin(o.eod_s, kEodBounds, "--eod-s", "value");
  RequireWithin(o.mass_kg, kVehicleMassBounds, "--mass-kg", "value");
  RequireWithin(o.thrust_n, kVehicleThrustBounds, "--thrust-n", "value");
  RequireWithin(o.max_tilt_deg, kTiltBounds, "--max-tilt-deg", "value");
  RequireWithin(o.maclaurin, kMaclaurinBounds, "--maclaurin", "value");
  FootprintParams params;
  params.initial_speed = o.speed_mps;
  params.eod = o.eod_s;
  params.mass = o.mass_kg;
  params.available_thrust = o.thrust_n;
  params.max_tilt = o.max_tilt_deg / kDegreesPerRadian;
  params.maclaurin_order = o.maclaurin;
  if (std::isnan(o.drag_slope)) {
    const auto table = models::DragTable::Default(models::PropellerConfiguration::kTractor);
    params.drag_slope = planning::CruiseDragSlope(table, o.speed_mps, o.mass_kg);
  } else {
    RequireWithin(o.drag_slope, kDragSlopeBounds, "--drag-slope", "value");
    params.drag_slope = o.drag_slope;
  }
  Require(o.maclaurin == 0 || params.drag_slope > 0.0, "--drag-slope",
          "a drag slope > 0 N*s/m with --maclaurin (the series constants divide by d_x)", params.drag_slope);
  return params;
}

FootprintResult Calculate(const FootprintParams& params) {
  FootprintResult result = planning::CalcFootprint(params);
  if (result.status == FootprintStatus::kCannotHoldAltitude) {
    throw InputError("--thrust-n", "value",
                     fmt::format("at least the weight m g = {:.3f} N to hold level flight, got {}",
                                 params.mass * kGravity, params.available_thrust));
  }
  if (result.status == FootprintStatus::kSingularSystem) throw InputError("--maclaurin", "value", result.message);
  if (!result.warning.empty()) std::fprintf(stderr, "uascma: warning: --maclaurin: %s\n", result.warning.c_str());
  return result;
}

nlohmann::json ShapeJson(const FootprintResult& r) {
  return {{"type", "ellipse"},
          {"frame", "heading: x along the velocity, y to its right, origin under the vehicle"},
          {"center_x_m", r.region.center_x},
          {"semi_axis_x_m", r.region.semi_axis_x},
          {"semi_axis_y_m", r.region.semi_axis_y},
          {"area_m2", r.region.Area()}};
}

std::string ModelName(int maclaurin) {
  return maclaurin == 0 ? "exact exponentials" : fmt::format("order-{} Maclaurin series", maclaurin);
}

void DrawPlot(const Options& o, const FootprintParams& params, const std::string& png) {
  std::vector<double> eods;
  if (params.eod / kPlotSweepCount > kPlotShortestEod) eods.push_back(kPlotShortestEod);
  for (int i = 1; i <= kPlotSweepCount; ++i) eods.push_back(params.eod * i / kPlotSweepCount);
  nlohmann::json footprints = nlohmann::json::array();
  for (double eod : eods) {
    FootprintParams swept = params;
    swept.eod = eod;
    const FootprintResult r = Calculate(swept);
    footprints.push_back({{"eod_s", swept.eod},
                          {"forward_m", r.forward_limit},
                          {"backward_m", r.backward_limit},
                          {"lateral_m", r.lateral_limit},
                          {"shape", ShapeJson(r)}});
  }
  const nlohmann::json data = {
      {"speed_mps", o.speed_mps}, {"eod_s", params.eod}, {"model", ModelName(o.maclaurin)}, {"footprints", footprints}};
  PlotJson("footprint.py", data, png);
}

}  // namespace

void AddFootprintCommand(CLI::App& app) {
  auto options = std::make_shared<Options>();
  CLI::App* command = app.add_subcommand(
      "footprint",
      "Approximate reachable footprint (dissertation §5.3.1, Algorithm 1): minimum-effort level flight\n"
      "(PMP, eqs. 5.3-5.11) bounded by the tilt limit and the available thrust, simulated until the End of\n"
      "Discharge. Prints the forward, backward and lateral limits (m, heading frame: x along the velocity,\n"
      "y to the right) and the ellipse inscribed in them");
  AddBoundedOption(command, "--speed-mps", options->speed_mps, "Initial horizontal speed v_init, m/s", kSpeedBounds)
      ->required();
  AddBoundedOption(command, "--eod-s", options->eod_s, "Battery End of Discharge time, s", kEodBounds)->required();
  AddBoundedOption(command, "--mass-kg", options->mass_kg, "Vehicle mass, kg (default 1.3, docs/defaults.md#vehicle)",
                   kVehicleMassBounds);
  AddBoundedOption(command, "--thrust-n", options->thrust_n,
                   "Available total thrust T_avail, N (default 26.85, Table 2.2 tractor at 1900 us)", kVehicleThrustBounds);
  AddBoundedOption(command, "--max-tilt-deg", options->max_tilt_deg,
                   "Pitch/roll limit, degrees (default 30, the wind-tunnel data's range)", kTiltBounds);
  AddBoundedOption(command, "--drag-slope", options->drag_slope,
                   "Linear drag coefficient d_x of eq. 5.1, N*s/m (default: slope of the default tractor\n"
                   "drag table at --speed-mps and the trim pitch, docs/defaults.md#drag)",
                   kDragSlopeBounds);
  AddBoundedOption(command, "--maclaurin", options->maclaurin,
                   "Replace exp by its order-N Maclaurin series as the dissertation did (N = 5); default 0, exact",
                   kMaclaurinBounds);
  command->add_flag("--json", options->json, "Print the limits, the shape and the bounds as JSON");
  command->add_option("--plot", options->plot,
                      "Also draw the footprints for EOD/10, 2 EOD/10, ..., EOD (and 1 s if shorter) like Fig. 5.4\n"
                      "to this PNG");
  command->callback([options] {
    const Options& o = *options;
    const FootprintParams params = ResolveParams(o);
    const FootprintResult r = Calculate(params);
    if (!o.plot.empty()) DrawPlot(o, params, o.plot);
    if (o.json) {
      PrintJson({{"speed_mps", params.initial_speed},
                 {"eod_s", params.eod},
                 {"mass_kg", params.mass},
                 {"thrust_n", params.available_thrust},
                 {"max_tilt_deg", params.max_tilt * kDegreesPerRadian},
                 {"drag_slope", params.drag_slope},
                 {"model", ModelName(params.maclaurin_order)},
                 {"forward_m", r.forward_limit},
                 {"backward_m", r.backward_limit},
                 {"lateral_m", r.lateral_limit},
                 {"unbounded",
                  {{"forward_m", r.unbounded_forward_limit},
                   {"backward_m", r.unbounded_backward_limit},
                   {"lateral_m", r.unbounded_lateral_limit}}},
                 {"max_force_n", r.max_control_force},
                 {"effective_max_tilt_deg", r.effective_max_tilt * kDegreesPerRadian},
                 {"saturation_s",
                  {{"forward", r.forward.saturation_time},
                   {"backward", r.backward.saturation_time},
                   {"lateral", r.lateral.saturation_time}}},
                 {"shape", ShapeJson(r)},
                 {"series_relative_error",
                  r.series_relative_error ? nlohmann::json(*r.series_relative_error) : nlohmann::json(nullptr)},
                 {"warning", r.warning}});
      return;
    }
    std::string text = fmt::format(
        "Approximate footprint (dissertation §5.3.1, Algorithm 1), {}:\n"
        "  v_init {:g} m/s, EOD {:g} s, mass {:g} kg, T_avail {:g} N, max tilt {:g} deg, d_x {:.4f} N*s/m\n"
        "  forward limit   {:10.2f} m\n"
        "  backward limit  {:10.2f} m\n"
        "  lateral limit   {:10.2f} m (each side)\n"
        "  shape: ellipse in the heading frame (x along the velocity, y right), centre x = {:.2f} m,\n"
        "         semi-axes {:.2f} m along x and {:.2f} m along y\n"
        "  bound: |u| <= {:.3f} N (tilt {:.1f} deg); saturated for the first {:.2f} s forward, {:.2f} s backward,"
        " {:.2f} s lateral\n",
        ModelName(params.maclaurin_order), params.initial_speed, params.eod, params.mass, params.available_thrust,
        params.max_tilt * kDegreesPerRadian, params.drag_slope, r.forward_limit, r.backward_limit, r.lateral_limit,
        r.region.center_x, r.region.semi_axis_x, r.region.semi_axis_y, r.max_control_force,
        r.effective_max_tilt * kDegreesPerRadian, r.forward.saturation_time, r.backward.saturation_time,
        r.lateral.saturation_time);
    if (!o.plot.empty()) text += fmt::format("wrote {}\n", o.plot);
    WriteOutput("", text);
  });
}

}  // namespace uascma::cli
