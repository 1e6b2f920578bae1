#pragma once
// Random sparse MDPs for solver tests and benchmarks: every state has `num_actions` actions, each
// with `successors` distinct next states drawn uniformly (probabilities from normalised uniform
// draws) and a reward uniform in [-1, 1]. The same seed gives the same MDP on every platform
// (RandomStream of common/random.h, no standard-library distributions).
#include <cstdint>

#include "uascma/decision/finite_mdp.h"

namespace uascma::decision {

FiniteMdp MakeRandomMdp(int num_states, int num_actions, int successors, std::uint64_t seed);

}  // namespace uascma::decision
