#include "uascma/identification/battery_validation_report.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include <fmt/format.h>

namespace uascma::identification {

nlohmann::json CellValidationJson(const CellValidation& result, const BatteryRecord& record,
                                  const CellValidationOptions& options) {
  nlohmann::json eod = nlohmann::json::array();
  for (const EodCheck& check : result.eod) {
    eod.push_back({{"at_fraction", check.at_fraction},
                   {"at_time_s", check.at_time_s},
                   {"current_a", check.current_a},
                   {"predicted_s", check.predicted_s},
                   {"actual_s", check.actual_s},
                   {"relative_error", check.relative_error}});
  }
  auto optional = [](const std::optional<double>& value) {
    return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
  };
  return {{"file", record.source},
          {"cycle", record.cycle ? nlohmann::json(*record.cycle) : nlohmann::json(nullptr)},
          {"voltage_rms_mv", result.voltage_rms_mv},
          {"voltage_max_mv", result.voltage_max_mv},
          {"window_samples", result.window_samples},
          {"window_low_v", optional(options.window_low_v)},
          {"window_high_v", optional(options.window_high_v)},
          {"voltage_rms_all_mv", result.voltage_rms_all_mv},
          {"initial_soc_fraction", result.initial_soc_fraction},
          {"initial_soc_clamped", result.initial_soc_clamped},
          {"cutoff_v", options.cutoff_v},
          {"cutoff_time_s", optional(result.cutoff_time_s)},
          {"eod", eod}};
}

std::string CellValidationText(const CellValidation& result, const BatteryRecord& record,
                               const CellValidationOptions& options) {
  std::string text = fmt::format(
      "{}{}: voltage error RMS {:.2f} mV, max {:.2f} mV over {} samples (every sample: RMS "
      "{:.2f} mV); start SOC {:.4f}{}\n",
      record.source, record.cycle ? fmt::format(" cycle {}", *record.cycle) : std::string(), result.voltage_rms_mv,
      result.voltage_max_mv, result.window_samples, result.voltage_rms_all_mv, result.initial_soc_fraction,
      result.initial_soc_clamped ? " (rest voltage outside the OCV table: clamped)" : "");
  if (result.eod.empty())
    text += fmt::format("  the record never reaches the {:g} V cut-off: no EOD check\n", options.cutoff_v);
  for (const EodCheck& check : result.eod) {
    text += fmt::format(
        "  EOD at {:.0f} % of the discharge ({:.1f} s, {:.3g} A): predicted {:.1f} s, actual {:.1f} s "
        "({:+.2f} %)\n",
        100.0 * check.at_fraction, check.at_time_s, check.current_a, check.predicted_s, check.actual_s,
        100.0 * check.relative_error);
  }
  return text;
}

PooledValidationError PoolValidationErrors(const std::vector<CellValidation>& results) {
  PooledValidationError pooled;
  double squares = 0.0;
  for (const CellValidation& result : results) {
    squares += result.voltage_rms_mv * result.voltage_rms_mv * result.window_samples;
    pooled.samples += result.window_samples;
    pooled.max_mv = std::max(pooled.max_mv, result.voltage_max_mv);
  }
  if (pooled.samples > 0) pooled.rms_mv = std::sqrt(squares / pooled.samples);
  return pooled;
}

nlohmann::json CellValidationsJson(const std::vector<CellValidation>& results,
                                   const std::vector<BatteryRecord>& records, const CellValidationOptions& options) {
  nlohmann::json each = nlohmann::json::array();
  for (std::size_t r = 0; r < records.size(); ++r) each.push_back(CellValidationJson(results[r], records[r], options));
  if (records.size() == 1) {
    nlohmann::json single = each.front();
    single["records"] = each;
    return single;
  }
  const PooledValidationError pooled = PoolValidationErrors(results);
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

std::string CellValidationsText(const std::vector<CellValidation>& results, const std::vector<BatteryRecord>& records,
                                const CellValidationOptions& options) {
  std::string text;
  for (std::size_t r = 0; r < records.size(); ++r) text += CellValidationText(results[r], records[r], options);
  if (records.size() > 1) {
    const PooledValidationError pooled = PoolValidationErrors(results);
    text += fmt::format("all {} records: voltage error RMS {:.2f} mV, max {:.2f} mV over {} samples\n", records.size(),
                        pooled.rms_mv, pooled.max_mv, pooled.samples);
  }
  return text;
}

}  // namespace uascma::identification
