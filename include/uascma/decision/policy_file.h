#pragma once
// Policies as files. A policy file is JSON:
//   {
//     "format": "uascma-policy/1",
//     "model": "cma",                       // which model family built the MDP
//     "model_hash": "…16 hex digits…",      // ModelHash() of the MDP: its tables and rewards
//     "gamma": 0.95,
//     "model_config": {…},                  // what rebuilds the model (for CMA: its weights)
//     "solver": {"method": …, "status": …, "iterations": …, "residual": …},
//     "states": [{"state": "N,NF,MM0,G,RM0", "action": "LandPract", "value": 1.23}, …]
//   }
// Loading a policy for use with a model checks the hash, so a policy solved for other weights or
// tables is refused (InputError naming the file and "model_hash").
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "uascma/decision/finite_mdp.h"
#include "uascma/decision/solvers.h"

namespace uascma::decision {

inline constexpr const char* kPolicyFormat = "uascma-policy/1";

// The identity of an MDP: a fingerprint of its state labels, action names, every row (successor and
// probability bit patterns) and every reward.
std::string ModelHash(const FiniteMdp& mdp);

struct PolicyDocument {
  std::string model;
  std::string model_hash;
  double gamma = 0.0;
  nlohmann::json model_config;
  nlohmann::json solver;
  std::vector<std::string> state_labels;
  std::vector<std::string> action_names;  // per state
  std::vector<double> values;             // per state
};

PolicyDocument MakePolicyDocument(const FiniteMdp& mdp, const Policy& policy, std::string model, double gamma,
                                  nlohmann::json model_config, const SolverSummary& summary, const std::string& method);
nlohmann::json PolicyToJson(const PolicyDocument& document);
// Structural checks only (fields present and typed); InputError names `source` and the field.
PolicyDocument PolicyFromJson(const nlohmann::json& json, const std::string& source);
PolicyDocument ReadPolicyFile(const std::filesystem::path& path);

// The policy as indices into `mdp`, after checking that the document was solved for this very model
// (hash), covers each of its states once, and picks only available actions.
Policy BindPolicy(const PolicyDocument& document, const FiniteMdp& mdp, const std::string& source);

// The CMA model a policy file was solved for: the weights of `weights_file` when given, else the weights
// the file records. InputError when the file is not a CMA policy or records no weights.
FiniteMdp CmaModelForPolicy(const PolicyDocument& document, const std::string& weights_file, const std::string& source);
// Reads a CMA policy file and binds it to its model (hash checked): the action and value per state.
// `ranking`, when given, receives per state the available actions by decreasing Q(s, a) of the bound model and
// the file's values, the file's own action first (RankActionsByQ; docs/modelling-choices.md#unavailable-actions).
Policy LoadCmaPolicy(const std::filesystem::path& path, const std::string& weights_file = "",
                     std::vector<std::vector<ActionIndex>>* ranking = nullptr);
// The policy every command calls "cma": the CMA MDP with the dissertation's weights (eqs. 5.28–5.29) and
// γ = 0.95 (docs/modelling-choices.md#rewards, #discount), solved by value iteration.
// `ranking` as LoadCmaPolicy's.
Policy SolveDefaultCmaPolicy(std::vector<std::vector<ActionIndex>>* ranking = nullptr);

}  // namespace uascma::decision
