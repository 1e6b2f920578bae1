#include "uascma/campaign/policies.h"

#include <set>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/hash.h"
#include "uascma/decision/cma_mdp.h"
#include "uascma/decision/policy_file.h"

namespace uascma::campaign {
namespace {

std::string HashOf(const std::string& kind, const std::vector<decision::ActionIndex>& actions) {
  Fingerprint f;
  f.Add(std::string_view(kind));
  f.Add(static_cast<std::uint64_t>(actions.size()));
  for (decision::ActionIndex a : actions) f.Add(static_cast<int>(a));
  return f.Hex();
}

CampaignPolicy TablePolicyOf(std::string name, std::string source, std::vector<decision::ActionIndex> actions) {
  CampaignPolicy policy;
  policy.name = std::move(name);
  policy.kind = "table";
  policy.source = std::move(source);
  policy.actions = std::move(actions);
  policy.hash = HashOf(policy.kind, policy.actions);
  return policy;
}

}  // namespace

CampaignPolicy NoOpCampaignPolicy() {
  CampaignPolicy policy;
  policy.name = "noop";
  policy.kind = "noop";
  policy.source = "noop";
  policy.hash = HashOf(policy.kind, policy.actions);
  return policy;
}

CampaignPolicy SolvedCmaPolicy() {
  return TablePolicyOf("cma", "cma default weights", decision::SolveDefaultCmaPolicy().action);
}

CampaignPolicy PolicyFromFile(const std::string& path) {
  decision::Policy bound = decision::LoadCmaPolicy(path);  // the model hash is checked
  std::string name = std::filesystem::path(path).stem().string();
  return TablePolicyOf(std::move(name), path, std::move(bound.action));
}

CampaignPolicy MakeStoredPolicy(const std::string& name, const std::string& kind, const std::string& source,
                                const std::vector<std::string>& action_names, const std::string& where) {
  if (kind == "noop") {
    CampaignPolicy policy = NoOpCampaignPolicy();
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
  return TablePolicyOf(name, source, std::move(actions));
}

std::vector<std::string> PolicyActionNames(const CampaignPolicy& policy) {
  std::vector<std::string> names;
  for (decision::ActionIndex a : policy.actions) {
    names.emplace_back(decision::CmaActionName(static_cast<decision::CmaAction>(a)));
  }
  return names;
}

std::vector<CampaignPolicy> ResolvePolicies(const std::vector<std::string>& specs, const std::string& source) {
  if (specs.empty()) throw InputError(source, "policies", "at least one of cma, noop or a policy JSON file");
  std::vector<CampaignPolicy> policies;
  std::set<std::string> names;
  for (const std::string& spec : specs) {
    CampaignPolicy policy;
    if (spec == "cma") {
      policy = SolvedCmaPolicy();
    } else if (spec == "noop") {
      policy = NoOpCampaignPolicy();
    } else if (std::filesystem::path(spec).extension() == ".json") {
      policy = PolicyFromFile(spec);
    } else {
      throw InputError(source, "policies", "cma, noop or a policy JSON file (*.json), got '" + spec + "'");
    }
    if (!names.insert(policy.name).second) {
      throw InputError(source, "policies", "each policy name once, got '" + policy.name + "' twice");
    }
    policies.push_back(std::move(policy));
  }
  return policies;
}

std::unique_ptr<sim::DecisionPolicy> MakeDecisionPolicy(const CampaignPolicy& policy) {
  if (policy.kind == "noop") return std::make_unique<sim::NoOpPolicy>();
  return std::make_unique<sim::TablePolicy>(policy.actions, policy.name);
}

std::string PolicySetHash(const std::vector<CampaignPolicy>& policies) {
  Fingerprint f;
  for (const CampaignPolicy& policy : policies) {
    f.Add(std::string_view(policy.name));
    f.Add(std::string_view(policy.hash));
  }
  return f.Hex();
}

}  // namespace uascma::campaign
