// uascma learn — learning from the simulator: the model-free CMA by Q-learning (dissertation §5.3.3) and the CMA
// transition model estimated from flights (§5.6; decision/cma_estimated_model.h).
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "bounded_option.h"
#include "commands.h"
#include "learn_options.h"
#include "output.h"
#include "plotting.h"
#include "uascma/campaign/config.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/common/progress.h"
#include "uascma/decision/cma_estimated_model.h"
#include "uascma/decision/policy_file.h"
#include "uascma/decision/solvers.h"
#include "uascma/learning/cma_q_learning.h"
#include "uascma/learning/transition_estimation.h"

namespace uascma::cli {
namespace {

using namespace uascma::learning;

// Our bounds: enough for any study on one machine, and a typo such as 1e12 episodes is refused.
constexpr Bounds kEpisodeBounds{1, 1e7, "episodes"};
constexpr Bounds kDecayEpisodeBounds{0, 1e7, "episodes"};
constexpr Bounds kAlphaBounds{1e-6, 1.0, ""};
constexpr Bounds kQGammaBounds{0.0, 0.999, ""};
constexpr Bounds kBatchBounds{1, 4096, "episodes"};
constexpr Bounds kStableBounds{0, 1e6, "batches"};
constexpr Bounds kAnchorBounds{0, 1e9, ""};
constexpr Bounds kDecayVisitBounds{0, 1e9, "updates"};

std::string CurveCsv(const QLearningResult& result) {
  std::string out = "episode,return,mean_return,steps,states_visited,epsilon,policy_changes\n";
  for (const CurvePoint& p : result.curve) {
    out += fmt::format("{},{:.6f},{:.6f},{},{},{:.6g},{}\n", p.episode, p.return_sum, p.mean_return, p.steps,
                       p.states_visited, p.epsilon, p.policy_changes);
  }
  return out;
}

nlohmann::json CurvePlotJson(const QLearningResult& result, const CmaQLearningOptions& options) {
  nlohmann::json episode = nlohmann::json::array(), returns = nlohmann::json::array(), mean = nlohmann::json::array(),
                 visited = nlohmann::json::array();
  for (const CurvePoint& p : result.curve) {
    episode.push_back(p.episode);
    returns.push_back(p.return_sum);
    mean.push_back(p.mean_return);
    visited.push_back(p.states_visited);
  }
  const std::string title = fmt::format(
      "Q-learning (Fig. 5.14): {} state, {} episodes, {}, alpha {}, gamma {}, epsilon {}",
      QStateKindName(options.state), EpisodeSettingName(options.setting), ExplorationName(options.exploration),
      options.learning.params.alpha, options.learning.params.gamma, options.learning.epsilon.start);
  return {
      {"title", title}, {"episode", episode}, {"return", returns}, {"mean_return", mean}, {"states_visited", visited}};
}

struct QOptions {
  std::int64_t episodes = 10000;
  std::string seed;
  int jobs = 1;
  std::string out, curve, plot, campaign_file;
  std::string setting = "one-mission";
  std::string state = "binned";
  std::string exploration = "epsilon-greedy";
  double alpha = 0.8, gamma = 0.9, epsilon = 0.01;
  double epsilon_end = -1.0;
  std::int64_t epsilon_decay = 0;
  double alpha_decay_visits = 0.0;
  int batch = 16;
  int until_stable = 0;
  std::int64_t anchor_run = 14;
  bool json = false;
};

void AddQOptions(CLI::App* command, QOptions& o) {
  AddBoundedOption(command, "--episodes", o.episodes, "Episodes, at most (§5.3.3: 10,000)", kEpisodeBounds);
  AddSeedOption(command, "--seed", o.seed, "Master seed (default: the campaign's); episode k flies campaign run k");
  AddBoundedOption(command, "--jobs", o.jobs, "Threads (the table does not depend on it)", kLearnJobBounds);
  command->add_option("--out", o.out, "Policy JSON to write (an ordinary CMA policy file)")->required();
  command->add_option("--curve", o.curve, "Write the learning curve (Fig. 5.14) as CSV");
  command->add_option("--plot", o.plot, "Draw the learning curve to this PNG file");
  command->add_option("--campaign", o.campaign_file, "Campaign YAML: the distribution of missions, faults, health");
  command
      ->add_option("--setting", o.setting,
                   "one-mission (§5.3.3: one route, faults and health drawn per episode) | campaign")
      ->check(CLI::IsMember({"one-mission", "campaign"}));
  command->add_option("--state", o.state, "binned (§5.3.3: completion and RM in 4 bins, 1,728) | cma (108)")
      ->check(CLI::IsMember({"binned", "cma"}));
  command
      ->add_option("--exploration", o.exploration,
                   "epsilon-greedy (§5.3.3: a random action with probability epsilon at every epoch) |\n"
                   "one-deviation (with probability epsilon per episode, one random action at a random epoch)")
      ->check(CLI::IsMember({"epsilon-greedy", "one-deviation"}));
  AddBoundedOption(command, "--alpha", o.alpha, "Step size (§5.3.3: 0.8)", kAlphaBounds);
  AddBoundedOption(command, "--gamma", o.gamma, "Discount factor (§5.3.3: 0.9)", kQGammaBounds);
  AddBoundedOption(command, "--epsilon", o.epsilon,
                   "Exploration at episode 0 (§5.3.3: 0.01; per epoch, or per episode\n"
                   "with one-deviation)",
                   kLearnProbabilityBounds);
  AddBoundedOption(command, "--epsilon-end", o.epsilon_end, "Exploration after the decay (default: --epsilon)",
                   kLearnProbabilityBounds);
  AddBoundedOption(command, "--epsilon-decay-episodes", o.epsilon_decay, "Episodes of the linear decay (0: none)",
                   kDecayEpisodeBounds);
  AddBoundedOption(command, "--alpha-decay-visits", o.alpha_decay_visits,
                   "Step size alpha / (1 + n(s,a) / this) (0: constant alpha, §5.3.3)", kDecayVisitBounds);
  AddBoundedOption(command, "--batch", o.batch, "Episodes flown against one frozen Q snapshot (ours: 16)",
                   kBatchBounds);
  AddBoundedOption(command, "--until-stable", o.until_stable,
                   "Stop once the greedy policy of the visited states is unchanged for this many batches (0: "
                   "fly all episodes)",
                   kStableBounds);
  AddBoundedOption(command, "--anchor-run", o.anchor_run,
                   "one-mission: the campaign run whose route is flown (default 14: a 563 s plan,\n"
                   "the mean of the default campaign's)",
                   kAnchorBounds);
  command->add_flag("--json", o.json, "Print the summary as JSON");
}

CmaQLearningOptions MakeQLearning(const QOptions& o) {
  CmaQLearningOptions options;
  options.config = ResolveLearningCampaign(o.campaign_file, o.seed);
  options.setting = o.setting == "campaign" ? EpisodeSetting::kCampaign : EpisodeSetting::kOneMission;
  options.state = o.state == "cma" ? QStateKind::kCma : QStateKind::kBinned;
  options.anchor_run = o.anchor_run;
  options.exploration = o.exploration == "one-deviation" ? Exploration::kOneDeviation : Exploration::kEpsilonGreedy;
  QLearningOptions& learning = options.learning;
  learning.params = {o.alpha, o.gamma, o.alpha_decay_visits};
  learning.epsilon = {o.epsilon, o.epsilon_end < 0.0 ? o.epsilon : o.epsilon_end, o.epsilon_decay};
  learning.max_episodes = o.episodes;
  learning.batch_size = o.batch;
  learning.jobs = o.jobs;
  learning.stable_batches = o.until_stable;
  std::string error;
  if (!learning.IsValid(&error)) throw InputError("learn q", "options", error);
  return options;
}

void PrintQSummary(const QOptions& o, const CmaQLearningOptions& options, const QLearningResult& result,
                   const decision::PolicyDocument& document) {
  double steps = 0.0, tail = 0.0;
  const std::size_t tail_from = result.curve.size() - std::max<std::size_t>(1, result.curve.size() / 10);
  for (std::size_t i = 0; i < result.curve.size(); ++i) {
    steps += result.curve[i].steps;
    if (i >= tail_from) tail += result.curve[i].return_sum;
  }
  const double episodes = static_cast<double>(result.episodes);
  const double cpu_ms = 1e3 * result.cpu_time_s / episodes;
  const double tail_mean = tail / static_cast<double>(result.curve.size() - tail_from);
  const bool stable = result.status == QLearningStatus::kPolicyStable;
  if (o.json) {
    PrintJson({{"out", o.out},
               {"episodes", result.episodes},
               {"status", stable ? "policy_stable" : "episode_limit"},
               {"stable_since_episode", result.stable_since_episode},
               {"states_visited", result.table.states_visited()},
               {"learning_states", result.table.num_states()},
               {"mean_return", result.curve.back().mean_return},
               {"mean_return_last_tenth", tail_mean},
               {"mean_episode_s", steps / episodes},
               {"updates", result.updates},
               {"cpu_ms_per_episode", cpu_ms},
               {"wall_time_s", result.wall_time_s},
               {"jobs", o.jobs},
               {"model_hash", document.model_hash}});
    return;
  }
  std::printf("Q-learning (%s state, %s episodes, %s): %lld episodes, %s\n", QStateKindName(options.state),
              EpisodeSettingName(options.setting), ExplorationName(options.exploration),
              static_cast<long long>(result.episodes),
              stable ? fmt::format("greedy policy unchanged since episode {}", result.stable_since_episode).c_str()
                     : "episode limit");
  std::printf("states visited: %d of %d learning states; %lld updates; episodes last %.0f simulated s on average\n",
              result.table.states_visited(), result.table.num_states(), static_cast<long long>(result.updates),
              steps / episodes);
  std::printf("average sum of rewards: %.4f over all episodes, %.4f over the last tenth\n",
              result.curve.back().mean_return, tail_mean);
  std::printf("%.1f ms of CPU per episode (%d threads), %.1f s wall\nwrote %s", cpu_ms, o.jobs, result.wall_time_s,
              o.out.c_str());
  if (!o.curve.empty()) std::printf(", %s", o.curve.c_str());
  if (!o.plot.empty()) std::printf(", %s", o.plot.c_str());
  std::printf("\n");
}

void AddLearnQ(CLI::App* learn) {
  auto o = std::make_shared<QOptions>();
  CLI::App* command = learn->add_subcommand(
      "q",
      "Model-free CMA (§5.3.3): tabular Q-learning in the simulator at the 1 Hz epoch, reward R(S,A) of\n"
      "eqs. 5.20-5.29. Writes the greedy policy as a CMA policy file, the learning curve (Fig. 5.14) and\n"
      "the states visited");
  AddQOptions(command, *o);
  command->callback([o] {
    const CmaQLearningOptions options = MakeQLearning(*o);
    QLearningResult result = [&] {
      ProgressBar bar(options.learning.max_episodes, "learn q");
      CmaQLearningOptions run = options;
      run.learning.on_episode_done = [&bar](std::int64_t) { bar.Advance(); };
      QLearningResult learned = LearnCmaQ(run);
      bar.Finish();
      return learned;
    }();
    const decision::PolicyDocument document = QPolicyDocument(result.table, options, result);
    // The drawing first: when it fails (no python3/matplotlib) nothing else has been written.
    if (!o->plot.empty()) PlotJson("learning_curve.py", CurvePlotJson(result, options), o->plot);
    if (!o->curve.empty()) WriteFileAtomically(o->curve, CurveCsv(result));
    WriteFileAtomically(o->out, decision::PolicyToJson(document).dump(2) + "\n");
    PrintQSummary(*o, options, result, document);
  });
}

}  // namespace

campaign::CampaignConfig ResolveLearningCampaign(const std::string& file, const std::string& seed_text) {
  campaign::CampaignConfig config = file.empty() ? campaign::CampaignConfig{} : campaign::LoadCampaignConfig(file);
  if (!seed_text.empty()) config.seed = ParseSeed(seed_text, "--seed", "value");
  std::string error;
  if (!config.IsValid(&error)) throw InputError(file.empty() ? "campaign" : file, "config", error);
  return config;
}

void AddLearnCommand(CLI::App& app) {
  CLI::App* learn = app.add_subcommand(
      "learn", "Learning from the simulator: Q-learning (§5.3.3) and the CMA transitions from flights (§5.6)");
  learn->require_subcommand(1);
  AddLearnQ(learn);
  AddLearnTransitions(learn);
}

}  // namespace uascma::cli
