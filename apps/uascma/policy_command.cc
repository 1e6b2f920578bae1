// uascma policy — inspect, solve, show and tune the contingency-management MDP (dissertation §5.3.2).
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "bounded_option.h"
#include "commands.h"
#include "output.h"
#include "plotting.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/decision/cma_mdp.h"
#include "uascma/decision/cma_policy_report.h"
#include "uascma/decision/cma_sensitivity.h"

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
    WriteOutput("", TransitionRowsTsv(mdp, static_cast<ActionIndex>(parsed)));
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
    const CmaSolution solution =
        SolveCma(ResolveConfig(options->model),
                 options->method == "pi" ? CmaSolveMethod::kPolicyIteration : CmaSolveMethod::kValueIteration,
                 options->transitions);
    WriteOutput(options->out, options->format == "tsv" ? CmaPolicyTsv(solution) : CmaPolicyFileJson(solution));
    if (options->out.empty() || options->out == "-") return;
    if (options->json) {
      PrintJson(CmaSolveSummaryJson(solution, options->out));
    } else {
      std::fputs(CmaSolveSummaryText(solution, options->out).c_str(), stdout);
    }
  });
}

// --- policy show -------------------------------------------------------------------------------
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
    if (*file == kCmaVehiclePolicyName && !weights_file->empty())
      throw InputError("--weights", "--weights", "a policy file (not cma-vehicle)");
    const CmaPolicyView view = LoadCmaPolicyView(*file, *weights_file);
    const nlohmann::json view_json = CmaPolicyViewJson(view);
    if (!plot->empty()) {
      PlotJson("policy_quadrants.py", view_json, *plot);
    }
    if (*json) {
      PrintJson(view_json);
      return;
    }
    std::fputs(CmaPolicyViewText(view, *file).c_str(), stdout);
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
    const std::vector<CmaSensitivityStep> steps =
        SweepCmaWeight(base, options->weight, options->from, options->to, options->step);
    if (options->json) {
      PrintJson(CmaSensitivityJson(base, options->weight, steps));
    } else {
      std::fputs(CmaSensitivityText(options->weight, options->from, options->to, steps).c_str(), stdout);
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
