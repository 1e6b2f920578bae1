#include "uascma/learning/q_learning.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "uascma/common/cpu_time.h"
#include "uascma/common/error.h"
#include "uascma/common/parallel_for.h"

namespace uascma::learning {
namespace {

// Flies episodes [first, first + count) against `snapshot` on `jobs` threads; episodes[k] is episode first + k.
// Throws Cancelled when the work is stopped (common/cancellation.h) before every episode flew.
std::vector<Episode> FlyBatch(const EpisodeFunction& fly, const QTable& snapshot, std::int64_t first, int count,
                              const QLearningOptions& options) {
  ParallelOptions parallel;
  parallel.jobs = options.jobs;
  return ParallelMap(count, parallel, [&](std::int64_t k) {
    const std::int64_t index = first + k;
    Episode episode = fly(index, snapshot, options.epsilon.At(index));
    if (options.on_episode_done) options.on_episode_done(index);
    return episode;
  });
}

// The greedy action of every visited state (-1 for states not visited yet).
std::vector<ActionIndex> GreedyOfVisited(const QTable& table) {
  std::vector<ActionIndex> greedy(static_cast<std::size_t>(table.num_states()), -1);
  for (StateIndex s = 0; s < table.num_states(); ++s) {
    if (table.state_visits(s) > 0) greedy[static_cast<std::size_t>(s)] = table.Greedy(s);
  }
  return greedy;
}

}  // namespace

bool QLearningParams::IsValid(std::string* error) const {
  auto fail = [error](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (!(alpha > 0.0 && alpha <= 1.0)) return fail(fmt::format("alpha: expected (0, 1], got {}", alpha));
  if (!(gamma >= 0.0 && gamma < 1.0)) return fail(fmt::format("gamma: expected [0, 1), got {}", gamma));
  if (!(alpha_decay_visits >= 0.0) || !std::isfinite(alpha_decay_visits)) {
    return fail(fmt::format("alpha_decay_visits: expected >= 0, got {}", alpha_decay_visits));
  }
  return true;
}

double EpsilonSchedule::At(std::int64_t episode) const {
  if (decay_episodes <= 0 || episode >= decay_episodes) return decay_episodes <= 0 ? start : end;
  const double fraction = static_cast<double>(episode) / static_cast<double>(decay_episodes);
  return start + (end - start) * fraction;
}

bool EpsilonSchedule::IsValid(std::string* error) const {
  if (start >= 0.0 && start <= 1.0 && end >= 0.0 && end <= 1.0 && decay_episodes >= 0) return true;
  if (error != nullptr) {
    *error = fmt::format("epsilon: expected start and end in [0, 1] and decay episodes >= 0, got {}, {}, {}", start,
                         end, decay_episodes);
  }
  return false;
}

bool QLearningOptions::IsValid(std::string* error) const {
  if (!params.IsValid(error) || !epsilon.IsValid(error)) return false;
  auto fail = [error](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (max_episodes < 1) return fail(fmt::format("episodes: expected >= 1, got {}", max_episodes));
  if (batch_size < 1) return fail(fmt::format("batch_size: expected >= 1, got {}", batch_size));
  if (jobs < 1) return fail(fmt::format("jobs: expected >= 1, got {}", jobs));
  if (stable_batches < 0) return fail(fmt::format("stable_batches: expected >= 0, got {}", stable_batches));
  return true;
}

QTable::QTable(int num_states, int num_actions, std::vector<std::uint8_t> availability)
    : num_states_(num_states),
      num_actions_(num_actions),
      available_(std::move(availability)),
      q_(static_cast<std::size_t>(num_states) * static_cast<std::size_t>(num_actions), 0.0),
      updates_(q_.size(), 0) {
  UASCMA_CHECK(num_states > 0 && num_actions > 0, "a non-empty table");
  UASCMA_CHECK(available_.size() == q_.size(), "one availability flag per (state, action)");
  for (StateIndex s = 0; s < num_states; ++s) {
    bool any = false;
    for (ActionIndex a = 0; a < num_actions; ++a) any = any || this->available(s, a);
    UASCMA_CHECK(any, "every state has an available action");
  }
}

std::size_t QTable::Index(StateIndex s, ActionIndex a) const {
  UASCMA_DCHECK(s >= 0 && s < num_states_ && a >= 0 && a < num_actions_, "a state and action of the table");
  return static_cast<std::size_t>(s) * static_cast<std::size_t>(num_actions_) + static_cast<std::size_t>(a);
}

std::int64_t QTable::state_visits(StateIndex s) const {
  std::int64_t total = 0;
  for (ActionIndex a = 0; a < num_actions_; ++a) total += updates_[Index(s, a)];
  return total;
}

int QTable::states_visited() const {
  int visited = 0;
  for (StateIndex s = 0; s < num_states_; ++s) visited += state_visits(s) > 0 ? 1 : 0;
  return visited;
}

ActionIndex QTable::Greedy(StateIndex s) const {
  ActionIndex best = -1;
  for (ActionIndex a = 0; a < num_actions_; ++a) {
    if (available(s, a) && (best < 0 || q(s, a) > q(s, best))) best = a;
  }
  return best;
}

double QTable::MaxQ(StateIndex s) const { return q(s, Greedy(s)); }

ActionIndex QTable::EpsilonGreedy(StateIndex s, double epsilon, RandomStream& random) const {
  if (epsilon > 0.0 && random.Bernoulli(epsilon)) {
    int count = 0;
    for (ActionIndex a = 0; a < num_actions_; ++a) count += available(s, a) ? 1 : 0;
    auto pick = static_cast<int>(random.UniformIndex(static_cast<std::uint64_t>(count)));
    for (ActionIndex a = 0; a < num_actions_; ++a) {
      if (available(s, a) && pick-- == 0) return a;
    }
  }
  return Greedy(s);
}

void QTable::Update(StateIndex s, ActionIndex a, double reward, StateIndex next_state, bool terminal,
                    const QLearningParams& params) {
  UASCMA_CHECK(available(s, a), "an update of an available action");
  const std::size_t i = Index(s, a);
  const double target = reward + (terminal ? 0.0 : params.gamma * MaxQ(next_state));
  const double alpha = params.alpha_decay_visits > 0.0
                           ? params.alpha / (1.0 + static_cast<double>(updates_[i]) / params.alpha_decay_visits)
                           : params.alpha;
  q_[i] += alpha * (target - q_[i]);
  ++updates_[i];
}

QLearningResult RunQLearning(QTable initial, const EpisodeFunction& fly, const QLearningOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("q-learning", "options", error);
  const auto wall_start = std::chrono::steady_clock::now();
  const double cpu_start = ProcessCpuSeconds();
  QLearningResult result{std::move(initial), {}, QLearningStatus::kEpisodeLimit, 0, -1, 0, 0.0, 0.0};
  double return_total = 0.0;
  int stable = 0;
  std::vector<ActionIndex> greedy = GreedyOfVisited(result.table);
  for (std::int64_t first = 0; first < options.max_episodes; first += options.batch_size) {
    const int count = static_cast<int>(std::min<std::int64_t>(options.batch_size, options.max_episodes - first));
    const QTable snapshot = result.table;
    std::vector<Episode> episodes = FlyBatch(fly, snapshot, first, count, options);
    for (int k = 0; k < count; ++k) {
      const Episode& episode = episodes[static_cast<std::size_t>(k)];
      for (const Experience& e : episode.steps) {
        result.table.Update(e.state, e.action, e.reward, e.next_state, e.terminal, options.params);
      }
      result.updates += static_cast<std::int64_t>(episode.steps.size());
      return_total += episode.return_sum;
      const std::int64_t index = first + k;
      result.curve.push_back({index, episode.return_sum, return_total / static_cast<double>(index + 1),
                              static_cast<int>(episode.steps.size()), result.table.states_visited(),
                              options.epsilon.At(index), 0});
    }
    result.episodes = first + count;
    std::vector<ActionIndex> now = GreedyOfVisited(result.table);
    int changes = 0;
    for (std::size_t s = 0; s < now.size(); ++s) changes += now[s] != greedy[s] ? 1 : 0;
    result.curve.back().policy_changes = changes;
    greedy = std::move(now);
    stable = changes == 0 ? stable + 1 : 0;
    if (options.stable_batches > 0 && stable >= options.stable_batches) {
      result.status = QLearningStatus::kPolicyStable;
      result.stable_since_episode = result.episodes - static_cast<std::int64_t>(stable) * options.batch_size;
      break;
    }
  }
  result.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  result.cpu_time_s = ProcessCpuSeconds() - cpu_start;
  return result;
}

std::vector<std::uint8_t> AvailableActions(const decision::FiniteMdp& mdp) {
  std::vector<std::uint8_t> available(
      static_cast<std::size_t>(mdp.num_states()) * static_cast<std::size_t>(mdp.num_actions()), 0);
  for (StateIndex s = 0; s < mdp.num_states(); ++s) {
    for (std::int64_t c = mdp.choice_begin(s); c < mdp.choice_end(s); ++c) {
      available[static_cast<std::size_t>(s) * static_cast<std::size_t>(mdp.num_actions()) +
                static_cast<std::size_t>(mdp.choice_action(c))] = 1;
    }
  }
  return available;
}

Episode SimulateMdpEpisode(const decision::FiniteMdp& mdp, const std::vector<std::uint8_t>& terminal, StateIndex start,
                           int max_steps, const QTable& snapshot, double epsilon, std::uint64_t seed) {
  RandomStream random(seed);
  Episode episode;
  StateIndex s = start;
  for (int step = 0; step < max_steps; ++step) {
    const ActionIndex a = snapshot.EpsilonGreedy(s, epsilon, random);
    const std::int64_t c = mdp.FindChoice(s, a);
    UASCMA_CHECK(c >= 0, "an available action");
    const auto next = mdp.choice_next_states(c);
    const auto prob = mdp.choice_probabilities(c);
    double u = random.Uniform();
    std::size_t k = 0;
    while (k + 1 < next.size() && u >= prob[k]) u -= prob[k++];
    const StateIndex s_next = next[k];
    const bool done = terminal[static_cast<std::size_t>(s_next)] != 0;
    episode.steps.push_back({s, a, mdp.choice_reward(c), s_next, done});
    episode.return_sum += mdp.choice_reward(c);
    if (done) break;
    s = s_next;
  }
  return episode;
}

}  // namespace uascma::learning
