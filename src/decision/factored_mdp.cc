#include "uascma/decision/factored_mdp.h"

#include <cmath>

#include <fmt/format.h>

#include "uascma/common/error.h"

namespace uascma::decision {

FactoredMdpBuilder::FactoredMdpBuilder(std::vector<DiscreteFeature> features, std::vector<std::string> actions)
    : features_(std::move(features)), actions_(std::move(actions)) {
  if (features_.empty()) throw InputError("factored MDP", "features", "at least one feature");
  if (actions_.empty()) throw InputError("factored MDP", "actions", "at least one action");
  for (const DiscreteFeature& f : features_) {
    if (f.values.empty()) throw InputError("factored MDP", "feature " + f.name, "at least one value");
    num_tuple_states_ *= static_cast<int>(f.values.size());
  }
  feature_tables_.resize(features_.size());
  forced_exit_.assign(actions_.size(), -1);
  allowed_.resize(features_.size());
  for (std::size_t f = 0; f < features_.size(); ++f) {
    allowed_[f].assign(features_[f].values.size(), std::vector<bool>(actions_.size(), true));
  }
}

int FactoredMdpBuilder::FeatureIndex(const std::string& name) const {
  for (std::size_t f = 0; f < features_.size(); ++f) {
    if (features_[f].name == name) return static_cast<int>(f);
  }
  return -1;
}

int FactoredMdpBuilder::ValueIndex(int feature, const std::string& value) const {
  const auto& values = features_[feature].values;
  for (std::size_t v = 0; v < values.size(); ++v) {
    if (values[v] == value) return static_cast<int>(v);
  }
  return -1;
}

int FactoredMdpBuilder::TerminalIndex(const std::string& name) const {
  for (std::size_t t = 0; t < terminals_.size(); ++t) {
    if (terminals_[t] == name) return static_cast<int>(t);
  }
  return -1;
}

ActionIndex FactoredMdpBuilder::ActionIndexOf(const std::string& name) const {
  for (std::size_t a = 0; a < actions_.size(); ++a) {
    if (actions_[a] == name) return static_cast<ActionIndex>(a);
  }
  return -1;
}

void FactoredMdpBuilder::AddTerminalState(const std::string& name, const std::string& absorbs_into) {
  if (TerminalIndex(name) >= 0) throw InputError("factored MDP", "terminal " + name, "a new name");
  terminals_.push_back(name);
  absorbs_into_.push_back(absorbs_into);
}

int FactoredMdpBuilder::CompiledTable::ParentIndex(const std::vector<int>& values) const {
  int index = 0;
  for (std::size_t p = 0; p < parent_features.size(); ++p) {
    index = index * parent_radix[p] + values[parent_features[p]];
  }
  return index;
}

FactoredMdpBuilder::CompiledTable FactoredMdpBuilder::Compile(const std::string& table_name, const std::string& feature,
                                                              const std::vector<std::string>& parents,
                                                              const std::vector<ConditionalRow>& rows,
                                                              bool is_exit) const {
  CompiledTable table;
  int feature_index = -1;
  if (!is_exit) {
    feature_index = FeatureIndex(feature);
    if (feature_index < 0) throw InputError(table_name, "feature", "a known feature, got " + feature);
    table.num_next_values = static_cast<int>(features_[feature_index].values.size());
  }
  for (const std::string& parent : parents) {
    const int p = FeatureIndex(parent);
    if (p < 0) throw InputError(table_name, "parents", "known features, got " + parent);
    table.parent_features.push_back(p);
    table.parent_radix.push_back(static_cast<int>(features_[p].values.size()));
    table.num_parent_tuples *= table.parent_radix.back();
  }
  const int num_actions = static_cast<int>(actions_.size());
  table.probability.assign(static_cast<std::size_t>(num_actions * table.num_parent_tuples * table.num_next_values),
                           0.0);
  std::vector<bool> seen(table.probability.size() / static_cast<std::size_t>(num_actions), false);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const ConditionalRow& row = rows[r];
    const std::string where = fmt::format("row {}", r + 1);
    if (row.parent_values.size() != parents.size()) {
      throw InputError(table_name, where, fmt::format("{} parent values", parents.size()));
    }
    if (static_cast<int>(row.probability_by_action.size()) != num_actions) {
      throw InputError(table_name, where, fmt::format("{} probabilities (one per action)", num_actions));
    }
    int parent_index = 0;
    for (std::size_t p = 0; p < parents.size(); ++p) {
      const int v = ValueIndex(table.parent_features[p], row.parent_values[p]);
      if (v < 0) {
        throw InputError(table_name, where, fmt::format("a value of {}, got '{}'", parents[p], row.parent_values[p]));
      }
      parent_index = parent_index * table.parent_radix[p] + v;
    }
    int next_index = 0;
    if (!is_exit) {
      next_index = ValueIndex(feature_index, row.next_value);
      if (next_index < 0) {
        throw InputError(table_name, where, fmt::format("a value of {}, got '{}'", feature, row.next_value));
      }
    }
    const std::size_t cell = static_cast<std::size_t>(parent_index * table.num_next_values + next_index);
    if (seen[cell]) throw InputError(table_name, where, "one row per (next value, parents)");
    seen[cell] = true;
    for (int a = 0; a < num_actions; ++a) {
      const double p = row.probability_by_action[a];
      if (!std::isfinite(p) || p < 0.0 || p > 1.0) {
        throw InputError(table_name, where + ", action " + actions_[a],
                         fmt::format("a probability in [0, 1], got {}", p));
      }
      table.probability[static_cast<std::size_t>(a) * seen.size() + cell] = p;
    }
  }
  return table;
}

void FactoredMdpBuilder::SetTransitionTable(ConditionalTable table) {
  const int f = FeatureIndex(table.feature);
  if (f < 0) throw InputError(table.name, "feature", "a known feature, got " + table.feature);
  feature_tables_[f] = Compile(table.name, table.feature, table.parents, table.rows, false);
}

void FactoredMdpBuilder::AddExitTable(ExitTable table) {
  const int t = TerminalIndex(table.terminal_state);
  if (t < 0) throw InputError(table.name, "terminal state", "a known terminal, got " + table.terminal_state);
  exit_tables_.emplace_back(t, Compile(table.name, "", table.parents, table.rows, true));
}

void FactoredMdpBuilder::SetForcedExit(const std::string& action, const std::string& terminal_state) {
  const ActionIndex a = ActionIndexOf(action);
  const int t = TerminalIndex(terminal_state);
  if (a < 0) throw InputError("factored MDP", "forced exit action", "a known action, got " + action);
  if (t < 0) throw InputError("factored MDP", "forced exit", "a known terminal, got " + terminal_state);
  forced_exit_[a] = t;
}

void FactoredMdpBuilder::RestrictActions(const std::string& feature, const std::string& value,
                                         std::vector<std::string> allowed) {
  const int f = FeatureIndex(feature);
  if (f < 0) throw InputError("action availability", "feature", "a known feature, got " + feature);
  const int v = ValueIndex(f, value);
  if (v < 0) throw InputError("action availability", feature, "a known value, got " + value);
  std::vector<bool> mask(actions_.size(), false);
  for (const std::string& name : allowed) {
    const ActionIndex a = ActionIndexOf(name);
    if (a < 0) throw InputError("action availability", feature + "=" + value, "known actions, got " + name);
    mask[a] = true;
  }
  for (std::size_t a = 0; a < actions_.size(); ++a) allowed_[f][v][a] = allowed_[f][v][a] && mask[a];
}

FactoredState FactoredMdpBuilder::Decode(StateIndex state) const {
  FactoredState decoded;
  if (state >= num_tuple_states_) {
    decoded.terminal = state - num_tuple_states_;
    return decoded;
  }
  decoded.values.resize(features_.size());
  for (int f = num_features() - 1; f >= 0; --f) {
    const int radix = static_cast<int>(features_[f].values.size());
    decoded.values[f] = state % radix;
    state /= radix;
  }
  return decoded;
}

StateIndex FactoredMdpBuilder::Encode(const FactoredState& state) const {
  if (state.is_terminal()) return num_tuple_states_ + state.terminal;
  StateIndex index = 0;
  for (int f = 0; f < num_features(); ++f) {
    index = index * static_cast<int>(features_[f].values.size()) + state.values[f];
  }
  return index;
}

std::string FactoredMdpBuilder::Label(StateIndex state) const {
  const FactoredState decoded = Decode(state);
  if (decoded.is_terminal()) return terminals_[decoded.terminal];
  std::string label;
  for (int f = 0; f < num_features(); ++f) {
    if (f > 0) label += ',';
    label += features_[f].values[decoded.values[f]];
  }
  return label;
}

FiniteMdp FactoredMdpBuilder::Build(const RewardFunction& reward) const {
  for (int f = 0; f < num_features(); ++f) {
    if (feature_tables_[f].probability.empty()) {
      throw InputError("factored MDP", "feature " + features_[f].name, "a transition table");
    }
  }
  std::vector<int> absorbs(terminals_.size());
  for (std::size_t t = 0; t < terminals_.size(); ++t) {
    absorbs[t] = TerminalIndex(absorbs_into_[t]);
    if (absorbs[t] < 0) {
      throw InputError("factored MDP", "terminal " + terminals_[t], "absorbs into a known terminal");
    }
  }
  std::vector<std::string> labels;
  labels.reserve(static_cast<std::size_t>(num_states()));
  for (StateIndex s = 0; s < num_states(); ++s) labels.push_back(Label(s));
  FiniteMdpBuilder builder(labels, actions_);
  const int num_actions = static_cast<int>(actions_.size());

  std::vector<Transition> row;
  // Per-feature distribution of the next value, for the current (state, action).
  std::vector<std::vector<double>> next_distribution(features_.size());
  std::vector<int> next_values(features_.size());
  for (StateIndex s = 0; s < num_tuple_states_; ++s) {
    const FactoredState x = Decode(s);
    for (ActionIndex a = 0; a < num_actions; ++a) {
      bool available = true;
      for (int f = 0; f < num_features(); ++f) available = available && allowed_[f][x.values[f]][a];
      if (!available) continue;
      row.clear();
      if (forced_exit_[a] >= 0) {
        row.push_back({num_tuple_states_ + forced_exit_[a], 1.0});
      } else {
        for (int f = 0; f < num_features(); ++f) {
          const CompiledTable& table = feature_tables_[f];
          const std::size_t offset =
              (static_cast<std::size_t>(a) * table.num_parent_tuples + table.ParentIndex(x.values)) *
              table.num_next_values;
          next_distribution[f].assign(table.probability.begin() + offset,
                                      table.probability.begin() + offset + table.num_next_values);
        }
        // Enumerate next tuples in mixed-radix order (so successors come out sorted), keeping
        // those with nonzero product.
        std::fill(next_values.begin(), next_values.end(), 0);
        for (StateIndex next = 0; next < num_tuple_states_; ++next) {
          double p = 1.0;
          for (int f = 0; f < num_features() && p > 0.0; ++f) p *= next_distribution[f][next_values[f]];
          if (p > 0.0) row.push_back({next, p});
          for (int f = num_features() - 1; f >= 0; --f) {  // increment the mixed-radix counter
            if (++next_values[f] < static_cast<int>(features_[f].values.size())) break;
            next_values[f] = 0;
          }
        }
        for (const auto& [terminal, table] : exit_tables_) {
          const double p =
              table.probability[static_cast<std::size_t>(a) * table.num_parent_tuples + table.ParentIndex(x.values)];
          if (p > 0.0) row.push_back({num_tuple_states_ + terminal, p});
        }
      }
      double total = 0.0;
      for (const Transition& t : row) total += t.probability;
      if (!(total > 0.0)) {
        throw InputError("factored MDP", fmt::format("state '{}', action '{}'", labels[s], actions_[a]),
                         "a row with positive total probability");
      }
      for (Transition& t : row) t.probability /= total;
      builder.AddRow(s, a, reward(x, a), row);
    }
  }
  for (std::size_t t = 0; t < terminals_.size(); ++t) {
    const StateIndex s = num_tuple_states_ + static_cast<StateIndex>(t);
    FactoredState terminal;
    terminal.terminal = static_cast<int>(t);
    const Transition absorb{num_tuple_states_ + absorbs[t], 1.0};
    for (ActionIndex a = 0; a < num_actions; ++a) {
      builder.AddRow(s, a, reward(terminal, a), std::span<const Transition>(&absorb, 1));
    }
  }
  return builder.Build();
}

}  // namespace uascma::decision
