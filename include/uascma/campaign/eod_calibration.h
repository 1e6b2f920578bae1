#pragma once
// The load forecast's error model fitted on a training campaign, and the EOD distribution scored on a test campaign
// (the truth: campaign/eod_truth_campaign.h, the model: sim/eod_error_model.h).
//
// Fit (FitEodErrorModel, ours): per cell (battery health, motor health, turbulence, bin of the conditioning variable,
// sim/eod_error_model.h) the mean and sample standard deviation of e = ln(I_actual / I_forecast) over the training
// predictions. A cell with predictions from fewer than kMinFlightsPerCell flights takes the values of the first coarser
// cell that has enough, dropping the bin, then the battery health, then the turbulence, then the motor health, down to
// all predictions whatever their number (a bias measured on a handful of flights is one flight's wind, not the
// forecast's). Each variable is fitted; the one
// whose cells leave the smallest pooled spread (the root mean square of e − its cell's mean over every prediction) is
// kept.
//
// Scoring (ScoreEodCalibration): each scored prediction's distribution is the flight's own (DecisionState: the cell
// its epoch used, through prognostics::CalcPackEodDistribution), given by its quantiles at the standard levels, and
// judged by prognostics/calibration.h per health group and overall: coverage of the central 50/80/90/95 % intervals
// (with Wilson intervals), the reliability table, the PIT histogram, and Saxena et al.'s prognostic horizon, α-λ
// accuracy and relative accuracy (one unit per flight, times from take-off, end of life the cut-off). Beside it, the
// exact load-only check: the standardised error z = (e − μ)/σ of the cell's normal ln-current error, whose central
// interval of probability c holds the true EOD iff |z| ≤ Φ⁻¹((1 + c)/2) (what the distribution would cover if
// CalcPackEodDistribution's split log-normal were exact).
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>
#include "uascma/campaign/eod_truth_campaign.h"

#include "uascma/prognostics/calibration.h"
#include "uascma/sim/eod_error_model.h"

namespace uascma::campaign {

inline constexpr int kMinFlightsPerCell = 10;
// The bins (upper edges; ours): tenths of the plan fraction up to the whole EOD inside the plan, and beyond; the
// time remaining in steps that halve the relative width towards the end of the plan; the point EOD in 100 s steps
// over the campaigns' range (plans of 0.5-0.9 of a ~1,000-1,300 s endurance).
inline const std::vector<double> kPlanFractionEdges = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0};
inline const std::vector<double> kTimeRemainingEdges = {30, 60, 120, 180, 240, 300, 400, 500, 600, 800};
inline const std::vector<double> kPointEodEdges = {100, 200, 300, 400, 500, 600, 700, 800, 900, 1000, 1200};

struct EodErrorFit {
  sim::EodErrorModel model;                                     // the kept variable's
  double pooled_sigma = 0.0;                                    // of the kept model
  std::vector<std::pair<std::string, double>> variable_sigmas;  // each variable's pooled spread
  double overall_sigma = 0.0;                                   // of e without any conditioning
  double overall_mean = 0.0;
  std::int64_t samples = 0, flights = 0;
};
EodErrorFit FitEodErrorModel(const std::vector<EodTruthRun>& runs, const std::string& command);

// The model as JSON ({"kind": "uascma eod error model", "version": 1, "command", "variable", "edges", "cells":
// [{samples, flights, log_mean, log_sigma, battery_health, motor_health, turbulence, bin}] in CellIndex order}) and
// back (InputError naming the file and field), and as the C++ initializer the default table is
// (src/sim/eod_error_table.inc).
nlohmann::json EodErrorModelJson(const sim::EodErrorModel& model);
sim::EodErrorModel ReadEodErrorModel(const std::string& path);
std::string EodErrorModelCxx(const sim::EodErrorModel& model);

inline constexpr std::array<double, 4> kCoverageLevels = {0.50, 0.80, 0.90, 0.95};

struct EodCalibrationGroup {
  std::string label;  // "G", "M", "P", "all"
  std::int64_t samples = 0, flights = 0;
  prognostics::CalibrationReport report;   // of the flights' quantiles
  std::array<std::int64_t, 4> z_inside{};  // the exact load-only check, per kCoverageLevels
  double ZCoverage(int level) const { return samples ? static_cast<double>(z_inside[level]) / samples : 0.0; }
};
struct EodCalibration {
  std::vector<EodCalibrationGroup> groups;  // G, M, P, all
  std::int64_t runs = 0, scored_runs = 0, censored_runs = 0, unscored_predictions = 0;
};
EodCalibration ScoreEodCalibration(const std::vector<EodTruthRun>& runs);

}  // namespace uascma::campaign
