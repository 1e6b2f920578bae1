// uascma validate battery | propulsion — an identified model checked on data not used in its fit, as the
// dissertation reports it (Fig. 3.5: mV error; Fig. 2.11: share within the 95 % bounds, thrust error);
// docs/identification.md.
#include <algorithm>
#include <cmath>
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
#include "uascma/identification/model_files.h"
#include "uascma/identification/propulsion_identification.h"
#include "uascma/identification/thrust_stand_data.h"
#include "uascma/models/battery_pack.h"

namespace uascma::cli {
namespace {

namespace ident = uascma::identification;

constexpr Bounds kWindowVoltageBounds{0.0, 5.0, "V"};  // a window on one cell's terminal voltage

nlohmann::json CellValidationJson(const ident::CellValidation& result, const ident::BatteryRecord& record,
                                  const ident::CellValidationOptions& options) {
  nlohmann::json eod = nlohmann::json::array();
  for (const ident::EodCheck& check : result.eod) {
    eod.push_back({{"at_fraction", check.at_fraction}, {"at_time_s", check.at_time_s}, {"current_a", check.current_a},
                   {"predicted_s", check.predicted_s}, {"actual_s", check.actual_s},
                   {"relative_error", check.relative_error}});
  }
  auto optional = [](const std::optional<double>& value) {
    return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
  };
  return {{"file", record.source}, {"cycle", record.cycle ? nlohmann::json(*record.cycle) : nlohmann::json(nullptr)},
          {"voltage_rms_mv", result.voltage_rms_mv}, {"voltage_max_mv", result.voltage_max_mv},
          {"window_samples", result.window_samples}, {"window_low_v", optional(options.window_low_v)},
          {"window_high_v", optional(options.window_high_v)}, {"voltage_rms_all_mv", result.voltage_rms_all_mv},
          {"initial_soc_fraction", result.initial_soc_fraction}, {"initial_soc_clamped", result.initial_soc_clamped},
          {"cutoff_v", options.cutoff_v}, {"cutoff_time_s", optional(result.cutoff_time_s)}, {"eod", eod}};
}

std::string CellValidationText(const ident::CellValidation& result, const ident::BatteryRecord& record,
                               const ident::CellValidationOptions& options) {
  std::string text = fmt::format(
      "{}{}: voltage error RMS {:.2f} mV, max {:.2f} mV over {} samples (every sample: RMS "
      "{:.2f} mV); start SOC {:.4f}{}\n",
      record.source, record.cycle ? fmt::format(" cycle {}", *record.cycle) : std::string(), result.voltage_rms_mv,
      result.voltage_max_mv, result.window_samples, result.voltage_rms_all_mv, result.initial_soc_fraction,
      result.initial_soc_clamped ? " (rest voltage outside the OCV table: clamped)" : "");
  if (result.eod.empty())
    text += fmt::format("  the record never reaches the {:g} V cut-off: no EOD check\n", options.cutoff_v);
  for (const ident::EodCheck& check : result.eod) {
    text += fmt::format(
        "  EOD at {:.0f} % of the discharge ({:.1f} s, {:.3g} A): predicted {:.1f} s, actual {:.1f} s "
        "({:+.2f} %)\n",
        100.0 * check.at_fraction, check.at_time_s, check.current_a, check.predicted_s, check.actual_s,
        100.0 * check.relative_error);
  }
  return text;
}

// The voltage errors of several records together: RMS over every record's window, the largest error of any.
struct PooledError {
  double rms_mv = 0.0, max_mv = 0.0;
  int samples = 0;
};

PooledError PoolErrors(const std::vector<ident::CellValidation>& results) {
  PooledError pooled;
  double squares = 0.0;
  for (const ident::CellValidation& result : results) {
    squares += result.voltage_rms_mv * result.voltage_rms_mv * result.window_samples;
    pooled.samples += result.window_samples;
    pooled.max_mv = std::max(pooled.max_mv, result.voltage_max_mv);
  }
  if (pooled.samples > 0) pooled.rms_mv = std::sqrt(squares / pooled.samples);
  return pooled;
}

// One record: its object (the keys as they always were) with "records": [it]. Several: the pooled errors, every
// EOD check with its file, and "records".
nlohmann::json ValidationsJson(const std::vector<ident::CellValidation>& results,
                               const std::vector<ident::BatteryRecord>& records,
                               const ident::CellValidationOptions& options) {
  nlohmann::json each = nlohmann::json::array();
  for (std::size_t r = 0; r < records.size(); ++r) each.push_back(CellValidationJson(results[r], records[r], options));
  if (records.size() == 1) {
    nlohmann::json single = each.front();
    single["records"] = each;
    return single;
  }
  const PooledError pooled = PoolErrors(results);
  nlohmann::json eod = nlohmann::json::array();
  for (const nlohmann::json& record : each) {
    for (nlohmann::json check : record["eod"]) {
      check["file"] = record["file"];
      check["cycle"] = record["cycle"];
      eod.push_back(check);
    }
  }
  return {{"voltage_rms_mv", pooled.rms_mv},
          {"voltage_max_mv", pooled.max_mv},
          {"window_samples", pooled.samples},
          {"cutoff_v", options.cutoff_v},
          {"eod", eod},
          {"records", each}};
}

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
    if (options->read.json) return PrintJson(ValidationsJson(results, records, validate));
    std::string text;
    for (std::size_t r = 0; r < records.size(); ++r) text += CellValidationText(results[r], records[r], validate);
    if (records.size() > 1) {
      const PooledError pooled = PoolErrors(results);
      text += fmt::format("all {} records: voltage error RMS {:.2f} mV, max {:.2f} mV over {} samples\n",
                          records.size(), pooled.rms_mv, pooled.max_mv, pooled.samples);
    }
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
