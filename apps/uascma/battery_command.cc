// uascma battery — the battery-reconfiguration MDP of dissertation Ch. IV (§4.3): learn its transitions from
// Monte Carlo flights, solve one policy per health pair and temperature, show them, run the case studies.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "bounded_option.h"
#include "commands.h"
#include "output.h"
#include "plotting.h"
#include "uascma/campaign/battery_case_studies.h"
#include "uascma/campaign/battery_controllers.h"
#include "uascma/campaign/battery_evaluation.h"
#include "uascma/campaign/battery_flights.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/common/progress.h"
#include "uascma/decision/battery_mdp.h"
#include "uascma/decision/battery_mdp_file.h"
#include "uascma/decision/battery_mdp_report.h"
#include "uascma/decision/battery_model.h"
#include "uascma/decision/battery_policy.h"
#include "uascma/learning/battery_transition_estimation.h"

namespace uascma::cli {
namespace {

using namespace uascma::decision;
using models::PackAction;

// Plausibility bounds of the numeric options. Flights: §4.3.2 learns from 5,000; 10^7 is the
// campaign's bound on runs. Threads: our bound, far above any machine this runs on. Case studies: Table 4.5.
constexpr Bounds kFlightsBounds{1.0, 1e7, "flights"};
constexpr Bounds kThreadsBounds{1.0, 256.0, "threads"};
constexpr Bounds kCaseStudyBounds{1.0, 4.0, ""};

BatteryContext ParseContextOption(const std::string& text, const std::string& option) {
  const auto first = text.find(',');
  const auto second = first == std::string::npos ? std::string::npos : text.find(',', first + 1);
  if (second == std::string::npos)
    throw InputError(option, "value", fmt::format("B1F,B2F,T such as F3,F3,TL, got '{}'", text));
  return {ParseBatteryHealth(text.substr(0, first), option),
          ParseBatteryHealth(text.substr(first + 1, second - first - 1), option),
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
      throw InputError(option, fmt::format("w{}", i + 1),
                       fmt::format("a number, got '{}'", text.substr(begin, end - begin)));
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

// What `battery learn` prints: the counts, the unobserved learned rows, the energy transitions seen in flight and
// how the flights shared their vehicle.
void PrintLearnSummary(const std::string& out, const BatteryModel& model,
                       const learning::BatteryLearningSummary& summary, bool json) {
  const BatteryModelReport report = ReportBatteryModel(model);
  const int unobserved = report.unobserved_rows;
  const EnergyTransitionCounts& energy = report.energy;
  if (json) {
    PrintJson({{"out", out},
               {"hash", BatteryModelHash(model)},
               {"flights", summary.flights},
               {"parameter_draws", summary.parameter_draws},
               {"failures", summary.failures},
               {"transitions", model.counts.total_transitions()},
               {"unobserved_rows", unobserved},
               {"learned_rows", 216 * kBatteryNumContexts},
               {"energy_transitions",
                {{"S1->S2", energy.s1_to_s2},
                 {"S2->S3", energy.s2_to_s3},
                 {"S1->S3", energy.s1_to_s3},
                 {"recoveries", energy.recoveries}}},
               {"shared_gnc_steps", summary.sharing.shared_steps},
               {"alone_gnc_steps", summary.sharing.alone_steps},
               {"isolation_flights", summary.isolation_flights},
               {"ours_transitions", model.OursCounts().total_transitions()},
               {"wall_time_s", summary.wall_time_s}});
    return;
  }
  std::printf(
      "learned the battery MDP from %lld flights (%lld parameter draws, %lld reached FAILURE) in %.1f s\n"
      "%lld transitions counted at 1 Hz; %d of %d learned rows unobserved (self-loops, "
      "docs/modelling-choices.md#battery-mdp-transitions)\n"
      "energy transitions observed in flight: S1->S2 %lld, S2->S3 %lld, S1->S3 %lld, recoveries %lld\n"
      "GNC steps that followed another action's vehicle: %lld; flown alone after the packs diverged: %lld\n"
      "wrote %s (hash %s)\n",
      static_cast<long long>(summary.flights), static_cast<long long>(summary.parameter_draws),
      static_cast<long long>(summary.failures), summary.wall_time_s,
      static_cast<long long>(model.counts.total_transitions()), unobserved, 216 * kBatteryNumContexts,
      static_cast<long long>(energy.s1_to_s2), static_cast<long long>(energy.s2_to_s3),
      static_cast<long long>(energy.s1_to_s3), static_cast<long long>(energy.recoveries),
      static_cast<long long>(summary.sharing.shared_steps), static_cast<long long>(summary.sharing.alone_steps),
      out.c_str(), BatteryModelHash(model).c_str());
  if (summary.isolation_flights > 0 || model.ours_counts) {
    std::printf(
        "pack faults: %lld isolation flights (UseBoth, then the unflagged pack alone from the first flag); the "
        "pack-fault indicator flagged a pack %s, so ours' flagged states (decision/battery_mdp.h item 10) are "
        "counted (%lld transitions in ours' abstraction)\n",
        static_cast<long long>(summary.isolation_flights), model.ours_counts ? "in flight" : "in no flight",
        static_cast<long long>(model.OursCounts().total_transitions()));
  }
}

// --pack-fault-share of learn and evaluate (campaign/pack_fault_sampling.h).
void AddPackFaultShareOption(CLI::App* command, double& share) {
  AddBoundedOption(command, "--pack-fault-share", share,
                   "Share of the flights with a sudden pack fault (internal short, failed cell or connector;\n"
                   "docs/modelling-choices.md#pack-faults; default 0: none)",
                   campaign::kPackFaultShareBounds);
}

// --- battery learn ---------------------------------------------------------------------------------
void AddLearn(CLI::App* battery) {
  struct Options {
    std::int64_t runs = 5000;
    std::uint64_t seed = 1;
    int jobs = 1;
    std::string out;
    bool drop_flights = false;
    double pack_fault_share = 0.0;
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
  command->add_flag("--drop-flights", options->drop_flights,
                    "Ours: every draw also flies UseBoth then one pack alone for good from a random time, so the\n"
                    "states a switching policy flies into are observed (the flights are split four ways)");
  AddPackFaultShareOption(command, options->pack_fault_share);
  command->add_flag("--json", options->json, "Print the summary as JSON");
  command->callback([options] {
    RequireWithin(static_cast<double>(options->runs), kFlightsBounds, "--runs", "value");
    RequireWithin(options->jobs, kThreadsBounds, "--jobs", "value");
    RequireWithin(options->pack_fault_share, campaign::kPackFaultShareBounds, "--pack-fault-share", "value");
    CheckOutputFile(options->out, "--out");  // before the flights
    ProgressBar bar(options->runs, "battery learn");
    learning::BatteryLearningOptions learn_options;
    learn_options.runs = options->runs;
    learn_options.seed = options->seed;
    learn_options.jobs = options->jobs;
    learn_options.drop_flights = options->drop_flights;
    learn_options.ranges.pack_faults.share = options->pack_fault_share;
    learn_options.on_flight_done = [&bar](std::int64_t) { bar.Advance(); };
    learning::BatteryLearningSummary summary;
    const BatteryModel model = learning::LearnBatteryModel(learn_options, &summary);
    bar.Finish();
    WriteFileAtomically(options->out, BatteryModelToJson(model).dump(1) + "\n");
    PrintLearnSummary(options->out, model, summary, options->json);
  });
}

// --- battery solve ---------------------------------------------------------------------------------
void AddSolve(CLI::App* battery) {
  struct Options {
    std::string model;
    std::string out;
    bool without_energy_dynamics = false;
    std::string weights;
    std::string formulation = "dissertation";
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
  command
      ->add_option("--formulation", options->formulation,
                   "dissertation (pi*, eqs. 4.1-4.9, gamma of the model, value iteration) or ours (both packs\n"
                   "charged, switching cost, absorbing COMPLETE/FAILURE, gamma seeing the longest plan, no\n"
                   "choice without evidence; decision/battery_mdp.h)")
      ->check(CLI::IsMember({"dissertation", "ours"}));
  command->add_flag("--json", options->json, "Print the summary as JSON");
  command->callback([options] {
    CheckOutputFile(options->out, "--out");
    BatteryModel model = ReadBatteryModelFile(options->model);
    if (!options->weights.empty()) model.weights = ParseWeightsOption(options->weights, "--weights");
    if (options->without_energy_dynamics) {
      model.counts = WithoutEnergyDynamics(model.counts);
      model.provenance["variant"] = "without energy dynamics";
    }
    const BatteryPolicySet set = options->formulation == "ours"
                                     ? SolveOursBatteryPolicies(model, campaign::OursBatteryDiscount())
                                     : SolveBatteryPolicies(model);
    WriteFileAtomically(options->out, BatteryPolicyToJson(set).dump(1) + "\n");
    const BatterySolveReport report = ReportBatterySolve(set);
    if (options->json) {
      PrintJson({{"out", options->out},
                 {"model_hash", set.model_hash},
                 {"gamma", set.gamma},
                 {"formulation", BatteryFormulationName(set.formulation)},
                 {"solve_time_s", report.wall_time_s},
                 {"contexts", report.contexts}});
      return;
    }
    const bool ours = set.formulation == BatteryFormulation::kOurs;
    std::printf(
        "solved %d battery policies (%s formulation, %s, gamma %.6g, %d %s in all, %.2f ms); %d of %d "
        "learned rows were unobserved (%s)\nwrote %s\n",
        kBatteryNumContexts, BatteryFormulationName(set.formulation), ours ? "policy iteration" : "value iteration",
        set.gamma, report.iterations, ours ? "improvement steps" : "sweeps", 1e3 * report.wall_time_s,
        report.unobserved_rows, report.learned_rows, ours ? "actions not offered there" : "self-loops",
        options->out.c_str());
  });
}

// --- battery show ----------------------------------------------------------------------------------
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
      "each leaf's policy over the 216 states that can occur (the 72 with both switches OFF cannot), the\n"
      "choices whose row was never observed marked, and the action at the state the context's case-study\n"
      "flight (the case studies' flight time) starts in; --plot draws every policy; --dot writes the transition\n"
      "graph of one action and context as Graphviz DOT (Fig. 4.4), unobserved rows marked");
  command->add_option("policy", options->policy, "Policy JSON written by 'uascma battery solve'")->required();
  command->add_option("--plot", options->plot, "Draw the policies to this PNG file");
  command->add_option("--dot", options->dot, "Write the transition graph (Fig. 4.4) to this DOT file");
  command->add_option("--context", options->context, "Context of --dot as B1F,B2F,T (default F3,F3,TL, Fig. 4.4)");
  command->add_option("--action", options->action, "Action of --dot (default UseBatt1, Fig. 4.4)");
  command->add_flag("--json", options->json, "Print the policies as JSON");
  command->callback([options] {
    CheckOutputFile(options->plot, "--plot");
    CheckOutputFile(options->dot, "--dot");
    const BatteryContext dot_context = ParseContextOption(options->context, "--context");
    const PackAction dot_action = models::ParsePackAction(options->action, "--action");
    const BatteryPolicySet set = ReadBatteryPolicyFile(options->policy);
    const double flight_time_s = campaign::CaseFlightTimeS();
    const std::vector<StateIndex> takeoff = campaign::CaseTakeoffStates(flight_time_s);
    const nlohmann::json view = BatteryPolicyViewJson(set, takeoff, flight_time_s);
    if (!options->dot.empty())
      WriteFileAtomically(options->dot, BatteryTransitionDot(set.Select(dot_context), dot_action));
    if (!options->plot.empty()) PlotJsonWhole("battery_policy.py", view, options->plot);
    if (options->json) {
      PrintJson(view);
      return;
    }
    std::fputs(BatteryPolicyViewText(set, takeoff, flight_time_s, options->policy).c_str(), stdout);
    if (!options->dot.empty()) std::printf("wrote %s\n", options->dot.c_str());
    if (!options->plot.empty()) std::printf("wrote %s\n", options->plot.c_str());
  });
}

// --- battery case-study ------------------------------------------------------------------------------
// Case N's folder: one CSV of the 1 Hz epochs and one plot per scenario, and case-N.json.
void WriteCaseFolder(OutputDirectory& folder, int number, const std::vector<campaign::CaseScenario>& scenarios,
                     const nlohmann::json& json) {
  const std::filesystem::path& dir = folder.staging();
  for (std::size_t i = 0; i < scenarios.size(); ++i) {
    const std::string stem = fmt::format("case-{}-scenario-{}", number, i + 1);
    WriteFileAtomically(dir / (stem + ".csv"), campaign::CaseEpochsCsv(scenarios[i].result));
    nlohmann::json plot = json["scenarios"][i];
    plot["csv"] = (dir / (stem + ".csv")).string();
    plot["case"] = number;
    PlotJson("battery_case.py", plot, (dir / (stem + ".png")).string());
  }
  WriteFileAtomically(dir / fmt::format("case-{}.json", number), json.dump(2) + "\n");
  folder.Commit();
}

void PrintCaseStudy(int number, std::uint64_t seed, const std::vector<campaign::CaseScenario>& scenarios) {
  std::printf("case study %d (Table 4.5), seed %llu\n", number, static_cast<unsigned long long>(seed));
  for (const auto& scenario : scenarios) {
    std::string switches;
    for (const auto& [time_s, action] : scenario.result.switches) {
      switches += fmt::format(" {}@{:.0f}s", models::PackActionName(action), time_s);
    }
    if (switches.size() > 200) switches = switches.substr(0, 200) + " ...";
    std::printf("  %-8s %-15s plan %.0f s: %s at %.0f s; %d switches:%s\n", scenario.name.c_str(),
                scenario.controller.c_str(), scenario.params.plan_duration_s, sim::OutcomeName(scenario.result.outcome),
                scenario.result.end_time_s, campaign::CountSwitches(scenario.result), switches.c_str());
    if (!scenario.schedule.empty()) {
      std::printf(
          "           best of %d schedules (UseBoth; one late drop, %.0f s grid; one rest window, %.0f s grid): %s\n",
          scenario.schedules_flown, campaign::kHindsightSwitchGridS, campaign::kHindsightWindowGridS,
          scenario.schedule.c_str());
    }
  }
}

void AddCaseStudy(CLI::App* battery) {
  struct Options {
    int number = 0;
    std::string out;
    std::string policy;
    std::string ours;
    std::uint64_t seed = 1;
    std::int64_t runs = 5000;
    int jobs = 1;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = battery->add_subcommand(
      "case-study",
      "Run a case study of Table 4.5: (1) flight time = one pack's EOD, UseBoth; (2) the same flights with\n"
      "UseBoth beside pi* (and ours with --ours); (3) the case studies' flight time (0.82 of the healthy pair's\n"
      "endurance), UseBoth, for (F1,F2), (F1,F3), (F3,F3); (4) the same flight time, (F2,F1) with pack 1's one\n"
      "capacity-faded cell (Fig. 4.11's caption): UseBoth, pi*, the voltage rule, ours (--ours) and the\n"
      "hindsight-best schedule of a stated family (UseBoth; UseBoth then one pack alone for good from t, 5 s\n"
      "grid; UseBoth with one window of one pack alone, 60 s grid), each flown in the simulator.\n"
      "pi* comes from --policy, or is learned (--runs flights) and solved first");
  AddBoundedOption(command, "N", options->number, "Case study (Table 4.5)", kCaseStudyBounds)->required();
  command->add_option("--out", options->out, "Write case-N.json, one CSV per scenario and plots to this folder");
  command->add_option("--policy", options->policy, "Battery policy JSON for pi* (cases 2 and 4; read for every case)");
  command->add_option("--ours", options->ours, "Our battery policy JSON (solve --formulation ours), flown beside");
  AddSeedOption(command, "--seed", options->seed, "The vehicle's seed (gusts, noise); default 1");
  AddBoundedOption(command, "--runs", options->runs, "Without --policy: flights to learn pi* from (default 5,000)",
                   kFlightsBounds);
  AddBoundedOption(command, "--jobs", options->jobs, "Without --policy: threads for learning", kThreadsBounds);
  command->add_flag("--json", options->json, "Print per scenario the outcome and the switch actions with times");
  command->callback([options] {
    RequireWithin(options->number, kCaseStudyBounds, "N", "value");
    RequireWithin(static_cast<double>(options->runs), kFlightsBounds, "--runs", "value");
    RequireWithin(options->jobs, kThreadsBounds, "--jobs", "value");
    // Every input and the output folder checked before any flight: a policy file named is read
    // whatever the case, and the folder is claimed now (written whole at the end, or not at all).
    std::optional<BatteryPolicySet> policies, ours;
    if (!options->policy.empty()) policies = ReadBatteryPolicyFile(options->policy);
    if (!options->ours.empty()) {
      ours = ReadBatteryPolicyFile(options->ours);
      if (ours->formulation != BatteryFormulation::kOurs) {
        throw InputError(options->ours, "formulation", "'ours' (battery solve --formulation ours), got 'dissertation'");
      }
    }
    std::optional<OutputDirectory> folder;
    if (!options->out.empty()) folder.emplace("--out", options->out);
    if ((options->number == 2 || options->number == 4) && !policies) {
      ProgressBar bar(options->runs, "battery learn (pi*)");
      learning::BatteryLearningOptions learn_options;
      learn_options.runs = options->runs;
      learn_options.jobs = options->jobs;
      learn_options.on_flight_done = [&bar](std::int64_t) { bar.Advance(); };
      policies = SolveBatteryPolicies(learning::LearnBatteryModel(learn_options));
    }
    campaign::CaseStudyOptions case_options;
    case_options.pistar = policies ? &*policies : nullptr;
    case_options.ours = ours ? &*ours : nullptr;
    case_options.seed = options->seed;
    const auto scenarios = campaign::RunCaseStudy(options->number, case_options);
    const nlohmann::json json = campaign::CaseStudyJson(options->number, scenarios);
    if (folder) WriteCaseFolder(*folder, options->number, scenarios, json);
    if (options->json) {
      PrintJson(json);
      return;
    }
    PrintCaseStudy(options->number, options->seed, scenarios);
    if (!options->out.empty()) std::printf("wrote %s\n", options->out.c_str());
  });
}

// --- battery evaluate ------------------------------------------------------------------------------
void AddEvaluate(CLI::App* battery) {
  struct Options {
    std::string policies = "useboth,rule:voltage";
    std::int64_t runs = 400;
    std::uint64_t seed = 2024;
    int jobs = 1;
    bool json = false;
    bool runs_detail = false;
    std::string plot;
    std::string out;
    double pack_fault_share = 0.0;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = battery->add_subcommand(
      "evaluate",
      "Judge battery policies on paired flights: run r draws a fresh flight from Table 4.4 (--seed; use one no\n"
      "learning used) and every policy flies that same flight. Completions with 95 % Wilson intervals, failures\n"
      "and the median failure time, charge left, switches per flight, per health pair and temperature, and\n"
      "McNemar's exact test for every pair of policies. Policies: useboth, pistar:POLICY.json,\n"
      "ours:POLICY.json, rule:voltage[:V] (UseBoth; drop a pack for good when its worst cell falls below V,\n"
      "default 3.31 V), rule:fault (UseBoth; drop the first pack the pack-fault indicator flags, for good)");
  command->add_option("--policies", options->policies, "Comma-separated policies (default useboth,rule:voltage)");
  AddBoundedOption(command, "--runs", options->runs, "Flights (each flown by every policy)", kFlightsBounds);
  AddSeedOption(command, "--seed", options->seed, "Seed of the flights (default 2024; learning uses 1)");
  AddBoundedOption(command, "--jobs", options->jobs, "Threads (the results do not depend on it)", kThreadsBounds);
  command->add_flag("--json", options->json, "Print the evaluation as JSON");
  command->add_flag("--runs-detail", options->runs_detail, "With --json or --out: every run's flights too");
  command->add_option("--plot", options->plot, "Draw completions and switches per policy to this PNG file");
  command->add_option("--out", options->out, "Write the evaluation JSON (with every run) to this file");
  AddPackFaultShareOption(command, options->pack_fault_share);
  command->callback([options] {
    RequireWithin(static_cast<double>(options->runs), kFlightsBounds, "--runs", "value");
    RequireWithin(options->jobs, kThreadsBounds, "--jobs", "value");
    RequireWithin(options->pack_fault_share, campaign::kPackFaultShareBounds, "--pack-fault-share", "value");
    CheckOutputFile(options->plot, "--plot");
    CheckOutputFile(options->out, "--out");
    const std::vector<campaign::BatteryPolicySpec> policies =
        campaign::ParseBatteryPolicies(options->policies, "--policies");
    ProgressBar bar(options->runs, "battery evaluate");
    campaign::BatteryEvaluationOptions evaluation_options;
    evaluation_options.runs = options->runs;
    evaluation_options.seed = options->seed;
    evaluation_options.jobs = options->jobs;
    evaluation_options.ranges.pack_faults.share = options->pack_fault_share;
    evaluation_options.on_run_done = [&bar](std::int64_t) { bar.Advance(); };
    const campaign::BatteryEvaluation evaluation = campaign::EvaluateBatteryPolicies(policies, evaluation_options);
    bar.Finish();
    if (!options->out.empty())
      WriteFileAtomically(options->out, campaign::BatteryEvaluationJson(evaluation, true).dump(1) + "\n");
    if (!options->plot.empty())
      PlotJsonWhole("battery_evaluation.py", campaign::BatteryEvaluationJson(evaluation, true), options->plot);
    if (options->json) {
      PrintJson(campaign::BatteryEvaluationJson(evaluation, options->runs_detail));
      return;
    }
    std::fputs(campaign::BatteryEvaluationText(evaluation).c_str(), stdout);
    if (!options->out.empty()) std::printf("wrote %s\n", options->out.c_str());
    if (!options->plot.empty()) std::printf("wrote %s\n", options->plot.c_str());
  });
}

}  // namespace

void AddBatteryCommand(CLI::App& app) {
  CLI::App* battery = app.add_subcommand(
      "battery",
      "The battery-reconfiguration MDP (Ch. IV, §4.3): learn, solve, show, case-study, evaluate, hindsight");
  battery->require_subcommand(1);
  AddLearn(battery);
  AddSolve(battery);
  AddShow(battery);
  AddCaseStudy(battery);
  AddEvaluate(battery);
  AddBatteryHindsight(battery);
}

}  // namespace uascma::cli
