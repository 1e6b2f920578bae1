#pragma once
// The battery MDP of one context built from transition counts (dissertation §4.3.2,
// docs/modelling-choices.md#battery-mdp-transitions, #battery-mdp-policies), and the model a policy is solved from: the
// counts with γ, the reward weights and their provenance. The states, actions, contexts and rewards are
// decision/battery_mdp.h; the counts are gathered from Monte Carlo flights by learning/battery_transition_estimation.h;
// the model's file is decision/battery_mdp_file.h.
//
// Transitions (§4.3.2, docs/modelling-choices.md#battery-mdp-transitions, #battery-mdp-policies): switching is
// deterministic and instantaneous. In a state
//   whose switches already are the action's, the row is the 1 Hz transition frequencies counted in Monte
//   Carlo flights flown with that action throughout (a "learned" row); a learned row never observed is a
//   self-loop with p = 1 (reported as "unobserved"). In a state whose switches differ, the switch takes
//   effect at once with p = 1 and without an intermediate state ("no intermediate change in any other MDP
//   state feature"), and the epoch then evolves from the switched state: its row is the learned row of
//   ApplySwitches(s, a) (so, unobserved, the switched state with p = 1 — the dissertation's example
//   ILONS3C0ONS3C0 → ILONS3C0OFFS3C0 under UseBatt1). Every successor thus carries the action's switch
//   positions with certainty. Our reading, not a pure switch step: a switch-only step would let a policy
//   cycle UseBatt1 ↔ UseBoth while no time (no battery drain) passes, which the 1 Hz executor cannot do.
//   FAILURE is absorbing.
// Ours (decision/battery_mdp.h, items 3 and 5-7) builds its rows from the same counts (BuildOursBatteryMdp).
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "uascma/decision/battery_mdp.h"
#include "uascma/decision/finite_mdp.h"

namespace uascma::decision {

// --- Transition counts (§4.3.2, docs/modelling-choices.md#battery-mdp-transitions) -----------------------------------
class BatteryTransitionCounts {
 public:
  BatteryTransitionCounts();

  // One observed 1 Hz transition.
  void Add(const BatteryContext& context, StateIndex state, models::PackAction action, StateIndex next,
           std::int64_t count = 1);
  // One flight flown with `action` throughout: `states` are the abstract states at 1 Hz from take-off;
  // consecutive pairs are counted; counting stops at the first FAILURE (absorbing). Every state must
  // have the action's switches (InputError otherwise: the flight was not flown with that action).
  // `completed`: the flight completed its plan; its last state's row then counts one completion (ours: the
  // absorbing COMPLETE of the formulation below; the dissertation's MDP has no such state and ignores it).
  void AddFlight(const BatteryContext& context, models::PackAction action, std::span<const StateIndex> states,
                 bool completed = false);
  // A flight whose action changed in flight (ours: the drop flights of learning::BatteryLearningOptions):
  // `actions[k]` applied at epoch k from `states[k]`; the transition to states[k + 1] is counted in the row of
  // (ApplySwitches(states[k], actions[k]), actions[k]), the switched state's learned row (the switch takes effect at
  // once, §4.3.2); stops at the first FAILURE; a completion counts at the last epoch's switched row. The flight is
  // counted under its last action.
  void AddSwitchingFlight(const BatteryContext& context, std::span<const StateIndex> states,
                          std::span<const models::PackAction> actions, bool completed);
  // Flights that ended completed from `state` (their last epoch), per row.
  void AddCompletion(const BatteryContext& context, StateIndex state, models::PackAction action,
                     std::int64_t count = 1);
  std::int64_t Completions(const BatteryContext& context, StateIndex state, models::PackAction action) const;
  void Merge(const BatteryTransitionCounts& other);

  // Row (state, action) of a context: next state → count, ordered by next state.
  const std::map<StateIndex, std::int64_t>& Row(const BatteryContext& context, StateIndex state,
                                                models::PackAction action) const;
  std::int64_t RowTotal(const BatteryContext& context, StateIndex state, models::PackAction action) const;
  // Every row of a context with a count or a completion, in (state, action) order: visit(state, action, row,
  // completions). The order is the file's and the fingerprint's.
  template <typename Visit>
  void ForEachRow(const BatteryContext& context, Visit&& visit) const {
    for (StateIndex s = 0; s < kOursNumStates; ++s) {
      if (s == kBatteryCompleteState) continue;
      for (models::PackAction action : kBatteryActions) {
        const auto& row = Row(context, s, action);
        const std::int64_t completed = Completions(context, s, action);
        if (!row.empty() || completed != 0) visit(s, action, row, completed);
      }
    }
  }
  std::int64_t flights(const BatteryContext& context, models::PackAction action) const;
  std::int64_t total_transitions() const;
  std::int64_t total_flights() const;
  void SetFlights(const BatteryContext& context, models::PackAction action, std::int64_t flights);

 private:
  static std::size_t RowIndex(const BatteryContext& context, StateIndex state, models::PackAction action);
  // Rows of every state of either formulation (ours' flagged states included; COMPLETE never has one).
  std::vector<std::map<StateIndex, std::int64_t>> rows_;  // [18 · 394 · 3]
  std::vector<std::int64_t> completions_;                 // [18 · 394 · 3]
  std::array<std::int64_t, kBatteryNumContexts * kBatteryNumActions> flights_{};
};

struct BatteryModelStats {
  int learned_rows = 0;  // (state, action) rows whose switches match the action: 3 × 72 = 216 (ours: + 78 flagged)
  int unobserved_rows = 0;  // of those, never observed: self-loops (docs/modelling-choices.md#battery-mdp-transitions)
  int switch_rows = 0;           // rows of states whose switches differ from the action's (switch, then the
                                 // switched state's learned row)
  std::int64_t transitions = 0;  // counted 1 Hz transitions behind the learned rows
};

// The MDP of one context: rows as the file comment says, rewards of eqs. 4.1–4.9.
FiniteMdp BuildBatteryMdp(const BatteryTransitionCounts& counts, const BatteryContext& context,
                          const BatteryRewardWeights& weights, BatteryModelStats* stats = nullptr);
FiniteMdp BuildOursBatteryMdp(const BatteryTransitionCounts& counts, const BatteryContext& context,
                              const BatteryRewardWeights& weights, BatteryModelStats* stats = nullptr);

// Transitions of one pack's energy feature (S1→S2, S2→S3, S1→S3 and back) counted in a model, per
// context: what flights with constant parameters could not observe (§4.3.2, "dynamics from B_iS_{1,2}
// states to B_iS_3 state elements are not observed").
struct EnergyTransitionCounts {
  std::int64_t s1_to_s2 = 0, s2_to_s3 = 0, s1_to_s3 = 0, recoveries = 0, unchanged = 0;
};
EnergyTransitionCounts CountEnergyTransitions(const BatteryTransitionCounts& counts, const BatteryContext& context);
// The same counts with every transition that changes a pack's energy feature removed (the dissertation's
// constant-parameter view): rows that only had such transitions become unobserved.
BatteryTransitionCounts WithoutEnergyDynamics(const BatteryTransitionCounts& counts);

// --- the model ------------------------------------------------------------------------------------
// Its file formats (decision/battery_mdp_file.h); the format and version are part of the fingerprints.
inline constexpr const char* kBatteryModelFormat = "uascma-battery-model";
inline constexpr const char* kBatteryPolicyFormat = "uascma-battery-policy";
inline constexpr int kBatteryFileVersion = 1;

struct BatteryModel {
  double gamma = 0.95;  // §4.3.2.1
  BatteryRewardWeights weights;
  nlohmann::json provenance = nlohmann::json::object();
  BatteryTransitionCounts counts;  // in the dissertation's abstraction (Table 4.1's 289 states)
  // The same flights counted in ours' abstraction (decision/battery_mdp.h ours item 10: the flagged states), kept
  // when a learning flight's indicator flagged a pack; without one the two abstractions agree on every epoch and
  // ours reads `counts` (OursCounts), so a model learned without pack faults keeps its file and hash.
  std::optional<BatteryTransitionCounts> ours_counts;
  const BatteryTransitionCounts& OursCounts() const { return ours_counts ? *ours_counts : counts; }
};
// The fingerprint of everything in the model (format, version, gamma, weights, provenance, counts): the "hash" of
// its file, and the model_hash a policy solved from it carries.
std::string BatteryModelHash(const BatteryModel& model);

}  // namespace uascma::decision
