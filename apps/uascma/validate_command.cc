// uascma validate battery | propulsion — an identified model checked on data not used in its fit, as the
// dissertation reports it (Fig. 3.5: mV error; Fig. 2.11: share within the 95 % bounds, thrust error);
// docs/identification.md.
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "battery_record_options.h"
#include "bounded_option.h"
#include "commands.h"
#include "identification_plots.h"
#include "output.h"
#include "plotting.h"
#include "uascma/common/error.h"
#include "uascma/identification/battery_validation.h"
#include "uascma/identification/battery_validation_report.h"
#include "uascma/identification/model_files.h"
#include "uascma/identification/propulsion_identification.h"
#include "uascma/identification/thrust_stand_data.h"
#include "uascma/models/battery_pack.h"

namespace uascma::cli {
namespace {

namespace ident = uascma::identification;

constexpr Bounds kWindowVoltageBounds{0.0, 5.0, "V"};  // a window on one cell's terminal voltage

void AddValidateBattery(CLI::App* parent) {
  struct ValidateBatteryOptions {
    BatteryOptions read;
    std::string model;
    double cutoff_v = models::kCutoffVoltage;
    double window_low_v = 0.0, window_high_v = 0.0;
    CLI::Option* low_option = nullptr;
    CLI::Option* high_option = nullptr;
  };
  auto options = std::make_shared<ValidateBatteryOptions>();
  CLI::App* command = parent->add_subcommand(
      "battery",
      "Simulate the recorded current of each DATA through an identified cell (CELL.json) from its start:\n"
      "terminal-voltage RMS and max error (mV, Fig. 3.5) and, at 25/50/75 % of the discharge, the EOD\n"
      "predicted from the model's state there against the recorded time to the cut-off (§3.3.2.1)");
  command->add_option("--model", options->model, "CELL.json written by 'uascma identify battery'")->required();
  AddBatteryReadOptions(command, &options->read);
  AddBoundedOption(command, "--cutoff-v", options->cutoff_v,
                   "Cell cut-off voltage of the EOD (default 3.3 V, §3.3.2.1)", models::kCutoffVoltageBounds);
  options->low_option = AddBoundedOption(command, "--window-low-v", options->window_low_v,
                                         "Voltage errors summarised until the measured voltage first falls below this",
                                         kWindowVoltageBounds);
  options->high_option = AddBoundedOption(command, "--window-high-v", options->window_high_v,
                                          "... and from the first sample at or below this", kWindowVoltageBounds);
  command->add_flag("--json", options->read.json,
                    "Print {voltage_rms_mv, voltage_max_mv, eod: [...], records: [...]} as JSON (several DATA: the\n"
                    "errors pooled over their windows, each EOD check with its file)");
  command->add_option("--plot", options->read.plot,
                      "Draw Fig. 3.5 to this PNG: measured and model voltage against time, the error (mV) below,\n"
                      "the summary window shaded, and the EOD checks (predicted against recorded time to cut-off)");
  command->callback([options] {
    CheckOutputFile(options->read.plot, "--plot");  // before the simulation
    if (options->read.plot.size() > 0 && options->read.data.size() > 1) {
      throw InputError(
          "--plot", "DATA",
          fmt::format("one DATA file to draw, got {} (draw each with its own run)", options->read.data.size()));
    }
    const models::SelfCorrectingCell cell = ident::ReadCellModelFile(options->model);
    std::vector<ident::BatteryRecord> records;
    for (const std::string& path : options->read.data) records.push_back(ReadRecord(options->read, path));
    ident::CellValidationOptions validate;
    validate.cutoff_v = options->cutoff_v;
    if (options->low_option->count() > 0) validate.window_low_v = options->window_low_v;
    if (options->high_option->count() > 0) validate.window_high_v = options->window_high_v;
    std::vector<ident::CellValidation> results;
    for (const ident::BatteryRecord& record : records) results.push_back(ident::ValidateCell(cell, record, validate));
    if (!options->read.plot.empty()) {
      PlotJsonWhole("battery_identification.py",
                    CellValidationPlotJson(results.front(), records.front(), validate, options->model),
                    options->read.plot);
    }
    if (options->read.json) return PrintJson(ident::CellValidationsJson(results, records, validate));
    std::string text = ident::CellValidationsText(results, records, validate);
    if (!options->read.plot.empty()) text += fmt::format("plot written to {}\n", options->read.plot);
    WriteOutput("", text);
  });
}

void AddValidatePropulsion(CLI::App* parent) {
  struct ValidatePropulsionOptions {
    std::string model;
    std::vector<std::string> data;
    std::string plot;
    int pole_pairs = 7;
    bool json = false;
  };
  auto options = std::make_shared<ValidatePropulsionOptions>();
  CLI::App* command = parent->add_subcommand(
      "propulsion", "Check an identified pair (PROP.json) on thrust-stand files not used in its fit: share of\n"
                    "measured RPM within the 95 % prediction bounds, RPM and thrust errors (Fig. 2.11); points\n"
                    "outside the fitted throttle/power range are flagged and left out of the figures");
  command->add_option("--model", options->model, "PROP.json written by 'uascma identify propulsion'")->required();
  command->add_option("DATA", options->data, "Thrust-stand CSV files")->required();
  AddBoundedOption(command, "--pole-pairs", options->pole_pairs, "Motor pole pairs (RCbenchmark's electrical RPM)",
                   ident::PropulsionIdentificationOptions::kPolePairsBounds)->required();
  command->add_flag("--json", options->json,
                    "Print {share_within_95_bounds, rpm_median_relative_error, thrust_median_relative_error, ...}");
  command->add_option("--plot", options->plot,
                      "Draw Fig. 2.11 to this PNG: measured RPM per file with the model's 95 % bounds, points\n"
                      "outside the fitted range flagged, and the measured thrust against C_T RPM^2 with the\n"
                      "+-10 % band above 1300 us");
  command->callback([options] {
    CheckOutputFile(options->plot, "--plot");
    const ident::PropulsionModel model = ident::ReadPropulsionModelFile(options->model);
    std::vector<ident::ThrustStandRecord> records;
    for (const std::string& path : options->data) records.push_back(ident::ReadThrustStandRecord(path, options->pole_pairs));
    const ident::PropulsionValidation result =
        ident::ValidatePropulsion(model.surface, model.thrust_coefficient_n_per_rpm2, records);
    if (!options->plot.empty()) {
      PlotJsonWhole("propulsion_identification.py", PropulsionValidationPlotJson(result, records, options->model),
                    options->plot);
    }
    if (options->json) {
      nlohmann::json points = nlohmann::json::array();
      for (const auto& p : result.detail) {
        points.push_back({{"throttle_us", p.throttle_us}, {"power_w", p.power_w}, {"rpm", p.rpm},
                          {"predicted_rpm", p.predicted_rpm}, {"bound_rpm", p.bound_rpm}, {"thrust_n", p.thrust_n},
                          {"predicted_thrust_n", p.predicted_thrust_n}, {"in_range", p.in_range}});
      }
      return PrintJson({{"points", result.points}, {"out_of_range", result.out_of_range},
                        {"share_within_95_bounds", result.share_within_95_bounds},
                        {"rpm_median_relative_error", result.rpm_median_relative_error},
                        {"rpm_max_relative_error", result.rpm_max_relative_error},
                        {"thrust_median_relative_error", result.thrust_median_relative_error}, {"detail", points}});
    }
    WriteOutput("", fmt::format("{} points ({} outside the fitted range, flagged and left out): {:.0f} % of the measured "
                                "RPM within the 95 % bounds; RPM error median {:.2f} %, max {:.2f} %; thrust from C_T "
                                "at the measured RPM: median error {:.2f} %\n",
                                result.points, result.out_of_range, 100.0 * result.share_within_95_bounds,
                                100.0 * result.rpm_median_relative_error, 100.0 * result.rpm_max_relative_error,
                                100.0 * result.thrust_median_relative_error) +
                (options->plot.empty() ? std::string() : fmt::format("plot written to {}\n", options->plot)));
  });
}

}  // namespace

void AddValidateCommand(CLI::App& app) {
  CLI::App* command = app.add_subcommand("validate", "Validate an identified model on other bench data (docs/identification.md)");
  command->require_subcommand(1);
  AddValidateBattery(command);
  AddValidatePropulsion(command);
}

}  // namespace uascma::cli
