#include "uascma/sim/policy.h"

#include <filesystem>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/hash.h"
#include "uascma/decision/policy_file.h"

namespace uascma::sim {
namespace {

std::string HashOf(const std::string& kind, const std::vector<decision::ActionIndex>& actions) {
  Fingerprint f;
  f.Add(std::string_view(kind));
  f.Add(static_cast<std::uint64_t>(actions.size()));
  for (decision::ActionIndex a : actions) f.Add(static_cast<int>(a));
  return f.Hex();
}

PolicyDefinition TableDefinition(std::string name, std::string source, std::vector<decision::ActionIndex> actions) {
  PolicyDefinition policy;
  policy.name = std::move(name);
  policy.kind = "table";
  policy.source = std::move(source);
  policy.actions = std::move(actions);
  policy.hash = HashOf(policy.kind, policy.actions);
  return policy;
}

}  // namespace

TablePolicy::TablePolicy(std::vector<decision::ActionIndex> action_per_state, std::string name)
    : action_(std::move(action_per_state)), name_(std::move(name)) {
  if (static_cast<int>(action_.size()) < decision::kCmaNumTupleStates) {
    throw InputError("policy", "states", "an action for each of the 108 CMA states");
  }
}

decision::CmaAction TablePolicy::Decide(const DecisionInputs& inputs) {
  return static_cast<decision::CmaAction>(action_[decision::CmaStateIndex(inputs.state)]);
}

PolicyDefinition NoOpPolicyDefinition() {
  PolicyDefinition policy;
  policy.name = "noop";
  policy.kind = "noop";
  policy.source = "noop";
  policy.hash = HashOf(policy.kind, policy.actions);
  return policy;
}

PolicyDefinition SolvedCmaPolicyDefinition() {
  return TableDefinition("cma", "cma default weights", decision::SolveDefaultCmaPolicy().action);
}

PolicyDefinition PolicyDefinitionFromFile(const std::string& path) {
  decision::Policy bound = decision::LoadCmaPolicy(path);  // the model hash is checked
  return TableDefinition(std::filesystem::path(path).stem().string(), path, std::move(bound.action));
}

PolicyDefinition ResolvePolicy(const std::string& spec, const std::string& source, const std::string& field) {
  if (spec == "noop") return NoOpPolicyDefinition();
  if (spec == "cma") return SolvedCmaPolicyDefinition();
  if (std::filesystem::path(spec).extension() != ".json") {
    throw InputError(source, field, "noop, cma or a policy JSON file (*.json), got '" + spec + "'");
  }
  return PolicyDefinitionFromFile(spec);  // names the file when it is missing or does not bind
}

PolicyDefinition MakeStoredPolicy(const std::string& name, const std::string& kind, const std::string& source,
                                  const std::vector<std::string>& action_names, const std::string& where) {
  if (kind == "noop") {
    PolicyDefinition policy = NoOpPolicyDefinition();
    policy.name = name;
    policy.source = source;
    return policy;
  }
  if (kind != "table") throw InputError(where, "kind", "'noop' or 'table', got '" + kind + "'");
  if (static_cast<int>(action_names.size()) != decision::kCmaNumStates) {
    throw InputError(where, "actions", fmt::format("{} actions, one per CMA state", decision::kCmaNumStates));
  }
  std::vector<decision::ActionIndex> actions;
  for (const std::string& action : action_names) {
    actions.push_back(static_cast<decision::ActionIndex>(decision::ParseCmaAction(action, where)));
  }
  return TableDefinition(name, source, std::move(actions));
}

std::vector<std::string> PolicyActionNames(const PolicyDefinition& policy) {
  std::vector<std::string> names;
  for (decision::ActionIndex a : policy.actions) {
    names.emplace_back(decision::CmaActionName(static_cast<decision::CmaAction>(a)));
  }
  return names;
}

std::unique_ptr<DecisionPolicy> MakeDecisionPolicy(const PolicyDefinition& policy) {
  if (policy.kind == "noop") return std::make_unique<NoOpPolicy>();
  return std::make_unique<TablePolicy>(policy.actions, policy.name);
}

std::unique_ptr<DecisionPolicy> MakePolicy(const std::string& spec, const std::string& source) {
  return MakeDecisionPolicy(ResolvePolicy(spec, source));
}

}  // namespace uascma::sim
