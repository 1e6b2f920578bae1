// uascma calibrate — the EOD's distribution from measured errors:
//   calibrate eod-error   fly a TRAINING campaign's NoOp twins to the cut-off (sim/eod_truth.h), measure the load
//                         forecast's error and fit the error table (campaign/eod_calibration.h); --out F.json, --cxx
//                         F.inc (the committed default table is that source);
//   calibrate eod         fly a TEST campaign (another seed) the same way and score the flights' EOD distributions:
//                         coverage of the 50/80/90/95 % intervals per health group, the reliability table and plot.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "bounded_option.h"
#include "calibration_output.h"
#include "commands.h"
#include "output.h"
#include "plotting.h"
#include "uascma/campaign/config.h"
#include "uascma/campaign/eod_calibration.h"
#include "uascma/campaign/eod_truth_campaign.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"

namespace uascma::cli {
namespace {

// Our bounds: 1 to 10⁵ runs (a 930-run campaign of twins flown to the cut-off takes minutes); threads as elsewhere.
constexpr Bounds kCalibrationRunsBounds{1.0, 100000.0, "runs"};
constexpr Bounds kCalibrationThreadsBounds{1.0, 256.0, "threads"};
// Default seeds (ours): the training and the test campaign apart from each other and from the default campaign's 1.
constexpr std::uint64_t kTrainingSeed = 2901;
constexpr std::uint64_t kTestSeed = 2902;

struct CalibrationCampaignOptions {
  std::string config;  // campaign YAML; empty: the built-in defaults (examples/campaign.yaml)
  std::int64_t runs = 930;
  std::uint64_t seed = 0;
  int jobs = 1;
};

void AddCampaignOptions(CLI::App* command, CalibrationCampaignOptions& options, std::uint64_t default_seed,
                        const char* which) {
  options.seed = default_seed;
  command->add_option(
      "--config", options.config,
      "Campaign file whose run sampling is used (default: the built-in defaults, examples/campaign.yaml)");
  AddBoundedOption(command, "--runs", options.runs, "Runs (each one NoOp twin flown to the cut-off; default 930)",
                   kCalibrationRunsBounds);
  AddSeedOption(command, "--seed", options.seed,
                fmt::format("Seed of the {} campaign (default {})", which, default_seed));
  AddBoundedOption(command, "--jobs", options.jobs, "Threads (the results do not depend on it)",
                   kCalibrationThreadsBounds);
}

std::vector<campaign::EodTruthRun> FlyTwins(const CalibrationCampaignOptions& options,
                                            std::shared_ptr<const sim::EodErrorModel> model = nullptr) {
  campaign::CampaignConfig config =
      options.config.empty() ? campaign::CampaignConfig{} : campaign::LoadCampaignConfig(options.config);
  campaign::EodTruthCampaignOptions fly;
  fly.seed = options.seed;
  fly.runs = options.runs;
  fly.jobs = options.jobs;
  fly.eod_error_model = std::move(model);
  return campaign::FlyEodTruthCampaign(config, fly);
}

std::string CampaignArguments(const CalibrationCampaignOptions& options) {
  std::string out = fmt::format("--runs {} --seed {}", options.runs, options.seed);
  if (!options.config.empty()) out += " --config " + options.config;
  return out;
}

void AddErrorCommand(CLI::App& calibrate) {
  struct Options {
    CalibrationCampaignOptions campaign;
    std::string out, cxx, samples;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = calibrate.add_subcommand(
      "eod-error",
      "Measure the load forecast's error over a training campaign (each run's NoOp twin holds at the top of its\n"
      "final descent until the cut-off: the true EOD of every 1 Hz prediction) and fit the error table of the\n"
      "EOD distribution per health group (sim/eod_error_model.h)");
  AddCampaignOptions(command, options->campaign, kTrainingSeed, "training");
  command->add_option("--out", options->out, "Write the error table as JSON (read by `calibrate eod --model`)");
  command->add_option("--cxx", options->cxx, "Write the table as the C++ initializer of src/sim/eod_error_table.inc");
  command->add_option("--samples", options->samples, "Write every scored prediction as CSV (for analysis)");
  command->add_flag("--json", options->json, "Print the fit as JSON");
  command->callback([options] {
    const auto runs = FlyTwins(options->campaign, std::make_shared<const sim::EodErrorModel>());
    if (!options->samples.empty()) WriteOutput(options->samples, campaign::EodTruthSamplesCsv(runs));
    const std::string made_by = "uascma calibrate eod-error " + CampaignArguments(options->campaign);
    const campaign::EodErrorFit fit = campaign::FitEodErrorModel(runs, made_by);
    const nlohmann::json model = campaign::EodErrorModelJson(fit.model);
    if (!options->out.empty()) WriteOutput(options->out, model.dump(2) + "\n");
    if (!options->cxx.empty()) WriteOutput(options->cxx, campaign::EodErrorModelCxx(fit.model));
    const auto censored = std::count_if(runs.begin(), runs.end(), [](const auto& run) { return !run.cutoff_time_s; });
    nlohmann::json variables = nlohmann::json::object();
    for (const auto& [name, sigma] : fit.variable_sigmas) variables[name] = sigma;
    nlohmann::json summary = {{"samples", fit.samples},
                              {"flights", fit.flights},
                              {"runs", runs.size()},
                              {"censored_runs", censored},
                              {"overall_log_mean", fit.overall_mean},
                              {"overall_log_sigma", fit.overall_sigma},
                              {"pooled_log_sigma", variables},
                              {"variable", sim::EodErrorVariableName(fit.model.variable())},
                              {"model", model}};
    if (options->json) {
      PrintJson(summary);
      return;
    }
    std::printf(
        "Load forecast error ln(I_actual / I_forecast) over %lld predictions of %lld flights (%lld runs, %lld "
        "censored)\n  overall: mean %+.4f, sd %.4f\n  pooled sd inside the cells (battery health, motor "
        "health, turbulence, bin) by variable:",
        static_cast<long long>(fit.samples), static_cast<long long>(fit.flights), static_cast<long long>(runs.size()),
        static_cast<long long>(censored), fit.overall_mean, fit.overall_sigma);
    for (const auto& [name, sigma] : fit.variable_sigmas) std::printf(" %s %.4f", name.c_str(), sigma);
    std::printf("\n  kept: %s\n", sim::EodErrorVariableName(fit.model.variable()));
  });
}

nlohmann::json CalibrationJson(const campaign::EodCalibration& calibration) {
  nlohmann::json groups = nlohmann::json::array();
  for (const campaign::EodCalibrationGroup& g : calibration.groups) {
    nlohmann::json coverage = nlohmann::json::object(), load_only = nlohmann::json::object();
    for (const prognostics::IntervalCoverage& c : g.report.intervals) {
      coverage[fmt::format("{:.0f}", 100 * c.nominal)] = c.fraction;
    }
    for (int l = 0; l < 4; ++l) load_only[fmt::format("{:.0f}", 100 * campaign::kCoverageLevels[l])] = g.ZCoverage(l);
    groups.push_back({{"group", g.label},
                      {"flights", g.flights},
                      {"samples", g.samples},
                      {"coverage", coverage},
                      {"load_only_coverage", load_only},
                      {"report", CalibrationReportJson(g.report)}});
  }
  return {{"runs", calibration.runs},
          {"scored_runs", calibration.scored_runs},
          {"censored_runs", calibration.censored_runs},
          {"unscored_predictions", calibration.unscored_predictions},
          {"groups", groups}};
}

void PrintCalibration(const campaign::EodCalibration& c, const std::string& model_source) {
  std::printf("EOD calibration: %lld runs, %lld scored, %lld censored (%lld predictions unscored); error table: %s\n",
              static_cast<long long>(c.runs), static_cast<long long>(c.scored_runs),
              static_cast<long long>(c.censored_runs), static_cast<long long>(c.unscored_predictions),
              model_source.c_str());
  std::printf(
      "  coverage of the true EOD by the central intervals (%%), and the load-only check (|z|), per group:\n"
      "  group  flights  predictions    50    80    90    95  |  50    80    90    95  |  PH (s)  a-l   RA\n");
  for (const auto& g : c.groups) {
    std::printf("  %-5s  %7lld  %11lld ", g.label.c_str(), static_cast<long long>(g.flights),
                static_cast<long long>(g.samples));
    for (const prognostics::IntervalCoverage& i : g.report.intervals) std::printf(" %5.1f", 100 * i.fraction);
    std::printf("  |");
    for (int l = 0; l < 4; ++l) std::printf(" %5.1f", 100 * g.ZCoverage(l));
    const prognostics::SaxenaMetrics& s = g.report.saxena;
    std::printf("  | %6.1f  %4.2f  %5.3f\n", s.mean_prognostic_horizon_s, s.alpha_lambda_fraction,
                s.mean_relative_accuracy);
  }
  for (const auto& g : c.groups) std::printf("  %s:\n%s", g.label.c_str(), CalibrationReportText(g.report).c_str());
}

void AddEodCalibrationCommand(CLI::App& calibrate) {
  struct Options {
    CalibrationCampaignOptions campaign;
    std::string model, plot;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = calibrate.add_subcommand(
      "eod",
      "Score the EOD distribution on a test campaign: the NoOp twins' true EODs against each 1 Hz prediction's\n"
      "distribution, coverage of the 50/80/90/95 % intervals per health group, the reliability table");
  AddCampaignOptions(command, options->campaign, kTestSeed, "test");
  command->add_option("--model", options->model,
                      "Error table JSON (`calibrate eod-error --out`; default: the "
                      "committed table)");
  command->add_option("--plot", options->plot, "Draw the reliability diagram (PNG, PDF or SVG)");
  command->add_flag("--json", options->json, "Print the result as JSON");
  command->callback([options] {
    std::shared_ptr<const sim::EodErrorModel> model;
    if (!options->model.empty()) {
      model = std::make_shared<const sim::EodErrorModel>(campaign::ReadEodErrorModel(options->model));
    }
    const std::string source = model ? options->model : sim::EodErrorModel::Default().command();
    const auto runs = FlyTwins(options->campaign, model);
    const campaign::EodCalibration calibration = campaign::ScoreEodCalibration(runs);
    nlohmann::json out = CalibrationJson(calibration);
    out["error_model"] = source.empty() ? "none (the empty table)" : source;
    out["campaign"] = CampaignArguments(options->campaign);
    if (!options->plot.empty()) PlotJson("eod_reliability.py", out, options->plot);
    if (options->json) {
      PrintJson(out);
      return;
    }
    PrintCalibration(calibration, source.empty() ? "none (the empty table)" : source);
  });
}

}  // namespace

void AddCalibrateCommand(CLI::App& app) {
  CLI::App* command = app.add_subcommand("calibrate", "Calibrate the prognoses' distributions against the simulator");
  command->require_subcommand(1);
  AddErrorCommand(*command);
  AddEodCalibrationCommand(*command);
}

}  // namespace uascma::cli
