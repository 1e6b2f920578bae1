#pragma once
// The decision policies a campaign compares (§5.5.3: the CMA MDP policy against the NoOp baseline). A policy is
// resolved by the simulator's one resolver (sim/policy.h: "cma", "noop" or a policy JSON file) into plain data,
// stored with the results so a run replays without the original file. The names below are the campaign's
// spelling of the same functions.
#include <string>
#include <vector>

#include "uascma/sim/policy.h"

namespace uascma::campaign {

using CampaignPolicy = sim::PolicyDefinition;
using sim::MakeDecisionPolicy;
using sim::MakeStoredPolicy;
using sim::PolicyActionNames;

inline CampaignPolicy NoOpCampaignPolicy() { return sim::NoOpPolicyDefinition(); }
inline CampaignPolicy SolvedCmaPolicy() { return sim::SolvedCmaPolicyDefinition(); }
inline CampaignPolicy PolicyFromFile(const std::string& path) { return sim::PolicyDefinitionFromFile(path); }

// sim::ResolvePolicy per entry; an empty list or a duplicate name is an error naming `source` (e.g. "--policies").
std::vector<CampaignPolicy> ResolvePolicies(const std::vector<std::string>& specs, const std::string& source);

// 16 hex digits over the names and hashes of the policies in order.
std::string PolicySetHash(const std::vector<CampaignPolicy>& policies);

}  // namespace uascma::campaign
