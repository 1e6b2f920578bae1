#pragma once
// A factored MDP described as a dynamic decision network (DDN), composed into a FiniteMdp.
//
// Non-terminal states are tuples of named discrete features (FS, MH, MM, BH, RM for the CMA MDP,
// dissertation §5.3.2.1). Each feature at t+1 has one conditional table over some features at t
// (its parents) and the action (Tables 5.1–5.5). Terminal states (C, T, FL, E) are entered through
// exit tables over parents and action (Tables 5.6–5.7), through forced exits (an action that leads to
// a terminal state with probability 1, e.g. Terminate → T), and chain into absorbing states
// (C, T, FL → E; E → E).
//
// Composition of the row of (x, a), eqs. 5.16–5.19 and docs/modelling-choices.md#transition-composition:
//   forced exit:          {terminal: 1}
//   otherwise:            p(x') = Π_f P(x'_f | parents_f(x), a) for every non-terminal x' with p > 0,
//                         plus P(exit | parents(x), a) for each exit table,
//                         then the row is divided by its sum (the printed tables do not always sum
//                         to exactly one).
// State order: non-terminal tuples in mixed radix (the first feature varies slowest), then the
// terminal states in the order they were added. Labels join the value names with ',' .
#include <functional>
#include <string>
#include <vector>

#include "uascma/decision/finite_mdp.h"

namespace uascma::decision {

struct DiscreteFeature {
  std::string name;
  std::vector<std::string> values;
};

// One row of a printed conditional table: P(next_value | parent_values, a) for every action a.
struct ConditionalRow {
  std::string next_value;                     // ignored for exit tables
  std::vector<std::string> parent_values;     // one per parent, in the table's parent order
  std::vector<double> probability_by_action;  // one per action, in the builder's action order
};

// P(feature_{t+1} | parents_t, a_t). Pairs (parents, action) with no row have probability 0.
struct ConditionalTable {
  std::string name;  // for messages, e.g. "Table 5.3"
  std::string feature;
  std::vector<std::string> parents;
  std::vector<ConditionalRow> rows;
};

// P(terminal_{t+1} | parents_t, a_t) for one terminal state.
struct ExitTable {
  std::string name;
  std::string terminal_state;
  std::vector<std::string> parents;
  std::vector<ConditionalRow> rows;  // next_value unused
};

// A state of the factored model: either a terminal state or a tuple of feature value indices.
struct FactoredState {
  int terminal = -1;        // index into terminal states, or -1
  std::vector<int> values;  // [num_features] when terminal == -1
  bool is_terminal() const { return terminal >= 0; }
};

class FactoredMdpBuilder {
 public:
  FactoredMdpBuilder(std::vector<DiscreteFeature> features, std::vector<std::string> actions);

  // A terminal state and the terminal it moves to under every action (itself when absorbing).
  // `absorbs_into` may name a terminal added later.
  void AddTerminalState(const std::string& name, const std::string& absorbs_into);
  void SetTransitionTable(ConditionalTable table);
  void AddExitTable(ExitTable table);
  void SetForcedExit(const std::string& action, const std::string& terminal_state);
  // In states whose `feature` has `value`, only `allowed` actions are available. Rules intersect.
  void RestrictActions(const std::string& feature, const std::string& value, std::vector<std::string> allowed);

  using RewardFunction = std::function<double(const FactoredState&, ActionIndex)>;
  // Composes the rows and validates them (InputError naming the table, state or action).
  FiniteMdp Build(const RewardFunction& reward) const;

  int num_features() const { return static_cast<int>(features_.size()); }
  const std::vector<DiscreteFeature>& features() const { return features_; }
  const std::vector<std::string>& actions() const { return actions_; }
  int num_tuple_states() const { return num_tuple_states_; }
  int num_states() const { return num_tuple_states_ + static_cast<int>(terminals_.size()); }
  FactoredState Decode(StateIndex state) const;
  StateIndex Encode(const FactoredState& state) const;
  std::string Label(StateIndex state) const;
  int FeatureIndex(const std::string& name) const;              // -1 when unknown
  int ValueIndex(int feature, const std::string& value) const;  // -1 when unknown
  int TerminalIndex(const std::string& name) const;             // -1 when unknown
  ActionIndex ActionIndexOf(const std::string& name) const;     // -1 when unknown

 private:
  // A table compiled to a dense array: probability[(action * num_parent_tuples + parents) *
  // num_next_values + next_value].
  struct CompiledTable {
    std::vector<int> parent_features;
    std::vector<int> parent_radix;
    int num_parent_tuples = 1;
    int num_next_values = 1;
    std::vector<double> probability;
    int ParentIndex(const std::vector<int>& values) const;
  };
  CompiledTable Compile(const std::string& table_name, const std::string& feature,
                        const std::vector<std::string>& parents, const std::vector<ConditionalRow>& rows,
                        bool is_exit) const;

  std::vector<DiscreteFeature> features_;
  std::vector<std::string> actions_;
  int num_tuple_states_ = 1;
  std::vector<std::string> terminals_;
  std::vector<std::string> absorbs_into_;
  std::vector<CompiledTable> feature_tables_;               // [num_features]; empty probability = not set
  std::vector<std::pair<int, CompiledTable>> exit_tables_;  // (terminal, table)
  std::vector<int> forced_exit_;                            // [num_actions] terminal index or -1
  // allowed_[feature][value][action]
  std::vector<std::vector<std::vector<bool>>> allowed_;
};

}  // namespace uascma::decision
