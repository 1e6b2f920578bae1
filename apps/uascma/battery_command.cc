// uascma battery — the battery-reconfiguration MDP of dissertation Ch. IV (§4.3): learn its transitions from
// Monte Carlo flights, solve one policy per health pair and temperature, show them, run the case studies.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <set>
#include <string>

#include <fmt/format.h>

#include "bounded_option.h"
#include "commands.h"
#include "output.h"
#include "plotting.h"
#include "uascma/campaign/battery_flights.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/common/progress.h"
#include "uascma/decision/battery_mdp.h"

namespace uascma::cli {
namespace {

using namespace uascma::decision;
using models::PackAction;

// Plausibility bounds of the numeric options (issue 16). Flights: §4.3.2 learns from 5,000; 10^7 is the
// campaign's bound on runs. Threads: our bound, far above any machine this runs on. Case studies: Table 4.5.
constexpr Bounds kFlightsBounds{1.0, 1e7, "flights"};
constexpr Bounds kThreadsBounds{1.0, 256.0, "threads"};
constexpr Bounds kCaseStudyBounds{1.0, 4.0, ""};

constexpr std::array<PackAction, 3> kActions = {PackAction::kUseBatt1, PackAction::kUseBatt2, PackAction::kUseBoth};

BatteryContext ParseContextOption(const std::string& text, const std::string& option) {
  const auto first = text.find(',');
  const auto second = first == std::string::npos ? std::string::npos : text.find(',', first + 1);
  if (second == std::string::npos) throw InputError(option, "value", fmt::format("B1F,B2F,T such as F3,F3,TL, got '{}'", text));
  return {ParseBatteryHealth(text.substr(0, first), option), ParseBatteryHealth(text.substr(first + 1, second - first - 1), option),
          ParseTemperatureClass(text.substr(second + 1), option)};
}

BatteryRewardWeights ParseWeightsOption(const std::string& text, const std::string& option) {
  BatteryRewardWeights weights;
  double* fields[3] = {&weights.w1, &weights.w2, &weights.w3};
  std::size_t begin = 0;
  for (int i = 0; i < 3; ++i) {
    const std::size_t end = i < 2 ? text.find(',', begin) : text.size();
    if (end == std::string::npos) throw InputError(option, "value", fmt::format("w1,w2,w3, got '{}'", text));
    try {
      std::size_t used = 0;
      *fields[i] = std::stod(text.substr(begin, end - begin), &used);
      if (used != end - begin) throw std::invalid_argument("trailing characters");
    } catch (const std::exception&) {
      throw InputError(option, fmt::format("w{}", i + 1), fmt::format("a number, got '{}'", text.substr(begin, end - begin)));
    }
    begin = end + 1;
  }
  if (text.find(',', begin > text.size() ? text.size() : begin) != std::string::npos) {
    throw InputError(option, "value", fmt::format("three weights w1,w2,w3, got '{}'", text));
  }
  std::string error;
  if (!weights.IsValid(&error)) throw InputError(option, "value", error);
  return weights;
}

// --- battery learn ---------------------------------------------------------------------------------
void AddLearn(CLI::App* battery) {
  struct Options {
    std::int64_t runs = 5000;
    std::uint64_t seed = 1;
    int jobs = 1;
    std::string out;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = battery->add_subcommand(
      "learn",
      "Fly Monte Carlo flights (Table 4.4; each flown with one action throughout, split equally between\n"
      "UseBatt1, UseBatt2 and UseBoth) and count the battery MDP's 1 Hz transitions per health pair and\n"
      "temperature (§4.3.2). A draw's three actions fly one vehicle while their packs cap the rotors alike\n"
      "(the same counts as flying each alone). Writes the model with its counts");
  AddBoundedOption(command, "--runs", options->runs, "Flights (§4.3.2: 5,000)", kFlightsBounds);
  AddSeedOption(command, "--seed", options->seed, "Seed; every flight replays from (seed, flight index)");
  AddBoundedOption(command, "--jobs", options->jobs, "Threads (the counts do not depend on it)", kThreadsBounds);
  command->add_option("--out", options->out, "Model JSON to write")->required();
  command->add_flag("--json", options->json, "Print the summary as JSON");
  command->callback([options] {
    RequireWithin(static_cast<double>(options->runs), kFlightsBounds, "--runs", "value");
    RequireWithin(options->jobs, kThreadsBounds, "--jobs", "value");
    ProgressBar bar(options->runs, "battery learn");
    campaign::BatteryLearningOptions learning;
    learning.runs = options->runs;
    learning.seed = options->seed;
    learning.jobs = options->jobs;
    learning.on_flight_done = [&bar](std::int64_t) { bar.Advance(); };
    campaign::BatteryLearningSummary summary;
    const BatteryModel model = campaign::LearnBatteryModel(learning, &summary);
    bar.Finish();
    WriteFileAtomically(options->out, BatteryModelToJson(model).dump(1) + "\n");
    int unobserved = 0;
    campaign::EnergyTransitionCounts energy;
    for (int c = 0; c < kBatteryNumContexts; ++c) {
      BatteryModelStats stats;
      BuildBatteryMdp(model.counts, BatteryContextFromIndex(c), model.weights, &stats);
      unobserved += stats.unobserved_rows;
      const auto e = campaign::CountEnergyTransitions(model.counts, BatteryContextFromIndex(c));
      energy.s1_to_s2 += e.s1_to_s2;
      energy.s2_to_s3 += e.s2_to_s3;
      energy.s1_to_s3 += e.s1_to_s3;
      energy.recoveries += e.recoveries;
    }
    if (options->json) {
      PrintJson({{"out", options->out},
                 {"hash", BatteryModelHash(model)},
                 {"flights", summary.flights},
                 {"parameter_draws", summary.parameter_draws},
                 {"failures", summary.failures},
                 {"transitions", model.counts.total_transitions()},
                 {"unobserved_rows", unobserved},
                 {"learned_rows", 216 * kBatteryNumContexts},
                 {"energy_transitions",
                  {{"S1->S2", energy.s1_to_s2}, {"S2->S3", energy.s2_to_s3}, {"S1->S3", energy.s1_to_s3},
                   {"recoveries", energy.recoveries}}},
                 {"shared_gnc_steps", summary.sharing.shared_steps},
                 {"alone_gnc_steps", summary.sharing.alone_steps},
                 {"wall_time_s", summary.wall_time_s}});
      return;
    }
    std::printf("learned the battery MDP from %lld flights (%lld parameter draws, %lld reached FAILURE) in %.1f s\n"
                "%lld transitions counted at 1 Hz; %d of %d learned rows unobserved (self-loops, decisions item 23)\n"
                "energy transitions observed in flight: S1->S2 %lld, S2->S3 %lld, S1->S3 %lld, recoveries %lld\n"
                "GNC steps that followed another action's vehicle: %lld; flown alone after the packs diverged: %lld\n"
                "wrote %s (hash %s)\n",
                static_cast<long long>(summary.flights), static_cast<long long>(summary.parameter_draws),
                static_cast<long long>(summary.failures), summary.wall_time_s,
                static_cast<long long>(model.counts.total_transitions()), unobserved, 216 * kBatteryNumContexts,
                static_cast<long long>(energy.s1_to_s2), static_cast<long long>(energy.s2_to_s3),
                static_cast<long long>(energy.s1_to_s3), static_cast<long long>(energy.recoveries),
                static_cast<long long>(summary.sharing.shared_steps), static_cast<long long>(summary.sharing.alone_steps),
                options->out.c_str(), BatteryModelHash(model).c_str());
  });
}

// --- battery solve ---------------------------------------------------------------------------------
void AddSolve(CLI::App* battery) {
  struct Options {
    std::string model;
    std::string out;
    bool without_energy_dynamics = false;
    std::string weights;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = battery->add_subcommand(
      "solve",
      "Solve one policy per (B1 health, B2 health, temperature) by value iteration (gamma of the model,\n"
      "0.95, §4.3.2.1) and write them with the model's hash");
  command->add_option("model", options->model, "Model JSON written by 'uascma battery learn'")->required();
  command->add_option("--out", options->out, "Policy JSON to write")->required();
  command->add_flag("--without-energy-dynamics", options->without_energy_dynamics,
                    "Drop every counted transition that changes a pack's energy feature (the dissertation's\n"
                    "constant-parameter flights could not see them) before solving");
  command->add_option("--weights", options->weights,
                      "Reward weights w1,w2,w3 of eqs. 4.1-4.3 (sum 1, eq. 4.9) instead of the model's");
  command->add_flag("--json", options->json, "Print the summary as JSON");
  command->callback([options] {
    BatteryModel model = ReadBatteryModelFile(options->model);
    if (!options->weights.empty()) model.weights = ParseWeightsOption(options->weights, "--weights");
    if (options->without_energy_dynamics) {
      model.counts = campaign::WithoutEnergyDynamics(model.counts);
      model.provenance["variant"] = "without energy dynamics";
    }
    const BatteryPolicySet set = SolveBatteryPolicies(model);
    WriteFileAtomically(options->out, BatteryPolicyToJson(set).dump(1) + "\n");
    double wall = 0.0;
    int iterations = 0, unobserved = 0;
    nlohmann::json contexts = nlohmann::json::array();
    for (const BatteryContextPolicy& p : set.policies) {
      wall += p.summary.wall_time_s;
      iterations += p.summary.iterations;
      unobserved += p.stats.unobserved_rows;
      contexts.push_back({{"context", BatteryContextLabel(p.context)},
                          {"iterations", p.summary.iterations},
                          {"unobserved_rows", p.stats.unobserved_rows},
                          {"transitions", p.stats.transitions}});
    }
    if (options->json) {
      PrintJson({{"out", options->out}, {"model_hash", set.model_hash}, {"gamma", set.gamma},
                 {"solve_time_s", wall}, {"contexts", contexts}});
      return;
    }
    std::printf("solved %d battery policies (value iteration, gamma %g, %d sweeps in all, %.2f ms); %d of %d "
                "learned rows were unobserved (self-loops)\nwrote %s\n",
                kBatteryNumContexts, set.gamma, iterations, 1e3 * wall, unobserved, 216 * kBatteryNumContexts,
                options->out.c_str());
  });
}

// --- battery show ----------------------------------------------------------------------------------
// Fig. 4.4: the transition graph of one action in one context, as Graphviz DOT. Learned rows with their
// probabilities, and the deterministic switch edges (dashed, p = 1) into their source states.
std::string TransitionDot(const BatteryContextPolicy& policy, PackAction action) {
  std::string out = fmt::format(
      "digraph battery_mdp {{\n  label=\"battery MDP transitions, action {}, context {} (Fig. 4.4)\";\n"
      "  rankdir=LR;\n  node [shape=box, style=rounded, fontsize=10];\n",
      models::PackActionName(action), BatteryContextLabel(policy.context));
  std::set<StateIndex> nodes;
  std::string edges;
  for (const BatteryLearnedRow& row : policy.observed_rows) {
    if (row.action != action) continue;
    nodes.insert(row.state);
    for (const Transition& t : row.next) {
      nodes.insert(t.next_state);
      edges += fmt::format("  \"{}\" -> \"{}\" [label=\"{:.3g}\"];\n", BatteryStateLabel(row.state),
                           BatteryStateLabel(t.next_state), t.probability);
    }
    // The states that differ from the row's source only in the switches reach it with p = 1.
    BatteryFeatures f = BatteryStateFeatures(row.state);
    for (int on1 = 0; on1 < 2; ++on1) {
      for (int on2 = 0; on2 < 2; ++on2) {
        f.pack[0].switch_on = on1 == 1;
        f.pack[1].switch_on = on2 == 1;
        const StateIndex from = BatteryStateIndex(f);
        if (from == row.state) continue;
        nodes.insert(from);
        edges += fmt::format("  \"{}\" -> \"{}\" [label=\"1\", style=dashed];\n", BatteryStateLabel(from),
                             BatteryStateLabel(row.state));
      }
    }
  }
  for (StateIndex s : nodes) {
    const bool failure = s == kBatteryFailureState;
    out += fmt::format("  \"{}\" [color=\"{}\"{}];\n", BatteryStateLabel(s), failure ? "red" : "black",
                       failure ? ", style=\"rounded,filled\", fillcolor=\"#ffcdd2\"" : "");
  }
  return out + edges + "}\n";
}

nlohmann::json PolicyViewJson(const BatteryPolicySet& set) {
  nlohmann::json contexts = nlohmann::json::array();
  for (const BatteryContextPolicy& p : set.policies) {
    nlohmann::json actions = nlohmann::json::array();
    for (ActionIndex a : p.action) actions.push_back(BatteryActionNames()[static_cast<std::size_t>(a)]);
    contexts.push_back({{"context", BatteryContextLabel(p.context)},
                        {"b1", BatteryHealthName(p.context.b1)},
                        {"b2", BatteryHealthName(p.context.b2)},
                        {"temperature", TemperatureClassName(p.context.temperature)},
                        {"unobserved_rows", p.stats.unobserved_rows},
                        {"action", actions}});
  }
  return {{"model_hash", set.model_hash}, {"gamma", set.gamma}, {"states", BatteryStateLabels()}, {"contexts", contexts}};
}

void AddShow(CLI::App* battery) {
  struct Options {
    std::string policy;
    std::string plot;
    std::string dot;
    std::string context = "F3,F3,TL";
    std::string action = "UseBatt1";
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = battery->add_subcommand(
      "show",
      "Show the battery policies: the decision tree of Fig. 4.5 (temperature, B1 health, B2 health) with\n"
      "each leaf's policy summarised; --plot draws every policy over the 288 states; --dot writes the\n"
      "transition graph of one action and context as Graphviz DOT (Fig. 4.4)");
  command->add_option("policy", options->policy, "Policy JSON written by 'uascma battery solve'")->required();
  command->add_option("--plot", options->plot, "Draw the policies to this PNG file");
  command->add_option("--dot", options->dot, "Write the transition graph (Fig. 4.4) to this DOT file");
  command->add_option("--context", options->context, "Context of --dot as B1F,B2F,T (default F3,F3,TL, Fig. 4.4)");
  command->add_option("--action", options->action, "Action of --dot (default UseBatt1, Fig. 4.4)");
  command->add_flag("--json", options->json, "Print the policies as JSON");
  command->callback([options] {
    const BatteryContext dot_context = ParseContextOption(options->context, "--context");
    const PackAction dot_action = models::ParsePackAction(options->action, "--action");
    const BatteryPolicySet set = ReadBatteryPolicyFile(options->policy);
    const nlohmann::json view = PolicyViewJson(set);
    if (!options->dot.empty()) WriteFileAtomically(options->dot, TransitionDot(set.Select(dot_context), dot_action));
    if (!options->plot.empty()) PlotJson("battery_policy.py", view, options->plot);
    if (options->json) {
      PrintJson(view);
      return;
    }
    // The take-off state of Fig. 4.11: both switches ON, both packs S1, C0, low current.
    const StateIndex takeoff = ParseBatteryState("ILONS1C0ONS1C0", "take-off state");
    std::string text = fmt::format("battery policies {} (model {}, gamma {})\nFig. 4.5 decision tree: T -> B1F -> B2F\n",
                                   options->policy, set.model_hash, set.gamma);
    text += "                         states per action                  at take-off      unobserved\n";
    text += "T    B1F  B2F            UseBatt1  UseBatt2  UseBoth           ILONS1C0ONS1C0   rows\n";
    for (const BatteryContextPolicy& p : set.policies) {
      std::array<int, 3> per_action{};
      for (StateIndex s = 0; s < kBatteryFailureState; ++s) ++per_action[static_cast<std::size_t>(p.action[s])];
      text += fmt::format("{:<4} {:<4} {:<4}           {:>8}  {:>8}  {:>7}           {:<16} {}\n",
                          TemperatureClassName(p.context.temperature), BatteryHealthName(p.context.b1),
                          BatteryHealthName(p.context.b2), per_action[0], per_action[1], per_action[2],
                          BatteryActionNames()[static_cast<std::size_t>(p.action[takeoff])], p.stats.unobserved_rows);
    }
    std::fputs(text.c_str(), stdout);
    if (!options->dot.empty()) std::printf("wrote %s\n", options->dot.c_str());
    if (!options->plot.empty()) std::printf("wrote %s\n", options->plot.c_str());
  });
}

// --- battery case-study ------------------------------------------------------------------------------
std::string EpochsCsv(const campaign::BatteryFlightResult& result) {
  std::string out =
      "time_s,state,action,total_current_a,branch1_current_a,branch2_current_a,eod1_s,eod2_s,remaining_flight_s,"
      "min_cell1_v,min_cell2_v\n";
  for (const campaign::BatteryEpoch& e : result.epochs) {
    out += fmt::format("{:.1f},{},{},{:.4f},{:.4f},{:.4f},{:.2f},{:.2f},{:.2f},{:.4f},{:.4f}\n", e.time_s,
                       BatteryStateLabel(e.state), models::PackActionName(e.action), e.total_current_a,
                       e.branch_current_a[0], e.branch_current_a[1], e.eod_s[0], e.eod_s[1], e.remaining_flight_s,
                       e.min_cell_voltage_v[0], e.min_cell_voltage_v[1]);
  }
  return out;
}

void AddCaseStudy(CLI::App* battery) {
  struct Options {
    int number = 0;
    std::string out;
    std::string policy;
    std::int64_t runs = 5000;
    int jobs = 1;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = battery->add_subcommand(
      "case-study",
      "Run a case study of Table 4.5: (1) flight time = one pack's EOD, UseBoth; (2) the same with pi*;\n"
      "(3) flight time = both packs' EOD, UseBoth, for (F1,F2), (F1,F3), (F3,F3); (4) pi* for (F2,F1)\n"
      "(pack 1 with one capacity-faded cell, Fig. 4.11's caption), with UseBoth on the same flight beside it.\n"
      "pi* comes from --policy, or is learned (--runs flights) and solved first");
  AddBoundedOption(command, "N", options->number, "Case study (Table 4.5)", kCaseStudyBounds)->required();
  command->add_option("--out", options->out, "Write case-N.json, one CSV per scenario and plots to this folder");
  command->add_option("--policy", options->policy, "Battery policy JSON for pi* (cases 2 and 4)");
  AddBoundedOption(command, "--runs", options->runs, "Without --policy: flights to learn pi* from (default 5,000)",
                   kFlightsBounds);
  AddBoundedOption(command, "--jobs", options->jobs, "Without --policy: threads for learning", kThreadsBounds);
  command->add_flag("--json", options->json, "Print per scenario the outcome and the switch actions with times");
  command->callback([options] {
    RequireWithin(options->number, kCaseStudyBounds, "N", "value");
    RequireWithin(static_cast<double>(options->runs), kFlightsBounds, "--runs", "value");
    RequireWithin(options->jobs, kThreadsBounds, "--jobs", "value");
    std::optional<BatteryPolicySet> policies;
    if (options->number == 2 || options->number == 4) {
      if (!options->policy.empty()) {
        policies = ReadBatteryPolicyFile(options->policy);
      } else {
        ProgressBar bar(options->runs, "battery learn (pi*)");
        campaign::BatteryLearningOptions learning;
        learning.runs = options->runs;
        learning.jobs = options->jobs;
        learning.on_flight_done = [&bar](std::int64_t) { bar.Advance(); };
        policies = SolveBatteryPolicies(campaign::LearnBatteryModel(learning));
      }
    }
    const auto scenarios = campaign::RunCaseStudy(options->number, policies ? &*policies : nullptr);
    const nlohmann::json json = campaign::CaseStudyJson(options->number, scenarios);
    if (!options->out.empty()) {
      // Written whole or not at all (common/files.h OutputDirectory).
      OutputDirectory folder("--out", options->out);
      const std::filesystem::path& dir = folder.staging();
      for (std::size_t i = 0; i < scenarios.size(); ++i) {
        const std::string stem = fmt::format("case-{}-scenario-{}", options->number, i + 1);
        WriteFileAtomically(dir / (stem + ".csv"), EpochsCsv(scenarios[i].result));
        nlohmann::json plot = json["scenarios"][i];
        plot["csv"] = (dir / (stem + ".csv")).string();
        plot["case"] = options->number;
        PlotJson("battery_case.py", plot, (dir / (stem + ".png")).string());
      }
      WriteFileAtomically(dir / fmt::format("case-{}.json", options->number), json.dump(2) + "\n");
      folder.Commit();
    }
    if (options->json) {
      PrintJson(json);
      return;
    }
    std::printf("case study %d (Table 4.5)\n", options->number);
    for (const auto& scenario : scenarios) {
      std::string switches;
      for (const auto& [time_s, action] : scenario.result.switches) {
        switches += fmt::format(" {}@{:.0f}s", models::PackActionName(action), time_s);
      }
      std::printf("  %-8s %-8s plan %.0f s: %s at %.0f s; switches:%s\n", scenario.name.c_str(),
                  scenario.controller.c_str(), scenario.params.plan_duration_s,
                  sim::OutcomeName(scenario.result.outcome), scenario.result.end_time_s, switches.c_str());
    }
    if (!options->out.empty()) std::printf("wrote %s\n", options->out.c_str());
  });
}

}  // namespace

void AddBatteryCommand(CLI::App& app) {
  CLI::App* battery = app.add_subcommand(
      "battery", "The battery-reconfiguration MDP (Ch. IV, §4.3): learn, solve, show, case-study");
  battery->require_subcommand(1);
  AddLearn(battery);
  AddSolve(battery);
  AddShow(battery);
  AddCaseStudy(battery);
}

}  // namespace uascma::cli
