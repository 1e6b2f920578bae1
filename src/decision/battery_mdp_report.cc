// What `uascma battery` reports of the battery MDP (battery_mdp_report.h): the learned model's and the solved set's
// totals, a policy's choices, its transition graph (Fig. 4.4) and the decision tree's view (Fig. 4.5).
#include "uascma/decision/battery_mdp_report.h"

#include <cstddef>
#include <set>
#include <utility>

#include <fmt/format.h>

namespace uascma::decision {
namespace {

using models::PackAction;

// Whether the row a policy's action uses in state s (the switched state's learned row) was observed in flights.
class ObservedBatteryRows {
 public:
  explicit ObservedBatteryRows(const BatteryContextPolicy& policy) {
    for (const BatteryLearnedRow& row : policy.observed_rows) rows.insert({row.state, static_cast<int>(row.action)});
  }
  bool Has(StateIndex s, PackAction action) const {
    if (s == kBatteryFailureState) return true;
    return rows.count({ApplySwitches(s, action), static_cast<int>(action)}) > 0;
  }
  std::set<std::pair<StateIndex, int>> rows;
};

// What the tree's root is: the dissertation's π* (a lookup of its solved tables), or ours' table (items 1-7 and 10
// of decision/battery_mdp.h; its guard and drop check act outside the table, in the evaluation's executor).
const char* FormulationLabel(BatteryFormulation formulation) {
  return formulation == BatteryFormulation::kOurs ? "ours' table (guard and drop check outside it)"
                                                  : "pi* lookup (the dissertation's)";
}

}  // namespace

bool IsPossibleBatteryState(StateIndex s) {
  if (s == kBatteryFailureState || s == kBatteryCompleteState) return true;
  const BatteryFeatures f = BatteryStateFeatures(s);
  return f.pack[0].switch_on || f.pack[1].switch_on;
}

bool BothPacksIn(StateIndex s) {
  if (s == kBatteryFailureState || s == kBatteryCompleteState) return false;
  const BatteryFeatures f = BatteryStateFeatures(s);
  return f.pack[0].switch_on && f.pack[1].switch_on;
}

BatteryModelReport ReportBatteryModel(const BatteryModel& model) {
  BatteryModelReport out;
  for (int c = 0; c < kBatteryNumContexts; ++c) {
    BatteryModelStats stats;
    BuildBatteryMdp(model.counts, BatteryContextFromIndex(c), model.weights, &stats);
    out.unobserved_rows += stats.unobserved_rows;
    const auto e = CountEnergyTransitions(model.counts, BatteryContextFromIndex(c));
    out.energy.s1_to_s2 += e.s1_to_s2;
    out.energy.s2_to_s3 += e.s2_to_s3;
    out.energy.s1_to_s3 += e.s1_to_s3;
    out.energy.recoveries += e.recoveries;
  }
  return out;
}

BatterySolveReport ReportBatterySolve(const BatteryPolicySet& set) {
  BatterySolveReport out;
  for (const BatteryContextPolicy& p : set.policies) {
    out.wall_time_s += p.summary.wall_time_s;
    out.iterations += p.summary.iterations;
    out.unobserved_rows += p.stats.unobserved_rows;
    out.learned_rows += p.stats.learned_rows;
    out.contexts.push_back({{"context", BatteryContextLabel(p.context)},
                            {"iterations", p.summary.iterations},
                            {"unobserved_rows", p.stats.unobserved_rows},
                            {"transitions", p.stats.transitions}});
  }
  return out;
}

BatteryPolicyChoices CountBatteryPolicyChoices(const BatteryContextPolicy& p) {
  BatteryPolicyChoices out;
  for (StateIndex s = 0; s < static_cast<StateIndex>(p.action.size()); ++s) {
    if (s == kBatteryFailureState || s == kBatteryCompleteState || !IsPossibleBatteryState(s)) continue;
    const auto action = static_cast<PackAction>(p.action[static_cast<std::size_t>(s)]);
    if (IsFlaggedBatteryState(s)) {
      if (!BothPacksIn(s)) continue;
      ++out.flagged_both_in;
      const BatteryFeatures f = BatteryStateFeatures(s);
      const bool isolates = (action == PackAction::kUseBatt1 && f.pack[1].flagged) ||
                            (action == PackAction::kUseBatt2 && f.pack[0].flagged);
      out.flagged_isolations += isolates ? 1 : 0;
    } else if (BothPacksIn(s)) {
      ++out.both_in[static_cast<std::size_t>(action)];
    } else {
      out.one_in_switches += SwitchesMatch(s, action) ? 0 : 1;
    }
  }
  return out;
}

std::string BatteryTransitionDot(const BatteryContextPolicy& policy, PackAction action) {
  std::string out = fmt::format(
      "digraph battery_mdp {{\n  label=\"battery MDP transitions, action {}, context {} (Fig. 4.4); grey dotted: "
      "row never observed\";\n  rankdir=LR;\n  node [shape=box, style=rounded, fontsize=10];\n",
      models::PackActionName(action), BatteryContextLabel(policy.context));
  const ObservedBatteryRows observed(policy);
  std::set<StateIndex> nodes;
  std::string edges;
  for (const BatteryLearnedRow& row : policy.observed_rows) {
    if (row.action != action) continue;
    nodes.insert(row.state);
    for (const Transition& t : row.next) {
      nodes.insert(t.next_state);
      edges += fmt::format("  \"{}\" -> \"{}\" [label=\"{:.3g}\"];\n", BatteryStateLabel(row.state),
                           BatteryStateLabel(t.next_state), t.probability);
    }
    // The states that differ from the row's source only in the switches reach it with p = 1.
    BatteryFeatures f = BatteryStateFeatures(row.state);
    for (int on1 = 0; on1 < 2; ++on1) {
      for (int on2 = 0; on2 < 2; ++on2) {
        f.pack[0].switch_on = on1 == 1;
        f.pack[1].switch_on = on2 == 1;
        const StateIndex from = BatteryStateIndex(f);
        if (from == row.state || !IsPossibleBatteryState(from)) continue;
        nodes.insert(from);
        edges += fmt::format("  \"{}\" -> \"{}\" [label=\"1\", style=dashed];\n", BatteryStateLabel(from),
                             BatteryStateLabel(row.state));
      }
    }
  }
  for (StateIndex s : nodes) {
    const bool failure = s == kBatteryFailureState;
    const bool unobserved = !failure && SwitchesMatch(s, action) && !observed.Has(s, action);
    if (failure) {
      out += fmt::format("  \"{}\" [color=\"red\", style=\"rounded,filled\", fillcolor=\"#ffcdd2\"];\n",
                         BatteryStateLabel(s));
    } else if (unobserved) {
      out += fmt::format(
          "  \"{}\" [color=\"grey\", fontcolor=\"grey40\", style=\"rounded,dotted\", "
          "label=\"{}\\n(unobserved)\"];\n",
          BatteryStateLabel(s), BatteryStateLabel(s));
    } else {
      out += fmt::format("  \"{}\" [color=\"black\"];\n", BatteryStateLabel(s));
    }
  }
  return out + edges + "}\n";
}

nlohmann::json BatteryPolicyViewJson(const BatteryPolicySet& set, std::span<const StateIndex> takeoff,
                                     double takeoff_flight_s) {
  nlohmann::json contexts = nlohmann::json::array();
  nlohmann::json impossible = nlohmann::json::array(), both_in = nlohmann::json::array();
  for (StateIndex s = 0; s < kBatteryNumStates; ++s) {
    impossible.push_back(!IsPossibleBatteryState(s));
    both_in.push_back(BothPacksIn(s));
  }
  for (const BatteryContextPolicy& p : set.policies) {
    const ObservedBatteryRows observed(p);
    nlohmann::json actions = nlohmann::json::array(), unobserved = nlohmann::json::array();
    int unobserved_possible = 0;
    for (StateIndex s = 0; s < kBatteryNumStates; ++s) {
      const auto action = static_cast<PackAction>(p.action[static_cast<std::size_t>(s)]);
      actions.push_back(BatteryActionNames()[static_cast<std::size_t>(action)]);
      const bool missing = IsPossibleBatteryState(s) && !observed.Has(s, action);
      unobserved.push_back(missing);
      unobserved_possible += missing ? 1 : 0;
    }
    const StateIndex start = takeoff[static_cast<std::size_t>(BatteryContextIndex(p.context))];
    const BatteryPolicyChoices choices = CountBatteryPolicyChoices(p);
    contexts.push_back({{"context", BatteryContextLabel(p.context)},
                        {"both_in_per_action", choices.both_in},
                        {"one_in_switches", choices.one_in_switches},
                        {"flagged_both_in", choices.flagged_both_in},
                        {"flagged_isolations", choices.flagged_isolations},
                        {"b1", BatteryHealthName(p.context.b1)},
                        {"b2", BatteryHealthName(p.context.b2)},
                        {"temperature", TemperatureClassName(p.context.temperature)},
                        {"unobserved_rows", p.stats.unobserved_rows},
                        {"unobserved_choices", unobserved_possible},
                        {"takeoff_state", BatteryStateLabel(start)},
                        {"takeoff_action", BatteryActionNames()[static_cast<std::size_t>(p.action[start])]},
                        {"takeoff_unobserved", unobserved[static_cast<std::size_t>(start)]},
                        {"action", actions},
                        {"unobserved", unobserved}});
  }
  return {{"model_hash", set.model_hash},
          {"formulation", BatteryFormulationName(set.formulation)},
          {"gamma", set.gamma},
          {"takeoff_flight_s", takeoff_flight_s},
          {"label", FormulationLabel(set.formulation)},
          {"states", BatteryStateLabels()},
          {"impossible", impossible},
          {"both_in", both_in},
          {"contexts", contexts}};
}

std::string BatteryPolicyViewText(const BatteryPolicySet& set, std::span<const StateIndex> takeoff,
                                  double takeoff_flight_s, const std::string& source) {
  const bool ours = set.formulation == BatteryFormulation::kOurs;
  std::string text = fmt::format(
      "battery policies {}: {} ({} formulation, model {}, gamma {:.6g})\nFig. 4.5 decision tree over (T, B1F, "
      "B2F), one leaf per context. Choices: per action in the 72 states with both packs in; switches in the 144 "
      "with one pack in (72 with both switches OFF cannot occur){}\n"
      "take-off: the first state of the context's case-study flight ({:.0f} s plan, "
      "docs/modelling-choices.md#battery-case-study-flight-time); * = the chosen "
      "action's row was never observed; unobserved: the choices with both packs in whose row was never observed\n",
      source, FormulationLabel(set.formulation), BatteryFormulationName(set.formulation), set.model_hash, set.gamma,
      ours ? "; flagged: isolations of a flagged pack in the 26 flagged states with both in" : "", takeoff_flight_s);
  text += "                 both packs in (72)              one in     unobserved   at take-off";
  text += ours ? "                         flagged\n" : "\n";
  text += "T    B1F  B2F    UseBatt1  UseBatt2  UseBoth     switches   choices      state              action";
  text += ours ? "              isolate\n" : "\n";
  for (const BatteryContextPolicy& p : set.policies) {
    const ObservedBatteryRows observed(p);
    const BatteryPolicyChoices choices = CountBatteryPolicyChoices(p);
    int unobserved = 0;
    for (StateIndex s = 0; s < kBatteryFailureState; ++s) {
      if (!BothPacksIn(s)) continue;
      const auto action = static_cast<PackAction>(p.action[static_cast<std::size_t>(s)]);
      unobserved += observed.Has(s, action) ? 0 : 1;
    }
    const StateIndex start = takeoff[static_cast<std::size_t>(BatteryContextIndex(p.context))];
    const auto start_action = static_cast<PackAction>(p.action[static_cast<std::size_t>(start)]);
    text += fmt::format("{:<4} {:<4} {:<4}   {:>8}  {:>8}  {:>7}     {:>8}   {:>3} of 72    {:<18} {}{}",
                        TemperatureClassName(p.context.temperature), BatteryHealthName(p.context.b1),
                        BatteryHealthName(p.context.b2), choices.both_in[0], choices.both_in[1], choices.both_in[2],
                        choices.one_in_switches, unobserved, BatteryStateLabel(start),
                        models::PackActionName(start_action), observed.Has(start, start_action) ? "" : " *");
    text += ours ? fmt::format("{:>{}}{} of {}\n", "", observed.Has(start, start_action) ? 12 : 10,
                               choices.flagged_isolations, choices.flagged_both_in)
                 : "\n";
  }
  return text;
}

}  // namespace uascma::decision
