#pragma once
// The decision module of the simulator (§5.4, Fig. 5.15: queried at 1 Hz with the abstract CMA state) and the
// one resolver of policy names used by scenario files, the CLI and campaigns:
//   "noop"       always NoOp: the baseline;
//   "cma"        the CMA MDP with the dissertation's weights (eqs. 5.28–5.29) and γ = 0.95 (decisions item 5),
//                solved by value iteration (decision/policy_file.h SolveDefaultCmaPolicy);
//   FILE.json    a policy file written by `uascma policy solve`; its model hash is checked against the CMA model
//                rebuilt from the weights it records. Named by the file stem ("tuned.json" → "tuned").
// A PolicyDefinition is plain data (the action of every CMA state), so campaigns store it with their results
// and a run replays without the original file.
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "uascma/decision/cma_mdp.h"
#include "uascma/decision/finite_mdp.h"

namespace uascma::sim {

// The 1 Hz view of the flight that a decision module sees (decisions items 7–11).
struct DecisionInputs {
  double time_s = 0.0;
  decision::CmaState state;
  double flight_time_remaining_s = 0.0;  // on the executing plan
  double eod_s = 0.0;
  double rul_s = std::numeric_limits<double>::infinity();  // +∞ without a motor fault
  double reach_margin = 0.0;     // RM = 1 − (t_remaining + t_sf) / t_EOD
  double motor_margin = 0.0;     // MM = 1 − t_remaining / t_RUL
};

// The pluggable decision module: called at 1 Hz, returns a CMA action.
class DecisionPolicy {
 public:
  virtual ~DecisionPolicy() = default;
  virtual decision::CmaAction Decide(const DecisionInputs& inputs) = 0;
  virtual std::string name() const = 0;
};

// Always NoOp: the baseline.
class NoOpPolicy final : public DecisionPolicy {
 public:
  decision::CmaAction Decide(const DecisionInputs&) override { return decision::CmaAction::kNoOp; }
  std::string name() const override { return "noop"; }
};

// A solved CMA policy: the action of the abstract state's row.
class TablePolicy final : public DecisionPolicy {
 public:
  TablePolicy(std::vector<decision::ActionIndex> action_per_state, std::string name);
  decision::CmaAction Decide(const DecisionInputs& inputs) override;
  std::string name() const override { return name_; }

 private:
  std::vector<decision::ActionIndex> action_;
  std::string name_;
};

struct PolicyDefinition {
  std::string name;    // "cma", "noop", a file stem: unique within a campaign
  std::string kind;    // "noop" | "table"
  std::string source;  // "cma default weights", "noop", or the file it came from
  std::vector<decision::ActionIndex> actions;  // kind "table": the action of each CMA state (112)
  std::string hash;    // 16 hex digits: fingerprint of the kind and the actions
};

PolicyDefinition NoOpPolicyDefinition();
PolicyDefinition SolvedCmaPolicyDefinition();
// A policy file; InputError names the file and field when it does not bind to the CMA model.
PolicyDefinition PolicyDefinitionFromFile(const std::string& path);
// "noop", "cma" or a policy JSON path; InputError names `source` (e.g. "--policy") and `field` otherwise.
PolicyDefinition ResolvePolicy(const std::string& spec, const std::string& source, const std::string& field = "policy");
// A policy from its stored form (results store); InputError names `where` when malformed.
PolicyDefinition MakeStoredPolicy(const std::string& name, const std::string& kind, const std::string& source,
                                  const std::vector<std::string>& action_names, const std::string& where);
// The action names of a table policy, per state.
std::vector<std::string> PolicyActionNames(const PolicyDefinition& policy);

// A fresh decision module (policies keep no state across flights; one per flight keeps threads apart).
std::unique_ptr<DecisionPolicy> MakeDecisionPolicy(const PolicyDefinition& policy);
// ResolvePolicy then MakeDecisionPolicy.
std::unique_ptr<DecisionPolicy> MakePolicy(const std::string& spec, const std::string& source);

}  // namespace uascma::sim
