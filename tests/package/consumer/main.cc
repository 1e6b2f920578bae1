// Solves the CMA MDP through the installed library and prints the action of Fig. 5.13.
#include <cstdio>

#include "uascma/decision/cma_mdp.h"
#include "uascma/decision/solvers.h"

int main() {
  using namespace uascma::decision;
  const FiniteMdp mdp = BuildCmaMdp({});
  const Policy policy = SolveValueIteration(mdp, {});
  const StateIndex s = mdp.FindState("N,NF,MM0,G,RM0");
  std::printf("%s\n", mdp.action_name(policy.action[s]).c_str());
  return mdp.action_name(policy.action[s]) == "LandPract" ? 0 : 1;
}
