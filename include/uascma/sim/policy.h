#pragma once
// The decision module of the simulator (§5.4, Fig. 5.15: queried at 1 Hz with the abstract CMA state) and the
// one resolver of policy names used by scenario files, the CLI and campaigns:
//   "noop"       always NoOp: the baseline;
//   "cma"        the CMA MDP with the dissertation's weights (eqs. 5.28–5.29) and γ = 0.95
//   (docs/modelling-choices.md#discount),
//                solved by value iteration (decision/policy_file.h SolveDefaultCmaPolicy);
//   "cma-vehicle" the CMA MDP under the vehicle-level motor margin (sim/vehicle_policy.h, sim/vehicle_margin.h): MM0
//                only when the vehicle after the predicted jam (a quadcopter, §4.4) could not finish the plan;
//   "cma-risk"   the default CMA policy deciding on beliefs: RM0 when P(EOD < t_remaining + t_sf) exceeds a level
//                derived from its values, MH the belief's MAP (sim/belief_policy.h);
//   "cma-risk@P" the same at a level the user states, P from 0 to 1 (e.g. "cma-risk@0.1": RM0 when the chance of
//                running short exceeds 10 %), an operator's risk appetite instead of the reward-derived level;
//   "cma-qmdp"   QMDP over the default CMA policy's Q-values and the beliefs (sim/belief_policy.h);
//   "cma-vehicle-risk", "cma-vehicle-risk@P", "cma-vehicle-qmdp"  the same two rules over the vehicle-level policy's
//                table and Q-values, each belief state's MM the vehicle-level margin (sim/belief_policy.h);
//   FILE.json    a policy file written by `uascma policy solve`; its model hash is checked against the CMA model
//                rebuilt from the weights it records. Named by the file stem ("tuned.json" → "tuned").
// A PolicyDefinition is plain data (the action of every CMA state), so campaigns store it with their results
// and a run replays without the original file.
#include <array>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "uascma/decision/cma_mdp.h"
#include "uascma/decision/finite_mdp.h"

namespace uascma::sim {

// The epoch's EOD and the reach margin it gives, RM = 1 − (t_remaining + t_sf) / t_EOD
// (docs/modelling-choices.md#margins): their values, or their lower bounds. Two types, not a flag: a reader that
// needs the value asks for an EodValue (DecisionInputs::eod_value()) and cannot read a bound by mistake; a reader of
// the reach margin's class alone may read either (ReachMarginAtLeast). A std::variant rather than a base class: each is
// plain data with ==, and a Python binding hands over the alternative it holds.
struct EodValue {
  double eod_s = 0.0;
  double reach_margin = 0.0;
  bool operator==(const EodValue&) const = default;
};
// Where the epoch's EOD was propagated only as far as the reach margin's class needs (sim/eod_precision.h
// EodPrecision::kReachMarginClass): the EOD is at least t_remaining + t_sf and RM at least 0 (RM1), until an action
// completes them (CompleteEod).
struct EodLowerBound {
  double eod_s = 0.0;
  double reach_margin = 0.0;
  bool operator==(const EodLowerBound&) const = default;
};
using EpochEod = std::variant<EodValue, EodLowerBound>;
// The value's EOD (s) or the bound's: the EOD is at least that.
inline double EodAtLeastS(const EpochEod& eod) {
  return std::visit([](const auto& e) { return e.eod_s; }, eod);
}
// The value's RM or the bound's: what the reach margin's class reads (a bound of 0 is RM1).
inline double ReachMarginAtLeast(const EpochEod& eod) {
  return std::visit([](const auto& e) { return e.reach_margin; }, eod);
}

// The EOD as a distribution: its 5, 50 and 95 % quantiles (s) and the chance that the EOD falls short of the rest of
// the plan with its margin, P(EOD < t_remaining + t_sf), from the load forecast's measured error
// (sim/eod_error_model.h). With no uncertainty (an empty error model) the quantiles are the EOD's value and the chance
// 0 or 1.
struct EodDistributionSummary {
  double p05_s = 0.0;
  double p50_s = 0.0;
  double p95_s = 0.0;
  double short_probability = 0.0;
  bool operator==(const EodDistributionSummary&) const = default;
};

// The 1 Hz view of the flight that a decision module sees (docs/modelling-choices.md#margins to #outcomes).
struct DecisionInputs {
  double time_s = 0.0;
  decision::CmaState state;
  double flight_time_remaining_s = 0.0;  // on the executing plan
  EpochEod eod;
  double rul_s = std::numeric_limits<double>::infinity();  // +∞ without a motor fault
  double motor_margin = 0.0;                               // MM = 1 − t_remaining / t_RUL
  // Computed only when asked for (Observe's `eod_distribution`: a policy that reads it, the telemetry, the EOD
  // calibration); empty otherwise.
  std::optional<EodDistributionSummary> eod_distribution;
  // The motor-health belief b(NF, SF, JF) (sim/sensing.h MotorHealthBelief under noisy sensing, the point
  // MH's one-hot without it) and the RUL the prognosis gives a spall detected now (the motor margin of a belief's SF
  // states; +∞ until the prognosis has run).
  std::array<double, 3> motor_health_belief{1.0, 0.0, 0.0};
  double rul_if_spall_s = std::numeric_limits<double>::infinity();
  // The vehicle-level motor margin (sim/vehicle_margin.h), the `cma-vehicle` policy's MM: eq. 5.14's value while the
  // motor outlives the plan, the quadcopter's reach margin when the predicted jam comes within it (a lower bound
  // above 0), RM once a rotor is isolated, −∞ for a seized motor not isolated.
  double vehicle_motor_margin = 1.0;
  // The RUL the vehicle-level margin reads (prognostics/rul_calibration.h: the time scale fitted to the simulated
  // spall's jams, the particles that have not jammed since the detection): +∞ without a detected spall, 0 once a rotor
  // is isolated; and that of a spall detected now (the vehicle-level belief policies' SF states).
  double vehicle_rul_s = std::numeric_limits<double>::infinity();
  double vehicle_rul_if_spall_s = std::numeric_limits<double>::infinity();
  // The vehicle-level margin under the hypothesis MH = SF at vehicle_rul_if_spall_s (the SF states of the
  // vehicle-level belief policies): with exact sensing vehicle_motor_margin when MH = SF; under noisy sensing computed
  // only for a policy that reads it (DecisionPolicy::ReadsVehicleBeliefs), else 1.
  double vehicle_motor_margin_if_spall = 1.0;
  bool operator==(const DecisionInputs&) const = default;

  // The EOD's value: a broken invariant (abort) while `eod` holds a lower bound. What every reader of eod_s or
  // reach_margin but the reach margin's class reads.
  const EodValue& eod_value() const;
  // The EOD's distribution: a broken invariant (abort) when the epoch did not compute it.
  const EodDistributionSummary& eod_distribution_value() const;
};

// A state's available actions by decreasing value Q(s, a) of a solved policy, its own action first.
using ActionRanking = std::span<const decision::ActionIndex>;

// The default CMA policy's ranking in `state` (SolvedCmaPolicyDefinition,
// docs/modelling-choices.md#unavailable-actions).
ActionRanking DefaultCmaActionRanking(const decision::CmaState& state);

// The pluggable decision module: called at 1 Hz, returns a CMA action.
class DecisionPolicy {
 public:
  virtual ~DecisionPolicy() = default;
  virtual decision::CmaAction Decide(const DecisionInputs& inputs) = 0;
  virtual std::string name() const = 0;
  // What the executor falls back on when the chosen action cannot be carried out at this epoch (a planner that
  // finds nothing, docs/modelling-choices.md#unavailable-actions): the state's actions by decreasing Q(s, a). A policy
  // without values of its own (NoOp, a Python callable) falls back on the default CMA policy's values.
  virtual ActionRanking Ranking(const DecisionInputs& inputs) const { return DefaultCmaActionRanking(inputs.state); }
  // True when Decide reads the EOD's distribution (DecisionInputs::eod_distribution): the kernel
  // computes it at every epoch for such a policy only (three more EOD propagations per epoch).
  virtual bool ReadsEodDistribution() const { return false; }
  // True when Decide and Ranking read nothing of DecisionInputs but `state` and `time_s`: the kernel may then stop the
  // epoch's EOD propagation once the reach margin's class is settled (sim/eod_precision.h).
  virtual bool ReadsOnlyCmaState() const { return false; }
  // The abstract CMA state Decide reads its row in: `inputs.state` (eq. 5.14's motor margin), or another abstraction
  // of the same MDP's states (the vehicle-level margin, sim/vehicle_policy.h). What the campaign's reward accounting
  // and records use.
  virtual decision::CmaState StateRead(const DecisionInputs& inputs) const { return inputs.state; }
  // True when Decide reads DecisionInputs::vehicle_motor_margin_if_spall under noisy sensing (the vehicle-level belief
  // policies): the kernel then computes the quadcopter's reach for the SF hypothesis at every epoch it bears on.
  virtual bool ReadsVehicleBeliefs() const { return false; }
};

// Always NoOp: the baseline.
class NoOpPolicy final : public DecisionPolicy {
 public:
  decision::CmaAction Decide(const DecisionInputs&) override { return decision::CmaAction::kNoOp; }
  std::string name() const override { return "noop"; }
  bool ReadsOnlyCmaState() const override { return true; }
};

// A solved CMA policy: the action of the abstract state's row.
// `ranking` (per state, its actions by decreasing Q) is what the executor falls back on; empty: the default CMA
// policy's.
class TablePolicy final : public DecisionPolicy {
 public:
  TablePolicy(std::vector<decision::ActionIndex> action_per_state, std::string name,
              std::vector<std::vector<decision::ActionIndex>> ranking = {});
  decision::CmaAction Decide(const DecisionInputs& inputs) override;
  std::string name() const override { return name_; }
  ActionRanking Ranking(const DecisionInputs& inputs) const override;
  bool ReadsOnlyCmaState() const override { return true; }

 private:
  std::vector<decision::ActionIndex> action_;
  std::string name_;
  std::vector<std::vector<decision::ActionIndex>> ranking_;
};

struct PolicyDefinition {
  std::string name;                            // "cma", "noop", a file stem: unique within a campaign
  std::string kind;  // "noop" | "table" | "cma-vehicle" | "cma-risk" | "cma-qmdp" (the default table's)
  std::string source;                          // "cma default weights", "noop", or the file it came from
  std::vector<decision::ActionIndex> actions;  // kind "table": the action of each CMA state (112)
  // Kind "table": per state, its available actions by decreasing Q(s, a), actions[s] first
  // (docs/modelling-choices.md#unavailable-actions); empty: the executor falls back on the default CMA policy's
  // ranking.
  std::vector<std::vector<decision::ActionIndex>> ranking;
  // Kind "cma-risk": the stated level of "cma-risk@P"; NaN: the level derived from the Q-values (CmaRiskLevel).
  double risk_level = std::numeric_limits<double>::quiet_NaN();
  std::string hash;  // 16 hex digits: fingerprint of the kind, the actions, the ranking and a stated level
};

PolicyDefinition NoOpPolicyDefinition();
// "cma-risk" or "cma-qmdp": the policies that decide on beliefs over the default CMA policy; "cma-vehicle-risk" or
// "cma-vehicle-qmdp": over the vehicle-level policy (sim/belief_policy.h).
inline bool IsVehicleBeliefPolicyKind(const std::string& kind) {
  return kind == "cma-vehicle-risk" || kind == "cma-vehicle-qmdp";
}
inline bool IsBeliefPolicyKind(const std::string& kind) {
  return kind == "cma-risk" || kind == "cma-qmdp" || IsVehicleBeliefPolicyKind(kind);
}
// "cma-risk" or "cma-vehicle-risk": the kinds a stated level "@P" may follow.
inline bool IsRiskPolicyKind(const std::string& kind) { return kind == "cma-risk" || kind == "cma-vehicle-risk"; }
PolicyDefinition SolvedCmaPolicyDefinition();
// A policy file; InputError names the file and field when it does not bind to the CMA model.
PolicyDefinition PolicyDefinitionFromFile(const std::string& path);
// The stated level of a "cma-risk@P" or "cma-vehicle-risk@P" name (P a number from 0 to 1); nullopt for any other
// name. InputError names `source` and `field` when the name starts with such a prefix but P is not such a number.
std::optional<double> StatedRiskLevel(const std::string& spec, const std::string& source, const std::string& field);
// "noop", "cma", "cma-vehicle", "cma-risk[@P]", "cma-qmdp", "cma-vehicle-risk[@P]", "cma-vehicle-qmdp" or a policy
// JSON path; InputError names `source` (e.g.
// "--policy") and `field` otherwise.
PolicyDefinition ResolvePolicy(const std::string& spec, const std::string& source, const std::string& field = "policy");
// A policy from its stored form (results store): `actions_json` is PolicyActionsJson's text, a list with one entry
// per state, an action name or the state's ranking as a list of names (its action first). InputError names
// `where` when malformed.
PolicyDefinition MakeStoredPolicy(const std::string& name, const std::string& kind, const std::string& source,
                                  const std::string& actions_json, const std::string& where);
// The action names of a table policy, per state.
std::vector<std::string> PolicyActionNames(const PolicyDefinition& policy);
// The stored form of a policy's actions (and ranking, when it has one), as MakeStoredPolicy reads it.
std::string PolicyActionsJson(const PolicyDefinition& policy);

// A fresh decision module (policies keep no state across flights; one per flight keeps threads apart).
std::unique_ptr<DecisionPolicy> MakeDecisionPolicy(const PolicyDefinition& policy);
// ResolvePolicy then MakeDecisionPolicy.
std::unique_ptr<DecisionPolicy> MakePolicy(const std::string& spec, const std::string& source);

}  // namespace uascma::sim
