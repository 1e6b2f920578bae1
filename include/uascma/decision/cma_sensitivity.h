#pragma once
// The reward-weight sensitivity of the CMA policy (dissertation §5.3.2.5, Figs. 5.10-5.12): one weight swept over a
// range, the others renormalised to keep the sum at one (eq. 5.22, CmaWeights::WithRenormalised), the MDP re-solved by
// value iteration at each step, and the quadrant actions (Fig. 5.9) that differ from the base policy's listed.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "uascma/decision/cma_mdp.h"

namespace uascma::decision {

// One quadrant action that differs from the base policy's.
struct CmaPolicyChange {
  std::string state;     // the quadrant cell's CMA state label
  const char* quadrant;  // kQuadrantNames
  std::string from, to;  // action names: the base policy's, the swept one's
};

struct CmaSensitivityStep {
  double value = 0.0;  // the swept weight before renormalising
  CmaWeights weights;  // after
  std::vector<CmaPolicyChange> changes;
};

// Steps value = from + i · step for i = 0 … ⌊(to − from) / step + 1e-9⌋ (the 1e-9 keeps `to` when the range is a
// whole number of steps in decimal), each solved at `base.gamma`. Requires 0 ≤ from ≤ to ≤ 1, step > 0 and a known
// weight `name` (InputError from CmaWeights::Get otherwise).
std::vector<CmaSensitivityStep> SweepCmaWeight(const CmaConfig& base, const std::string& name, double from, double to,
                                               double step);

// The sweep of weight `name` from `base`: {"weight", "gamma", "base_weights", "steps": [{"value", "weights",
// "changes": [{"state", "quadrant", "from", "to"}, …]}, …]}.
nlohmann::json CmaSensitivityJson(const CmaConfig& base, const std::string& name,
                                  const std::vector<CmaSensitivityStep>& steps);
// The same as text: a heading naming the range from … to, then per step its value, its number of changes and each
// change (state, quadrant, base action -> swept action).
std::string CmaSensitivityText(const std::string& name, double from, double to,
                               const std::vector<CmaSensitivityStep>& steps);

}  // namespace uascma::decision
