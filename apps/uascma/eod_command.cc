// uascma eod — battery end of discharge of the default battery under a constant total current
// (dissertation §3.3.2.1, docs/modelling-choices.md#pack-eod; models: §3.3, §4.3, Tables 3.1–3.2).
//
// The battery: two 3S packs of Table 3.1 cells 1–3 in parallel (Fig. 4.1), switched per --use, every
// cell at rest at --initial-cell-voltage (z = OCV⁻¹(v), docs/defaults.md#battery).
// --health applies Table 3.2 to EVERY cell of both packs (docs/modelling-choices.md#battery-health-label defines the
// classes; which fade makes "M" is our choice): G none; M power fade (R0 → 2 R0); P power and capacity fade
// (R0 → 2 R0, Q → 0.8 Q). --temp-degf below 50 °F multiplies R0 by 1.5 as well.
// JSON: eod_s is always a number (0 when already below the cut-off or no pack is on; the horizon, a lower
// bound, when not reached); limiting_cell is {"pack": 1|2, "cell": 1..3} (1-based) or null.
// --quantiles: the EOD as a distribution (prognostics/eod_distribution.h) from the 1σ of each
// source given (--load-log-mean/--load-log-sigma, --soc-sigma, --r0-log-sigma, --capacity-log-sigma,
// --cold-probability); JSON adds "distribution" {levels, quantiles_s, ...}.
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "bounded_option.h"
#include "commands.h"
#include "output.h"
#include "uascma/common/error.h"
#include "uascma/identification/model_files.h"
#include "uascma/models/battery.h"
#include "uascma/prognostics/eod.h"
#include "uascma/prognostics/eod_distribution.h"
#include "uascma/prognostics/eod_report.h"

namespace uascma::cli {
namespace {

using namespace uascma::models;
using namespace uascma::prognostics;

struct EodCommandOptions {
  double current_a = std::nan("");
  double initial_cell_voltage_v = 4.1;  // inside Table 4.4's 4.05–4.12 V
  std::string health = "G";
  double temp_degf = kRoomTemperatureDegf;
  std::string use = "UseBoth";
  std::string ocv_csv;
  std::string cell_model;  // --cell-model CELL.json: every cell of both packs is this identified cell
  double cutoff_v = kCutoffVoltage;
  double horizon_s = EodOptions{}.horizon_s;
  double reference_dt_s = 0.0;
  bool json = false;
  bool quantiles = false;
  EodUncertainty uncertainty;
  double before_s = std::nan("");  // --probability-before-s
};

PerCell<CellHealth> HealthOfEveryCell(HealthClass health) {
  PerCell<CellHealth> cells{};
  for (auto& pack : cells) pack.fill(CellHealthForClass(health));
  return cells;
}

// --reference-dt-s: 0 (off), else 1 ms to 60 s (our bound: below 1 ms a day's horizon takes 10^8 steps;
// above 60 s the fixed step no longer resolves a discharge of minutes).
constexpr Bounds kReferenceStepBounds{0.001, 60.0, "s"};
// --cold-probability: a probability (given, the class is uncertain).
constexpr Bounds kColdProbabilityBounds{0.0, 1.0, ""};

void Run(const EodCommandOptions& options) {
  // The CLI checked each option against its bounds; EodOptions::IsValid holds the same ones for callers
  // of the library.
  RequireWithin(options.current_a, kPackCurrentBounds, "--current-a", "value");
  RequireWithin(options.temp_degf, kAmbientTemperatureBounds, "--temp-degf", "value");
  RequireWithin(options.cutoff_v, kCutoffVoltageBounds, "--cutoff-v", "value");
  RequireWithin(options.horizon_s, EodOptions::kHorizonBounds, "--horizon-s", "value");
  if (options.reference_dt_s != 0.0) {
    RequireWithin(options.reference_dt_s, kReferenceStepBounds, "--reference-dt-s", "value");
  }
  const HealthClass health = ParseHealthClass(options.health, "--health");
  const PackAction use = ParsePackAction(options.use, "--use");
  if (!options.cell_model.empty() && !options.ocv_csv.empty()) {
    throw InputError("--ocv-csv", "value", "not with --cell-model (the identified cell carries its OCV table)");
  }
  const OcvTable ocv = options.ocv_csv.empty() ? DefaultOcvTable() : LoadOcvTableCsv(options.ocv_csv);
  const BatteryPack pack(options.cell_model.empty()
                             ? MakePackParams(HealthOfEveryCell(health), options.temp_degf, ocv)
                             : identification::MakeIdentifiedPackParams(
                                   identification::ReadCellModelFile(options.cell_model), HealthOfEveryCell(health),
                                   options.temp_degf));
  const PackState state = pack.MakeRestingState(options.initial_cell_voltage_v, use, "--initial-cell-voltage");
  // The packs' internal resistance limits what they deliver: a current that would pull the bus to 0 V or
  // below is one these cells cannot supply (10^9 A once printed a negative bus voltage).
  const double bus_voltage_v = pack.CalcOutputs(state, options.current_a).split.bus_voltage_v;
  if (!(bus_voltage_v > 0.0)) {
    throw InputError("--current-a", "value",
                     fmt::format("a current these packs can deliver at {} V per cell ({} A would pull the bus "
                                 "to {:.2f} V)",
                                 options.initial_cell_voltage_v, options.current_a, bus_voltage_v));
  }
  EodReportOptions report_options;
  report_options.current_a = options.current_a;
  report_options.distribution = options.quantiles;
  report_options.uncertainty = options.uncertainty;
  report_options.reference_dt_s = options.reference_dt_s;
  report_options.eod.cutoff_v = options.cutoff_v;
  report_options.eod.horizon_s = options.horizon_s;
  if (!std::isnan(options.before_s)) report_options.probability_before_s = options.before_s;
  if ((report_options.distribution || report_options.probability_before_s) &&
      options.uncertainty.cold_probability >= 0.0 && options.temp_degf < kColdThresholdDegf) {
    throw InputError("--cold-probability", "value",
                     "an uncertain temperature class with a warm --temp-degf (>= 50 °F): the cold class is the "
                     "warm pack's R0 x 1.5");
  }
  const EodReport report = ReportPackEod(pack, state, report_options);
  const EodBatteryLabel battery{health, options.temp_degf, use, options.initial_cell_voltage_v};
  if (options.json) {
    PrintJson(EodReportJson(report, report_options, battery));
    return;
  }
  std::fputs(EodReportText(report, report_options, battery).c_str(), stdout);
}

}  // namespace

void AddEodCommand(CLI::App& app) {
  auto options = std::make_shared<EodCommandOptions>();
  CLI::App* command = app.add_subcommand(
      "eod",
      "Battery end of discharge (dissertation §3.3.2.1): the time until the first cell of the two\n"
      "parallel 3S packs (Table 3.1 cells, Fig. 4.1) reaches the cut-off under a constant total current,\n"
      "propagating every cell's Enhanced Self-Correcting model (eqs. 3.1-3.3) with the branch split of\n"
      "eqs. 3.4-3.7. Health applies Table 3.2 to every cell: G none, M power fade (R0 x2), P power and\n"
      "capacity fade (R0 x2, Q x0.8); below 50 °F R0 x1.5 as well");
  AddBoundedOption(command, "--current-a", options->current_a,
                   "Total discharge current drawn from the battery, A (up to I_max, Table 4.1)", kPackCurrentBounds)
      ->required();
  command->add_option("--initial-cell-voltage", options->initial_cell_voltage_v,
                      "Rest voltage of every cell, V, within the OCV table (default 4.1; Table 4.4: 4.05-4.12)");
  command->add_option("--health", options->health, "G | M | P (default G; see above)");
  AddBoundedOption(command, "--temp-degf", options->temp_degf,
                   "Ambient temperature, °F (default 77, room temperature: an estimate)", kAmbientTemperatureBounds);
  command->add_option("--use", options->use, "UseBoth | UseBatt1 | UseBatt2 (Table 4.3; default UseBoth)");
  command->add_option("--ocv-csv", options->ocv_csv,
                      "OCV(SOC) table as CSV with header 'soc_percent,ocv_v' (default: docs/defaults.md#battery)");
  command->add_option("--cell-model", options->cell_model,
                      "CELL.json from 'uascma identify battery': every cell of both packs is this cell (Table 3.2's "
                      "health and temperature applied), instead of Table 3.1");
  AddBoundedOption(command, "--cutoff-v", options->cutoff_v, "Cell cut-off voltage, V (default 3.3, §3.3.2.1)",
                   kCutoffVoltageBounds);
  AddBoundedOption(command, "--horizon-s", options->horizon_s, "Longest EOD searched, s (default 86400)",
                   EodOptions::kHorizonBounds);
  command
      ->add_option("--reference-dt-s", options->reference_dt_s,
                   "Also run the fixed-step reference integration with this step, s, and compare [0 (off), or " +
                       kReferenceStepBounds.Text() + "]")
      ->check(CLI::Validator(
          [](const std::string& text) {
            return text == "0" ? std::string() : BoundsValidator(kReferenceStepBounds)(text);
          },
          "STEP"));
  command->add_flag("--quantiles", options->quantiles,
                    "Also the EOD as a distribution from the 1σ given below: quantiles p05-p95");
  AddBoundedOption(command, "--load-log-mean", options->uncertainty.load_log_mean,
                   "With --quantiles: bias of ln(I_actual / I), the load's error (default 0)",
                   EodUncertainty::kLoadLogMeanBounds);
  AddBoundedOption(command, "--load-log-sigma", options->uncertainty.load_log_sigma,
                   "With --quantiles: 1σ of ln(I_actual / I) (default 0)", EodUncertainty::kLogSigmaBounds);
  AddBoundedOption(command, "--soc-sigma", options->uncertainty.soc_sigma,
                   "With --quantiles: 1σ of every cell's SOC estimate, fraction (default 0)",
                   EodUncertainty::kSocSigmaBounds);
  AddBoundedOption(command, "--r0-log-sigma", options->uncertainty.r0_log_sigma,
                   "With --quantiles: 1σ of ln R0 of the cells (default 0)", EodUncertainty::kLogSigmaBounds);
  AddBoundedOption(command, "--capacity-log-sigma", options->uncertainty.capacity_log_sigma,
                   "With --quantiles: 1σ of ln Q of the cells (default 0)", EodUncertainty::kLogSigmaBounds);
  AddBoundedOption(command, "--cold-probability", options->uncertainty.cold_probability,
                   "With --quantiles: P(cold class, R0 x1.5, Table 3.2) when the class is uncertain "
                   "(default: known)",
                   kColdProbabilityBounds);
  AddBoundedOption(command, "--probability-before-s", options->before_s,
                   "Also print P(EOD < this time), s (implies --quantiles)", EodOptions::kHorizonBounds);
  command->add_flag("--json", options->json,
                    "Print JSON: eod_s (a number), status, limiting_cell {pack, cell} (1-based) or null, inputs");
  command->callback([options] { Run(*options); });
}

}  // namespace uascma::cli
