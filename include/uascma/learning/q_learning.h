#pragma once
// Tabular Q-learning (Watkins 1989; Sutton & Barto, "Reinforcement Learning", 2nd ed., §6.5 — the dissertation's
// reference [69] for §5.3.3), for any episodic task with finite states and actions, and a batched driver whose
// results do not depend on the number of threads.
//
// The update of one experience (s, a, r, s') with step size α and discount γ:
//   Q(s, a) ← Q(s, a) + α_n (r + γ max_{a' available in s'} Q(s', a') − Q(s, a)),  the max taken as 0 when the
//   episode ended with this step (its terminal's own reward is part of r, sim/environment.h);
//   α_n = α / (1 + n(s, a) / alpha_decay_visits) with n(s, a) the updates of (s, a) so far, or α when
//   alpha_decay_visits = 0 (the dissertation's constant α = 0.8).
// Behaviour: ε-greedy over the actions available in the state (ties of the greedy action go to the lowest action
// index), ε from EpsilonSchedule per episode. Q starts at 0.
//
// Parallel and deterministic. Episodes are flown in batches of `batch_size` (fixed, independent of `jobs`): every
// episode of a batch sees the same frozen copy of Q taken when the batch starts and draws its randomness from its
// own index only; after the batch, the experiences are applied in episode order, step by step. So the learned
// table is the same for any number of threads. With batch_size = 1 this is sequential Q-learning exactly; a larger
// batch delays the effect of an episode on the behaviour of the next ones by at most batch_size − 1 episodes (the
// updates themselves are the same sequential ones), which matters only while few episodes have been flown.
//
// Stopping. After `max_episodes`, or — when stable_batches > 0 — once the greedy action of every state visited so
// far has not changed (and no new state was visited) for `stable_batches` consecutive batches.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "uascma/common/random.h"
#include "uascma/decision/finite_mdp.h"

namespace uascma::learning {

using decision::ActionIndex;
using decision::StateIndex;

struct QLearningParams {
  double alpha = 0.8;               // §5.3.3 step size
  double gamma = 0.9;               // §5.3.3 discount factor
  double alpha_decay_visits = 0.0;  // 0: constant α (the dissertation's); else α / (1 + n(s,a) / this)
  bool IsValid(std::string* error) const;
};

// ε per episode: `start` at episode 0, linearly to `end` at `decay_episodes`, then `end` (decay_episodes = 0:
// `start` throughout). §5.3.3: ε = 0.01 constant.
struct EpsilonSchedule {
  double start = 0.01;
  double end = 0.01;
  std::int64_t decay_episodes = 0;
  double At(std::int64_t episode) const;
  bool IsValid(std::string* error) const;
};

class QTable {
 public:
  // available[s * num_actions + a] != 0 when action a may be taken in state s (every state needs one).
  QTable(int num_states, int num_actions, std::vector<std::uint8_t> available);

  int num_states() const { return num_states_; }
  int num_actions() const { return num_actions_; }
  bool available(StateIndex s, ActionIndex a) const { return available_[Index(s, a)] != 0; }
  double q(StateIndex s, ActionIndex a) const { return q_[Index(s, a)]; }
  std::int64_t updates(StateIndex s, ActionIndex a) const { return updates_[Index(s, a)]; }
  std::int64_t state_visits(StateIndex s) const;  // updates summed over the state's actions
  int states_visited() const;

  ActionIndex Greedy(StateIndex s) const;
  double MaxQ(StateIndex s) const;  // over available actions
  ActionIndex EpsilonGreedy(StateIndex s, double epsilon, RandomStream& random) const;

  // One Q-learning update (file comment). next_state is ignored when `terminal`.
  void Update(StateIndex s, ActionIndex a, double reward, StateIndex next_state, bool terminal,
              const QLearningParams& params);

 private:
  std::size_t Index(StateIndex s, ActionIndex a) const;
  int num_states_, num_actions_;
  std::vector<std::uint8_t> available_;
  std::vector<double> q_;
  std::vector<std::int64_t> updates_;
};

struct Experience {
  StateIndex state = 0;
  ActionIndex action = 0;
  double reward = 0.0;
  StateIndex next_state = 0;
  bool terminal = false;
};

struct Episode {
  std::vector<Experience> steps;
  double return_sum = 0.0;  // undiscounted sum of the rewards (Fig. 5.14)
};

// Flies episode `index` with behaviour ε-greedy on `snapshot`; must depend only on (index, snapshot, epsilon).
// Called from worker threads.
using EpisodeFunction = std::function<Episode(std::int64_t index, const QTable& snapshot, double epsilon)>;

struct QLearningOptions {
  QLearningParams params;
  EpsilonSchedule epsilon;
  std::int64_t max_episodes = 10000;                  // §5.3.3
  int batch_size = 16;                                // episodes per frozen snapshot (ours; see the file comment)
  int jobs = 1;                                       // worker threads (results do not depend on it)
  int stable_batches = 0;                             // 0: fly max_episodes
  std::function<void(std::int64_t)> on_episode_done;  // from any thread, may be empty
  bool IsValid(std::string* error) const;
};

struct CurvePoint {
  std::int64_t episode = 0;
  double return_sum = 0.0;
  double mean_return = 0.0;  // average over episodes 0 … episode (Fig. 5.14's "average sum of rewards")
  int steps = 0;
  int states_visited = 0;  // after the episode's updates
  double epsilon = 0.0;
  int policy_changes = 0;  // greedy actions changed by the episode's batch (the batch's last episode only)
};

enum class QLearningStatus { kEpisodeLimit, kPolicyStable };

struct QLearningResult {
  QTable table;
  std::vector<CurvePoint> curve;
  QLearningStatus status = QLearningStatus::kEpisodeLimit;
  std::int64_t episodes = 0;
  std::int64_t stable_since_episode = -1;  // first episode of the final stable stretch (kPolicyStable)
  std::int64_t updates = 0;
  double wall_time_s = 0.0;
  double cpu_time_s = 0.0;  // process CPU time over the run (all threads)
};

// InputError when the options are invalid.
QLearningResult RunQLearning(QTable initial, const EpisodeFunction& fly, const QLearningOptions& options);

// A learning episode of a FiniteMdp (tests and benchmarks): from `start`, ε-greedy on `snapshot`, successors drawn
// from the rows, ending after `max_steps` or on reaching a state in `terminal` (the reward of the step into it
// included; terminal[s] != 0). Randomness from `seed` only.
Episode SimulateMdpEpisode(const decision::FiniteMdp& mdp, const std::vector<std::uint8_t>& terminal, StateIndex start,
                           int max_steps, const QTable& snapshot, double epsilon, std::uint64_t seed);
// The availability mask of a FiniteMdp's choices, for QTable.
std::vector<std::uint8_t> AvailableActions(const decision::FiniteMdp& mdp);

}  // namespace uascma::learning
