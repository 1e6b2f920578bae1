// Text and JSON of a prognostics calibration report.
#include "calibration_output.h"

#include <fmt/format.h>

namespace uascma::cli {

nlohmann::json CalibrationReportJson(const prognostics::CalibrationReport& report) {
  nlohmann::json intervals = nlohmann::json::array();
  for (const prognostics::IntervalCoverage& c : report.intervals) {
    intervals.push_back({{"nominal", c.nominal},
                         {"fraction", c.fraction},
                         {"wilson_low", c.wilson_low},
                         {"wilson_high", c.wilson_high},
                         {"covered", c.covered},
                         {"below", c.below},
                         {"above", c.above},
                         {"predictions", c.predictions}});
  }
  nlohmann::json reliability = nlohmann::json::array();
  for (const prognostics::ReliabilityRow& row : report.reliability) {
    reliability.push_back({{"nominal", row.nominal}, {"observed", row.observed}});
  }
  const prognostics::SaxenaMetrics& s = report.saxena;
  return {{"intervals", intervals},
          {"reliability", reliability},
          {"pit_histogram", report.pit_histogram},
          {"saxena",
           {{"alpha", s.options.alpha},
            {"beta", s.options.beta},
            {"lambda", s.options.lambda},
            {"units", s.units},
            {"mean_prognostic_horizon_s", s.mean_prognostic_horizon_s},
            {"alpha_lambda_fraction", s.alpha_lambda_fraction},
            {"mean_relative_accuracy", s.mean_relative_accuracy}}}};
}

std::string CalibrationReportText(const prognostics::CalibrationReport& report) {
  std::string text;
  for (const prognostics::IntervalCoverage& c : report.intervals) {
    const double n = c.predictions > 0 ? c.predictions : 1.0;
    text += fmt::format(
        "  {:.0f} % interval covers {:.1f} % [{:.1f}, {:.1f}] of {} (truth below {:.1f} %, above {:.1f} %)\n",
        100.0 * c.nominal, 100.0 * c.fraction, 100.0 * c.wilson_low, 100.0 * c.wilson_high, c.predictions,
        100.0 * c.below / n, 100.0 * c.above / n);
  }
  text += "  reliability (nominal: observed P(truth <= q)):";
  for (const prognostics::ReliabilityRow& row : report.reliability) {
    text += fmt::format(" {:.2f}:{:.3f}", row.nominal, row.observed);
  }
  text += "\n  PIT histogram (10 bins):";
  for (int count : report.pit_histogram) text += fmt::format(" {}", count);
  const prognostics::SaxenaMetrics& s = report.saxena;
  text += fmt::format(
      "\n  Saxena et al. (alpha {}, beta {}, lambda {}; {} units): mean PH {:.1f} s, alpha-lambda met by {:.1f} %, "
      "mean RA {:.3f}\n",
      s.options.alpha, s.options.beta, s.options.lambda, s.units, s.mean_prognostic_horizon_s,
      100.0 * s.alpha_lambda_fraction, s.mean_relative_accuracy);
  return text;
}

}  // namespace uascma::cli
