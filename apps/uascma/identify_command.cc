// uascma identify battery | propulsion | drag — the component models identified from bench data (dissertation §2.5.2,
// §3.3.1.1; docs/identification.md). Parses, calls the identification library, writes the model file.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "battery_record_options.h"
#include "bounded_option.h"
#include "commands.h"
#include "identification_plots.h"
#include "output.h"
#include "plotting.h"
#include "uascma/common/bounds.h"
#include "uascma/common/error.h"
#include "uascma/identification/battery_data.h"
#include "uascma/identification/battery_identification.h"
#include "uascma/identification/drag_identification.h"
#include "uascma/identification/model_files.h"
#include "uascma/identification/propulsion_identification.h"
#include "uascma/identification/thrust_stand_data.h"

namespace uascma::cli {
namespace {

namespace identify_ns = uascma::identification;

void PrintCellSummary(const identify_ns::CellIdentification& result, const identify_ns::BatteryRecord& record,
                      const std::string& out, const std::string& plot) {
  const models::CellParams& p = result.params;
  auto error = [](const std::optional<double>& se, double scale) {
    return se ? fmt::format(" ± {:.3g}", *se * scale) : std::string(" (no standard error)");
  };
  std::string text = fmt::format(
      "{} ({} layout{}), {} samples, {} fitted:\n"
      "  Q  {:.4f} ± {:.4f} Ah\n  R0 {:.2f}{} mΩ\n  R1 {:.2f}{} mΩ, C1 {:.4g}{} F (τ1 {:.3g} s)\n"
      "  fit: RMS {:.2f} mV, max {:.2f} mV (every sample, the rest after the cut-off included: RMS {:.2f} mV)\n",
      record.source, record.layout, record.cycle ? fmt::format(", cycle {}", *record.cycle) : std::string(),
      result.samples, result.fitted_samples, p.capacity_ah, result.capacity_standard_error_ah, 1e3 * p.r0_ohm,
      error(result.r0_standard_error_ohm, 1e3), 1e3 * p.rc[0].resistance_ohm, error(result.r1_standard_error_ohm, 1e3),
      p.rc[0].capacitance_f, error(result.c1_standard_error_f, 1.0), p.rc[0].resistance_ohm * p.rc[0].capacitance_f,
      result.fit_rms_mv, result.fit_max_mv, result.rms_every_sample_mv);
  if (result.charge) {
    const identify_ns::ChargeIdentification& c = *result.charge;
    text += fmt::format(
        "  charge branch: M + M0 {:.2f}{} mV over {} shared SOC nodes (M {:.2f}, M0 {:.2f} mV); "
        "η_charge {:.4f}{}\n  charge record: {} samples, RMS {:.2f} mV, max {:.2f} mV\n",
        1e3 * c.hysteresis_total_v, error(c.hysteresis_total_standard_error_v, 1e3), c.shared_nodes,
        1e3 * p.hysteresis_m_v, 1e3 * p.hysteresis_m0_v, p.eta_charge,
        c.eta_charge_standard_error ? fmt::format(" ± {:.4f}", *c.eta_charge_standard_error) : std::string(" (kept)"),
        c.samples, c.fit_rms_mv, c.fit_max_mv);
  }
  for (const identify_ns::NotIdentified& item : result.not_identified) {
    text += fmt::format("  not identified: {}: {} (kept {:g})\n", item.parameter, item.reason, item.kept_value);
  }
  if (!out.empty()) text += fmt::format("written to {}\n", out);
  if (!plot.empty()) text += fmt::format("plot written to {}\n", plot);
  WriteOutput("", text);
}

void AddIdentifyBattery(CLI::App* parent) {
  struct IdentifyBatteryOptions {
    BatteryOptions read;
    std::string charge;
    int charge_cycle = 1;
    CLI::Option* charge_cycle_option = nullptr;
  };
  auto options = std::make_shared<IdentifyBatteryOptions>();
  CLI::App* command = parent->add_subcommand(
      "battery",
      "The cell model of eqs. 3.1-3.3 (Q, R0, R1/C1, OCV(z)) from one recorded discharge, with\n"
      "uncertainties and what the data could not identify (§3.3.1.1); with --charge, OCV(z) as the\n"
      "mean of the charge and discharge branches, the hysteresis M + M0 and η_charge as well");
  AddBatteryReadOptions(command, &options->read);
  command->get_option("DATA")->expected(1);
  command->add_option("--charge", options->charge,
                      "CSV of the same cell charged from the discharge's empty state to full (current negative;\n"
                      "same layout, --columns and --cells as DATA)");
  options->charge_cycle_option = AddBoundedOption(command, "--charge-cycle", options->charge_cycle,
                                                  "Cycle of the charge file (default: the first)", kRecordCycleBounds);
  command->add_option("--out", options->read.out, "Write the model to this CELL.json");
  command->add_flag("--json", options->read.json,
                    "Print the model file's document (capacity_ah, r0_ohm, fit_rms_mv, ...)");
  command->add_option("--plot", options->read.plot,
                      "Draw the fit to this PNG: measured and model terminal voltage against time, the current and\n"
                      "the error (mV) below, and the OCV(z) curve identified (with --charge: both branches)");
  command->callback([options] {
    const BatteryOptions& read = options->read;
    CheckOutputFile(read.plot, "--plot");  // before the fit
    const identify_ns::BatteryRecord record = ReadRecord(read, read.data.front());
    std::optional<identify_ns::BatteryRecord> charge;
    if (!options->charge.empty()) {
      identify_ns::BatteryReadOptions charge_read = MakeReadOptions(
          read, options->charge_cycle_option->count() > 0 ? std::optional<int>(options->charge_cycle) : std::nullopt);
      charge_read.charge = true;
      charge = identify_ns::ReadBatteryRecord(options->charge, charge_read);
    } else if (options->charge_cycle_option->count() > 0) {
      throw InputError("--charge-cycle", "--charge", "a charge file to pick the cycle of");
    }
    const identify_ns::CellIdentification result = identify_ns::IdentifyCell(record, charge);
    const nlohmann::json document = identify_ns::CellIdentificationJson(result, record, charge);
    // The drawing first: when it fails nothing else has been written.
    if (!read.plot.empty())
      PlotJsonWhole("battery_identification.py", CellFitPlotJson(result, record, charge), read.plot);
    if (!read.out.empty()) WriteOutput(read.out, document.dump(2) + "\n");
    if (read.json) {
      PrintJson(document);
    } else {
      PrintCellSummary(result, record, read.out, read.plot);
    }
  });
}

void AddIdentifyPropulsion(CLI::App* parent) {
  struct Options {
    std::vector<std::string> data;
    std::string out, plot;
    int pole_pairs = 7;
    double diameter_in = 5.0;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = parent->add_subcommand(
      "propulsion", "Eq. 2.12's RPM surface by Least Absolute Residuals and eq. 2.1's C_T from static\n"
                    "thrust-stand steps of ONE motor-propeller pair (all files together), with\n"
                    "leave-one-step-out cross-validation (§2.5.2)");
  command->add_option("THRUSTSTAND", options->data, "CSV files of one pair (RCbenchmark or our layout)")->required();
  AddBoundedOption(command, "--pole-pairs", options->pole_pairs,
                   "Motor pole pairs: RCbenchmark's electrical RPM is divided by it",
                   identify_ns::PropulsionIdentificationOptions::kPolePairsBounds)->required();
  AddBoundedOption(command, "--diameter-in", options->diameter_in, "Propeller diameter (inches)",
                   identify_ns::PropulsionIdentificationOptions::kDiameterBounds)->required();
  command->add_option("--out", options->out, "Write the model to this PROP.json");
  command->add_flag("--json", options->json, "Print the model file's document (c_t, loo_rpm_median_relative_error, ...)");
  command->add_option("--plot", options->plot,
                      "Draw the fit to this PNG (Fig. 2.10): measured RPM against throttle per file with eq. 2.12\n"
                      "along the file's measured power and its 95 % bounds, the leave-one-step-out errors, and the\n"
                      "measured thrust against C_T RPM^2 (eq. 2.1) with the +-10 % band above 1300 us");
  command->callback([options] {
    CheckOutputFile(options->plot, "--plot");  // before the fit
    identify_ns::PropulsionIdentificationOptions identify;
    identify.pole_pairs = options->pole_pairs;
    identify.diameter_in = options->diameter_in;
    std::vector<identify_ns::ThrustStandRecord> records;
    for (const std::string& path : options->data) records.push_back(identify_ns::ReadThrustStandRecord(path, options->pole_pairs));
    const identify_ns::PropulsionIdentification result = identify_ns::IdentifyPropulsion(records, identify);
    const nlohmann::json document = identify_ns::PropulsionIdentificationJson(result, identify);
    if (!options->plot.empty()) {
      PlotJsonWhole("propulsion_identification.py", PropulsionFitPlotJson(result, records, identify), options->plot);
    }
    if (!options->out.empty()) WriteOutput(options->out, document.dump(2) + "\n");
    if (options->json) return PrintJson(document);
    std::string text = fmt::format(
        "{} points from {} file(s); eq. 2.12 with {} terms; leave-one-step-out RPM error median {:.2f} %, max "
        "{:.2f} %, {:.0f} % within the 95 % bounds\n  C_T {:.5g} N/RPM² (dimensionless {:.3f}); thrust from C_T above "
        "{:g} µs: median error {:.2f} %, max {:.2f} % ({} points)\n",
        result.points, records.size(), result.surface.terms.size(), 100.0 * result.loo_rpm_median_relative_error,
        100.0 * result.loo_rpm_max_relative_error, 100.0 * result.loo_share_within_95_bounds,
        result.thrust_coefficient_n_per_rpm2, result.thrust_coefficient_dimensionless, identify.thrust_check_above_us,
        100.0 * result.thrust_median_relative_error, 100.0 * result.thrust_max_relative_error, result.thrust_check_points);
    // What a vehicle file's rotor takes (docs/modelling-choices.md#vehicle-file).
    text += fmt::format("  largest measured thrust {:.3f} N; ", result.max_thrust_n);
    text += result.power_law_exponent
                ? fmt::format("power law P = {:.4g} W x (T / 1 N)^{:.4g} ({} points above {:g} µs)\n",
                              *result.power_law_w_at_one_newton, *result.power_law_exponent, result.power_law_points,
                              identify.thrust_check_above_us)
                : fmt::format("no power law (fewer than 3 points above {:g} µs)\n", identify.thrust_check_above_us);
    for (const std::string& warning : result.warnings) text += "  warning: " + warning + "\n";
    if (!options->plot.empty()) text += fmt::format("plot written to {}\n", options->plot);
    WriteOutput("", text);
  });
}

struct DragOptions {
  std::string data;
  std::string out, plot;
  bool json = false;
};

void AddIdentifyDrag(CLI::App* parent) {
  auto options = std::make_shared<DragOptions>();
  CLI::App* command = parent->add_subcommand(
      "drag", "The simulator's drag table (airspeed x pitch, models/drag.h) from wind-tunnel rows of the bare\n"
              "airframe (§2.5.3.2): columns airspeed_mps, pitch_deg, lift_n, drag_n, throttle_us (0: motors off;\n"
              "other rows are left out). docs/identification.md#drag-table");
  command->add_option("data", options->data, "Wind-tunnel CSV")->required();
  command->add_option("--out", options->out, "Write the table to this DRAG.csv (a vehicle file's drag:)");
  command->add_flag("--json", options->json, "Print the table and the counts as JSON");
  command->add_option("--plot", options->plot,
                      "Draw the table to this PNG: drag against airspeed, one line per pitch, over the\n"
                      "bare-airframe rows it was reduced from");
  command->callback([options] {
    CheckOutputFile(options->plot, "--plot");
    const identify_ns::WindTunnelRecord record = identify_ns::ReadWindTunnelRecord(options->data);
    const identify_ns::DragIdentification result = identify_ns::IdentifyDrag(record);
    const std::string csv = result.DragCsv();
    if (!options->plot.empty()) PlotJsonWhole("drag_table.py", DragTablePlotJson(result, record), options->plot);
    if (!options->out.empty()) WriteOutput(options->out, csv);
    if (options->json) {
      return PrintJson({{"airspeeds_mps", result.airspeeds_mps}, {"pitches_deg", result.pitches_deg},
                        {"drag_n", result.drag_n}, {"zero_speed_added", result.zero_speed_added},
                        {"bare_rows", result.bare_rows}, {"powered_rows", result.powered_rows},
                        {"largest_repeat_count", result.largest_repeat_count},
                        {"largest_repeat_spread_n", result.largest_repeat_spread_n},
                        {"largest_lift_n", result.largest_lift_n}});
    }
    WriteOutput("", fmt::format("{} bare-airframe rows ({} powered rows left out): {} speeds{} x {} pitches; repeats "
                                "per cell up to {}, their spread up to {:.3g} N; |lift| up to {:.3g} N (not used)\n{}",
                                result.bare_rows, result.powered_rows, result.airspeeds_mps.size(),
                                result.zero_speed_added ? " (0 m/s added)" : "", result.pitches_deg.size(),
                                result.largest_repeat_count, result.largest_repeat_spread_n, result.largest_lift_n,
                                options->out.empty() ? csv : "written to " + options->out + "\n") +
                (options->plot.empty() ? std::string() : fmt::format("plot written to {}\n", options->plot)));
  });
}

}  // namespace

void AddIdentifyCommand(CLI::App& app) {
  CLI::App* command = app.add_subcommand("identify", "Identify a component model from bench data (docs/identification.md)");
  command->require_subcommand(1);
  AddIdentifyBattery(command);
  AddIdentifyPropulsion(command);
  AddIdentifyDrag(command);
}

}  // namespace uascma::cli
