// Tabular Q-learning (learning/q_learning.h): convergence to the optimum of a small MDP solved by value iteration,
// the batched driver against a hand-written sequential loop, thread-count independence, and the stop rule.
#include "uascma/learning/q_learning.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "uascma/decision/random_mdp.h"
#include "uascma/decision/solvers.h"

namespace uascma::learning {
namespace {

using decision::FiniteMdp;

constexpr double kGamma = 0.9;
// Random MDP rewards are in [-1, 1], so values lie within ±1 / (1 − γ) = ±10: 0.15 is 1.5 % of that range.
constexpr double kQTolerance = 0.15;

struct SmallProblem {
  FiniteMdp mdp = decision::MakeRandomMdp(6, 3, 3, 11);
  std::vector<std::uint8_t> never_terminal = std::vector<std::uint8_t>(6, 0);
};

// Episodes of 50 steps from start state (episode mod 6): a continuing task cut into pieces; the last step of an
// episode bootstraps (it is not terminal).
EpisodeFunction MdpEpisodes(const SmallProblem& problem, std::uint64_t seed) {
  return [&problem, seed](std::int64_t index, const QTable& snapshot, double epsilon) {
    return SimulateMdpEpisode(problem.mdp, problem.never_terminal, static_cast<StateIndex>(index % 6), 50, snapshot,
                              epsilon, DeriveSeed(seed, static_cast<std::uint64_t>(index)));
  };
}

QLearningOptions ConvergenceOptions() {
  QLearningOptions options;
  options.params = {1.0, kGamma, 20.0};  // α_n = 1 / (1 + n/20): Robbins–Monro step sizes
  options.epsilon = {1.0, 1.0, 0};       // uniform behaviour: Q-learning is off-policy
  options.max_episodes = 3000;
  options.batch_size = 8;
  return options;
}

TEST(QLearningTest, ConvergesToTheValueIterationOptimumOfASmallMdp) {
  const SmallProblem problem;
  decision::ValueIterationOptions vi;
  vi.gamma = kGamma;
  const decision::Policy optimum = decision::SolveValueIteration(problem.mdp, vi);
  const QLearningResult result =
      RunQLearning(QTable(6, 3, AvailableActions(problem.mdp)), MdpEpisodes(problem, 5), ConvergenceOptions());
  for (StateIndex s = 0; s < 6; ++s) {
    std::vector<double> q_star;
    for (std::int64_t c = problem.mdp.choice_begin(s); c < problem.mdp.choice_end(s); ++c) {
      q_star.push_back(decision::ChoiceQValue(problem.mdp, c, kGamma, optimum.value));
      EXPECT_NEAR(result.table.q(s, problem.mdp.choice_action(c)), q_star.back(), kQTolerance)
          << "state " << s << " action " << problem.mdp.choice_action(c);
    }
    // The greedy action is the optimal one wherever the optimum is not a near-tie.
    std::vector<double> sorted = q_star;
    std::sort(sorted.rbegin(), sorted.rend());
    if (sorted[0] - sorted[1] > 2.0 * kQTolerance) {
      EXPECT_EQ(result.table.Greedy(s), optimum.action[static_cast<std::size_t>(s)]) << "state " << s;
    }
  }
  EXPECT_EQ(result.table.states_visited(), 6);
}

TEST(QLearningTest, BatchOfOneIsSequentialQLearning) {
  const SmallProblem problem;
  QLearningOptions options;  // the dissertation's α = 0.8, γ = 0.9, ε = 0.01
  options.max_episodes = 40;
  options.batch_size = 1;
  const EpisodeFunction fly = MdpEpisodes(problem, 9);
  const QLearningResult batched = RunQLearning(QTable(6, 3, AvailableActions(problem.mdp)), fly, options);
  // The same by hand: fly against the live table, update after each episode.
  QTable table(6, 3, AvailableActions(problem.mdp));
  for (std::int64_t e = 0; e < options.max_episodes; ++e) {
    const Episode episode = fly(e, table, options.epsilon.At(e));
    for (const Experience& x : episode.steps) {
      table.Update(x.state, x.action, x.reward, x.next_state, x.terminal, options.params);
    }
  }
  for (StateIndex s = 0; s < 6; ++s) {
    for (ActionIndex a = 0; a < 3; ++a) EXPECT_EQ(batched.table.q(s, a), table.q(s, a));  // bit for bit
  }
}

TEST(QLearningTest, TableDoesNotDependOnThreads) {
  const SmallProblem problem;
  QLearningOptions options = ConvergenceOptions();
  options.max_episodes = 200;
  options.epsilon = {0.3, 0.05, 150};
  const QLearningResult one =
      RunQLearning(QTable(6, 3, AvailableActions(problem.mdp)), MdpEpisodes(problem, 3), options);
  options.jobs = 3;
  const QLearningResult three =
      RunQLearning(QTable(6, 3, AvailableActions(problem.mdp)), MdpEpisodes(problem, 3), options);
  for (StateIndex s = 0; s < 6; ++s) {
    for (ActionIndex a = 0; a < 3; ++a) EXPECT_EQ(one.table.q(s, a), three.table.q(s, a));  // bit for bit
  }
  ASSERT_EQ(one.curve.size(), three.curve.size());
  for (std::size_t i = 0; i < one.curve.size(); ++i) EXPECT_EQ(one.curve[i].return_sum, three.curve[i].return_sum);
}

TEST(QLearningTest, StopsWhenTheGreedyPolicyIsStable) {
  const SmallProblem problem;
  QLearningOptions options = ConvergenceOptions();
  options.max_episodes = 100000;
  options.stable_batches = 50;
  const QLearningResult result =
      RunQLearning(QTable(6, 3, AvailableActions(problem.mdp)), MdpEpisodes(problem, 5), options);
  ASSERT_EQ(result.status, QLearningStatus::kPolicyStable);
  EXPECT_LT(result.episodes, options.max_episodes);
  // The last 50 batches changed no greedy action.
  int changes = 0;
  for (const CurvePoint& p : result.curve) {
    if (p.episode >= result.stable_since_episode) changes += p.policy_changes;
  }
  EXPECT_EQ(changes, 0);
  EXPECT_EQ(result.stable_since_episode, result.episodes - 50 * options.batch_size);
}

TEST(QLearningTest, EpsilonScheduleAndValidation) {
  const EpsilonSchedule schedule{0.5, 0.1, 100};
  EXPECT_DOUBLE_EQ(schedule.At(0), 0.5);
  EXPECT_DOUBLE_EQ(schedule.At(50), 0.3);
  EXPECT_DOUBLE_EQ(schedule.At(100), 0.1);
  EXPECT_DOUBLE_EQ(schedule.At(5000), 0.1);
  EXPECT_DOUBLE_EQ((EpsilonSchedule{0.01, 0.5, 0}).At(7), 0.01);
  QLearningOptions bad;
  bad.params.alpha = 0.0;
  std::string error;
  EXPECT_FALSE(bad.IsValid(&error));
  EXPECT_NE(error.find("alpha"), std::string::npos);
  bad = {};
  bad.params.gamma = 1.0;
  EXPECT_FALSE(bad.IsValid(&error));
  bad = {};
  bad.batch_size = 0;
  EXPECT_FALSE(bad.IsValid(&error));
}

TEST(QLearningTest, GreedyTiesGoToTheLowestAvailableAction) {
  QTable table(2, 3, {0, 1, 1, 1, 1, 1});
  EXPECT_EQ(table.Greedy(0), 1);  // action 0 unavailable in state 0
  EXPECT_EQ(table.Greedy(1), 0);
  RandomStream random(1);
  for (int i = 0; i < 200; ++i) EXPECT_NE(table.EpsilonGreedy(0, 1.0, random), 0);
}

}  // namespace
}  // namespace uascma::learning
