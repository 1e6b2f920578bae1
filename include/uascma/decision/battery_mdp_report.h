#pragma once
// What `uascma battery` reports of the battery MDP (dissertation Ch. IV, §4.3.2): a learned model's rows and the energy
// transitions its flights saw, a solved policy set's totals, and a policy set seen as Fig. 4.5's decision tree (each
// leaf's choices, the chosen action at the context's take-off state, the rows never observed) and one policy's
// transition graph (Fig. 4.4, Graphviz DOT).
#include <array>
#include <cstdint>
#include <span>
#include <string>

#include <nlohmann/json.hpp>

#include "uascma/decision/battery_mdp.h"
#include "uascma/decision/battery_model.h"
#include "uascma/decision/battery_policy.h"
#include "uascma/models/battery_pack.h"

namespace uascma::decision {

// The 72 states with both switches OFF cannot occur: no action of Table 4.3 opens both switches.
bool IsPossibleBatteryState(StateIndex s);
// Both packs switched in (false for FAILURE and COMPLETE).
bool BothPacksIn(StateIndex s);

// A learned model over its 18 contexts: the learned rows never observed (self-loops,
// docs/modelling-choices.md#battery-mdp-transitions) and the energy-feature transitions counted.
struct BatteryModelReport {
  int unobserved_rows = 0;
  EnergyTransitionCounts energy;
};
BatteryModelReport ReportBatteryModel(const BatteryModel& model);

// A solved set's totals over its contexts, and per context its label, iterations, unobserved rows and transitions.
struct BatterySolveReport {
  double wall_time_s = 0.0;
  int iterations = 0, unobserved_rows = 0, learned_rows = 0;
  nlohmann::json contexts = nlohmann::json::array();
};
BatterySolveReport ReportBatterySolve(const BatteryPolicySet& set);

// What a policy chooses where it has a choice to make: in the 72 states with both packs in, the states per action;
// in the 144 with one pack in, the states in which it changes the switches (ours never does: item 6); ours' flagged
// states with both packs in (26), the states in which it takes a flagged pack out. Counting the one-pack states'
// holds with the choices would hide a policy that never leaves UseBoth.
struct BatteryPolicyChoices {
  std::array<int, 3> both_in{};  // per action
  int one_in_switches = 0;
  int flagged_both_in = 0, flagged_isolations = 0;
};
BatteryPolicyChoices CountBatteryPolicyChoices(const BatteryContextPolicy& policy);

// Fig. 4.4: the transition graph of one action in one context, as Graphviz DOT. Learned rows with their
// probabilities, and the deterministic switch edges (dashed, p = 1) into their source states from the states that
// can occur. A state the graph reaches whose own row under this action was never observed is drawn grey and
// dotted, labelled "unobserved" (docs/modelling-choices.md#battery-mdp-transitions: the dissertation's MDP lets it loop
// on itself).
std::string BatteryTransitionDot(const BatteryContextPolicy& policy, models::PackAction action);

// The policies as Fig. 4.5's decision tree, per context: the choices, the chosen actions over every state with the
// ones whose row was never observed, and the action at `takeoff[BatteryContextIndex(context)]`, the first state of
// the context's flight of `takeoff_flight_s` (what python/plots/battery_policy.py draws and `--json` prints).
nlohmann::json BatteryPolicyViewJson(const BatteryPolicySet& set, std::span<const StateIndex> takeoff,
                                     double takeoff_flight_s);
// The same as the text table `uascma battery show` prints, headed by the policy file's name `source`.
std::string BatteryPolicyViewText(const BatteryPolicySet& set, std::span<const StateIndex> takeoff,
                                  double takeoff_flight_s, const std::string& source);

}  // namespace uascma::decision
