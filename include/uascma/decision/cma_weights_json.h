#pragma once
// The CMA reward weights (decision/cma_mdp.h, eqs. 5.28-5.29) as the JSON object stored in policy files
// (model_config.weights). Kept out of cma_mdp.h so that the MDP's header, which every simulator file
// includes, does not pull in the JSON library.
#include <string>

#include <nlohmann/json.hpp>

#include "uascma/decision/cma_mdp.h"

namespace uascma::decision {

// The weights as a JSON object {"C": …, …, "RM": …}, and back (InputError naming `source` and the missing
// or non-numeric weight, or one outside kCmaWeightBounds).
nlohmann::json CmaWeightsJson(const CmaWeights& weights);
CmaWeights CmaWeightsFromJson(const nlohmann::json& json, const std::string& source);

}  // namespace uascma::decision
