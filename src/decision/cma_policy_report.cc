// What `uascma policy` reports of the CMA MDP (cma_policy_report.h, §5.3.2).
#include "uascma/decision/cma_policy_report.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "uascma/decision/cma_estimated_model.h"
#include "uascma/decision/cma_vehicle_mdp.h"
#include "uascma/decision/cma_weights_json.h"

namespace uascma::decision {

std::string TransitionRowsTsv(const FiniteMdp& mdp, ActionIndex action) {
  std::string out;
  for (StateIndex s = 0; s < mdp.num_states(); ++s) {
    const std::int64_t c = mdp.FindChoice(s, action);
    if (c < 0) continue;
    const auto next = mdp.choice_next_states(c);
    const auto prob = mdp.choice_probabilities(c);
    for (std::size_t k = 0; k < next.size(); ++k) {
      out += fmt::format("{}\t{}\t{:.10g}\n", mdp.state_label(s), mdp.state_label(next[k]), prob[k]);
    }
  }
  return out;
}

// --- solving -------------------------------------------------------------------------------------------------------
namespace {

Policy SolveBy(const FiniteMdp& mdp, double gamma, CmaSolveMethod method, SolverSummary* summary) {
  if (method == CmaSolveMethod::kPolicyIteration) {
    PolicyIterationOptions options;
    options.gamma = gamma;
    return SolvePolicyIteration(mdp, options, summary);
  }
  ValueIterationOptions options;
  options.gamma = gamma;
  return SolveValueIteration(mdp, options, summary);
}

}  // namespace

CmaSolution SolveCma(const CmaConfig& config, CmaSolveMethod method, const std::string& transitions_file) {
  CmaSolution solution;
  solution.mdp = BuildCmaMdp(config.weights);
  solution.gamma = config.gamma;
  solution.method = method;
  solution.model_config = {{"weights", CmaWeightsJson(config.weights)}};
  if (!transitions_file.empty()) {
    const CmaTransitionCounts counts = ReadCmaTransitionsFile(transitions_file);
    solution.mdp = BuildEstimatedCmaMdp(config.weights, counts);
    solution.model_config["transition_counts"] = CmaTransitionCountsToJson(counts);
    solution.model_config["transitions_file"] = transitions_file;
  }
  solution.policy = SolveBy(solution.mdp, config.gamma, method, &solution.summary);
  return solution;
}

std::string CmaPolicyTsv(const CmaSolution& solution) {
  std::string content;
  for (StateIndex s = 0; s < kCmaNumTupleStates; ++s) {
    content += fmt::format("{}\t{}\t{:.10g}\n", solution.mdp.state_label(s),
                           solution.mdp.action_name(solution.policy.action[s]), solution.policy.value[s]);
  }
  return content;
}

std::string CmaPolicyFileJson(const CmaSolution& solution) {
  const PolicyDocument document =
      MakePolicyDocument(solution.mdp, solution.policy, "cma", solution.gamma, solution.model_config, solution.summary,
                         solution.method == CmaSolveMethod::kPolicyIteration ? "policy_iteration" : "value_iteration");
  return PolicyToJson(document).dump(2) + "\n";
}

nlohmann::json CmaSolveSummaryJson(const CmaSolution& solution, const std::string& out) {
  return {{"out", out},
          {"model_hash", ModelHash(solution.mdp)},
          {"gamma", solution.gamma},
          {"status", solution.summary.status == SolverStatus::kConverged ? "converged" : "max_iterations"},
          {"iterations", solution.summary.iterations},
          {"residual", solution.summary.residual},
          {"wall_time_s", solution.summary.wall_time_s}};
}

std::string CmaSolveSummaryText(const CmaSolution& solution, const std::string& out) {
  const StateIndex start = CmaStateIndex({});
  return fmt::format("solved CMA MDP ({} states, gamma {:g}): {}\nwrote {}; action at {}: {}\n",
                     solution.mdp.num_states(), solution.gamma, solution.summary.BriefReport(), out,
                     solution.mdp.state_label(start), solution.mdp.action_name(solution.policy.action[start]));
}

// --- the quadrant view ---------------------------------------------------------------------------------------------
CmaPolicyView LoadCmaPolicyView(const std::string& policy, const std::string& weights_file) {
  if (policy == kCmaVehiclePolicyName) {
    CmaPolicyView view;
    view.mdp = BuildCmaVehicleMdp(CmaWeights{});
    view.policy = SolveCmaVehiclePolicy();
    view.document.model_hash = ModelHash(view.mdp);
    view.document.gamma = CmaConfig{}.gamma;
    view.rows = CmaQuadrantView(view.policy.action, view.policy.value);
    return view;
  }
  CmaPolicyView view;
  view.document = ReadPolicyFile(policy);
  view.mdp = CmaModelForPolicy(view.document, weights_file, policy);
  view.policy = BindPolicy(view.document, view.mdp, policy);
  view.rows = CmaQuadrantView(view.policy.action, view.policy.value);
  return view;
}

nlohmann::json CmaPolicyViewJson(const CmaPolicyView& view) {
  nlohmann::json json = {
      {"model_hash", view.document.model_hash}, {"gamma", view.document.gamma}, {"rows", nlohmann::json::array()}};
  for (const QuadrantRow& row : view.rows) {
    nlohmann::json quadrants = nlohmann::json::object();
    for (int q = 0; q < 4; ++q) {
      quadrants[kQuadrantNames[q]] = {{"state", CmaStateLabel(row.quadrants[q].state)},
                                      {"action", view.mdp.action_name(row.quadrants[q].action)},
                                      {"value", row.quadrants[q].value}};
    }
    json["rows"].push_back(quadrants);
  }
  return json;
}

std::string CmaPolicyViewText(const CmaPolicyView& view, const std::string& source) {
  std::string out =
      fmt::format("CMA policy {} (model {}, gamma {:g})\n\n", source, view.document.model_hash, view.document.gamma);
  out += fmt::format("{:<8} {:<3} {:<3} | {:<10} {:<10} {:<10} {:<10}\n", "FS", "MH", "BH", "I safe", "II hazard",
                     "III hyper", "IV crit");
  out += fmt::format("{:<8} {:<3} {:<3} | {:<10} {:<10} {:<10} {:<10}\n", "", "", "", "RM1,MM1", "RM1,MM0", "RM0,MM0",
                     "RM0,MM1");
  out += std::string(61, '-') + "\n";
  FlightStatus previous = view.rows.front().fs;
  for (const QuadrantRow& row : view.rows) {
    if (row.fs != previous) out += "\n";
    previous = row.fs;
    out +=
        fmt::format("{:<8} {:<3} {:<3} |", CmaFeatureValueName(0, static_cast<int>(row.fs)),
                    CmaFeatureValueName(1, static_cast<int>(row.mh)), CmaFeatureValueName(3, static_cast<int>(row.bh)));
    for (const QuadrantCell& cell : row.quadrants) {
      out += fmt::format(" {:<10}", view.mdp.action_name(cell.action));
    }
    out += "\n";
  }
  return out;
}

}  // namespace uascma::decision
