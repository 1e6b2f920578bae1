// uascma rul — motor remaining useful life from a bearing spall (dissertation §3.4.1, eq. 3.8) and the
// per-second jam probability of a spalled motor measured as Table 5.4 was
// (docs/modelling-choices.md#spall-growth-time-scale). --quantiles adds the particle RUL's quantiles; --calibrate
// scores the RUL distribution against the jam times of simulated spalls instead (prognostics/rul_calibration.h).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "bounded_option.h"
#include "calibration_output.h"
#include "commands.h"
#include "output.h"
#include "uascma/common/error.h"
#include "uascma/common/random.h"
#include "uascma/prognostics/motor_rul.h"
#include "uascma/prognostics/rul_calibration.h"

namespace uascma::cli {
namespace {

using namespace uascma::prognostics;

// Our bound on --particles and --runs: 10⁷ samples take ~80 MB and some tens of seconds; more is a typo.
constexpr int kMaxSamples = 10'000'000;
constexpr Bounds kSampleBounds{1.0, kMaxSamples, ""};

// Sub-streams of --seed: the RUL particles and the jam-probability histories draw independently, so
// changing --runs does not change the RUL distribution and vice versa.
constexpr std::uint64_t kParticleStream = 0;
constexpr std::uint64_t kHistoryStream = 1;

void RequireCount(int value, const char* option, const char* what) {
  if (value < 1 || value > kMaxSamples) {
    throw InputError(option, "value",
                     fmt::format("a positive number of {} up to {}, got {}", what, kMaxSamples, value));
  }
}

struct RulCommandOptions {
  int particles = SpallGrowthParams{}.particles;
  std::uint64_t seed = 1;
  int runs = CalibrationOptions{}.runs;
  double time_per_step_s = SpallGrowthParams{}.time_per_growth_step_s;
  bool json = false;
  bool quantiles = false;
  bool calibrate = false;
  int histories = RulCalibrationOptions{}.histories;
  double truth_time_per_step_s = kCampaignTruthTimePerGrowthStep_s;
  std::string mode = RulPredictionModeName(RulPredictionMode::kOnsetCountdown);
};

// --calibrate: the prognoser (--time-per-step, --particles, --mode) against --histories spalls growing at
// --truth-time-per-step; then the distribution `cma-vehicle` and the vehicle-level belief policies read (its τ fitted
// on training histories, survival-conditioned) against the same histories.
struct CalibrationRun {
  RulCalibration calibration;
  std::string mode;
};

CalibrationRun CalibrateWith(const RulCommandOptions& options, double prognosis_time_per_step_s,
                             RulPredictionMode mode) {
  RulCalibrationOptions calibration_options;
  calibration_options.histories = options.histories;
  calibration_options.seed = options.seed;
  calibration_options.truth_time_per_growth_step_s = options.truth_time_per_step_s;
  calibration_options.prognosis_time_per_growth_step_s = prognosis_time_per_step_s;
  calibration_options.particles = options.particles;
  calibration_options.mode = mode;
  return {CalibrateRul(calibration_options), RulPredictionModeName(mode)};
}

nlohmann::json RulCalibrationJson(const RulCommandOptions& options, const CalibrationRun& run) {
  const RulCalibrationOptions& used = run.calibration.options;
  nlohmann::json document = CalibrationReportJson(run.calibration.report);
  document["histories"] = options.histories;
  document["seed"] = options.seed;
  document["mode"] = run.mode;
  document["truth_time_per_growth_step_s"] = used.truth_time_per_growth_step_s;
  document["prognosis_time_per_growth_step_s"] = used.prognosis_time_per_growth_step_s;
  document["time_scale_ratio"] = used.prognosis_time_per_growth_step_s / used.truth_time_per_growth_step_s;
  document["predictions"] = run.calibration.predictions.predictions.size();
  document["censored_histories"] = run.calibration.censored_histories;
  document["mean_jam_time_s"] = run.calibration.mean_jam_time_s;
  document["mean_predicted_rul_at_onset_s"] = run.calibration.mean_predicted_rul_at_onset_s;
  return document;
}

std::string CalibrationText(const RulCommandOptions& options, const CalibrationRun& run) {
  const RulCalibrationOptions& used = run.calibration.options;
  return fmt::format(
      "  {} spall histories (seed {}) growing at {:g} s per step, the prognoser at {:g} s per step (x{:.2f}), {}, a "
      "prediction every 1 s epoch before the jam ({})\n"
      "  mean jam time {:.2f} s after the onset; mean predicted RUL at the onset {:.2f} s; {} censored\n{}",
      options.histories, options.seed, used.truth_time_per_growth_step_s, used.prognosis_time_per_growth_step_s,
      used.prognosis_time_per_growth_step_s / used.truth_time_per_growth_step_s, run.mode,
      run.calibration.predictions.predictions.size(), run.calibration.mean_jam_time_s,
      run.calibration.mean_predicted_rul_at_onset_s, run.calibration.censored_histories,
      CalibrationReportText(run.calibration.report));
}

void RunRulCalibration(const RulCommandOptions& options) {
  const CalibrationRun given =
      CalibrateWith(options, options.time_per_step_s, ParseRulPredictionMode(options.mode, "--mode"));
  const RulTimeScaleFit fit = FitRulTimeScale(options.truth_time_per_step_s);
  const CalibrationRun vehicle =
      CalibrateWith(options, fit.time_per_growth_step_s, RulPredictionMode::kSurvivalConditioned);
  if (options.json) {
    nlohmann::json document = RulCalibrationJson(options, given);
    nlohmann::json fitted = RulCalibrationJson(options, vehicle);
    fitted["training"] = {{"histories", fit.histories},
                          {"seed", fit.seed},
                          {"mean_jam_time_s", fit.mean_jam_time_s},
                          {"censored_histories", fit.censored_histories},
                          {"mean_particle_growth_steps", fit.mean_particle_growth_steps},
                          {"time_per_growth_step_s", fit.time_per_growth_step_s}};
    document["vehicle_level"] = std::move(fitted);
    PrintJson(document);
    return;
  }
  std::printf(
      "Motor RUL calibration, the prognoser at --time-per-step (default Table 5.4's scale: `cma`, `reproduce`)\n%s",
      CalibrationText(options, given).c_str());
  std::printf(
      "\nThe distribution `cma-vehicle` and the vehicle-level belief policies read "
      "(docs/modelling-choices.md#vehicle-rul):\n"
      "  its time scale fitted on %d training histories of the simulated spall (their own seed stream): mean jam time "
      "%.2f s / mean %.2f growth steps = %.4f s per step; %d censored\n%s",
      fit.histories, fit.mean_jam_time_s, fit.mean_particle_growth_steps, fit.time_per_growth_step_s,
      fit.censored_histories, CalibrationText(options, vehicle).c_str());
}

}  // namespace

void AddRulCommand(CLI::App& app) {
  auto options = std::make_shared<RulCommandOptions>();
  CLI::App* command = app.add_subcommand(
      "rul",
      "Motor RUL from a bearing spall (§3.4.1, eq. 3.8: Paris-law growth from 0.01 to 1 mm², C_D 0.2,\n"
      "n 1, zero-mean parameter noise): the RUL distribution of the particles from the initial spall\n"
      "and the per-second jam probability measured over spall histories as Table 5.4's 0.002809 was\n"
      "(jams per spalled 1 s epoch)");
  AddBoundedOption(command, "--particles", options->particles,
                   "Particles of the RUL distribution (default 100, §3.4.1)", kSampleBounds);
  AddSeedOption(command, "--seed", options->seed, "Seed of the random streams (default 1)");
  AddBoundedOption(command, "--runs", options->runs,
                   "Spall histories for the jam probability (default 1000, as in §5.3.2.3)", kSampleBounds);
  AddBoundedOption(command, "--time-per-step", options->time_per_step_s,
                   fmt::format("Seconds per growth step (default {}: calibrated to Table 5.4, "
                               "docs/modelling-choices.md#spall-growth-time-scale)",
                               SpallGrowthParams{}.time_per_growth_step_s),
                   SpallGrowthParams::kTimePerGrowthStepBounds);
  command->add_flag("--json", options->json, "Print the result as JSON");
  command->add_flag("--quantiles", options->quantiles,
                    "Also the particle RUL's quantiles at p = 0.025, 0.05, 0.10, ..., 0.95, 0.975");
  command->add_flag("--calibrate", options->calibrate,
                    "Instead: score the RUL distribution (prognoser at --time-per-step) against the jam times of\n"
                    "--histories simulated spalls growing at --truth-time-per-step: interval coverage, reliability,\n"
                    "PIT, Saxena et al. PH / alpha-lambda / RA; then the same for the distribution cma-vehicle reads\n"
                    "(its time scale fitted on training histories, survival-conditioned)");
  AddBoundedOption(command, "--histories", options->histories, "With --calibrate: spall histories (default 930)",
                   RulCalibrationOptions::kHistoryBounds);
  AddBoundedOption(command, "--truth-time-per-step", options->truth_time_per_step_s,
                   "With --calibrate: seconds per growth step of the simulated spall (default 0.7128, the "
                   "campaigns' fault.time_per_growth_step_s)",
                   SpallGrowthParams::kTimePerGrowthStepBounds);
  command->add_option("--mode", options->mode,
                      "With --calibrate: onset_countdown (the CMA: predicted at the onset, counted down), "
                      "observed_area (re-predicted every epoch from the spall's area) or survival_conditioned (the "
                      "onset's particles that have not jammed yet)");
  command->callback([options] {
    RequireCount(options->particles, "--particles", "particles");
    if (options->calibrate) {
      RequireWithin(options->time_per_step_s, SpallGrowthParams::kTimePerGrowthStepBounds, "--time-per-step", "value");
      RunRulCalibration(*options);
      return;
    }
    RequireCount(options->runs, "--runs", "runs");
    RequireWithin(options->time_per_step_s, SpallGrowthParams::kTimePerGrowthStepBounds, "--time-per-step", "value");
    SpallGrowthParams params;
    params.particles = options->particles;
    params.time_per_growth_step_s = options->time_per_step_s;
    const MotorRulModel model(params);

    RandomStream particle_random(DeriveSeed(options->seed, kParticleStream));
    const RulDistribution rul = model.PredictRulFromArea(params.initial_area_mm2, particle_random);
    RandomStream history_random(DeriveSeed(options->seed, kHistoryStream));
    const JamProbabilityMeasurement jam = model.MeasureJamProbability(options->runs, history_random);
    const char* status = rul.status == RulStatus::kOk ? "ok" : "horizon_reached";
    const std::vector<double> levels = StandardQuantileLevels();
    const std::vector<double> quantiles = CalcRulQuantiles(rul, levels);

    if (options->json) {
      nlohmann::json document = {{"particles", options->particles},
                                 {"seed", options->seed},
                                 {"runs", options->runs},
                                 {"time_per_growth_step_s", params.time_per_growth_step_s},
                                 {"initial_area_mm2", params.initial_area_mm2},
                                 {"failure_area_mm2", params.failure_area_mm2},
                                 {"status", status},
                                 {"rul_mean_s", rul.mean_s},
                                 {"rul_p05_s", rul.p05_s},
                                 {"rul_p50_s", rul.p50_s},
                                 {"rul_p95_s", rul.p95_s},
                                 {"jam_probability_per_s", jam.jam_probability_per_epoch},
                                 {"mean_time_to_jam_s", jam.mean_time_to_jam_s},
                                 {"table_5_4_jam_probability_per_s", kTable54JamProbabilityPerEpoch}};
      if (options->quantiles) document["rul_quantiles"] = {{"levels", levels}, {"quantiles_s", quantiles}};
      PrintJson(document);
      return;
    }
    std::printf(
        "Motor RUL from a %g mm² spall to the %g mm² jam threshold (%d particles, seed %llu, %g s per "
        "growth step)%s\n"
        "  RUL mean %.1f s, p05 %.1f s, p50 %.1f s, p95 %.1f s\n"
        "  jam probability %.6f per 1 s epoch over %d spall histories (mean time to jam %.1f s); "
        "Table 5.4: %.6f\n",
        params.initial_area_mm2, params.failure_area_mm2, options->particles,
        static_cast<unsigned long long>(options->seed), params.time_per_growth_step_s,
        rul.status == RulStatus::kOk ? "" : " — some particles censored at the step horizon", rul.mean_s, rul.p05_s,
        rul.p50_s, rul.p95_s, jam.jam_probability_per_epoch, options->runs, jam.mean_time_to_jam_s,
        kTable54JamProbabilityPerEpoch);
    if (options->quantiles) {
      std::printf("  RUL quantiles:");
      for (std::size_t i = 0; i < levels.size(); ++i) std::printf(" p%g %.1f s", 100.0 * levels[i], quantiles[i]);
      std::printf("\n");
    }
  });
}

}  // namespace uascma::cli
