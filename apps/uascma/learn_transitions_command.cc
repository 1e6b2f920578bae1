// uascma learn transitions — the CMA MDP's transition rows counted from simulated campaign flights (dissertation
// §5.6, §5.3.2.3; learning/transition_estimation.h), compared with the DDN tables of §5.3.2 and solved.
#include <cstdio>
#include <memory>
#include <string>

#include "bounded_option.h"
#include "commands.h"
#include "learn_options.h"
#include "output.h"
#include "uascma/campaign/config.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/common/progress.h"
#include "uascma/decision/cma_estimated_model.h"
#include "uascma/learning/transition_estimation.h"
#include "uascma/learning/transition_report.h"

namespace uascma::cli {
namespace {

using namespace uascma::decision;

// Our bounds.
constexpr Bounds kRunBounds{1, 1e6, "runs"};
constexpr Bounds kTopBounds{0, 432, "rows"};
constexpr Bounds kMinSampleBounds{1, 1e9, "samples"};

struct TransitionOptions {
  std::int64_t runs = 300;
  std::string seed;
  int jobs = 1;
  std::string out, campaign_file;
  double exploration = 0.002;
  int top = 10;
  std::int64_t min_samples = 30;
  bool json = false;
};

}  // namespace

void AddLearnTransitions(CLI::App* learn) {
  auto o = std::make_shared<TransitionOptions>();
  CLI::App* command = learn->add_subcommand(
      "transitions",
      "Count the CMA MDP's 1 Hz transitions per action over campaign flights (every available action tried\n"
      "from every epoch the flights reach, on one-epoch branches), compare each row with the DDN tables of\n"
      "§5.3.2 and keep the counts. Solve with 'uascma policy solve --model cma --transitions T.json'");
  AddBoundedOption(command, "--runs", o->runs, "Campaign flights", kRunBounds);
  AddSeedOption(command, "--seed", o->seed, "Master seed (default: the campaign's); flight r is campaign run r");
  AddBoundedOption(command, "--jobs", o->jobs, "Threads (the counts do not depend on it)", kLearnJobBounds);
  command->add_option("--out", o->out, "Transitions JSON to write")->required();
  command->add_option("--campaign", o->campaign_file, "Campaign YAML: the distribution of missions, faults, health");
  AddBoundedOption(command, "--exploration", o->exploration,
                   "Per-epoch probability that the flight takes a random non-Terminate action (ours: 0.002)",
                   kLearnProbabilityBounds);
  AddBoundedOption(command, "--top", o->top, "Largest disagreements to list", kTopBounds);
  AddBoundedOption(command, "--min-samples", o->min_samples, "Rows with fewer samples are not ranked",
                   kMinSampleBounds);
  command->add_flag("--json", o->json, "Print the summary as JSON");
  command->callback([o] {
    learning::TransitionEstimationOptions options;
    options.config = ResolveLearningCampaign(o->campaign_file, o->seed);
    options.runs = o->runs;
    options.jobs = o->jobs;
    options.exploration = o->exploration;
    learning::TransitionEstimationSummary summary;
    CmaTransitionCounts counts;
    {
      ProgressBar bar(o->runs, "learn transitions");
      options.on_run_done = [&bar](std::int64_t) { bar.Advance(); };
      counts = learning::EstimateCmaTransitions(options, &summary);
      bar.Finish();
    }
    const learning::TransitionRanking ranking{.top = o->top, .min_samples = o->min_samples};
    const nlohmann::json document = learning::CmaTransitionsDocument(options, counts, summary, ranking);
    WriteFileAtomically(o->out, document.dump(1) + "\n");
    if (o->json) {
      PrintJson(learning::CmaTransitionsSummaryJson(document, o->out));
    } else {
      std::fputs(learning::CmaTransitionsSummaryText(document, ranking, o->out).c_str(), stdout);
    }
  });
}

}  // namespace uascma::cli
