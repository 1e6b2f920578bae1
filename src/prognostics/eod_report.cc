// What `uascma eod` reports (eod_report.h, §3.3.2.1).
#include "uascma/prognostics/eod_report.h"

#include <cmath>
#include <string>

#include <fmt/format.h>

#include "uascma/prognostics/eod_reference.h"

namespace uascma::prognostics {
namespace {

nlohmann::json LimitingCellJson(const EodResult& result) {
  if (result.limiting_branch < 0) return nullptr;
  return {{"pack", result.limiting_branch + 1}, {"cell", result.limiting_cell + 1}};
}

std::string FormatDuration(double seconds) {
  if (seconds < 60.0) return fmt::format("{:.1f} s", seconds);
  const double minutes = std::floor(seconds / 60.0);
  return fmt::format("{:.1f} s = {:.0f} min {:.1f} s", seconds, minutes, seconds - 60.0 * minutes);
}

// The reference's EOD relative to the exact one (0 when the reference's is 0).
double ReferenceDifference(const EodResult& result, const EodResult& reference) {
  return reference.eod_s > 0.0 ? (result.eod_s - reference.eod_s) / reference.eod_s : 0.0;
}

nlohmann::json DistributionJson(const EodDistribution& distribution, const EodReportOptions& options) {
  nlohmann::json levels = nlohmann::json::array(), quantiles = nlohmann::json::array();
  for (double level : kEodReportLevels) {
    levels.push_back(level);
    quantiles.push_back(distribution.Quantile(level));
  }
  const EodUncertainty& u = options.uncertainty;
  nlohmann::json json = {{"levels", levels},
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
  if (options.probability_before_s) {
    json["probability_before"] = {{"t_s", *options.probability_before_s},
                                  {"probability", distribution.ProbabilityBefore(*options.probability_before_s)}};
  }
  return json;
}

std::string DistributionText(const EodDistribution& distribution, const EodReportOptions& options) {
  std::string text = fmt::format("EOD distribution ({} CalcPackEod calls):", distribution.evaluations);
  for (double level : kEodReportLevels) {
    text += fmt::format(" p{:02.0f} {:.1f} s", 100.0 * level, distribution.Quantile(level));
  }
  text += "\n";
  if (options.probability_before_s) {
    text += fmt::format("P(EOD < {} s) = {:.4f}\n", *options.probability_before_s,
                        distribution.ProbabilityBefore(*options.probability_before_s));
  }
  return text;
}

std::string Headline(const EodResult& result, const EodReportOptions& options) {
  const double cutoff_v = options.eod.cutoff_v;
  switch (result.status) {
    case EodStatus::kReached:
      return fmt::format("EOD {} at {} A: {} reaches {} V first", FormatDuration(result.eod_s), options.current_a,
                         models::CellLabel(result.limiting_branch, result.limiting_cell), cutoff_v);
    case EodStatus::kAlreadyBelowCutoff:
      return fmt::format("EOD 0 s at {} A: {} is already at or below {} V", options.current_a,
                         models::CellLabel(result.limiting_branch, result.limiting_cell), cutoff_v);
    case EodStatus::kNotReachedWithinHorizon:
      return fmt::format("EOD beyond {} at {} A: no cell reaches {} V within the horizon", FormatDuration(result.eod_s),
                         options.current_a, cutoff_v);
    case EodStatus::kNoBranchConnected:
      return "EOD 0 s: no pack is switched on";
  }
  return "";
}

}  // namespace

EodReport ReportPackEod(const models::BatteryPack& pack, const models::PackState& state,
                        const EodReportOptions& options) {
  EodReport report;
  report.result = CalcPackEod(pack, state, options.current_a, options.eod);
  report.now = pack.CalcOutputs(state, options.current_a);
  report.initial_soc_fraction = state.cells[0][0].soc_fraction;
  if (options.distribution || options.probability_before_s) {
    report.distribution = CalcPackEodDistribution(pack, state, options.current_a, options.uncertainty, options.eod);
  }
  if (options.reference_dt_s > 0.0) {
    report.reference = SimulatePackEod(pack, state, options.current_a, options.reference_dt_s, options.eod);
  }
  return report;
}

nlohmann::json EodReportJson(const EodReport& report, const EodReportOptions& options, const EodBatteryLabel& battery) {
  const EodResult& result = report.result;
  nlohmann::json document = {{"eod_s", result.eod_s},
                             {"status", EodStatusName(result.status)},
                             {"limiting_cell", LimitingCellJson(result)},
                             {"current_a", options.current_a},
                             {"initial_cell_voltage_v", battery.initial_cell_voltage_v},
                             {"initial_soc_fraction", report.initial_soc_fraction},
                             {"health", models::HealthClassName(battery.health)},
                             {"temp_degf", battery.temp_degf},
                             {"use", models::PackActionName(battery.use)},
                             {"cutoff_v", options.eod.cutoff_v},
                             {"branch_current_a", {report.now.split.current_a[0], report.now.split.current_a[1]}},
                             {"bus_voltage_v", report.now.split.bus_voltage_v},
                             {"segments", result.segments}};
  if (report.distribution) document["distribution"] = DistributionJson(*report.distribution, options);
  if (report.reference) {
    document["reference"] = {{"dt_s", options.reference_dt_s},
                             {"eod_s", report.reference->eod_s},
                             {"status", EodStatusName(report.reference->status)},
                             {"limiting_cell", LimitingCellJson(*report.reference)},
                             {"relative_difference", ReferenceDifference(result, *report.reference)}};
  }
  return document;
}

std::string EodReportText(const EodReport& report, const EodReportOptions& options, const EodBatteryLabel& battery) {
  const models::BranchSplit& split = report.now.split;
  std::string text = Headline(report.result, options) + "\n";
  text += fmt::format("  {}, cells at rest at {:g} V (SOC {:.1f} %), health {}, {:g} °F\n",
                      models::PackActionName(battery.use), battery.initial_cell_voltage_v,
                      100.0 * report.initial_soc_fraction, models::HealthClassName(battery.health), battery.temp_degf);
  text +=
      fmt::format("  now: branch currents {:.2f} A and {:.2f} A, bus {:.3f} V (eqs. 3.4-3.7); {} segments propagated\n",
                  split.current_a[0], split.current_a[1], split.bus_voltage_v, report.result.segments);
  if (report.distribution) text += DistributionText(*report.distribution, options);
  if (report.reference) {
    text += fmt::format("fixed-step reference (dt {} s): {}; relative difference {:.2e}\n", options.reference_dt_s,
                        report.reference->BriefReport(), ReferenceDifference(report.result, *report.reference));
  }
  return text;
}

}  // namespace uascma::prognostics
