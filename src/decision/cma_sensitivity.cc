// The CMA policy's reward-weight sensitivity (cma_sensitivity.h, §5.3.2.5).
#include "uascma/decision/cma_sensitivity.h"

#include <cmath>
#include <cstddef>
#include <utility>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/decision/cma_weights_json.h"
#include "uascma/decision/finite_mdp.h"
#include "uascma/decision/solvers.h"

namespace uascma::decision {
namespace {

Policy SolveAt(const FiniteMdp& mdp, double gamma) {
  ValueIterationOptions options;
  options.gamma = gamma;
  return SolveValueIteration(mdp, options, nullptr);
}

}  // namespace

std::vector<CmaSensitivityStep> SweepCmaWeight(const CmaConfig& base, const std::string& name, double from, double to,
                                               double step) {
  base.weights.Get(name);  // validates the name
  UASCMA_CHECK(from >= 0.0 && to <= 1.0 && from <= to && step > 0.0, "a sweep 0 <= from <= to <= 1, step > 0");
  const Policy base_policy = SolveAt(BuildCmaMdp(base.weights), base.gamma);
  const auto base_rows = CmaQuadrantView(base_policy.action, base_policy.value);
  std::vector<CmaSensitivityStep> steps;
  const int count = static_cast<int>(std::floor((to - from) / step + 1e-9)) + 1;
  for (int i = 0; i < count; ++i) {
    CmaSensitivityStep out;
    out.value = from + i * step;
    out.weights = base.weights.WithRenormalised(name, out.value);
    const FiniteMdp mdp = BuildCmaMdp(out.weights);
    const Policy solved = SolveAt(mdp, base.gamma);
    const auto rows = CmaQuadrantView(solved.action, solved.value);
    for (std::size_t r = 0; r < rows.size(); ++r) {
      for (int q = 0; q < 4; ++q) {
        const ActionIndex was = base_rows[r].quadrants[q].action;
        const ActionIndex is = rows[r].quadrants[q].action;
        if (was == is) continue;
        out.changes.push_back(
            {CmaStateLabel(rows[r].quadrants[q].state), kQuadrantNames[q], mdp.action_name(was), mdp.action_name(is)});
      }
    }
    steps.push_back(std::move(out));
  }
  return steps;
}

nlohmann::json CmaSensitivityJson(const CmaConfig& base, const std::string& name,
                                  const std::vector<CmaSensitivityStep>& steps) {
  nlohmann::json steps_json = nlohmann::json::array();
  for (const CmaSensitivityStep& step : steps) {
    nlohmann::json changes = nlohmann::json::array();
    for (const CmaPolicyChange& change : step.changes) {
      changes.push_back(
          {{"state", change.state}, {"quadrant", change.quadrant}, {"from", change.from}, {"to", change.to}});
    }
    steps_json.push_back({{"value", step.value}, {"weights", CmaWeightsJson(step.weights)}, {"changes", changes}});
  }
  return {
      {"weight", name}, {"gamma", base.gamma}, {"base_weights", CmaWeightsJson(base.weights)}, {"steps", steps_json}};
}

std::string CmaSensitivityText(const std::string& name, double from, double to,
                               const std::vector<CmaSensitivityStep>& steps) {
  std::string text = fmt::format(
      "Sweep of w_{} from {} to {} (others renormalised to sum 1 - w); changes "
      "against the base policy:\n",
      name, from, to);
  for (const CmaSensitivityStep& step : steps) {
    std::string listed;
    for (const CmaPolicyChange& change : step.changes) {
      listed += fmt::format("\n    {:<22} Quad {:<3} {} -> {}", change.state, change.quadrant, change.from, change.to);
    }
    text += fmt::format("  w_{} = {:.4f}: {} change{}{}\n", name, step.value, step.changes.size(),
                        step.changes.size() == 1 ? "" : "s", listed);
  }
  return text;
}

}  // namespace uascma::decision
