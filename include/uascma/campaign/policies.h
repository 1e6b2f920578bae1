#pragma once
// The decision policies a campaign compares (§5.5.3: the CMA MDP policy against the NoOp baseline).
//
//   "cma"        the CMA MDP (decision/cma_mdp.h) with the dissertation's weights (eqs. 5.28–5.29) and
//                γ = 0.95, solved by value iteration when the campaign starts (decisions item 5)
//   "noop"       always NoOp (sim::NoOpPolicy)
//   FILE.json    a policy file written by `uascma policy solve` (decision/policy_file.h); its hash is
//                checked against the CMA model rebuilt from the weights it records. Named by the file
//                stem ("tuned.json" → "tuned").
//
// A CampaignPolicy is plain data (the action of every CMA state), so it is stored with the results and
// a run replays without the original file.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "uascma/decision/finite_mdp.h"
#include "uascma/sim/simulator.h"

namespace uascma::campaign {

struct CampaignPolicy {
  std::string name;    // unique within a campaign: "cma", "noop", a file stem
  std::string kind;    // "noop" | "table"
  std::string source;  // "cma default weights", "noop", or the file it came from
  std::vector<decision::ActionIndex> actions;  // kind "table": the action of each CMA state (112)
  std::string hash;    // 16 hex digits: fingerprint of the kind and the actions
};

CampaignPolicy NoOpCampaignPolicy();
// The CMA MDP with default weights solved by value iteration (decision/solvers.h).
CampaignPolicy SolvedCmaPolicy();
// A policy file; InputError names the file and field when it does not bind to the CMA model.
CampaignPolicy PolicyFromFile(const std::string& path);
// A policy from its stored form (results store); InputError names `source` when malformed.
CampaignPolicy MakeStoredPolicy(const std::string& name, const std::string& kind, const std::string& source,
                                const std::vector<std::string>& action_names, const std::string& where);
// The action names of a table policy, per state (what the store keeps).
std::vector<std::string> PolicyActionNames(const CampaignPolicy& policy);

// "cma", "noop" or a path per entry; duplicate names are an error naming `source` (e.g. "--policies").
std::vector<CampaignPolicy> ResolvePolicies(const std::vector<std::string>& specs, const std::string& source);

// A fresh decision module for one flight (policies keep no state across flights, but a new one per
// flight keeps the threads apart).
std::unique_ptr<sim::DecisionPolicy> MakeDecisionPolicy(const CampaignPolicy& policy);

// 16 hex digits over the names and hashes of the policies in order.
std::string PolicySetHash(const std::vector<CampaignPolicy>& policies);

}  // namespace uascma::campaign
