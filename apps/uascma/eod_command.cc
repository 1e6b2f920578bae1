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
#include "uascma/prognostics/eod_reference.h"

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

// The levels printed by --quantiles (ours: the ends of the 90 % and 50 % central intervals, the median and
// the 80 % interval's ends).
constexpr double kPrintedLevels[] = {0.05, 0.10, 0.25, 0.50, 0.75, 0.90, 0.95};

// --quantiles: the distribution into the JSON document and its text lines.
std::string AddDistribution(const EodCommandOptions& options, const BatteryPack& pack, const PackState& state,
                            const EodOptions& eod_options, nlohmann::json& document) {
  if (options.uncertainty.cold_probability >= 0.0 && options.temp_degf < kColdThresholdDegf) {
    throw InputError("--cold-probability", "value",
                     "an uncertain temperature class with a warm --temp-degf (>= 50 °F): the cold class is the "
                     "warm pack's R0 x 1.5");
  }
  const EodDistribution distribution =
      CalcPackEodDistribution(pack, state, options.current_a, options.uncertainty, eod_options);
  nlohmann::json levels = nlohmann::json::array(), quantiles = nlohmann::json::array();
  std::string text = fmt::format("EOD distribution ({} CalcPackEod calls):", distribution.evaluations);
  for (double level : kPrintedLevels) {
    const double quantile_s = distribution.Quantile(level);
    levels.push_back(level);
    quantiles.push_back(quantile_s);
    text += fmt::format(" p{:02.0f} {:.1f} s", 100.0 * level, quantile_s);
  }
  text += "\n";
  const EodUncertainty& u = options.uncertainty;
  document["distribution"] = {{"levels", levels},
                              {"quantiles_s", quantiles},
                              {"components", distribution.components},
                              {"weight", {distribution.weight[0], distribution.weight[1]}},
                              {"centre_eod_s", {distribution.centre_eod_s[0], distribution.centre_eod_s[1]}},
                              {"log_sigma", {distribution.log_sigma[0], distribution.log_sigma[1]}},
                              {"log_sigma_above", {distribution.log_sigma_above[0], distribution.log_sigma_above[1]}},
                              {"evaluations", distribution.evaluations},
                              {"uncertainty",
                               {{"load_log_mean", u.load_log_mean},
                                {"load_log_sigma", u.load_log_sigma},
                                {"soc_sigma", u.soc_sigma},
                                {"r0_log_sigma", u.r0_log_sigma},
                                {"capacity_log_sigma", u.capacity_log_sigma},
                                {"cold_probability", u.cold_probability}}}};
  if (!std::isnan(options.before_s)) {
    const double probability = distribution.ProbabilityBefore(options.before_s);
    document["distribution"]["probability_before"] = {{"t_s", options.before_s}, {"probability", probability}};
    text += fmt::format("P(EOD < {} s) = {:.4f}\n", options.before_s, probability);
  }
  return text;
}

PerCell<CellHealth> HealthOfEveryCell(HealthClass health) {
  PerCell<CellHealth> cells{};
  for (auto& pack : cells) pack.fill(CellHealthForClass(health));
  return cells;
}

nlohmann::json LimitingCellJson(const EodResult& result) {
  if (result.limiting_branch < 0) return nullptr;
  return {{"pack", result.limiting_branch + 1}, {"cell", result.limiting_cell + 1}};
}

std::string FormatDuration(double seconds) {
  if (seconds < 60.0) return fmt::format("{:.1f} s", seconds);
  const double minutes = std::floor(seconds / 60.0);
  return fmt::format("{:.1f} s = {:.0f} min {:.1f} s", seconds, minutes, seconds - 60.0 * minutes);
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

  EodOptions eod_options;
  eod_options.cutoff_v = options.cutoff_v;
  eod_options.horizon_s = options.horizon_s;
  const EodResult result = CalcPackEod(pack, state, options.current_a, eod_options);
  const PackOutputs now = pack.CalcOutputs(state, options.current_a);
  // The packs' internal resistance limits what they deliver: a current that would pull the bus to 0 V or
  // below is one these cells cannot supply (10^9 A once printed a negative bus voltage).
  if (!(now.split.bus_voltage_v > 0.0)) {
    throw InputError("--current-a", "value",
                     fmt::format("a current these packs can deliver at {} V per cell ({} A would pull the bus "
                                 "to {:.2f} V)",
                                 options.initial_cell_voltage_v, options.current_a, now.split.bus_voltage_v));
  }
  const double soc = state.cells[0][0].soc_fraction;

  nlohmann::json document = {{"eod_s", result.eod_s},
                             {"status", EodStatusName(result.status)},
                             {"limiting_cell", LimitingCellJson(result)},
                             {"current_a", options.current_a},
                             {"initial_cell_voltage_v", options.initial_cell_voltage_v},
                             {"initial_soc_fraction", soc},
                             {"health", HealthClassName(health)},
                             {"temp_degf", options.temp_degf},
                             {"use", PackActionName(use)},
                             {"cutoff_v", options.cutoff_v},
                             {"branch_current_a", {now.split.current_a[0], now.split.current_a[1]}},
                             {"bus_voltage_v", now.split.bus_voltage_v},
                             {"segments", result.segments}};
  std::string reference_text;
  const bool wants_distribution = options.quantiles || !std::isnan(options.before_s);
  if (wants_distribution) reference_text += AddDistribution(options, pack, state, eod_options, document);
  if (options.reference_dt_s > 0.0) {
    const EodResult reference = SimulatePackEod(pack, state, options.current_a, options.reference_dt_s, eod_options);
    const double difference = reference.eod_s > 0.0 ? (result.eod_s - reference.eod_s) / reference.eod_s : 0.0;
    document["reference"] = {{"dt_s", options.reference_dt_s},
                             {"eod_s", reference.eod_s},
                             {"status", EodStatusName(reference.status)},
                             {"limiting_cell", LimitingCellJson(reference)},
                             {"relative_difference", difference}};
    reference_text += fmt::format("fixed-step reference (dt {} s): {}; relative difference {:.2e}\n",
                                  options.reference_dt_s, reference.BriefReport(), difference);
  }
  if (options.json) {
    PrintJson(document);
    return;
  }
  std::string headline;
  switch (result.status) {
    case EodStatus::kReached:
      headline = fmt::format("EOD {} at {} A: {} reaches {} V first", FormatDuration(result.eod_s), options.current_a,
                             CellLabel(result.limiting_branch, result.limiting_cell), options.cutoff_v);
      break;
    case EodStatus::kAlreadyBelowCutoff:
      headline = fmt::format("EOD 0 s at {} A: {} is already at or below {} V", options.current_a,
                             CellLabel(result.limiting_branch, result.limiting_cell), options.cutoff_v);
      break;
    case EodStatus::kNotReachedWithinHorizon:
      headline = fmt::format("EOD beyond {} at {} A: no cell reaches {} V within the horizon",
                             FormatDuration(result.eod_s), options.current_a, options.cutoff_v);
      break;
    case EodStatus::kNoBranchConnected:
      headline = "EOD 0 s: no pack is switched on";
      break;
  }
  std::printf("%s\n", headline.c_str());
  std::printf("  %s, cells at rest at %g V (SOC %.1f %%), health %s, %g °F\n", PackActionName(use),
              options.initial_cell_voltage_v, 100.0 * soc, HealthClassName(health), options.temp_degf);
  std::printf("  now: branch currents %.2f A and %.2f A, bus %.3f V (eqs. 3.4-3.7); %d segments propagated\n",
              now.split.current_a[0], now.split.current_a[1], now.split.bus_voltage_v, result.segments);
  std::fputs(reference_text.c_str(), stdout);
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
