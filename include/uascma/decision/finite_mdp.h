#pragma once
// A finite Markov decision process <S, A, p(s'|s,a), r(s,a)> stored as compressed sparse rows,
// and the solvers used for the CMA MDP (dissertation §5.3.2) and any larger model.
//
// Storage. Each available (state, action) pair is a "choice": an action id, a reward r(s,a) and a
// row of successors (next state, probability). Choices of a state are contiguous and states are in
// order, so one value-iteration sweep streams through memory once:
//   state_choice_begin  [num_states + 1]   choices of state s: [begin[s], begin[s+1])
//   choice_action       [num_choices]      action id of each choice
//   choice_reward       [num_choices]      r(s, a)
//   choice_row_begin    [num_choices + 1]  successors of choice c: [begin[c], begin[c+1])
//   next_state          [num_transitions]  s'
//   probability         [num_transitions]  p(s'|s,a)
// The model is immutable once built (a model apart from its state); solvers take it by const reference.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace uascma::decision {

using StateIndex = std::int32_t;
using ActionIndex = std::int32_t;

struct Transition {
  StateIndex next_state = 0;
  double probability = 0.0;
};

class FiniteMdp {
 public:
  int num_states() const { return static_cast<int>(state_labels_.size()); }
  int num_actions() const { return static_cast<int>(action_names_.size()); }
  std::int64_t num_choices() const { return static_cast<std::int64_t>(choice_action_.size()); }
  std::int64_t num_transitions() const { return static_cast<std::int64_t>(next_state_.size()); }

  const std::vector<std::string>& state_labels() const { return state_labels_; }
  const std::vector<std::string>& action_names() const { return action_names_; }
  const std::string& state_label(StateIndex s) const { return state_labels_[s]; }
  const std::string& action_name(ActionIndex a) const { return action_names_[a]; }
  // Index of a state label or action name, or -1 when unknown.
  StateIndex FindState(const std::string& label) const;
  ActionIndex FindAction(const std::string& name) const;

  std::int64_t choice_begin(StateIndex s) const { return state_choice_begin_[s]; }
  std::int64_t choice_end(StateIndex s) const { return state_choice_begin_[s + 1]; }
  ActionIndex choice_action(std::int64_t c) const { return choice_action_[c]; }
  double choice_reward(std::int64_t c) const { return choice_reward_[c]; }
  std::span<const StateIndex> choice_next_states(std::int64_t c) const {
    return {next_state_.data() + choice_row_begin_[c],
            static_cast<std::size_t>(choice_row_begin_[c + 1] - choice_row_begin_[c])};
  }
  std::span<const double> choice_probabilities(std::int64_t c) const {
    return {probability_.data() + choice_row_begin_[c],
            static_cast<std::size_t>(choice_row_begin_[c + 1] - choice_row_begin_[c])};
  }
  // The choice of action `a` in state `s`, or -1 when `a` is not available there.
  std::int64_t FindChoice(StateIndex s, ActionIndex a) const;
  bool IsAvailable(StateIndex s, ActionIndex a) const { return FindChoice(s, a) >= 0; }

  // Raw arrays, for solvers and bindings (shapes in the file comment above).
  const std::vector<std::int64_t>& state_choice_begin() const { return state_choice_begin_; }
  const std::vector<ActionIndex>& choice_action() const { return choice_action_; }
  const std::vector<double>& choice_reward() const { return choice_reward_; }
  const std::vector<std::int64_t>& choice_row_begin() const { return choice_row_begin_; }
  const std::vector<StateIndex>& next_state() const { return next_state_; }
  const std::vector<double>& probability() const { return probability_; }

 private:
  friend class FiniteMdpBuilder;
  std::vector<std::string> state_labels_;
  std::vector<std::string> action_names_;
  std::vector<std::int64_t> state_choice_begin_;
  std::vector<ActionIndex> choice_action_;
  std::vector<double> choice_reward_;
  std::vector<std::int64_t> choice_row_begin_;
  std::vector<StateIndex> next_state_;
  std::vector<double> probability_;
};

// Builds a FiniteMdp row by row. Rows must be added in nondecreasing state order (so building a
// 10^6-state model appends straight into the final arrays); within a state, actions in any order,
// each at most once. Build() validates and throws InputError naming the state and action when:
// a probability is outside [0, 1] or not finite, a row does not sum to 1 within 1e-9, a successor
// index is out of range, a reward is not finite, or a state has no available action.
class FiniteMdpBuilder {
 public:
  FiniteMdpBuilder(std::vector<std::string> state_labels, std::vector<std::string> action_names);

  void AddRow(StateIndex state, ActionIndex action, double reward, std::span<const Transition> successors);
  FiniteMdp Build();

  static constexpr double kRowSumTolerance = 1e-9;

 private:
  void CloseStatesUpTo(StateIndex state);
  FiniteMdp mdp_;
  StateIndex current_state_ = 0;
};

}  // namespace uascma::decision
