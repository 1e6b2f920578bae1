#include "uascma/decision/solvers.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <Eigen/Dense>

#include "uascma/common/error.h"

namespace uascma::decision {
namespace {

constexpr double kMinusInfinity = -std::numeric_limits<double>::infinity();

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

void CheckGamma(double gamma) {
  if (!(gamma >= 0.0 && gamma < 1.0)) {
    throw InputError("solver options", "gamma", fmt::format("a value in [0, 1), got {}", gamma));
  }
}

// Q(s, a) with the self-transition p(s|s,a) solved exactly, given the current values of the
// other states: Q = (r + γ Σ_{s'≠s} p V(s')) / (1 − γ p_ss). Used by in-place sweeps.
inline double SelfLoopSolvedQ(const FiniteMdp& mdp, std::int64_t c, StateIndex s, double gamma, const double* value) {
  const auto& row_begin = mdp.choice_row_begin();
  const StateIndex* next = mdp.next_state().data();
  const double* prob = mdp.probability().data();
  double others = 0.0;
  double self = 0.0;
  for (std::int64_t k = row_begin[c]; k < row_begin[c + 1]; ++k) {
    if (next[k] == s) {
      self += prob[k];
    } else {
      others += prob[k] * value[next[k]];
    }
  }
  return (mdp.choice_reward()[c] + gamma * others) / (1.0 - gamma * self);
}

// Σ_k p_k V(s'_k) over one row. Four partial sums break the floating-point add latency chain, which
// otherwise bounds a sweep of 10-successor rows (measured: 5.8 → see bench/mdp_bench.cc).
inline double RowExpectation(const StateIndex* next, const double* prob, std::int64_t begin, std::int64_t end,
                             const double* value) {
  double sum0 = 0.0, sum1 = 0.0, sum2 = 0.0, sum3 = 0.0;
  std::int64_t k = begin;
  for (; k + 4 <= end; k += 4) {
    sum0 += prob[k] * value[next[k]];
    sum1 += prob[k + 1] * value[next[k + 1]];
    sum2 += prob[k + 2] * value[next[k + 2]];
    sum3 += prob[k + 3] * value[next[k + 3]];
  }
  for (; k < end; ++k) sum0 += prob[k] * value[next[k]];
  return (sum0 + sum1) + (sum2 + sum3);
}

// One in-place sweep of the optimality (policy == nullptr) or evaluation operator.
double GaussSeidelSweep(const FiniteMdp& mdp, double gamma, std::vector<double>& value,
                        const std::vector<std::int64_t>* policy_choice) {
  double residual = 0.0;
  const auto& state_begin = mdp.state_choice_begin();
  for (StateIndex s = 0; s < mdp.num_states(); ++s) {
    double best = kMinusInfinity;
    if (policy_choice != nullptr) {
      best = SelfLoopSolvedQ(mdp, (*policy_choice)[s], s, gamma, value.data());
    } else {
      for (std::int64_t c = state_begin[s]; c < state_begin[s + 1]; ++c) {
        best = std::max(best, SelfLoopSolvedQ(mdp, c, s, gamma, value.data()));
      }
    }
    residual = std::max(residual, std::abs(best - value[s]));
    value[s] = best;
  }
  return residual;
}

std::vector<std::int64_t> PolicyChoices(const FiniteMdp& mdp, const std::vector<ActionIndex>& policy) {
  if (static_cast<int>(policy.size()) != mdp.num_states()) {
    throw InputError("policy", "actions",
                     fmt::format("one action per state ({}), got {}", mdp.num_states(), policy.size()));
  }
  std::vector<std::int64_t> choices(policy.size());
  for (StateIndex s = 0; s < mdp.num_states(); ++s) {
    const std::int64_t c = (policy[s] >= 0 && policy[s] < mdp.num_actions()) ? mdp.FindChoice(s, policy[s]) : -1;
    if (c < 0) {
      throw InputError("policy", fmt::format("state '{}'", mdp.state_label(s)), "an action available in that state");
    }
    choices[s] = c;
  }
  return choices;
}

}  // namespace

bool ValueIterationOptions::IsValid(std::string* error) const {
  if (!(gamma >= 0.0 && gamma < 1.0)) {
    if (error) *error = fmt::format("gamma: expected a value in [0, 1), got {}", gamma);
    return false;
  }
  if (!(residual_tolerance > 0.0)) {
    if (error) *error = fmt::format("residual_tolerance: expected > 0, got {}", residual_tolerance);
    return false;
  }
  if (max_iterations < 1) {
    if (error) *error = fmt::format("max_iterations: expected >= 1, got {}", max_iterations);
    return false;
  }
  return true;
}

std::string SolverSummary::BriefReport() const {
  return fmt::format("{} after {} iterations, residual {:.3g}, {:.3g} ms{}",
                     status == SolverStatus::kConverged ? "converged" : "stopped at max iterations", iterations,
                     residual, wall_time_s * 1e3, message.empty() ? "" : " (" + message + ")");
}

double ChoiceQValue(const FiniteMdp& mdp, std::int64_t choice, double gamma, const std::vector<double>& value) {
  double expected = 0.0;
  const auto next = mdp.choice_next_states(choice);
  const auto prob = mdp.choice_probabilities(choice);
  for (std::size_t k = 0; k < next.size(); ++k) expected += prob[k] * value[next[k]];
  return mdp.choice_reward(choice) + gamma * expected;
}

double BellmanSweep(const FiniteMdp& mdp, double gamma, const std::vector<double>& in, std::vector<double>& out,
                    std::vector<ActionIndex>* greedy) {
  const int num_states = mdp.num_states();
  out.resize(static_cast<std::size_t>(num_states));
  if (greedy != nullptr) greedy->resize(static_cast<std::size_t>(num_states));
  const std::int64_t* state_begin = mdp.state_choice_begin().data();
  const std::int64_t* row_begin = mdp.choice_row_begin().data();
  const double* reward = mdp.choice_reward().data();
  const StateIndex* next = mdp.next_state().data();
  const double* prob = mdp.probability().data();
  const double* v = in.data();
  double residual = 0.0;
  for (StateIndex s = 0; s < num_states; ++s) {
    double best = kMinusInfinity;
    std::int64_t best_choice = state_begin[s];
    for (std::int64_t c = state_begin[s]; c < state_begin[s + 1]; ++c) {
      const double q = reward[c] + gamma * RowExpectation(next, prob, row_begin[c], row_begin[c + 1], v);
      if (q > best) {
        best = q;
        best_choice = c;
      }
    }
    residual = std::max(residual, std::abs(best - v[s]));
    out[s] = best;
    if (greedy != nullptr) (*greedy)[s] = mdp.choice_action(best_choice);
  }
  return residual;
}

std::vector<ActionIndex> GreedyPolicy(const FiniteMdp& mdp, double gamma, const std::vector<double>& value) {
  std::vector<ActionIndex> policy(static_cast<std::size_t>(mdp.num_states()));
  for (StateIndex s = 0; s < mdp.num_states(); ++s) {
    double best = kMinusInfinity;
    for (std::int64_t c = mdp.choice_begin(s); c < mdp.choice_end(s); ++c) {
      const double q = ChoiceQValue(mdp, c, gamma, value);
      if (q > best) {
        best = q;
        policy[s] = mdp.choice_action(c);
      }
    }
  }
  return policy;
}

std::vector<std::vector<ActionIndex>> RankActionsByQ(const FiniteMdp& mdp, double gamma,
                                                     const std::vector<double>& value,
                                                     const std::vector<ActionIndex>* policy_action) {
  std::vector<std::vector<ActionIndex>> ranking(static_cast<std::size_t>(mdp.num_states()));
  for (StateIndex s = 0; s < mdp.num_states(); ++s) {
    std::vector<std::pair<double, ActionIndex>> scored;
    for (std::int64_t c = mdp.choice_begin(s); c < mdp.choice_end(s); ++c) {
      scored.emplace_back(-ChoiceQValue(mdp, c, gamma, value), mdp.choice_action(c));
    }
    std::sort(scored.begin(), scored.end());  // decreasing Q, then increasing action index
    std::vector<ActionIndex>& order = ranking[static_cast<std::size_t>(s)];
    for (const auto& [minus_q, action] : scored) order.push_back(action);
    if (policy_action != nullptr) {
      const auto own = std::find(order.begin(), order.end(), (*policy_action)[static_cast<std::size_t>(s)]);
      if (own != order.end()) std::rotate(order.begin(), own, own + 1);
    }
  }
  return ranking;
}

Policy SolveValueIteration(const FiniteMdp& mdp, const ValueIterationOptions& options, SolverSummary* summary) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("value iteration options: " + error);
  const auto start = Clock::now();
  std::vector<double> value(static_cast<std::size_t>(mdp.num_states()), 0.0);
  std::vector<double> next_value;
  SolverSummary result;
  for (result.iterations = 1; result.iterations <= options.max_iterations; ++result.iterations) {
    if (options.order == SweepOrder::kGaussSeidel) {
      result.residual = GaussSeidelSweep(mdp, options.gamma, value, nullptr);
    } else {
      result.residual = BellmanSweep(mdp, options.gamma, value, next_value);
      value.swap(next_value);
    }
    if (result.residual < options.residual_tolerance) {
      result.status = SolverStatus::kConverged;
      break;
    }
  }
  result.iterations = std::min(result.iterations, options.max_iterations);
  Policy policy;
  policy.action = GreedyPolicy(mdp, options.gamma, value);
  policy.value = std::move(value);
  result.wall_time_s = SecondsSince(start);
  if (result.status != SolverStatus::kConverged) {
    result.message = fmt::format("residual still above {:g}", options.residual_tolerance);
  }
  if (summary != nullptr) *summary = result;
  return policy;
}

std::vector<double> EvaluatePolicy(const FiniteMdp& mdp, const std::vector<ActionIndex>& policy,
                                   const PolicyEvaluationOptions& options) {
  CheckGamma(options.gamma);
  const std::vector<std::int64_t> choices = PolicyChoices(mdp, policy);
  const int n = mdp.num_states();
  EvaluationMethod method = options.method;
  if (method == EvaluationMethod::kAuto) {
    method = n <= kDirectEvaluationMaxStates ? EvaluationMethod::kDirect : EvaluationMethod::kIterative;
  }
  if (method == EvaluationMethod::kDirect) {
    // (I − γ P_π) V = r_π, solved by LU with partial pivoting (the matrix is strictly diagonally
    // dominant for γ < 1, so it is well conditioned).
    Eigen::MatrixXd system = Eigen::MatrixXd::Identity(n, n);
    Eigen::VectorXd reward(n);
    for (StateIndex s = 0; s < n; ++s) {
      const std::int64_t c = choices[s];
      reward(s) = mdp.choice_reward(c);
      const auto next = mdp.choice_next_states(c);
      const auto prob = mdp.choice_probabilities(c);
      for (std::size_t k = 0; k < next.size(); ++k) system(s, next[k]) -= options.gamma * prob[k];
    }
    const Eigen::VectorXd solution = system.partialPivLu().solve(reward);
    return {solution.data(), solution.data() + n};
  }
  std::vector<double> value(static_cast<std::size_t>(n), 0.0);
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    if (GaussSeidelSweep(mdp, options.gamma, value, &choices) < options.residual_tolerance) break;
  }
  return value;
}

Policy SolvePolicyIteration(const FiniteMdp& mdp, const PolicyIterationOptions& options, SolverSummary* summary) {
  CheckGamma(options.gamma);
  const auto start = Clock::now();
  Policy policy;
  policy.action.resize(static_cast<std::size_t>(mdp.num_states()));
  for (StateIndex s = 0; s < mdp.num_states(); ++s) {
    policy.action[s] = mdp.choice_action(mdp.choice_begin(s));
  }
  PolicyEvaluationOptions evaluation;
  evaluation.gamma = options.gamma;
  evaluation.method = options.evaluation;
  SolverSummary result;
  for (result.iterations = 1; result.iterations <= options.max_iterations; ++result.iterations) {
    policy.value = EvaluatePolicy(mdp, policy.action, evaluation);
    bool changed = false;
    for (StateIndex s = 0; s < mdp.num_states(); ++s) {
      const double incumbent = ChoiceQValue(mdp, mdp.FindChoice(s, policy.action[s]), options.gamma, policy.value);
      double best = incumbent;
      for (std::int64_t c = mdp.choice_begin(s); c < mdp.choice_end(s); ++c) {
        const double q = ChoiceQValue(mdp, c, options.gamma, policy.value);
        if (q > best + options.improvement_tolerance) {
          best = q;
          policy.action[s] = mdp.choice_action(c);
          changed = true;
        }
      }
    }
    if (!changed) {
      result.status = SolverStatus::kConverged;
      break;
    }
  }
  result.iterations = std::min(result.iterations, options.max_iterations);
  result.wall_time_s = SecondsSince(start);
  if (result.status != SolverStatus::kConverged) result.message = "policy still changing";
  if (summary != nullptr) *summary = result;
  return policy;
}

}  // namespace uascma::decision
