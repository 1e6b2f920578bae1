#pragma once
// Dynamic-programming solvers for a FiniteMdp with discount factor gamma in [0, 1):
// value iteration, policy evaluation and policy iteration (Puterman, "Markov Decision Processes",
// 1994, §6.3–6.4). Each returns a Summary (status, iterations, residual, time), never a bare bool.
#include <string>
#include <vector>

#include "uascma/decision/finite_mdp.h"

namespace uascma::decision {

// A deterministic stationary policy: the action per state and the value it earns.
struct Policy {
  std::vector<ActionIndex> action;  // [num_states]
  std::vector<double> value;        // [num_states]
};

enum class SweepOrder {
  // Synchronous (Jacobi) sweeps: V_{k+1} = T V_k, the textbook operator.
  kJacobi,
  // In-place (Gauss-Seidel) sweeps in state order, with each choice's self-transition solved
  // exactly: Q = (r + γ Σ_{s'≠s} p V(s')) / (1 − γ p_ss). Same fixed point, far fewer sweeps when
  // states mostly loop on themselves, as the 1 Hz CMA MDP does.
  kGaussSeidel,
};

struct ValueIterationOptions {
  double gamma = 0.95;                // docs/modelling-choices.md#discount
  double residual_tolerance = 1e-10;  // stop when max_s |V_{k+1}(s) − V_k(s)| < this
                                      // (docs/modelling-choices.md#discount)
  int max_iterations = 100000;
  SweepOrder order = SweepOrder::kGaussSeidel;
  bool IsValid(std::string* error) const;
};

enum class SolverStatus { kConverged, kMaxIterations };

struct SolverSummary {
  SolverStatus status = SolverStatus::kMaxIterations;
  int iterations = 0;     // sweeps (value iteration) or improvement steps (policy iteration)
  double residual = 0.0;  // the last sweep's max |ΔV|; 0 for policy iteration's exact stop
  double wall_time_s = 0.0;
  std::string message;
  std::string BriefReport() const;
};

// Value iteration from V = 0. Throws InputError when options are invalid.
Policy SolveValueIteration(const FiniteMdp& mdp, const ValueIterationOptions& options,
                           SolverSummary* summary = nullptr);

// One Jacobi Bellman-optimality sweep: out = T(in), and the greedy action in `greedy` if given.
// Exposed for benchmarks and tests. Returns max_s |out(s) − in(s)|.
double BellmanSweep(const FiniteMdp& mdp, double gamma, const std::vector<double>& in, std::vector<double>& out,
                    std::vector<ActionIndex>* greedy = nullptr);

enum class EvaluationMethod {
  kAuto,       // kDirect up to kDirectEvaluationMaxStates states, kIterative beyond
  kDirect,     // solve (I − γ P_π) V = r_π by dense LU (exact to round-off)
  kIterative,  // Gauss-Seidel sweeps to the residual tolerance
};
inline constexpr int kDirectEvaluationMaxStates = 1000;

struct PolicyEvaluationOptions {
  double gamma = 0.95;
  EvaluationMethod method = EvaluationMethod::kAuto;
  double residual_tolerance = 1e-12;
  int max_iterations = 1000000;
};

// V^π for a policy whose every action is available in its state (InputError otherwise).
std::vector<double> EvaluatePolicy(const FiniteMdp& mdp, const std::vector<ActionIndex>& policy,
                                   const PolicyEvaluationOptions& options);

struct PolicyIterationOptions {
  double gamma = 0.95;
  int max_iterations = 1000;
  EvaluationMethod evaluation = EvaluationMethod::kAuto;
  // An action replaces the incumbent only when it is better by more than this (avoids cycling
  // between ties).
  double improvement_tolerance = 1e-12;
};

// Howard's policy iteration from the policy "first available action".
Policy SolvePolicyIteration(const FiniteMdp& mdp, const PolicyIterationOptions& options,
                            SolverSummary* summary = nullptr);

// The greedy policy of a value function, and Q(s, a) for one choice.
std::vector<ActionIndex> GreedyPolicy(const FiniteMdp& mdp, double gamma, const std::vector<double>& value);
double ChoiceQValue(const FiniteMdp& mdp, std::int64_t choice, double gamma, const std::vector<double>& value);
// Per state, its available actions by decreasing Q(s, a) under `value` (ties: the lower action index first), with
// `policy_action[s]` moved to the front when given (a policy's own choice leads even where another action has the
// same value). What an executor falls back on when the chosen action cannot be carried out
// (docs/modelling-choices.md#unavailable-actions).
std::vector<std::vector<ActionIndex>> RankActionsByQ(const FiniteMdp& mdp, double gamma,
                                                     const std::vector<double>& value,
                                                     const std::vector<ActionIndex>* policy_action = nullptr);

}  // namespace uascma::decision
