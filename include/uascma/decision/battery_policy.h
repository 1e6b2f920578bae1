#pragma once
// The battery MDP's policies (dissertation §4.3.2.1, docs/modelling-choices.md#battery-mdp-policies) and their 1 Hz
// executor. Policies: value iteration, γ = 0.95 (§4.3.2.1), one per context (Table 4.2, 18 contexts); the decision tree
// of Fig. 4.5 (temperature, then B1 health, then B2 health) picks one at take-off. Ours (decision/battery_mdp.h):
// policy iteration at our discount. The policy file is decision/battery_mdp_file.h.
#include <array>
#include <string>
#include <vector>

#include "uascma/decision/battery_abstraction.h"
#include "uascma/decision/battery_mdp.h"
#include "uascma/decision/battery_model.h"
#include "uascma/decision/finite_mdp.h"
#include "uascma/decision/solvers.h"

namespace uascma::decision {

// A learned row with evidence: p(next | state, action) from the counts.
struct BatteryLearnedRow {
  StateIndex state = 0;
  models::PackAction action = models::PackAction::kUseBoth;
  std::vector<Transition> next;
};

struct BatteryContextPolicy {
  BatteryContext context;
  std::vector<ActionIndex> action;  // [289] (dissertation) or [394] (ours: its flagged states, item 10)
  std::vector<double> value;        // the same
  SolverSummary summary;
  BatteryModelStats stats;
  std::string mdp_hash;  // ModelHash of the context's MDP
  // The observed rows of the MDP it was solved on (switch rows and self-loops follow from the rules), so
  // the policy file alone draws the transition graph of Fig. 4.4.
  std::vector<BatteryLearnedRow> observed_rows;
};

struct BatteryPolicySet {
  std::string model_hash;  // BatteryModelHash of the model it was solved from
  BatteryFormulation formulation = BatteryFormulation::kDissertation;
  double gamma = 0.95;
  BatteryRewardWeights weights;
  std::array<BatteryContextPolicy, kBatteryNumContexts> policies;  // by BatteryContextIndex

  // Fig. 4.5: temperature → B1 health → B2 health.
  const BatteryContextPolicy& Select(const BatteryContext& context) const;
};

// Value iteration per context (γ of the model, residual 1e-10).
BatteryPolicySet SolveBatteryPolicies(const BatteryModel& model);
// Ours (above): policy iteration per context at `gamma` (campaign::OursBatteryDiscount).
BatteryPolicySet SolveOursBatteryPolicies(const BatteryModel& model, double gamma);

// The 1 Hz battery executor (docs/modelling-choices.md#battery-mdp-policies): the context's policy looked up per
// abstract state; the action takes effect at once.
class BatteryPolicyExecutor {
 public:
  BatteryPolicyExecutor(const BatteryPolicySet& policies, const BatteryContext& context);
  models::PackAction Decide(StateIndex state) const;
  // The observation in the formulation's abstraction (ours reads the pack-fault flags).
  StateIndex Abstract(const BatteryObservation& observation) const {
    return AbstractBatteryState(observation, thresholds_, formulation_);
  }
  models::PackAction Decide(const BatteryObservation& observation) const { return Decide(Abstract(observation)); }
  const BatteryContext& context() const { return context_; }
  const BatteryThresholds& thresholds() const { return thresholds_; }
  BatteryFormulation formulation() const { return formulation_; }

 private:
  BatteryContext context_;
  BatteryFormulation formulation_;
  std::vector<ActionIndex> action_;  // [289] or [394]
  BatteryThresholds thresholds_;
};

}  // namespace uascma::decision
