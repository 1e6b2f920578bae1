// uascma policy — inspect, solve, show and tune the contingency-management MDP (dissertation §5.3.2).
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "bounded_option.h"
#include "commands.h"
#include "output.h"
#include "plotting.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/decision/cma_estimated_model.h"
#include "uascma/decision/cma_mdp.h"
#include "uascma/decision/cma_sensitivity.h"
#include "uascma/decision/cma_vehicle_mdp.h"
#include "uascma/decision/cma_weights_json.h"
#include "uascma/decision/policy_file.h"
#include "uascma/decision/solvers.h"

namespace uascma::cli {
namespace {

using namespace uascma::decision;

struct ModelOptions {
  std::string model = "cma";
  std::string weights_file;
  double gamma = std::nan("");
};

void AddModelOptions(CLI::App* command, ModelOptions& options, bool with_gamma) {
  command->add_option("--model", options.model, "Model to use (only 'cma', dissertation §5.3.2)")
      ->check(CLI::IsMember({"cma"}));
  command->add_option("--weights", options.weights_file,
                      "YAML file of reward weights and gamma (default: eqs. 5.28-5.29, gamma 0.95)");
  if (with_gamma) {
    AddBoundedOption(command, "--gamma", options.gamma, "Discount factor (overrides the file)", kGammaBounds);
  }
}

CmaConfig ResolveConfig(const ModelOptions& options) {
  CmaConfig config = options.weights_file.empty() ? CmaConfig{} : LoadCmaConfig(options.weights_file);
  if (!std::isnan(options.gamma)) {
    RequireWithin(options.gamma, kGammaBounds, "--gamma", "value");
    config.gamma = options.gamma;
  }
  return config;
}

Policy Solve(const FiniteMdp& mdp, double gamma, const std::string& method, SolverSummary* summary) {
  if (method == "pi") {
    PolicyIterationOptions options;
    options.gamma = gamma;
    return SolvePolicyIteration(mdp, options, summary);
  }
  ValueIterationOptions options;
  options.gamma = gamma;
  return SolveValueIteration(mdp, options, summary);
}

// --- policy transitions ------------------------------------------------------------------------
void AddTransitions(CLI::App* policy) {
  auto options = std::make_shared<ModelOptions>();
  auto action = std::make_shared<std::string>();
  CLI::App* command = policy->add_subcommand(
      "transitions",
      "Print the composed transition rows of one action as TSV: state, next_state, probability\n"
      "(every available row, the terminal states C, T, FL, E included; Tables 5.1-5.7, eqs. 5.16-5.19)");
  AddModelOptions(command, *options, false);
  command->add_option("--action", *action, "NoOp | Terminate | LandASAP | LandPract")->required();
  command->callback([options, action] {
    const CmaAction parsed = ParseCmaAction(*action, "--action");
    const FiniteMdp mdp = BuildCmaMdp(ResolveConfig(*options).weights);
    const ActionIndex a = static_cast<ActionIndex>(parsed);
    std::string out;
    for (StateIndex s = 0; s < mdp.num_states(); ++s) {
      const std::int64_t c = mdp.FindChoice(s, a);
      if (c < 0) continue;
      const auto next = mdp.choice_next_states(c);
      const auto prob = mdp.choice_probabilities(c);
      for (std::size_t k = 0; k < next.size(); ++k) {
        out += fmt::format("{}\t{}\t{:.10g}\n", mdp.state_label(s), mdp.state_label(next[k]), prob[k]);
      }
    }
    WriteOutput("", out);
  });
}

// --- policy solve ------------------------------------------------------------------------------
void AddPolicySolve(CLI::App* policy) {
  struct Options {
    ModelOptions model;
    std::string out;
    std::string format = "json";
    std::string method = "vi";
    std::string transitions;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = policy->add_subcommand(
      "solve",
      "Solve the CMA MDP (value iteration to a Bellman residual below 1e-10, or policy iteration)\n"
      "and write the policy: JSON (with the model hash) or TSV state, action, value for the 108\n"
      "non-terminal states");
  AddModelOptions(command, options->model, true);
  command->add_option("--out", options->out, "Write the policy here (default: standard output)");
  command->add_option("--format", options->format, "json | tsv")->check(CLI::IsMember({"json", "tsv"}));
  command->add_option("--method", options->method, "vi (value iteration) | pi (policy iteration)")
      ->check(CLI::IsMember({"vi", "pi"}));
  command->add_option("--transitions", options->transitions,
                      "Transitions JSON from 'uascma learn transitions': solve on the rows estimated from\n"
                      "flights (unobserved rows keep the DDN's); the counts are kept in the policy file");
  command->add_flag("--json", options->json, "With --out: print the solver summary as JSON");
  command->callback([options] {
    const CmaConfig config = ResolveConfig(options->model);
    nlohmann::json model_config = {{"weights", CmaWeightsJson(config.weights)}};
    FiniteMdp mdp = BuildCmaMdp(config.weights);
    if (!options->transitions.empty()) {
      const CmaTransitionCounts counts = ReadCmaTransitionsFile(options->transitions);
      mdp = BuildEstimatedCmaMdp(config.weights, counts);
      model_config["transition_counts"] = CmaTransitionCountsToJson(counts);
      model_config["transitions_file"] = options->transitions;
    }
    SolverSummary summary;
    const Policy policy = Solve(mdp, config.gamma, options->method, &summary);
    std::string content;
    if (options->format == "tsv") {
      for (StateIndex s = 0; s < kCmaNumTupleStates; ++s) {
        content +=
            fmt::format("{}\t{}\t{:.10g}\n", mdp.state_label(s), mdp.action_name(policy.action[s]), policy.value[s]);
      }
    } else {
      const PolicyDocument document =
          MakePolicyDocument(mdp, policy, "cma", config.gamma, model_config, summary,
                             options->method == "pi" ? "policy_iteration" : "value_iteration");
      content = PolicyToJson(document).dump(2) + "\n";
    }
    WriteOutput(options->out, content);
    if (options->out.empty() || options->out == "-") return;
    const StateIndex start = CmaStateIndex({});
    if (options->json) {
      PrintJson({{"out", options->out},
                 {"model_hash", ModelHash(mdp)},
                 {"gamma", config.gamma},
                 {"status", summary.status == SolverStatus::kConverged ? "converged" : "max_iterations"},
                 {"iterations", summary.iterations},
                 {"residual", summary.residual},
                 {"wall_time_s", summary.wall_time_s}});
    } else {
      std::printf("solved CMA MDP (%d states, gamma %g): %s\nwrote %s; action at %s: %s\n", mdp.num_states(),
                  config.gamma, summary.BriefReport().c_str(), options->out.c_str(), mdp.state_label(start).c_str(),
                  mdp.action_name(policy.action[start]).c_str());
    }
  });
}

// --- policy show -------------------------------------------------------------------------------
std::string QuadrantTable(const std::vector<QuadrantRow>& rows, const FiniteMdp& mdp) {
  std::string out = fmt::format("{:<8} {:<3} {:<3} | {:<10} {:<10} {:<10} {:<10}\n", "FS", "MH", "BH", "I safe",
                                "II hazard", "III hyper", "IV crit");
  out += fmt::format("{:<8} {:<3} {:<3} | {:<10} {:<10} {:<10} {:<10}\n", "", "", "", "RM1,MM1", "RM1,MM0", "RM0,MM0",
                     "RM0,MM1");
  out += std::string(61, '-') + "\n";
  const char* fs_names[] = {"N", "ELASAP", "ELPRACT"};
  const char* mh_names[] = {"NF", "SF", "JF"};
  const char* bh_names[] = {"G", "M", "P"};
  FlightStatus previous = rows.front().fs;
  for (const QuadrantRow& row : rows) {
    if (row.fs != previous) out += "\n";
    previous = row.fs;
    out += fmt::format("{:<8} {:<3} {:<3} |", fs_names[static_cast<int>(row.fs)], mh_names[static_cast<int>(row.mh)],
                       bh_names[static_cast<int>(row.bh)]);
    for (const QuadrantCell& cell : row.quadrants) {
      out += fmt::format(" {:<10}", mdp.action_name(cell.action));
    }
    out += "\n";
  }
  return out;
}

void AddPolicyShow(CLI::App* policy) {
  auto file = std::make_shared<std::string>();
  auto weights_file = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  auto plot = std::make_shared<std::string>();
  CLI::App* command = policy->add_subcommand(
      "show",
      "Show a CMA policy file in the quadrant view of Fig. 5.9: rows by FS, MH, BH; columns by the\n"
      "RM x MM quadrants (I safe, II hazardous, III hyper-critical, IV critical). The file's model\n"
      "hash is checked against the model rebuilt from its weights (or --weights). 'cma-vehicle' shows the\n"
      "vehicle-level motor margin's model solved with the default weights (docs/cma-vehicle.md)");
  command->add_option("policy", *file, "Policy JSON written by 'uascma policy solve', or cma-vehicle")->required();
  command->add_option("--weights", *weights_file, "Check the policy against the model of these weights");
  command->add_flag("--json", *json, "Print the quadrant view as JSON");
  command->add_option("--plot", *plot, "Also draw the quadrant view to this PNG file");
  command->callback([file, weights_file, json, plot] {
    const bool vehicle = *file == "cma-vehicle";
    if (vehicle && !weights_file->empty())
      throw InputError("--weights", "--weights", "a policy file (not cma-vehicle)");
    PolicyDocument document;
    if (vehicle) {
      document.model_hash = ModelHash(BuildCmaVehicleMdp(CmaWeights{}));
      document.gamma = CmaConfig{}.gamma;
    } else {
      document = ReadPolicyFile(*file);
    }
    const FiniteMdp mdp =
        vehicle ? BuildCmaVehicleMdp(CmaWeights{}) : CmaModelForPolicy(document, *weights_file, *file);
    const Policy policy = vehicle ? SolveCmaVehiclePolicy() : BindPolicy(document, mdp, *file);
    const auto rows = CmaQuadrantView(policy.action, policy.value);
    nlohmann::json view = {
        {"model_hash", document.model_hash}, {"gamma", document.gamma}, {"rows", nlohmann::json::array()}};
    for (const QuadrantRow& row : rows) {
      nlohmann::json quadrants = nlohmann::json::object();
      for (int q = 0; q < 4; ++q) {
        quadrants[kQuadrantNames[q]] = {{"state", CmaStateLabel(row.quadrants[q].state)},
                                        {"action", mdp.action_name(row.quadrants[q].action)},
                                        {"value", row.quadrants[q].value}};
      }
      view["rows"].push_back(quadrants);
    }
    if (!plot->empty()) {
      PlotJson("policy_quadrants.py", view, *plot);
    }
    if (*json) {
      PrintJson(view);
      return;
    }
    std::printf("CMA policy %s (model %s, gamma %g)\n\n%s", file->c_str(), document.model_hash.c_str(), document.gamma,
                QuadrantTable(rows, mdp).c_str());
  });
}

// --- policy sensitivity ------------------------------------------------------------------------
// Our bound: a step of 1e-4 re-solves the MDP at most 10^4 + 1 times (~0.1 s).
constexpr Bounds kSensitivityStepBounds{1e-4, 1.0, ""};

void AddSensitivity(CLI::App* policy) {
  struct Options {
    ModelOptions model;
    std::string weight;
    double from = 0.0, to = 0.0, step = 0.0;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = policy->add_subcommand(
      "sensitivity",
      "Sweep one reward weight, renormalising the others to keep the sum at one (Fig. 5.10), re-solve\n"
      "at each step and report which quadrant actions differ from the base policy (Figs. 5.11-5.12)");
  AddModelOptions(command, options->model, true);
  command
      ->add_option("--weight", options->weight,
                   "Weight to sweep: C FL T E NoOp Terminate LandASAP LandPract FS MH MM BH RM")
      ->required();
  AddBoundedOption(command, "--from", options->from, "First value", kCmaWeightBounds)->required();
  AddBoundedOption(command, "--to", options->to, "Last value (>= --from)", kCmaWeightBounds)->required();
  AddBoundedOption(command, "--step", options->step, "Step", kSensitivityStepBounds)->required();
  command->add_flag("--json", options->json, "Print the sweep as JSON");
  command->callback([options] {
    const CmaConfig base = ResolveConfig(options->model);
    base.weights.Get(options->weight);  // validates the name
    RequireWithin(options->step, kSensitivityStepBounds, "--step", "value");
    if (!(options->from >= 0.0 && options->to <= 1.0 && options->from <= options->to)) {
      throw InputError("--from/--to", "range", "0 <= from <= to <= 1");
    }
    nlohmann::json steps = nlohmann::json::array();
    std::string text = fmt::format(
        "Sweep of w_{} from {} to {} (others renormalised to sum 1 - w); changes "
        "against the base policy:\n",
        options->weight, options->from, options->to);
    for (const CmaSensitivityStep& step :
         SweepCmaWeight(base, options->weight, options->from, options->to, options->step)) {
      nlohmann::json changes = nlohmann::json::array();
      std::string listed;
      for (const CmaPolicyChange& change : step.changes) {
        changes.push_back(
            {{"state", change.state}, {"quadrant", change.quadrant}, {"from", change.from}, {"to", change.to}});
        listed +=
            fmt::format("\n    {:<22} Quad {:<3} {} -> {}", change.state, change.quadrant, change.from, change.to);
      }
      steps.push_back({{"value", step.value}, {"weights", CmaWeightsJson(step.weights)}, {"changes", changes}});
      text += fmt::format("  w_{} = {:.4f}: {} change{}{}\n", options->weight, step.value, changes.size(),
                          changes.size() == 1 ? "" : "s", listed);
    }
    if (options->json) {
      PrintJson({{"weight", options->weight},
                 {"gamma", base.gamma},
                 {"base_weights", CmaWeightsJson(base.weights)},
                 {"steps", steps}});
    } else {
      std::fputs(text.c_str(), stdout);
    }
  });
}

}  // namespace

void AddPolicyCommand(CLI::App& app) {
  CLI::App* policy =
      app.add_subcommand("policy", "The contingency-management MDP (§5.3.2): transitions, solve, show, sensitivity");
  policy->require_subcommand(1);
  AddTransitions(policy);
  AddPolicySolve(policy);
  AddPolicyShow(policy);
  AddSensitivity(policy);
}

}  // namespace uascma::cli
