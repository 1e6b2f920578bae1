#pragma once
// What `uascma policy` reports of the contingency-management MDP (dissertation §5.3.2): the composed transition rows
// of one action (Tables 5.1-5.7, eqs. 5.16-5.19), the MDP solved and its policy written as the policy file
// (policy_file.h) or as a table of the non-terminal states, and a policy seen in the quadrant view of Fig. 5.9.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "uascma/decision/cma_mdp.h"
#include "uascma/decision/finite_mdp.h"
#include "uascma/decision/policy_file.h"
#include "uascma/decision/solvers.h"

namespace uascma::decision {

// Every available row of `action`, the terminal states' included, as TSV lines "state<TAB>next_state<TAB>probability"
// (the probability to 10 significant digits), in state order and, within a row, in the row's successor order.
std::string TransitionRowsTsv(const FiniteMdp& mdp, ActionIndex action);

enum class CmaSolveMethod { kValueIteration, kPolicyIteration };

// The CMA MDP solved at config.gamma: the model of config.weights (BuildCmaMdp) or, with a transitions file of
// `uascma learn transitions`, the rows estimated from flights (BuildEstimatedCmaMdp; unobserved rows keep the DDN's).
struct CmaSolution {
  FiniteMdp mdp;
  Policy policy;
  SolverSummary summary;
  double gamma = 0.0;
  CmaSolveMethod method = CmaSolveMethod::kValueIteration;
  // The policy file's model_config: the weights, and with a transitions file its counts and its path.
  nlohmann::json model_config;
};
// Value iteration to a Bellman residual below its tolerance, or policy iteration (solvers.h). InputError for an
// unreadable transitions file.
CmaSolution SolveCma(const CmaConfig& config, CmaSolveMethod method, const std::string& transitions_file = "");

// "state<TAB>action<TAB>value" (the value to 10 significant digits) for the kCmaNumTupleStates non-terminal states.
std::string CmaPolicyTsv(const CmaSolution& solution);
// The policy file (MakePolicyDocument of the "cma" model, PolicyToJson) indented by 2, with a final line break.
std::string CmaPolicyFileJson(const CmaSolution& solution);
// The solver's result for a policy written to `out`: its model hash, gamma, status, iterations, residual and time.
nlohmann::json CmaSolveSummaryJson(const CmaSolution& solution, const std::string& out);
// The same in two lines: the model, the solver's BriefReport, and the action at the nominal start state.
std::string CmaSolveSummaryText(const CmaSolution& solution, const std::string& out);

// The name that shows the vehicle-level motor margin's model (cma_vehicle_mdp.h) solved with the default weights.
inline constexpr const char* kCmaVehiclePolicyName = "cma-vehicle";

// A policy with its model, in the quadrant view of Fig. 5.9 (CmaQuadrantView).
struct CmaPolicyView {
  PolicyDocument document;  // the file read; for kCmaVehiclePolicyName only the model hash and gamma
  FiniteMdp mdp;
  Policy policy;
  std::vector<QuadrantRow> rows;
};
// `policy` names a policy file of `uascma policy solve`, bound to the model of `weights_file` (or, empty, of the
// weights the file records; the model hash is checked: CmaModelForPolicy, BindPolicy), or kCmaVehiclePolicyName.
CmaPolicyView LoadCmaPolicyView(const std::string& policy, const std::string& weights_file);
// {"model_hash", "gamma", "rows": [{"I": {"state", "action", "value"}, "II": …, "III": …, "IV": …}, …]}: what
// python/plots/policy_quadrants.py draws.
nlohmann::json CmaPolicyViewJson(const CmaPolicyView& view);
// The quadrant table headed by the policy's name `source`, its model hash and gamma.
std::string CmaPolicyViewText(const CmaPolicyView& view, const std::string& source);

}  // namespace uascma::decision
