#include "uascma/sim/policy.h"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "uascma/common/error.h"
#include "uascma/common/hash.h"
#include "uascma/common/text.h"
#include "uascma/decision/policy_file.h"
#include "uascma/sim/belief_policy.h"
#include "uascma/sim/vehicle_policy.h"
#include "uascma/decision/cma_vehicle_mdp.h"

namespace uascma::sim {
namespace {

using RankingTable = std::vector<std::vector<decision::ActionIndex>>;

// The ranking (and a stated risk level) enter the hash only when there is one, so a policy without one keeps the
// hash it always had.
std::string HashOf(const std::string& kind, const std::vector<decision::ActionIndex>& actions,
                   const RankingTable& ranking, double risk_level = std::numeric_limits<double>::quiet_NaN()) {
  Fingerprint f;
  f.Add(std::string_view(kind));
  f.Add(static_cast<std::uint64_t>(actions.size()));
  for (decision::ActionIndex a : actions) f.Add(static_cast<int>(a));
  if (!ranking.empty()) {
    f.Add(std::string_view("ranking"));
    for (const auto& order : ranking) {
      f.Add(static_cast<std::uint64_t>(order.size()));
      for (decision::ActionIndex a : order) f.Add(static_cast<int>(a));
    }
  }
  if (!std::isnan(risk_level)) {
    f.Add(std::string_view("risk_level"));
    f.Add(risk_level);
  }
  return f.Hex();
}

PolicyDefinition TableDefinition(std::string name, std::string source, std::vector<decision::ActionIndex> actions,
                                 RankingTable ranking) {
  PolicyDefinition policy;
  policy.name = std::move(name);
  policy.kind = "table";
  policy.source = std::move(source);
  policy.actions = std::move(actions);
  policy.ranking = std::move(ranking);
  policy.hash = HashOf(policy.kind, policy.actions, policy.ranking);
  return policy;
}

// A ranking must list, per state, distinct actions led by the state's own.
void CheckRanking(const std::vector<decision::ActionIndex>& actions, const RankingTable& ranking,
                  const std::string& where) {
  if (ranking.empty()) return;
  if (ranking.size() != actions.size()) {
    throw InputError(where, "actions", "one ranking per state");
  }
  for (std::size_t s = 0; s < ranking.size(); ++s) {
    const auto& order = ranking[s];
    std::vector<bool> seen(decision::kCmaNumActions, false);
    for (decision::ActionIndex a : order) {
      if (a < 0 || a >= decision::kCmaNumActions || seen[static_cast<std::size_t>(a)]) {
        throw InputError(where, fmt::format("actions[{}]", s), "distinct action names");
      }
      seen[static_cast<std::size_t>(a)] = true;
    }
    if (order.empty() || order.front() != actions[s]) {
      throw InputError(where, fmt::format("actions[{}]", s), "a ranking led by the state's action");
    }
  }
}

}  // namespace

const EodValue& DecisionInputs::eod_value() const {
  const EodValue* value = std::get_if<EodValue>(&eod);
  UASCMA_CHECK(value != nullptr, "the EOD's value read where the epoch held only its lower bound (CompleteEod)");
  return *value;
}

const EodDistributionSummary& DecisionInputs::eod_distribution_value() const {
  UASCMA_CHECK(eod_distribution.has_value(), "the EOD's distribution read at an epoch that did not compute it");
  return *eod_distribution;
}

ActionRanking DefaultCmaActionRanking(const decision::CmaState& state) {
  static const RankingTable ranking = SolvedCmaPolicyDefinition().ranking;  // solved once (thread-safe static)
  return ranking[static_cast<std::size_t>(decision::CmaStateIndex(state))];
}

TablePolicy::TablePolicy(std::vector<decision::ActionIndex> action_per_state, std::string name, RankingTable ranking)
    : action_(std::move(action_per_state)), name_(std::move(name)), ranking_(std::move(ranking)) {
  if (static_cast<int>(action_.size()) < decision::kCmaNumTupleStates) {
    throw InputError("policy", "states", "an action for each of the 108 CMA states");
  }
  CheckRanking(action_, ranking_, "policy " + name_);
}

decision::CmaAction TablePolicy::Decide(const DecisionInputs& inputs) {
  return static_cast<decision::CmaAction>(action_[decision::CmaStateIndex(inputs.state)]);
}

ActionRanking TablePolicy::Ranking(const DecisionInputs& inputs) const {
  if (ranking_.empty()) return DefaultCmaActionRanking(inputs.state);
  return ranking_[static_cast<std::size_t>(decision::CmaStateIndex(inputs.state))];
}

PolicyDefinition NoOpPolicyDefinition() {
  PolicyDefinition policy;
  policy.name = "noop";
  policy.kind = "noop";
  policy.source = "noop";
  policy.hash = HashOf(policy.kind, policy.actions, policy.ranking);
  return policy;
}

PolicyDefinition SolvedCmaPolicyDefinition() {
  RankingTable ranking;
  decision::Policy solved = decision::SolveDefaultCmaPolicy(&ranking);
  return TableDefinition("cma", "cma default weights", std::move(solved.action), std::move(ranking));
}

PolicyDefinition PolicyDefinitionFromFile(const std::string& path) {
  RankingTable ranking;
  decision::Policy bound = decision::LoadCmaPolicy(path, "", &ranking);  // the model hash is checked
  RequireUtf8(std::filesystem::path(path).stem().string(), EscapeInvalidUtf8(path),
              "name (the policy's name is the file's name)");
  return TableDefinition(std::filesystem::path(path).stem().string(), path, std::move(bound.action),
                         std::move(ranking));
}

PolicyDefinition VehicleCmaPolicyDefinition() {
  RankingTable ranking;
  decision::Policy solved = decision::SolveCmaVehiclePolicy(&ranking);
  PolicyDefinition policy = TableDefinition(kVehiclePolicyKind, "cma vehicle-level motor margin, default weights",
                                            std::move(solved.action), std::move(ranking));
  policy.kind = kVehiclePolicyKind;
  policy.hash = HashOf(policy.kind, policy.actions, policy.ranking);
  return policy;
}

// "cma-risk", "cma-risk@P" (name: the spec) or "cma-qmdp" over the default CMA policy's table; "cma-vehicle-risk",
// "cma-vehicle-risk@P" or "cma-vehicle-qmdp" over the vehicle-level policy's.
PolicyDefinition BeliefCmaPolicyDefinition(const std::string& name, const std::string& kind, double risk_level) {
  PolicyDefinition policy = IsVehicleBeliefPolicyKind(kind) ? VehicleCmaPolicyDefinition() : SolvedCmaPolicyDefinition();
  policy.name = name;
  policy.kind = kind;
  policy.risk_level = risk_level;
  policy.hash = HashOf(policy.kind, policy.actions, policy.ranking, policy.risk_level);
  return policy;
}

// The risk kind a "KIND@P" spec names ("cma-risk" or "cma-vehicle-risk"), "" for any other spec.
std::string StatedRiskKind(const std::string& spec) {
  for (const char* kind : {"cma-risk", "cma-vehicle-risk"}) {
    if (spec.starts_with(std::string(kind) + "@")) return kind;
  }
  return "";
}

std::optional<double> StatedRiskLevel(const std::string& spec, const std::string& source, const std::string& field) {
  const std::string kind = StatedRiskKind(spec);
  if (kind.empty()) return std::nullopt;
  const std::string text = spec.substr(kind.size() + 1);
  double level = std::numeric_limits<double>::quiet_NaN();
  const auto [end, status] = std::from_chars(text.data(), text.data() + text.size(), level);
  if (text.empty() || status != std::errc() || end != text.data() + text.size() || !(level >= 0.0 && level <= 1.0)) {
    throw InputError(source, field,
                     kind + "@P with P a probability from 0 to 1 (e.g. " + kind + "@0.1), got '" + spec + "'");
  }
  return level;
}

PolicyDefinition ResolvePolicy(const std::string& spec, const std::string& source, const std::string& field) {
  if (spec == "noop") return NoOpPolicyDefinition();
  if (spec == "cma") return SolvedCmaPolicyDefinition();
  if (spec == kVehiclePolicyKind) return VehicleCmaPolicyDefinition();
  if (IsBeliefPolicyKind(spec)) return BeliefCmaPolicyDefinition(spec, spec, std::numeric_limits<double>::quiet_NaN());
  if (const std::optional<double> level = StatedRiskLevel(spec, source, field)) {
    return BeliefCmaPolicyDefinition(spec, StatedRiskKind(spec), *level);
  }
  if (std::filesystem::path(spec).extension() != ".json") {
    throw InputError(source, field,
                     "noop, cma, cma-vehicle, cma-risk, cma-risk@P, cma-qmdp, cma-vehicle-risk, cma-vehicle-risk@P, "
                     "cma-vehicle-qmdp or a policy JSON file (*.json), got '" +
                         spec + "'");
  }
  return PolicyDefinitionFromFile(spec);  // names the file when it is missing or does not bind
}

PolicyDefinition MakeStoredPolicy(const std::string& name, const std::string& kind, const std::string& source,
                                  const std::string& actions_json, const std::string& where) {
  nlohmann::json stored;
  try {
    stored = nlohmann::json::parse(actions_json);
  } catch (const nlohmann::json::exception&) {
    throw InputError(where, "actions_json", "a JSON list of action names");
  }
  if (!stored.is_array()) throw InputError(where, "actions_json", "a JSON list of action names");
  if (kind == "noop") {
    PolicyDefinition policy = NoOpPolicyDefinition();
    policy.name = name;
    policy.source = source;
    return policy;
  }
  if (kind != "table" && kind != kVehiclePolicyKind && !IsBeliefPolicyKind(kind)) {
    throw InputError(where, "kind",
                     "'noop', 'table', 'cma-vehicle', 'cma-risk', 'cma-qmdp', 'cma-vehicle-risk' or "
                     "'cma-vehicle-qmdp', got '" + kind + "'");
  }
  if (static_cast<int>(stored.size()) != decision::kCmaNumStates) {
    throw InputError(where, "actions", fmt::format("{} actions, one per CMA state", decision::kCmaNumStates));
  }
  auto parse = [&](const nlohmann::json& entry) {
    if (!entry.is_string()) throw InputError(where, "actions_json", "action names (strings)");
    return static_cast<decision::ActionIndex>(decision::ParseCmaAction(entry.get<std::string>(), where));
  };
  std::vector<decision::ActionIndex> actions;
  RankingTable ranking;
  const bool ranked = !stored.empty() && stored.front().is_array();
  for (const nlohmann::json& entry : stored) {
    if (entry.is_array() != ranked) throw InputError(where, "actions_json", "entries all names or all rankings");
    if (!ranked) {
      actions.push_back(parse(entry));
      continue;
    }
    std::vector<decision::ActionIndex>& order = ranking.emplace_back();
    for (const nlohmann::json& a : entry) order.push_back(parse(a));
    if (order.empty()) throw InputError(where, "actions_json", "a non-empty ranking per state");
    actions.push_back(order.front());
  }
  CheckRanking(actions, ranking, where);
  PolicyDefinition policy = TableDefinition(name, source, std::move(actions), std::move(ranking));
  if (kind == kVehiclePolicyKind) {  // the vehicle-level model's table, read on the vehicle-level state
    policy.kind = kind;
    policy.hash = HashOf(policy.kind, policy.actions, policy.ranking);
  }
  if (IsBeliefPolicyKind(kind)) {  // the default (or vehicle-level) CMA policy's table, decided on beliefs
    policy.kind = kind;
    if (IsRiskPolicyKind(kind)) policy.risk_level = StatedRiskLevel(name, where, "name").value_or(policy.risk_level);
    policy.hash = HashOf(policy.kind, policy.actions, policy.ranking, policy.risk_level);
  }
  return policy;
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
  if (policy.kind == "cma-risk") return std::make_unique<RiskCmaPolicy>(policy.name, policy.risk_level);
  if (policy.kind == "cma-qmdp") return std::make_unique<QmdpCmaPolicy>(policy.name);
  if (policy.kind == "cma-vehicle-risk") {
    return std::make_unique<RiskCmaPolicy>(policy.name, policy.risk_level, BeliefAbstraction::kVehicle);
  }
  if (policy.kind == "cma-vehicle-qmdp") {
    return std::make_unique<QmdpCmaPolicy>(policy.name, BeliefAbstraction::kVehicle);
  }
  if (policy.kind == kVehiclePolicyKind) {
    return std::make_unique<VehicleCmaPolicy>(policy.actions, policy.name, policy.ranking);
  }
  return std::make_unique<TablePolicy>(policy.actions, policy.name, policy.ranking);
}

std::unique_ptr<DecisionPolicy> MakePolicy(const std::string& spec, const std::string& source) {
  return MakeDecisionPolicy(ResolvePolicy(spec, source));
}

std::string PolicyActionsJson(const PolicyDefinition& policy) {
  if (policy.ranking.empty()) return nlohmann::json(PolicyActionNames(policy)).dump();
  nlohmann::json stored = nlohmann::json::array();
  for (const auto& order : policy.ranking) {
    nlohmann::json names = nlohmann::json::array();
    for (decision::ActionIndex a : order) names.push_back(decision::CmaActionName(static_cast<decision::CmaAction>(a)));
    stored.push_back(std::move(names));
  }
  return stored.dump();
}

}  // namespace uascma::sim
