#pragma once
// Decision modules by name, for scenario files, the CLI and campaigns:
//   "noop"          the NoOp baseline;
//   "cma"           the CMA MDP solved with the dissertation's weights and γ = 0.95 (§5.3.2.5);
//   a file path     a policy JSON written by `uascma policy solve` (its model hash is checked).
#include <memory>
#include <string>

#include "uascma/sim/simulator.h"

namespace uascma::sim {

// Throws InputError naming `source` when the name is neither noop, cma nor a readable policy file.
std::unique_ptr<DecisionPolicy> MakePolicy(const std::string& spec, const std::string& source);

}  // namespace uascma::sim
