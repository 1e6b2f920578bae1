// The EOD truth over a campaign and the load forecast's error (eod_truth_campaign.h).
#include "uascma/campaign/eod_truth_campaign.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "uascma/campaign/sampler.h"
#include "uascma/campaign/world.h"
#include "uascma/common/parallel_for.h"
#include "uascma/prognostics/calibration.h"
#include "uascma/prognostics/eod.h"
#include "uascma/sim/eod_truth.h"
#include "uascma/sim/flight.h"

namespace uascma::campaign {
namespace {

// ln EOD(e^x) − ln target: strictly decreasing in x; +inf when the EOD is not reached (no discharge to speak of),
// −inf when a cell is at the cut-off already.
double LogEodResidual(const models::BatteryPack& pack, const models::PackState& state, double log_current,
                      double log_target) {
  const prognostics::EodResult eod = prognostics::CalcPackEod(pack, state, std::exp(log_current));
  if (eod.status == prognostics::EodStatus::kNotReachedWithinHorizon) return INFINITY;
  if (eod.status != prognostics::EodStatus::kReached || !(eod.eod_s > 0.0)) return -INFINITY;
  return std::log(eod.eod_s) - log_target;
}

EodTruthRun FlyTruthRun(const CampaignConfig& config, const CampaignWorld& world,
                        const EodTruthCampaignOptions& options, std::int64_t run_index) {
  SampledRun sampled = SampleRun(config, world, options.seed, run_index);
  sampled.scenario.eod_error_model = options.eod_error_model;
  const sim::FlightModel model(sampled.scenario);
  const sim::EodTruthFlight flight = sim::FlyEodTruthTwin(model);
  EodTruthRun run;
  run.run_index = run_index;
  run.battery_health = static_cast<int>(model.battery_health());
  run.outcome = flight.outcome;
  run.cutoff_time_s = flight.cutoff_time_s;
  run.hold_start_s = flight.hold_start_s;
  run.cruise_speed_mps = sampled.cruise_speed_mps;
  run.wind_speed_mps = sampled.scenario.wind.mean_speed;
  run.turbulence = static_cast<int>(sampled.scenario.wind.turbulence);
  run.cold = sampled.cold;
  run.fault = sampled.scenario.fault.enabled;
  run.predictions = static_cast<int>(flight.predictions.size());
  static const std::vector<double> levels = prognostics::StandardQuantileLevels();
  for (const sim::EodTruthPrediction& p : flight.predictions) {
    const double truth = flight.cutoff_time_s ? flight.TrueEod(p) : 0.0;
    const std::optional<double> actual = truth > 0.0 && p.eod_current_a > 0.0
                                             ? CalcEquivalentCurrent(model.pack(), p.pack, truth, p.eod_current_a)
                                             : std::nullopt;
    if (!actual) {
      ++run.unscored;
      continue;
    }
    EodTruthSample s;
    s.time_s = p.time_s;
    s.battery_health = run.battery_health;
    s.motor_health = static_cast<int>(p.motor_health);
    s.turbulence = static_cast<int>(sampled.scenario.wind.turbulence);
    s.flight_time_remaining_s = p.flight_time_remaining_s;
    s.eod_s = p.eod_s;
    s.true_eod_s = truth;
    s.current_a = p.eod_current_a;
    s.log_ratio = std::log(*actual / p.eod_current_a);
    const sim::EodDistributionSummary& d = p.inputs.eod_distribution_value();
    s.eod_p05_s = d.p05_s;
    s.eod_p50_s = d.p50_s;
    s.eod_p95_s = d.p95_s;
    s.eod_short_probability = d.short_probability;
    s.eod_load_log_mean = p.uncertainty.load_log_mean;
    s.eod_load_log_sigma = p.uncertainty.load_log_sigma;
    // Without spread (an empty table: the training campaign) a point at the EOD.
    for (double level : levels) {
      s.eod_quantiles_s.push_back(p.uncertainty.load_log_sigma > 0.0 ? p.distribution.Quantile(level) : p.eod_s);
    }
    run.samples.push_back(s);
  }
  return run;
}

}  // namespace

std::optional<double> CalcEquivalentCurrent(const models::BatteryPack& pack, const models::PackState& state,
                                            double eod_s, double guess_a) {
  if (!(eod_s > 0.0) || !(guess_a > 0.0)) return std::nullopt;
  const double log_target = std::log(eod_s);
  constexpr double kLogLow = -6.907755278982137;  // ln 1e-3
  constexpr double kLogHigh = 6.907755278982137;  // ln 1e3
  constexpr double kTolerance = 1e-6;
  // A bracket [a, b] with f(a) > 0 > f(b), grown from the guess by the EOD's own slope (EOD ~ 1/I: one e-fold of the
  // EOD is about one of the current).
  double a = std::clamp(std::log(guess_a), kLogLow, kLogHigh);
  double fa = LogEodResidual(pack, state, a, log_target);
  if (fa == 0.0) return std::exp(a);
  double step = std::isfinite(fa) ? std::max(std::abs(fa), 1e-3) : 1.0;
  double b = a, fb = fa;
  while ((fa > 0.0) == (fb > 0.0)) {
    b = fa > 0.0 ? b + step : b - step;
    if (b < kLogLow || b > kLogHigh) return std::nullopt;
    fb = LogEodResidual(pack, state, b, log_target);
    if ((fa > 0.0) == (fb > 0.0)) a = b, fa = fb, step *= 2.0;
  }
  // Illinois false position on [a, b]; a bisection where a bound is infinite.
  int side = 0;
  for (int iteration = 0; iteration < 100 && std::abs(b - a) > kTolerance; ++iteration) {
    const double x = std::isfinite(fa) && std::isfinite(fb) ? (a * fb - b * fa) / (fb - fa) : 0.5 * (a + b);
    const double fx = LogEodResidual(pack, state, x, log_target);
    if (fx == 0.0) return std::exp(x);
    if ((fx > 0.0) == (fa > 0.0)) {
      a = x, fa = fx;
      if (side == -1 && std::isfinite(fb)) fb *= 0.5;
      side = -1;
    } else {
      b = x, fb = fx;
      if (side == 1 && std::isfinite(fa)) fa *= 0.5;
      side = 1;
    }
    if (std::abs(fx) < 1e-9) return std::exp(x);
  }
  return std::exp(0.5 * (a + b));
}

std::vector<EodTruthRun> FlyEodTruthCampaign(const CampaignConfig& config, const EodTruthCampaignOptions& options) {
  const CampaignWorld world = BuildCampaignWorld(config);
  std::vector<EodTruthRun> runs;
  runs.reserve(static_cast<std::size_t>(options.runs));
  ParallelOptions parallel;
  parallel.jobs = options.jobs;
  const std::int64_t merged = ParallelFor(
      options.runs, parallel, [&](std::int64_t r) { return FlyTruthRun(config, world, options, r); },
      [&](std::int64_t, EodTruthRun&& run) {
        runs.push_back(std::move(run));
        if (options.on_run_done) options.on_run_done(static_cast<std::int64_t>(runs.size()));
      });
  if (merged < options.runs) throw Cancelled();
  return runs;
}

// One row per scored prediction: what the error model may condition on, the prediction, its truth and its error.
std::string EodTruthSamplesCsv(const std::vector<EodTruthRun>& runs) {
  std::string out =
      "run,time_s,battery_health,motor_health,flight_time_remaining_s,eod_s,true_eod_s,current_a,log_ratio,"
      "cutoff_time_s,hold_start_s,cruise_speed_mps,wind_speed_mps,turbulence,cold,fault\n";
  for (const EodTruthRun& run : runs) {
    for (const EodTruthSample& s : run.samples) {
      out += fmt::format("{},{:.3f},{},{},{:.3f},{:.3f},{:.3f},{:.5f},{:.6f},{:.3f},{:.3f}", run.run_index, s.time_s,
                         s.battery_health, s.motor_health, s.flight_time_remaining_s, s.eod_s, s.true_eod_s,
                         s.current_a, s.log_ratio, run.cutoff_time_s.value_or(-1.0), run.hold_start_s.value_or(-1.0));
      out += fmt::format(",{:.3f},{:.3f},{},{:d},{:d}\n", run.cruise_speed_mps, run.wind_speed_mps, run.turbulence,
                         run.cold, run.fault);
    }
  }
  return out;
}

}  // namespace uascma::campaign
