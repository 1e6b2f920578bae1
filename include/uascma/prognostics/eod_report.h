#pragma once
// What `uascma eod` reports of a battery's end of discharge under a constant total current (dissertation §3.3.2.1,
// docs/modelling-choices.md#pack-eod): the EOD (eod.h) with its limiting cell, the branch split and bus voltage now
// (eqs. 3.4-3.7), and on request the EOD as a distribution (eod_distribution.h) and the fixed-step reference
// (eod_reference.h) compared with it.
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "uascma/models/battery_pack.h"
#include "uascma/prognostics/eod.h"
#include "uascma/prognostics/eod_distribution.h"

namespace uascma::prognostics {

// How the battery was made (every cell of one health class, at rest at one voltage), for the report's text and JSON.
struct EodBatteryLabel {
  models::HealthClass health = models::HealthClass::kG;
  double temp_degf = models::kRoomTemperatureDegf;
  models::PackAction use = models::PackAction::kUseBoth;
  double initial_cell_voltage_v = 0.0;
};

struct EodReportOptions {
  double current_a = 0.0;  // A, the constant total discharge current
  EodOptions eod;          // the cut-off and the horizon
  // Also the EOD as a distribution of `uncertainty` (quantiles at kEodReportLevels), and with `probability_before_s`
  // P(EOD < that time).
  bool distribution = false;
  EodUncertainty uncertainty;
  std::optional<double> probability_before_s;  // s; implies `distribution`
  double reference_dt_s = 0.0;                 // s: > 0 also runs the fixed-step reference at this step
};

// The levels of the distribution's quantiles (ours: the ends of the 90 % and 50 % central intervals, the median and
// the 80 % interval's ends).
inline constexpr double kEodReportLevels[] = {0.05, 0.10, 0.25, 0.50, 0.75, 0.90, 0.95};

struct EodReport {
  EodResult result;                   // CalcPackEod
  models::PackOutputs now;            // the outputs at the state and the current
  double initial_soc_fraction = 0.0;  // pack 1 cell 1's SOC
  std::optional<EodDistribution> distribution;
  std::optional<EodResult> reference;
};

// The report (header comment). InputError from the EOD, its distribution or the reference for invalid options.
EodReport ReportPackEod(const models::BatteryPack& pack, const models::PackState& state,
                        const EodReportOptions& options);

// {"eod_s", "status", "limiting_cell": {"pack", "cell"} 1-based or null, the inputs, "branch_current_a",
// "bus_voltage_v", "segments"}, with "distribution" {levels, quantiles_s, the mixture, the uncertainty and
// "probability_before" {t_s, probability}} and "reference" {dt_s, eod_s, status, limiting_cell,
// relative_difference} when computed.
nlohmann::json EodReportJson(const EodReport& report, const EodReportOptions& options, const EodBatteryLabel& battery);
// The same as text: a headline by the EOD's status, the battery, the split now, then the distribution and the
// reference.
std::string EodReportText(const EodReport& report, const EodReportOptions& options, const EodBatteryLabel& battery);

}  // namespace uascma::prognostics
