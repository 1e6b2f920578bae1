#include "uascma/decision/battery_model.h"

#include <algorithm>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/hash.h"

namespace uascma::decision {

using models::PackAction;

FiniteMdp BuildOursBatteryMdp(const BatteryTransitionCounts& counts, const BatteryContext& context,
                              const BatteryRewardWeights& weights, BatteryModelStats* stats) {
  std::string error;
  if (!weights.IsValid(&error)) throw InputError("battery MDP", "weights", error);
  FiniteMdpBuilder builder(BatteryFormulationStateLabels(BatteryFormulation::kOurs), BatteryActionNames());
  BatteryModelStats local;
  std::vector<Transition> row;
  for (StateIndex s = 0; s < kOursNumStates; ++s) {
    if (s == kBatteryFailureState || s == kBatteryCompleteState) {  // absorbing (the builder takes rows in order)
      const Transition loop{s, 1.0};
      for (PackAction action : kBatteryActions) {
        builder.AddRow(s, BatteryActionIndex(action), OursBatteryReward(s, action, context, weights),
                       std::span<const Transition>(&loop, 1));
      }
      continue;
    }
    bool any = false;
    const BatteryFeatures features = BatteryStateFeatures(s);
    for (PackAction action : kBatteryActions) {
      const StateIndex switched = ApplySwitches(s, action);
      const bool learned = switched == s;
      if (learned)
        ++local.learned_rows;
      else
        ++local.switch_rows;
      if (!OursOffers(features, action)) continue;  // items 6-7
      const auto& observed = counts.Row(context, switched, action);
      const std::int64_t completed = counts.Completions(context, switched, action);
      std::int64_t total = completed;
      for (const auto& [next, count] : observed) total += count;
      if (total == 0) {  // no evidence: the action is not offered here (ours, decision/battery_mdp.h item 5)
        if (learned) ++local.unobserved_rows;
        continue;
      }
      row.clear();
      for (const auto& [next, count] : observed) {
        row.push_back({next, static_cast<double>(count) / static_cast<double>(total)});
      }
      if (completed > 0)
        row.push_back({kBatteryCompleteState, static_cast<double>(completed) / static_cast<double>(total)});
      if (learned) local.transitions += total;
      builder.AddRow(s, BatteryActionIndex(action), OursBatteryReward(s, action, context, weights), row);
      any = true;
    }
    if (!any) {  // nothing offered was ever observed: hold the present switches (UseBoth at take-off), as a loop
      const PackAction hold = HoldSwitchesAction(features);
      const Transition loop{ApplySwitches(s, hold), 1.0};
      builder.AddRow(s, BatteryActionIndex(hold), OursBatteryReward(s, hold, context, weights),
                     std::span<const Transition>(&loop, 1));
    }
  }
  if (stats) *stats = local;
  return builder.Build();
}

// ================================ counts ==========================================================
BatteryTransitionCounts::BatteryTransitionCounts()
    : rows_(static_cast<std::size_t>(kBatteryNumContexts) * kOursNumStates * kBatteryNumActions),
      completions_(rows_.size(), 0) {}

std::size_t BatteryTransitionCounts::RowIndex(const BatteryContext& context, StateIndex state, PackAction action) {
  UASCMA_CHECK(state >= 0 && state < kOursNumStates && state != kBatteryCompleteState, "a battery state index");
  return (static_cast<std::size_t>(BatteryContextIndex(context)) * kOursNumStates +
          static_cast<std::size_t>(state)) *
             kBatteryNumActions +
         static_cast<std::size_t>(BatteryActionIndex(action));
}

void BatteryTransitionCounts::Add(const BatteryContext& context, StateIndex state, PackAction action, StateIndex next,
                                  std::int64_t count) {
  UASCMA_CHECK(next >= 0 && next < kOursNumStates && next != kBatteryCompleteState, "a battery next-state index");
  UASCMA_CHECK(count >= 0, "a non-negative count");
  if (count == 0) return;
  rows_[RowIndex(context, state, action)][next] += count;
}

void BatteryTransitionCounts::AddCompletion(const BatteryContext& context, StateIndex state, PackAction action,
                                            std::int64_t count) {
  UASCMA_CHECK(state != kBatteryFailureState, "a completion from a non-failure state");
  UASCMA_CHECK(count >= 0, "a non-negative count");
  completions_[RowIndex(context, state, action)] += count;
}

std::int64_t BatteryTransitionCounts::Completions(const BatteryContext& context, StateIndex state,
                                                  PackAction action) const {
  return completions_[RowIndex(context, state, action)];
}

void BatteryTransitionCounts::AddFlight(const BatteryContext& context, PackAction action,
                                        std::span<const StateIndex> states, bool completed) {
  for (std::size_t k = 0; k < states.size(); ++k) {
    if (states[k] < 0 || states[k] >= kOursNumStates || states[k] == kBatteryCompleteState) {
      throw InputError("battery flight", fmt::format("states[{}]", k), "a battery MDP state index");
    }
    if (!SwitchesMatch(states[k], action)) {
      throw InputError("battery flight", fmt::format("states[{}]", k),
                       fmt::format("the switches of {} (flown throughout), got {}", models::PackActionName(action),
                                   BatteryStateLabel(states[k])));
    }
  }
  for (std::size_t k = 0; k + 1 < states.size(); ++k) {
    if (states[k] == kBatteryFailureState) break;
    Add(context, states[k], action, states[k + 1]);
  }
  if (completed && !states.empty() && states.back() != kBatteryFailureState) {
    AddCompletion(context, states.back(), action);
  }
  flights_[static_cast<std::size_t>(BatteryContextIndex(context) * kBatteryNumActions + BatteryActionIndex(action))] +=
      1;
}

void BatteryTransitionCounts::AddSwitchingFlight(const BatteryContext& context, std::span<const StateIndex> states,
                                                 std::span<const PackAction> actions, bool completed) {
  UASCMA_CHECK(!actions.empty() && actions.size() <= states.size(), "an action per epoch");
  for (std::size_t k = 0; k < states.size(); ++k) {
    if (states[k] < 0 || states[k] >= kOursNumStates || states[k] == kBatteryCompleteState) {
      throw InputError("battery flight", fmt::format("states[{}]", k), "a battery MDP state index");
    }
  }
  std::size_t last = 0;
  for (std::size_t k = 0; k + 1 < states.size() && k < actions.size(); ++k) {
    if (states[k] == kBatteryFailureState) break;
    Add(context, ApplySwitches(states[k], actions[k]), actions[k], states[k + 1]);
    last = k + 1;
  }
  const std::size_t end = std::min(last, actions.size() - 1);
  if (completed && states[end] != kBatteryFailureState) {
    AddCompletion(context, ApplySwitches(states[end], actions[end]), actions[end]);
  }
  flights_[static_cast<std::size_t>(BatteryContextIndex(context) * kBatteryNumActions +
                                    BatteryActionIndex(actions.back()))] += 1;
}

void BatteryTransitionCounts::Merge(const BatteryTransitionCounts& other) {
  for (std::size_t r = 0; r < rows_.size(); ++r) {
    for (const auto& [next, count] : other.rows_[r]) rows_[r][next] += count;
    completions_[r] += other.completions_[r];
  }
  for (std::size_t i = 0; i < flights_.size(); ++i) flights_[i] += other.flights_[i];
}

const std::map<StateIndex, std::int64_t>& BatteryTransitionCounts::Row(const BatteryContext& context, StateIndex state,
                                                                       PackAction action) const {
  return rows_[RowIndex(context, state, action)];
}

std::int64_t BatteryTransitionCounts::RowTotal(const BatteryContext& context, StateIndex state,
                                               PackAction action) const {
  std::int64_t total = 0;
  for (const auto& [next, count] : Row(context, state, action)) total += count;
  return total;
}

std::int64_t BatteryTransitionCounts::flights(const BatteryContext& context, PackAction action) const {
  return flights_[static_cast<std::size_t>(BatteryContextIndex(context) * kBatteryNumActions +
                                           BatteryActionIndex(action))];
}

void BatteryTransitionCounts::SetFlights(const BatteryContext& context, PackAction action, std::int64_t flights) {
  flights_[static_cast<std::size_t>(BatteryContextIndex(context) * kBatteryNumActions + BatteryActionIndex(action))] =
      flights;
}

std::int64_t BatteryTransitionCounts::total_transitions() const {
  std::int64_t total = 0;
  for (const auto& row : rows_) {
    for (const auto& [next, count] : row) total += count;
  }
  return total;
}

std::int64_t BatteryTransitionCounts::total_flights() const {
  std::int64_t total = 0;
  for (std::int64_t f : flights_) total += f;
  return total;
}

// ================================ the MDP of one context ==========================================
FiniteMdp BuildBatteryMdp(const BatteryTransitionCounts& counts, const BatteryContext& context,
                          const BatteryRewardWeights& weights, BatteryModelStats* stats) {
  std::string error;
  if (!weights.IsValid(&error)) throw InputError("battery MDP", "weights", error);
  FiniteMdpBuilder builder(BatteryStateLabels(), BatteryActionNames());
  BatteryModelStats local;
  std::vector<Transition> row;
  for (StateIndex s = 0; s < kBatteryNumStates; ++s) {
    for (PackAction action : kBatteryActions) {
      const double reward = BatteryReward(s, action, context, weights);
      row.clear();
      if (s == kBatteryFailureState) {
        row.push_back({s, 1.0});  // absorbing
      } else {
        // The switch takes effect at once and with certainty (§4.3.2,
        // docs/modelling-choices.md#battery-mdp-transitions, #battery-mdp-policies): the epoch then runs from the
        // switched state, whose row under this action is what the flights counted.
        const StateIndex switched = ApplySwitches(s, action);
        const bool learned = switched == s;
        if (learned)
          ++local.learned_rows;
        else
          ++local.switch_rows;
        const auto& observed = counts.Row(context, switched, action);
        std::int64_t total = 0;
        for (const auto& [next, count] : observed) total += count;
        if (total == 0) {
          row.push_back({switched, 1.0});  // never observed: the switched state loops on itself
                                           // (docs/modelling-choices.md#battery-mdp-transitions)
          if (learned) ++local.unobserved_rows;
        } else {
          for (const auto& [next, count] : observed) {
            row.push_back({next, static_cast<double>(count) / static_cast<double>(total)});
          }
          if (learned) local.transitions += total;
        }
      }
      builder.AddRow(s, BatteryActionIndex(action), reward, row);
    }
  }
  if (stats) *stats = local;
  return builder.Build();
}

EnergyTransitionCounts CountEnergyTransitions(const BatteryTransitionCounts& counts, const BatteryContext& context) {
  EnergyTransitionCounts out;
  for (StateIndex s = 0; s < kBatteryFailureState; ++s) {
    const BatteryFeatures from = BatteryStateFeatures(s);
    for (PackAction action : kBatteryActions) {
      for (const auto& [next, count] : counts.Row(context, s, action)) {
        if (next == kBatteryFailureState) continue;
        const BatteryFeatures to = BatteryStateFeatures(next);
        for (int j = 0; j < models::kBranchCount; ++j) {
          const int a = static_cast<int>(from.pack[j].energy), b = static_cast<int>(to.pack[j].energy);
          if (a == b)
            out.unchanged += count;
          else if (a == 0 && b == 1)
            out.s1_to_s2 += count;
          else if (a == 1 && b == 2)
            out.s2_to_s3 += count;
          else if (a == 0 && b == 2)
            out.s1_to_s3 += count;
          else
            out.recoveries += count;
        }
      }
    }
  }
  return out;
}

BatteryTransitionCounts WithoutEnergyDynamics(const BatteryTransitionCounts& counts) {
  BatteryTransitionCounts out;
  for (int c = 0; c < kBatteryNumContexts; ++c) {
    const BatteryContext context = BatteryContextFromIndex(c);
    for (PackAction action : kBatteryActions) out.SetFlights(context, action, counts.flights(context, action));
    for (StateIndex s = 0; s < kBatteryFailureState; ++s) {
      const BatteryFeatures from = BatteryStateFeatures(s);
      for (PackAction action : kBatteryActions) {
        for (const auto& [next, count] : counts.Row(context, s, action)) {
          bool energy_changes = false;
          if (next != kBatteryFailureState) {
            const BatteryFeatures to = BatteryStateFeatures(next);
            for (int j = 0; j < models::kBranchCount; ++j) energy_changes |= to.pack[j].energy != from.pack[j].energy;
          }
          if (!energy_changes) out.Add(context, s, action, next, count);
        }
      }
    }
  }
  return out;
}

// ================================ the model =======================================================
namespace {

// Every non-empty row of a count table (a table without flagged states fingerprints as it did before they existed:
// empty rows are skipped).
void AddCounts(const BatteryTransitionCounts& counts, Fingerprint& fingerprint) {
  for (int c = 0; c < kBatteryNumContexts; ++c) {
    const BatteryContext context = BatteryContextFromIndex(c);
    for (PackAction action : kBatteryActions) fingerprint.Add(counts.flights(context, action));
    counts.ForEachRow(context, [&](StateIndex s, PackAction action, const auto& row, std::int64_t completed) {
      fingerprint.Add(static_cast<std::int64_t>(BatteryContextIndex(context)));
      fingerprint.Add(static_cast<std::int64_t>(s));
      fingerprint.Add(BatteryActionIndex(action));
      for (const auto& [next, count] : row) {
        fingerprint.Add(static_cast<std::int64_t>(next));
        fingerprint.Add(count);
      }
      // Completions only when counted, so a model without them keeps its hash.
      if (completed > 0) {
        fingerprint.Add(std::string_view("completed"));
        fingerprint.Add(completed);
      }
    });
  }
}

}  // namespace

std::string BatteryModelHash(const BatteryModel& model) {
  Fingerprint fingerprint;
  fingerprint.Add(std::string_view(kBatteryModelFormat));
  fingerprint.Add(kBatteryFileVersion);
  fingerprint.Add(model.gamma);
  fingerprint.Add(model.weights.w1);
  fingerprint.Add(model.weights.w2);
  fingerprint.Add(model.weights.w3);
  fingerprint.Add(model.provenance.dump());
  AddCounts(model.counts, fingerprint);
  // Only when kept, so a model without flagged states keeps its hash.
  if (model.ours_counts) {
    fingerprint.Add(std::string_view("ours_counts"));
    AddCounts(*model.ours_counts, fingerprint);
  }
  return fingerprint.Hex();
}

}  // namespace uascma::decision
