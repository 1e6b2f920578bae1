#include "uascma/decision/policy_file.h"

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/hash.h"
#include "uascma/common/json_io.h"
#include "uascma/common/json_reader.h"
#include "uascma/decision/cma_estimated_model.h"
#include "uascma/decision/cma_mdp.h"
#include "uascma/decision/cma_weights_json.h"

namespace uascma::decision {

std::string ModelHash(const FiniteMdp& mdp) {
  Fingerprint fingerprint;
  fingerprint.Add(std::string_view("uascma-mdp"));
  for (const auto& label : mdp.state_labels()) fingerprint.Add(label);
  for (const auto& name : mdp.action_names()) fingerprint.Add(name);
  for (StateIndex s = 0; s < mdp.num_states(); ++s) {
    fingerprint.Add(static_cast<std::int64_t>(s));
    for (std::int64_t c = mdp.choice_begin(s); c < mdp.choice_end(s); ++c) {
      fingerprint.Add(mdp.choice_action(c));
      fingerprint.Add(mdp.choice_reward(c));
      const auto next = mdp.choice_next_states(c);
      const auto prob = mdp.choice_probabilities(c);
      for (std::size_t k = 0; k < next.size(); ++k) {
        fingerprint.Add(next[k]);
        fingerprint.Add(prob[k]);
      }
    }
  }
  return fingerprint.Hex();
}

PolicyDocument MakePolicyDocument(const FiniteMdp& mdp, const Policy& policy, std::string model, double gamma,
                                  nlohmann::json model_config, const SolverSummary& summary,
                                  const std::string& method) {
  PolicyDocument document;
  document.model = std::move(model);
  document.model_hash = ModelHash(mdp);
  document.gamma = gamma;
  document.model_config = std::move(model_config);
  document.solver = {
      {"method", method},
      {"status", summary.status == SolverStatus::kConverged ? "converged" : "max_iterations"},
      {"iterations", summary.iterations},
      {"residual", summary.residual},
  };
  for (StateIndex s = 0; s < mdp.num_states(); ++s) {
    document.state_labels.push_back(mdp.state_label(s));
    document.action_names.push_back(mdp.action_name(policy.action[s]));
    document.values.push_back(policy.value[s]);
  }
  return document;
}

nlohmann::json PolicyToJson(const PolicyDocument& document) {
  nlohmann::json states = nlohmann::json::array();
  for (std::size_t i = 0; i < document.state_labels.size(); ++i) {
    states.push_back(
        {{"state", document.state_labels[i]}, {"action", document.action_names[i]}, {"value", document.values[i]}});
  }
  return {{"format", kPolicyFormat},
          {"model", document.model},
          {"model_hash", document.model_hash},
          {"gamma", document.gamma},
          {"model_config", document.model_config},
          {"solver", document.solver},
          {"states", states}};
}

PolicyDocument PolicyFromJson(const nlohmann::json& json, const std::string& source) {
  const JsonValue root(&json, &source, "");
  root.RequireObject("a JSON object");
  PolicyDocument document;
  const std::string format = root.Member("format").String();
  if (format != kPolicyFormat) {
    throw InputError(source, "format", fmt::format("'{}', got '{}'", kPolicyFormat, format));
  }
  document.model = root.Member("model").String("a model name string");
  document.model_hash = root.Member("model_hash").String("a hash string");
  document.gamma = root.Member("gamma").Number(kGammaBounds);
  if (root.Has("model_config")) document.model_config = root.Member("model_config").json();
  if (root.Has("solver")) document.solver = root.Member("solver").json();
  for (const JsonValue& entry : root.Member("states").Elements("an array of {state, action, value}")) {
    constexpr std::string_view kEntry = "an object with string 'state', string 'action', number 'value'";
    entry.RequireObject(kEntry);
    document.state_labels.push_back(entry.Member("state").String());
    document.action_names.push_back(entry.Member("action").String());
    document.values.push_back(entry.Member("value").Number());
  }
  return document;
}

PolicyDocument ReadPolicyFile(const std::filesystem::path& path) {
  return PolicyFromJson(ReadJsonFile(path), path.string());
}

Policy BindPolicy(const PolicyDocument& document, const FiniteMdp& mdp, const std::string& source) {
  const std::string expected_hash = ModelHash(mdp);
  if (document.model_hash != expected_hash) {
    throw InputError(source, "model_hash",
                     fmt::format("{} (the model it is used with), got {}: the policy was solved for "
                                 "another model or weights",
                                 expected_hash, document.model_hash));
  }
  Policy policy;
  policy.action.assign(static_cast<std::size_t>(mdp.num_states()), -1);
  policy.value.assign(static_cast<std::size_t>(mdp.num_states()), 0.0);
  for (std::size_t i = 0; i < document.state_labels.size(); ++i) {
    const std::string where = fmt::format("states[{}]", i);
    const StateIndex s = mdp.FindState(document.state_labels[i]);
    if (s < 0)
      throw InputError(source, where + ".state", "a state of the model, got '" + document.state_labels[i] + "'");
    if (policy.action[s] >= 0) throw InputError(source, where + ".state", "each state once");
    const ActionIndex a = mdp.FindAction(document.action_names[i]);
    if (a < 0 || !mdp.IsAvailable(s, a)) {
      throw InputError(
          source, where + ".action",
          "an action available in " + document.state_labels[i] + ", got '" + document.action_names[i] + "'");
    }
    policy.action[s] = a;
    policy.value[s] = document.values[i];
  }
  for (StateIndex s = 0; s < mdp.num_states(); ++s) {
    if (policy.action[s] < 0) throw InputError(source, "states", "an entry for state " + mdp.state_label(s));
  }
  return policy;
}

FiniteMdp CmaModelForPolicy(const PolicyDocument& document, const std::string& weights_file,
                            const std::string& source) {
  if (document.model != "cma") throw InputError(source, "model", "'cma', got '" + document.model + "'");
  CmaWeights weights;
  if (!weights_file.empty()) {
    weights = LoadCmaConfig(weights_file).weights;
  } else if (!document.model_config.contains("weights")) {
    throw InputError(source, "model_config.weights", "the weights the policy was solved with");
  } else {
    weights = CmaWeightsFromJson(document.model_config.at("weights"), source);
  }
  // A policy solved on transitions estimated from flights (decision/cma_estimated_model.h) keeps their counts.
  if (document.model_config.contains("transition_counts")) {
    return BuildEstimatedCmaMdp(weights, CmaTransitionCountsFromJson(document.model_config.at("transition_counts"),
                                                                     source + ": model_config.transition_counts"));
  }
  return BuildCmaMdp(weights);
}

Policy LoadCmaPolicy(const std::filesystem::path& path, const std::string& weights_file,
                     std::vector<std::vector<ActionIndex>>* ranking) {
  const PolicyDocument document = ReadPolicyFile(path);
  const FiniteMdp mdp = CmaModelForPolicy(document, weights_file, path.string());
  Policy bound = BindPolicy(document, mdp, path.string());
  if (ranking != nullptr) *ranking = RankActionsByQ(mdp, document.gamma, bound.value, &bound.action);
  return bound;
}

Policy SolveDefaultCmaPolicy(std::vector<std::vector<ActionIndex>>* ranking) {
  const CmaConfig config;
  ValueIterationOptions options;
  options.gamma = config.gamma;
  SolverSummary summary;
  const FiniteMdp mdp = BuildCmaMdp(config.weights);
  Policy solved = SolveValueIteration(mdp, options, &summary);
  UASCMA_CHECK(summary.status == SolverStatus::kConverged, "the CMA MDP must converge");
  if (ranking != nullptr) *ranking = RankActionsByQ(mdp, config.gamma, solved.value, &solved.action);
  return solved;
}

}  // namespace uascma::decision
