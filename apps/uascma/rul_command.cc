// uascma rul — motor remaining useful life from a bearing spall (dissertation §3.4.1, eq. 3.8) and the
// per-second jam probability of a spalled motor measured as Table 5.4 was (decisions item 15).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "bounded_option.h"
#include "commands.h"
#include "output.h"
#include "uascma/common/error.h"
#include "uascma/common/random.h"
#include "uascma/prognostics/motor_rul.h"

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

}  // namespace

void AddRulCommand(CLI::App& app) {
  struct Options {
    int particles = SpallGrowthParams{}.particles;
    std::uint64_t seed = 1;
    int runs = CalibrationOptions{}.runs;
    double time_per_step_s = SpallGrowthParams{}.time_per_growth_step_s;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
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
                   fmt::format("Seconds per growth step (default {}: calibrated to Table 5.4, decisions item 15)",
                               SpallGrowthParams{}.time_per_growth_step_s),
                   SpallGrowthParams::kTimePerGrowthStepBounds);
  command->add_flag("--json", options->json, "Print the result as JSON");
  command->callback([options] {
    RequireCount(options->particles, "--particles", "particles");
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

    if (options->json) {
      PrintJson({{"particles", options->particles},
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
                 {"table_5_4_jam_probability_per_s", kTable54JamProbabilityPerEpoch}});
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
  });
}

}  // namespace uascma::cli
