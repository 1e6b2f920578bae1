// The Monte Carlo campaign of §5.5.3 (Figs. 5.30-5.32 and the abstract's 1.3 % and 71 %), in two profiles: the
// default (ours, docs/modelling-choices.md#campaign-missions: plans of 0.5-0.9 of a healthy pack's endurance) and the
// dissertation's (docs/modelling-choices.md#dissertation-profile: the plan-length range calibrated, by the bisection
// below, to NoOp's 71 % in poor health; everything else of it a prediction).
#include "items_campaign.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "uascma/campaign/config.h"
#include "uascma/campaign/policies.h"
#include "uascma/campaign/runner.h"
#include "uascma/campaign/statistics.h"
#include "uascma/common/error.h"
#include "uascma/reproduce/reproduce.h"

namespace uascma::reproduce {
namespace {

using campaign::CampaignConfig;
using campaign::GroupStatistics;
using campaign::RunRecord;

std::vector<RunRecord> Fly(const CampaignConfig& config, const Context& context) {
  const std::vector<campaign::CampaignPolicy> policies = campaign::ResolvePolicies(config.policies, "reproduce");
  const std::vector<campaign::FlightTask> tasks = campaign::MissingFlights(config.runs, policies, {});
  campaign::ExecuteOptions execute;
  execute.jobs = context.options.jobs;
  std::vector<RunRecord> records;
  campaign::ExecuteFlights(config, policies, tasks, execute, [&records](std::vector<RunRecord>&& batch) {
    records.insert(records.end(), std::make_move_iterator(batch.begin()), std::make_move_iterator(batch.end()));
  });
  // Finished in any order: the report is built from the records in flight order, so it is the same for any jobs.
  std::sort(records.begin(), records.end(),
            [](const RunRecord& a, const RunRecord& b) { return a.flight_id < b.flight_id; });
  return records;
}

const GroupStatistics& Group(const std::vector<GroupStatistics>& groups, const std::string& policy,
                             const std::string& health) {
  for (const GroupStatistics& g : groups) {
    if (g.policy == policy && g.battery_health == health) return g;
  }
  throw InputError("reproduce", policy + "/" + health, "a campaign group with flights (too few runs?)");
}

nlohmann::json HealthBars(const std::vector<GroupStatistics>& groups, const std::string& metric) {
  nlohmann::json series = nlohmann::json::array();
  for (const std::string policy : {"noop", "cma"}) {
    nlohmann::json values = nlohmann::json::array(), errors = nlohmann::json::array();
    for (const std::string health : {"G", "M", "P"}) {
      const GroupStatistics& g = Group(groups, policy, health);
      const campaign::Estimate e = metric == "failure"      ? g.failure_rate
                                   : metric == "completion" ? g.completion_rate
                                                            : g.average_reward;
      const double scale = metric == "reward" ? 1.0 : 100.0;
      values.push_back(scale * e.value);
      errors.push_back(scale * e.sem);
    }
    series.push_back({{"label", policy == "cma" ? "CMA" : "NoOp (baseline)"}, {"values", values}, {"errors", errors}});
  }
  return series;
}

// Figs. 5.30-5.32 as the dissertation draws them: failure rate, original-plan completion and average reward per
// battery health, with the SEM.
void AddCampaignFigures(Item& item, const std::string& prefix, const std::vector<GroupStatistics>& groups) {
  const nlohmann::json categories = {"G", "M", "P"};
  item.figures.push_back(
      {prefix + "-fig-5.30.png",
       "Fig. 5.30: failure rate ± SEM by battery health (markers: the dissertation's P values)",
       {{"kind", "groups"},
        {"categories", categories},
        {"ylabel", "failure rate (%)"},
        {"series", HealthBars(groups, "failure")},
        {"theirs",
         {{{"category", "P"}, {"series", 0}, {"value", 71.0}}, {{"category", "P"}, {"series", 1}, {"value", 1.3}}}}}});
  item.figures.push_back({prefix + "-fig-5.31.png",
                          "Fig. 5.31: original flight plan completed ± SEM by battery health",
                          {{"kind", "groups"},
                           {"categories", categories},
                           {"ylabel", "completed (%)"},
                           {"series", HealthBars(groups, "completion")}}});
  item.figures.push_back({prefix + "-fig-5.32.png",
                          "Fig. 5.32: average reward per epoch ± SEM by battery health",
                          {{"kind", "groups"},
                           {"categories", categories},
                           {"ylabel", "average R(S, A)"},
                           {"series", HealthBars(groups, "reward")}}});
}

nlohmann::json GroupsJson(const std::vector<GroupStatistics>& groups) {
  nlohmann::json out = nlohmann::json::object();
  for (const GroupStatistics& g : groups) {
    out[g.policy][g.battery_health] = {{"runs", g.runs},
                                       {"failures", g.failures},
                                       {"completions", g.completions},
                                       {"emergency_landings", g.emergency_landings},
                                       {"groundings", g.groundings},
                                       {"terminations", g.terminations},
                                       {"average_reward", g.average_reward.value}};
  }
  return out;
}

// The shape of Figs. 5.30-5.32 that §5.5.3 states in words, checked as predictions.
void AddShapeQuantities(Item& item, const std::vector<GroupStatistics>& groups, const std::string& why_cma_p) {
  const GroupStatistics& cma_p = Group(groups, "cma", "P");
  item.quantities.push_back(CompareRate("CMA failure rate, poor health", cma_p.failures, cma_p.runs, 0.013,
                                        "the abstract's 1.3 %, our rate's 95 % Wilson interval", why_cma_p));
  for (const std::string health : {"M", "P"}) {
    const bool lower =
        Group(groups, "cma", health).failure_rate.value < Group(groups, "noop", health).failure_rate.value;
    item.quantities.push_back(CompareText("CMA fails less than NoOp, " + health, lower ? "yes" : "no", "yes",
                                          "Fig. 5.30: 'the CMA offers improved safety in medium and poor health'",
                                          "NoOp fails no more often than the CMA here."));
  }
  const bool cautious =
      Group(groups, "noop", "G").completion_rate.value > Group(groups, "cma", "G").completion_rate.value;
  item.quantities.push_back(CompareText("NoOp completes more original plans in good health", cautious ? "yes" : "no",
                                        "yes", "Fig. 5.31: 'the Baseline Policy of NoOp has a higher completion rate'",
                                        "The CMA is not more cautious than NoOp in good health."));
  const bool reward =
      Group(groups, "cma", "all").average_reward.value > Group(groups, "noop", "all").average_reward.value;
  item.quantities.push_back(CompareText("CMA's average reward above NoOp's", reward ? "yes" : "no", "yes",
                                        "Fig. 5.32: 'CMA has higher average reward values'",
                                        "NoOp's average reward is not below the CMA's."));
}

CampaignConfig LoadProfile(const Context& context, const std::string& file, std::int64_t runs, std::uint64_t seed) {
  CampaignConfig config = campaign::LoadCampaignConfig(context.options.source_dir / "examples" / file);
  config.runs = runs;
  config.seed = seed;
  config.policies = {"cma", "noop"};
  return config;
}

}  // namespace

Item ReproduceCampaignDefault(const Context& context) {
  Item item;
  item.source = "§5.5.3, Figs. 5.30-5.32, abstract";
  const std::int64_t runs = context.options.quick ? 150 : 465;  // §5.5: 930 flights, CMA and NoOp
  const CampaignConfig config = LoadProfile(context, "campaign.yaml", runs, context.options.seed);
  context.Log(
      fmt::format("campaign-default: {} runs x 2 policies (examples/campaign.yaml, seed {})", runs, config.seed));
  const std::vector<RunRecord> records = Fly(config, context);
  const std::vector<GroupStatistics> groups = campaign::Summarise(records, {"cma", "noop"});
  item.samples = {{"runs", runs}, {"flights", records.size()}};
  const GroupStatistics& noop_p = Group(groups, "noop", "P");
  item.quantities.push_back(CompareRate(
      "NoOp failure rate, poor health", noop_p.failures, noop_p.runs, 0.71,
      "the abstract's 71 %, our rate's 95 % Wilson interval",
      fmt::format("A setting the dissertation does not print: our plans last 0.5-0.9 of a healthy pack's endurance "
                  "(docs/modelling-choices.md#campaign-missions, ours), and a capacity-faded cell ends a flight only "
                  "above ~0.8 of it, so NoOp fails "
                  "{:.1f} %; the dissertation profile (docs/modelling-choices.md#dissertation-profile) calibrates the "
                  "range to 71 %.",
                  100.0 * noop_p.failure_rate.value)));
  AddShapeQuantities(item, groups,
                     "The CMA fails fewer poor-health flights than the dissertation's 1.3 % "
                     "(docs/modelling-choices.md#outcomes-refined, #eod-load-forecast, #unavailable-actions: "
                     "grounding, the load forecast, substitutions).");
  item.data["groups"] = GroupsJson(groups);
  AddCampaignFigures(item, "campaign-default", groups);
  item.notes.push_back(
      "`uascma campaign examples/campaign.yaml --runs N --seed S`: the same flights (ExecuteFlights).");
  return item;
}

namespace {

// NoOp's poor-health failure rate with plans drawn on [low, high] of a healthy pack's endurance: only P batteries,
// only NoOp, `runs` runs of `seed`.
campaign::RateEstimate PoorHealthRate(const Context& context, CampaignConfig config, double low,
                                      const std::vector<std::string>& policies, const std::string& policy,
                                      std::vector<RunRecord>* all = nullptr) {
  config.mission.endurance_fraction.low = low;
  config.battery.health_weights = {0.0, 0.0, 1.0};
  config.policies = policies;
  const std::vector<RunRecord> records = Fly(config, context);
  std::int64_t failures = 0, n = 0;
  for (const RunRecord& r : records) {
    if (r.policy != policy) continue;
    n += 1;
    failures += r.failure ? 1 : 0;
  }
  if (all != nullptr) *all = records;
  return campaign::EstimateRateWithIntervals(failures, n);
}

}  // namespace

namespace {

struct Calibration {
  double result = 0.0;
  nlohmann::json steps = nlohmann::json::array();
};

// The dissertation profile (docs/modelling-choices.md#dissertation-profile). The one parameter: the low end L of the
// plan-length range [L, high] (the high end stays the default's 0.9, the longest plan a healthy pack flies with its
// margin in the vehicle's own judgement, campaign/config.h). NoOp's P failure rate rises with L; bisection on [0.5,
// high] to 71 %, every step on the same flights (seed S, common random numbers), so the rate is a step function of L
// alone.
Calibration CalibrateLowEnd(const Context& context, const CampaignConfig& profile, std::int64_t runs, int steps) {
  Calibration calibration;
  double lo = 0.5, hi = profile.mission.endurance_fraction.high;
  CampaignConfig config = profile;
  config.runs = runs;
  config.seed = context.options.seed;
  for (int step = 1; step <= steps; ++step) {
    const double mid = 0.5 * (lo + hi);
    const campaign::RateEstimate rate = PoorHealthRate(context, config, mid, {"noop"}, "noop");
    const double value = rate.estimate.value;
    context.Log(fmt::format("  calibration step {}: L = {:.4f}: NoOp fails {} of {} P flights ({:.1f} %)", step, mid,
                            rate.count, runs, 100.0 * value));
    calibration.steps.push_back(
        {{"step", step}, {"low_fraction", mid}, {"failures", rate.count}, {"runs", runs}, {"rate", value}});
    (value < 0.71 ? lo : hi) = mid;
  }
  calibration.result = 0.5 * (lo + hi);
  return calibration;
}

// The campaign's sensitivity to the setting the dissertation does not print: poor-health failure rates of NoOp and
// the CMA against L, on the calibration's seed.
void AddPlanLengthSensitivity(const Context& context, const CampaignConfig& profile, Item& item) {
  const std::int64_t runs = context.options.quick ? 60 : 200;
  const double high = profile.mission.endurance_fraction.high;
  nlohmann::json xs = nlohmann::json::array(), noop = nlohmann::json::array(), cma = nlohmann::json::array();
  for (const double low : {0.5, 0.6, 0.7, 0.8, 0.9}) {
    CampaignConfig sweep = profile;
    sweep.runs = runs;
    sweep.seed = context.options.seed;
    std::vector<RunRecord> flown;
    const campaign::RateEstimate n = PoorHealthRate(context, sweep, low, {"cma", "noop"}, "noop", &flown);
    std::int64_t cma_failures = 0, cma_runs = 0;
    for (const RunRecord& r : flown) {
      if (r.policy != "cma") continue;
      cma_runs += 1;
      cma_failures += r.failure ? 1 : 0;
    }
    xs.push_back(low);
    noop.push_back(100.0 * n.estimate.value);
    cma.push_back(100.0 * static_cast<double>(cma_failures) / static_cast<double>(std::max<std::int64_t>(1, cma_runs)));
  }
  item.samples["sensitivity_runs_per_point"] = runs;
  item.data["sensitivity"] = {{"low_fraction", xs}, {"noop_rate_pct", noop}, {"cma_rate_pct", cma}};
  item.figures.push_back(
      {"campaign-plan-length.png",
       fmt::format(
           "Poor-health failure rates against the plan-length range [L, {:g}] (the dissertation profile's parameter); "
           "dotted: the dissertation's 71 % and 1.3 %, and the profile's L",
           high),
       {{"kind", "lines"},
        {"xlabel", fmt::format("L, plans on [L, {:g}] of a healthy pack's endurance", high)},
        {"ylabel", "poor-health failure rate (%)"},
        {"series", {{{"label", "NoOp"}, {"x", xs}, {"y", noop}}, {{"label", "CMA"}, {"x", xs}, {"y", cma}}}},
        {"hlines", {71.0, 1.3}},
        {"vline", profile.mission.endurance_fraction.low}}});
}

void AddFlyability(const std::vector<RunRecord>& records, Item& item) {
  std::int64_t healthy_battery_failures = 0, healthy_fault_free = 0;
  for (const RunRecord& r : records) {
    if (r.battery_health != "G" || r.fault) continue;
    healthy_fault_free += 1;
    healthy_battery_failures += campaign::FailureCauseOf(r.outcome) == campaign::FailureCause::kBattery ? 1 : 0;
  }
  item.quantities.push_back(CompareAbsolute(
      "healthy fault-free flights failing their battery", healthy_battery_failures, 0.0,
      fmt::format("of {}", healthy_fault_free), 0.0,
      "docs/modelling-choices.md#campaign-missions, #dissertation-profile: every plan is flyable by a healthy pack "
      "with its margin",
      "Plans near the range's top are not flyable by a healthy pack over their whole load "
      "(docs/modelling-choices.md#dissertation-profile asks for the "
      "climb, descent and gusts in the flyability, which the sampler's cruise-current EOD leaves out)."));
}

}  // namespace

// The dissertation profile: the calibration re-run (its steps printed), then the profile as the file states it flown
// with both policies on fresh flights (seed S + 1: the calibration's flights are not the prediction's).
Item ReproduceCampaignDissertation(const Context& context) {
  Item item;
  item.source = "docs/modelling-choices.md#dissertation-profile; abstract (1.3 %, 71 %), §5.5.3, Figs. 5.30-5.32";
  const bool quick = context.options.quick;
  const std::int64_t calibration_runs = quick ? 100 : 300;
  const int steps = quick ? 5 : 7;
  CampaignConfig profile = LoadProfile(context, "campaign-dissertation.yaml", calibration_runs, context.options.seed);
  const double file_low = profile.mission.endurance_fraction.low;
  const double high = profile.mission.endurance_fraction.high;
  context.Log(fmt::format("campaign-dissertation: calibration, {} bisection steps of {} NoOp P flights (seed {})",
                          steps, calibration_runs, context.options.seed));
  const Calibration calibration = CalibrateLowEnd(context, profile, calibration_runs, steps);
  item.data["calibration"] = {{"parameter", "mission.endurance_fraction low end L, high end fixed"},
                              {"high", high},
                              {"target", 0.71},
                              {"seed", context.options.seed},
                              {"runs_per_step", calibration_runs},
                              {"steps", calibration.steps},
                              {"result", calibration.result}};
  item.samples["calibration_runs_per_step"] = calibration_runs;
  item.samples["calibration_steps"] = steps;
  const double resolution = (high - 0.5) / static_cast<double>(1 << steps);
  item.quantities.push_back(CompareAbsolute(
      "calibrated L (this run) vs examples/campaign-dissertation.yaml", calibration.result, file_low, "",
      2.0 * resolution,
      fmt::format("the file holds the full run's result (7 steps of 300 flights, seed 1); two of this run's bisection "
                  "intervals, (0.9 - 0.5) / 2^{} each",
                  steps),
      fmt::format("This run's calibration ({} steps of {} flights, seed {}) gives {:.4f}; the file holds the full "
                  "run's (7 x 300, seed 1), and a smaller or other-seed sample resolves L only to its own noise.",
                  steps, calibration_runs, context.options.seed, calibration.result),
      4));

  const std::int64_t runs = quick ? 150 : 465;
  profile.runs = runs;
  profile.seed = context.options.seed + 1;
  context.Log(
      fmt::format("campaign-dissertation: {} runs x 2 policies, L = {:.4f} (seed {})", runs, file_low, profile.seed));
  const std::vector<RunRecord> records = Fly(profile, context);
  const std::vector<GroupStatistics> groups = campaign::Summarise(records, {"cma", "noop"});
  item.samples["runs"] = runs;
  item.samples["flights"] = records.size();
  const GroupStatistics& noop_p = Group(groups, "noop", "P");
  item.quantities.push_back(
      CompareRate("NoOp failure rate, poor health (calibrated)", noop_p.failures, noop_p.runs, 0.71,
                  "the calibration target, on fresh flights (seed S + 1): the calibration's own "
                  "result with its interval",
                  fmt::format("On the profile's fresh flights NoOp fails {:.1f} %: the "
                              "calibration's rate carries a binomial standard error of {:.1f} "
                              "points ({} flights a step), and this sample's own is {:.1f}.",
                              100.0 * noop_p.failure_rate.value, 100.0 * std::sqrt(0.71 * 0.29 / calibration_runs),
                              calibration_runs, 100.0 * noop_p.failure_rate.sem)));
  AddShapeQuantities(item, groups,
                     "A prediction: the CMA fails fewer poor-health flights than the dissertation's "
                     "1.3 % (docs/modelling-choices.md#outcomes-refined, #eod-load-forecast, #unavailable-actions: "
                     "grounding, the load forecast, substitutions).");
  AddFlyability(records, item);
  // The headline is the prediction: the calibration's own check goes last.
  std::rotate(item.quantities.begin(), item.quantities.begin() + 1, item.quantities.end());
  const GroupStatistics& cma_all = Group(groups, "cma", "all");
  item.data["groups"] = GroupsJson(groups);
  item.data["cma_grounded_rate"] = cma_all.grounded_rate.value;
  item.data["cma_emergency_landing_rate"] = cma_all.emergency_landing_rate.value;
  AddCampaignFigures(item, "campaign-dissertation", groups);
  AddPlanLengthSensitivity(context, profile, item);
  item.notes.push_back(
      fmt::format("The one calibrated setting of this report (docs/modelling-choices.md#dissertation-profile): L, by "
                  "{} bisection steps of {} NoOp poor-health "
                  "flights each (seed {}); result {:.4f}; the file's {:.4f} is the full run's.",
                  steps, calibration_runs, context.options.seed, calibration.result, file_low));
  return item;
}

}  // namespace uascma::reproduce
