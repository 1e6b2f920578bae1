#pragma once
// Text and JSON of a prognostics calibration report (prognostics/calibration.h), for the commands that
// score predicted distributions against truths (`uascma rul --calibrate`, the EOD calibration).
#include <string>

#include <nlohmann/json.hpp>

#include "uascma/prognostics/calibration.h"

namespace uascma::cli {

// {"intervals": [{nominal, fraction, wilson_low, wilson_high, covered, below, above, predictions}],
//  "reliability": [{nominal, observed}], "pit_histogram": [...], "saxena": {alpha, beta, lambda, units,
//  mean_prognostic_horizon_s, alpha_lambda_fraction, mean_relative_accuracy}}.
nlohmann::json CalibrationReportJson(const prognostics::CalibrationReport& report);

// Indented lines: coverage per interval (with its 95 % Wilson interval), the reliability table, the PIT
// histogram and the Saxena et al. metrics.
std::string CalibrationReportText(const prognostics::CalibrationReport& report);

}  // namespace uascma::cli
