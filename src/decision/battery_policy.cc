#include "uascma/decision/battery_policy.h"

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/decision/policy_file.h"

namespace uascma::decision {

using models::PackAction;

// ================================ policies ========================================================
const BatteryContextPolicy& BatteryPolicySet::Select(const BatteryContext& context) const {
  // Fig. 4.5's tree: the temperature branch, then the B1 health branch, then the B2 health leaf. The
  // array is laid out in that order (BatteryContextIndex), so the walk is one index computation.
  return policies[static_cast<std::size_t>(BatteryContextIndex(context))];
}

BatteryPolicySet SolveBatteryPolicies(const BatteryModel& model) {
  BatteryPolicySet set;
  set.model_hash = BatteryModelHash(model);
  set.gamma = model.gamma;
  set.weights = model.weights;
  ValueIterationOptions options;
  options.gamma = model.gamma;  // 0.95, §4.3.2.1
  for (int c = 0; c < kBatteryNumContexts; ++c) {
    BatteryContextPolicy& out = set.policies[static_cast<std::size_t>(c)];
    out.context = BatteryContextFromIndex(c);
    const FiniteMdp mdp = BuildBatteryMdp(model.counts, out.context, model.weights, &out.stats);
    Policy policy = SolveValueIteration(mdp, options, &out.summary);
    out.action = std::move(policy.action);
    out.value = std::move(policy.value);
    out.mdp_hash = ModelHash(mdp);
    for (StateIndex s = 0; s < kBatteryFailureState; ++s) {
      for (PackAction action : kBatteryActions) {
        if (!SwitchesMatch(s, action) || model.counts.Row(out.context, s, action).empty()) continue;
        const std::int64_t choice = mdp.FindChoice(s, BatteryActionIndex(action));
        BatteryLearnedRow row{s, action, {}};
        const auto next = mdp.choice_next_states(choice);
        const auto prob = mdp.choice_probabilities(choice);
        for (std::size_t k = 0; k < next.size(); ++k) row.next.push_back({next[k], prob[k]});
        out.observed_rows.push_back(std::move(row));
      }
    }
  }
  return set;
}

BatteryPolicySet SolveOursBatteryPolicies(const BatteryModel& model, double gamma) {
  if (!(gamma > 0.0 && gamma < 1.0)) throw InputError("battery MDP", "gamma", fmt::format("in (0, 1), got {}", gamma));
  BatteryPolicySet set;
  set.model_hash = BatteryModelHash(model);
  set.formulation = BatteryFormulation::kOurs;
  set.gamma = gamma;
  set.weights = model.weights;
  PolicyIterationOptions options;
  options.gamma = gamma;
  options.evaluation = EvaluationMethod::kDirect;  // 394 states: exact
  const BatteryTransitionCounts& counts = model.OursCounts();
  for (int c = 0; c < kBatteryNumContexts; ++c) {
    BatteryContextPolicy& out = set.policies[static_cast<std::size_t>(c)];
    out.context = BatteryContextFromIndex(c);
    const FiniteMdp mdp = BuildOursBatteryMdp(counts, out.context, model.weights, &out.stats);
    Policy policy = SolvePolicyIteration(mdp, options, &out.summary);
    out.action = std::move(policy.action);  // all 394 (COMPLETE is never observed in flight)
    out.value = std::move(policy.value);
    out.mdp_hash = ModelHash(mdp);
    // The counted rows (p over the counted next states, completions left out), for drawing Fig. 4.4.
    for (StateIndex s = 0; s < kOursNumStates; ++s) {
      if (s == kBatteryFailureState || s == kBatteryCompleteState) continue;
      for (PackAction action : kBatteryActions) {
        const auto& counted = counts.Row(out.context, s, action);
        if (!SwitchesMatch(s, action) || counted.empty()) continue;
        std::int64_t total = 0;
        for (const auto& [next, count] : counted) total += count;
        BatteryLearnedRow row{s, action, {}};
        for (const auto& [next, count] : counted) {
          row.next.push_back({next, static_cast<double>(count) / static_cast<double>(total)});
        }
        out.observed_rows.push_back(std::move(row));
      }
    }
  }
  return set;
}

// ================================ the executor ====================================================
BatteryPolicyExecutor::BatteryPolicyExecutor(const BatteryPolicySet& policies, const BatteryContext& context)
    : context_(context), formulation_(policies.formulation), action_(policies.Select(context).action) {
  UASCMA_CHECK(action_.size() == static_cast<std::size_t>(BatteryPolicyStates(formulation_)),
               "a policy of the formulation's states");
}

PackAction BatteryPolicyExecutor::Decide(StateIndex state) const {
  UASCMA_CHECK(state >= 0 && state < static_cast<StateIndex>(action_.size()), "a battery state index");
  return static_cast<PackAction>(action_[static_cast<std::size_t>(state)]);
}

}  // namespace uascma::decision
