#include "uascma/learning/cma_q_learning.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "uascma/campaign/sampler.h"
#include "uascma/common/error.h"
#include "uascma/decision/cma_abstraction.h"
#include "uascma/decision/cma_weights_json.h"

namespace uascma::learning {
namespace {

using decision::CmaAction;
using decision::FlightStatus;
using decision::kCmaNumActions;
using decision::kCmaNumTupleStates;

// Tuple states per flight status: MH × MM × BH × RM = 3 · 2 · 3 · 2 (FS varies slowest, cma_mdp.h).
constexpr int kTuplesPerFlightStatus = 36;

FlightStatus FlightStatusOfTuple(StateIndex tuple) { return static_cast<FlightStatus>(tuple / kTuplesPerFlightStatus); }

// The scenario of one episode given the anchor run (kOneMission) — see the header.
sim::Scenario OneMissionScenario(const campaign::SampledRun& anchor, const campaign::SampledRun& draw) {
  sim::Scenario scenario = anchor.scenario;
  scenario.name = fmt::format("q-learning-{}", draw.run_index);
  scenario.battery = draw.scenario.battery;
  scenario.fault = draw.scenario.fault;
  if (scenario.fault.enabled && draw.plan_duration_s > 0.0) {
    const double fraction = draw.scenario.fault.spall_onset_s / draw.plan_duration_s;
    scenario.fault.spall_onset_s = fraction * anchor.plan_duration_s;
  }
  scenario.seed = draw.scenario.seed;
  return scenario;
}

// The episodes' scenarios, with the anchor drawn once.
class EpisodeSource {
 public:
  explicit EpisodeSource(const CmaQLearningOptions& options)
      : options_(options), world_(campaign::BuildCampaignWorld(options.config)) {
    if (options.setting == EpisodeSetting::kOneMission) {
      anchor_ = campaign::SampleRun(options.config, world_, options.config.seed, options.anchor_run);
    }
  }
  sim::Scenario Scenario(std::int64_t episode) const {
    if (options_.setting == EpisodeSetting::kCampaign) {
      return campaign::SampleRun(options_.config, world_, options_.config.seed, episode).scenario;
    }
    // Draws after the anchor's own index, so the anchor's draw is not reused as an episode.
    const std::int64_t run = episode + options_.anchor_run + 1;
    return OneMissionScenario(*anchor_, campaign::SampleRun(options_.config, world_, options_.config.seed, run));
  }

 private:
  const CmaQLearningOptions& options_;
  const campaign::CampaignWorld world_;  // built once for every episode (campaign/world.h)
  std::optional<campaign::SampledRun> anchor_;
};

Episode FlyScenario(const CmaQLearningOptions& options, const sim::Scenario& scenario, std::uint64_t explore_seed,
                    const QTable& snapshot, double epsilon) {
  sim::DecisionEnvironment environment(scenario);
  RandomStream random(explore_seed);
  Episode episode;
  sim::Observation observation = environment.Reset(scenario.seed);
  StateIndex s = EncodeQState(options.state, observation, environment.state(), environment.model());
  const bool one_deviation = options.exploration == Exploration::kOneDeviation;
  std::int64_t deviation_epoch = -1;
  if (one_deviation && random.Bernoulli(epsilon)) {
    const double epochs = std::ceil(environment.model().nominal_plan().duration());
    deviation_epoch = static_cast<std::int64_t>(random.UniformIndex(static_cast<std::uint64_t>(std::max(1.0, epochs))));
  }
  for (std::int64_t epoch = 0; !environment.done(); ++epoch) {
    const ActionIndex a = !one_deviation             ? snapshot.EpsilonGreedy(s, epsilon, random)
                          : epoch == deviation_epoch ? snapshot.EpsilonGreedy(s, 1.0, random)
                                                     : snapshot.Greedy(s);
    const sim::EnvironmentStep step = environment.Step(static_cast<CmaAction>(a));
    const StateIndex next =
        step.done ? 0 : EncodeQState(options.state, step.observation, environment.state(), environment.model());
    episode.steps.push_back({s, a, step.reward, next, step.done});
    episode.return_sum += step.reward;
    s = next;
  }
  return episode;
}

}  // namespace

int NumQStates(QStateKind kind) {
  return kind == QStateKind::kCma ? kCmaNumTupleStates : kCompletionBins * kReachMarginBins * kCmaNumTupleStates;
}

int CompletionBin(double completion_fraction) {
  const double clamped = std::clamp(completion_fraction, 0.0, 1.0);
  return std::min(kCompletionBins - 1, static_cast<int>(std::floor(clamped * kCompletionBins)));
}

int ReachMarginBin(double reach_margin) {
  if (!(reach_margin > 0.0)) return 0;  // RM0 and RM in [0, 25 %), and NaN
  return std::min(kReachMarginBins - 1, static_cast<int>(std::floor(reach_margin * kReachMarginBins)));
}

StateIndex EncodeQState(QStateKind kind, const sim::Observation& observation, const sim::FlightState& state,
                        const sim::FlightModel& model) {
  const StateIndex tuple = decision::CmaStateIndex(observation.state);
  if (kind == QStateKind::kCma) return tuple;
  const double duration = state.plan(model).duration();
  const double completion = duration > 0.0 ? (observation.time_s - state.guidance.plan_start_s) / duration : 1.0;
  const int bins = CompletionBin(completion) * kReachMarginBins + ReachMarginBin(observation.reach_margin);
  return bins * kCmaNumTupleStates + tuple;
}

StateIndex CmaTupleOfQState(QStateKind kind, StateIndex q_state) {
  return kind == QStateKind::kCma ? q_state : q_state % kCmaNumTupleStates;
}

std::vector<std::uint8_t> QStateAvailability(QStateKind kind) {
  const int states = NumQStates(kind);
  std::vector<std::uint8_t> available(static_cast<std::size_t>(states) * kCmaNumActions, 0);
  for (StateIndex q = 0; q < states; ++q) {
    const FlightStatus fs = FlightStatusOfTuple(CmaTupleOfQState(kind, q));
    for (ActionIndex a = 0; a < kCmaNumActions; ++a) {
      available[static_cast<std::size_t>(q) * kCmaNumActions + static_cast<std::size_t>(a)] =
          decision::IsCmaActionAvailable(fs, static_cast<CmaAction>(a)) ? 1 : 0;
    }
  }
  return available;
}

std::string QStateLabel(QStateKind kind, StateIndex q_state) {
  static const decision::FiniteMdp labels = decision::BuildCmaMdp(decision::CmaWeights{});
  const std::string tuple = labels.state_label(CmaTupleOfQState(kind, q_state));
  if (kind == QStateKind::kCma) return tuple;
  const int bins = q_state / kCmaNumTupleStates;
  const int completion = bins / kReachMarginBins, reach = bins % kReachMarginBins;
  return fmt::format("completion {}-{}%,RM {}-{}%,{}", 25 * completion, 25 * (completion + 1), 25 * reach,
                     25 * (reach + 1), tuple);
}

sim::Scenario EpisodeScenario(const CmaQLearningOptions& options, std::int64_t episode) {
  return EpisodeSource(options).Scenario(episode);
}

Episode FlyCmaEpisode(const CmaQLearningOptions& options, std::int64_t episode, const QTable& snapshot,
                      double epsilon) {
  const std::uint64_t explore = DeriveSeed(campaign::RunSeed(options.config.seed, episode), kExplorationStream);
  return FlyScenario(options, EpisodeScenario(options, episode), explore, snapshot, epsilon);
}

QLearningResult LearnCmaQ(const CmaQLearningOptions& options) {
  std::string error;
  if (!options.config.IsValid(&error)) throw InputError("campaign: " + error);
  if (options.anchor_run < 0) throw InputError("q-learning", "anchor_run", "a run index >= 0");
  const EpisodeSource source(options);
  QTable table(NumQStates(options.state), kCmaNumActions, QStateAvailability(options.state));
  const EpisodeFunction fly = [&](std::int64_t episode, const QTable& snapshot, double epsilon) {
    const std::uint64_t explore = DeriveSeed(campaign::RunSeed(options.config.seed, episode), kExplorationStream);
    return FlyScenario(options, source.Scenario(episode), explore, snapshot, epsilon);
  };
  return RunQLearning(std::move(table), fly, options.learning);
}

decision::Policy ProjectToCmaPolicy(const QTable& table, QStateKind kind) {
  decision::Policy policy;
  policy.action.assign(decision::kCmaNumStates, static_cast<ActionIndex>(CmaAction::kNoOp));
  policy.value.assign(decision::kCmaNumStates, 0.0);
  std::vector<double> weighted(static_cast<std::size_t>(kCmaNumTupleStates) * kCmaNumActions, 0.0);
  std::vector<double> weight(kCmaNumTupleStates, 0.0);
  for (StateIndex q = 0; q < table.num_states(); ++q) {
    const auto n = static_cast<double>(table.state_visits(q));
    if (n == 0.0) continue;
    const StateIndex c = CmaTupleOfQState(kind, q);
    weight[static_cast<std::size_t>(c)] += n;
    for (ActionIndex a = 0; a < kCmaNumActions; ++a) {
      weighted[static_cast<std::size_t>(c) * kCmaNumActions + static_cast<std::size_t>(a)] += n * table.q(q, a);
    }
  }
  for (StateIndex c = 0; c < kCmaNumTupleStates; ++c) {
    const double w = weight[static_cast<std::size_t>(c)];
    if (w == 0.0) continue;
    const FlightStatus fs = FlightStatusOfTuple(c);
    ActionIndex best = -1;
    double best_q = 0.0;
    for (ActionIndex a = 0; a < kCmaNumActions; ++a) {
      if (!decision::IsCmaActionAvailable(fs, static_cast<CmaAction>(a))) continue;
      const double q = weighted[static_cast<std::size_t>(c) * kCmaNumActions + static_cast<std::size_t>(a)] / w;
      if (best < 0 || q > best_q) best = a, best_q = q;
    }
    policy.action[static_cast<std::size_t>(c)] = best;
    policy.value[static_cast<std::size_t>(c)] = best_q;
  }
  return policy;
}

decision::PolicyDocument QPolicyDocument(const QTable& table, const CmaQLearningOptions& options,
                                         const QLearningResult& result) {
  const decision::CmaWeights weights;  // the environment's reward (EnvironmentOptions default)
  const decision::FiniteMdp mdp = decision::BuildCmaMdp(weights);
  decision::SolverSummary summary;
  summary.status = result.status == QLearningStatus::kPolicyStable ? decision::SolverStatus::kConverged
                                                                   : decision::SolverStatus::kMaxIterations;
  summary.iterations = static_cast<int>(result.episodes);
  summary.wall_time_s = result.wall_time_s;
  summary.message = result.status == QLearningStatus::kPolicyStable ? "greedy policy stable" : "episode limit";
  const nlohmann::json learning = {{"state", QStateKindName(options.state)},
                                   {"episodes_setting", EpisodeSettingName(options.setting)},
                                   {"exploration", ExplorationName(options.exploration)},
                                   {"episodes", result.episodes},
                                   {"alpha", options.learning.params.alpha},
                                   {"alpha_decay_visits", options.learning.params.alpha_decay_visits},
                                   {"epsilon",
                                    {{"start", options.learning.epsilon.start},
                                     {"end", options.learning.epsilon.end},
                                     {"decay_episodes", options.learning.epsilon.decay_episodes}}},
                                   {"batch_size", options.learning.batch_size},
                                   {"seed", std::to_string(options.config.seed)},
                                   {"campaign_config_hash", campaign::CampaignConfigHash(options.config)},
                                   {"anchor_run", options.anchor_run},
                                   {"states_visited", table.states_visited()},
                                   {"learning_states", table.num_states()}};
  return decision::MakePolicyDocument(
      mdp, ProjectToCmaPolicy(table, options.state), "cma", options.learning.params.gamma,
      {{"weights", decision::CmaWeightsJson(weights)}, {"q_learning", learning}}, summary, "q_learning");
}

const char* QStateKindName(QStateKind kind) { return kind == QStateKind::kCma ? "cma" : "binned"; }
const char* ExplorationName(Exploration e) {
  return e == Exploration::kOneDeviation ? "one-deviation" : "epsilon-greedy";
}
const char* EpisodeSettingName(EpisodeSetting s) { return s == EpisodeSetting::kCampaign ? "campaign" : "one-mission"; }

}  // namespace uascma::learning
