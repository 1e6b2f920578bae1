#include "uascma/decision/finite_mdp.h"

#include <cmath>

#include <fmt/format.h>

#include "uascma/common/error.h"

namespace uascma::decision {

StateIndex FiniteMdp::FindState(const std::string& label) const {
  for (std::size_t s = 0; s < state_labels_.size(); ++s) {
    if (state_labels_[s] == label) return static_cast<StateIndex>(s);
  }
  return -1;
}

ActionIndex FiniteMdp::FindAction(const std::string& name) const {
  for (std::size_t a = 0; a < action_names_.size(); ++a) {
    if (action_names_[a] == name) return static_cast<ActionIndex>(a);
  }
  return -1;
}

std::int64_t FiniteMdp::FindChoice(StateIndex s, ActionIndex a) const {
  for (std::int64_t c = choice_begin(s); c < choice_end(s); ++c) {
    if (choice_action_[c] == a) return c;
  }
  return -1;
}

FiniteMdpBuilder::FiniteMdpBuilder(std::vector<std::string> state_labels, std::vector<std::string> action_names) {
  if (state_labels.empty()) throw InputError("MDP", "states", "at least one state");
  if (action_names.empty()) throw InputError("MDP", "actions", "at least one action");
  mdp_.state_labels_ = std::move(state_labels);
  mdp_.action_names_ = std::move(action_names);
  mdp_.state_choice_begin_.reserve(mdp_.state_labels_.size() + 1);
  mdp_.state_choice_begin_.push_back(0);
  mdp_.choice_row_begin_.push_back(0);
}

void FiniteMdpBuilder::CloseStatesUpTo(StateIndex state) {
  // Every state before `state` is complete: record where its choices end.
  while (static_cast<StateIndex>(mdp_.state_choice_begin_.size()) <= state) {
    mdp_.state_choice_begin_.push_back(static_cast<std::int64_t>(mdp_.choice_action_.size()));
  }
}

void FiniteMdpBuilder::AddRow(StateIndex state, ActionIndex action, double reward,
                              std::span<const Transition> successors) {
  const int num_states = mdp_.num_states();
  if (state < 0 || state >= num_states) {
    throw InputError("MDP", fmt::format("state {}", state), fmt::format("a state index in [0, {})", num_states));
  }
  if (action < 0 || action >= mdp_.num_actions()) {
    throw InputError("MDP", fmt::format("state '{}', action {}", mdp_.state_labels_[state], action),
                     fmt::format("an action index in [0, {})", mdp_.num_actions()));
  }
  const std::string where =
      fmt::format("state '{}', action '{}'", mdp_.state_labels_[state], mdp_.action_names_[action]);
  if (state < current_state_) {
    throw InputError("MDP", where, "rows added in nondecreasing state order");
  }
  current_state_ = state;
  CloseStatesUpTo(state);
  for (std::int64_t c = mdp_.state_choice_begin_[state]; c < static_cast<std::int64_t>(mdp_.choice_action_.size());
       ++c) {
    if (mdp_.choice_action_[c] == action) throw InputError("MDP", where, "one row per action");
  }
  if (!std::isfinite(reward)) {
    throw InputError("MDP", where, fmt::format("a finite reward, got {}", reward));
  }
  if (successors.empty()) throw InputError("MDP", where, "at least one successor");
  double row_sum = 0.0;
  for (const Transition& t : successors) {
    if (t.next_state < 0 || t.next_state >= num_states) {
      throw InputError("MDP", where, fmt::format("successor indices in [0, {}), got {}", num_states, t.next_state));
    }
    if (!std::isfinite(t.probability) || t.probability < 0.0 || t.probability > 1.0) {
      throw InputError("MDP", where + fmt::format(", successor '{}'", mdp_.state_labels_[t.next_state]),
                       fmt::format("a probability in [0, 1], got {}", t.probability));
    }
    row_sum += t.probability;
  }
  if (std::abs(row_sum - 1.0) > kRowSumTolerance) {
    throw InputError("MDP", where,
                     fmt::format("probabilities summing to 1 within {:g}, got {:.12g}", kRowSumTolerance, row_sum));
  }
  mdp_.choice_action_.push_back(action);
  mdp_.choice_reward_.push_back(reward);
  for (const Transition& t : successors) {
    mdp_.next_state_.push_back(t.next_state);
    mdp_.probability_.push_back(t.probability);
  }
  mdp_.choice_row_begin_.push_back(static_cast<std::int64_t>(mdp_.next_state_.size()));
}

FiniteMdp FiniteMdpBuilder::Build() {
  const int num_states = mdp_.num_states();
  CloseStatesUpTo(num_states);
  for (StateIndex s = 0; s < num_states; ++s) {
    if (mdp_.state_choice_begin_[s] == mdp_.state_choice_begin_[s + 1]) {
      throw InputError("MDP", fmt::format("state '{}'", mdp_.state_labels_[s]), "at least one available action");
    }
  }
  FiniteMdp built = std::move(mdp_);
  mdp_ = FiniteMdp{};
  return built;
}

}  // namespace uascma::decision
