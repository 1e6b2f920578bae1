// `uascma battery hindsight`: what any switching schedule could do on the flights with a sudden pack fault that
// UseBoth fails (campaign/battery_hindsight.h): the bound on what isolating a faulted pack can gain.
#include <cstdio>
#include <memory>

#include <CLI/CLI.hpp>

#include "bounded_option.h"
#include "commands.h"
#include "output.h"
#include "uascma/campaign/battery_hindsight.h"
#include "uascma/campaign/pack_fault_sampling.h"

namespace uascma::cli {
namespace {

// As `battery evaluate`'s: 10^7 flights, the campaign's bound on runs; threads, our bound.
constexpr Bounds kFlights{1.0, 1e7, "flights"};
constexpr Bounds kThreads{1.0, 256.0, "threads"};

}  // namespace

void AddBatteryHindsight(CLI::App* battery) {
  struct Options {
    std::int64_t runs = 400;
    std::uint64_t seed = 2024;
    int jobs = 1;
    double pack_fault_share = 0.2;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = battery->add_subcommand(
      "hindsight",
      "The flights of 'battery evaluate' (the same --runs, --seed and --pack-fault-share) that carry a sudden pack\n"
      "fault: UseBoth on each, and where it fails every schedule of the case studies' hindsight family (UseBoth;\n"
      "UseBoth then one pack alone for good from t, 5 s grid; one window of one pack alone, 60 s grid): how many any\n"
      "switching schedule could complete, per fault kind, and how many one that leaves UseBoth only from the\n"
      "fault's onset on (a policy told of the fault the moment it came)");
  AddBoundedOption(command, "--runs", options->runs, "Flights of the evaluation (the faulted ones are searched)",
                   kFlights);
  AddSeedOption(command, "--seed", options->seed, "Seed of the evaluation's flights (default 2024)");
  AddBoundedOption(command, "--jobs", options->jobs, "Threads (the results do not depend on it)", kThreads);
  AddBoundedOption(command, "--pack-fault-share", options->pack_fault_share,
                   "Share of the flights with a sudden pack fault (default 0.2; docs/modelling-choices.md#pack-faults)",
                   campaign::kPackFaultShareBounds);
  command->add_flag("--json", options->json, "Print the search as JSON");
  command->callback([options] {
    RequireWithin(static_cast<double>(options->runs), kFlights, "--runs", "value");
    RequireWithin(options->jobs, kThreads, "--jobs", "value");
    RequireWithin(options->pack_fault_share, campaign::kPackFaultShareBounds, "--pack-fault-share", "value");
    campaign::BatteryFlightRanges ranges;
    ranges.pack_faults.share = options->pack_fault_share;
    const campaign::FaultHindsight hindsight =
        campaign::SearchFaultHindsight(ranges, options->seed, options->runs, options->jobs);
    if (options->json) {
      PrintJson(campaign::FaultHindsightJson(hindsight));
      return;
    }
    std::fputs(campaign::FaultHindsightText(hindsight).c_str(), stdout);
  });
}

}  // namespace uascma::cli
