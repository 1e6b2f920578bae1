#include "uascma/campaign/battery_evaluation.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>
#include <set>
#include <thread>

#include <fmt/format.h>

#include "uascma/common/error.h"

namespace uascma::campaign {
namespace {

using decision::BatteryContext;
using decision::StateIndex;
using models::HealthClass;
using models::PackAction;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

const char* KindName(BatteryPolicyKind kind) {
  switch (kind) {
    case BatteryPolicyKind::kUseBoth: return "useboth";
    case BatteryPolicyKind::kVoltageRule: return "rule:voltage";
    case BatteryPolicyKind::kPiStar: return "pistar";
    case BatteryPolicyKind::kOurs: return "ours";
  }
  return "?";
}

double Median(std::vector<double> values) {
  if (values.empty()) return kNaN;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

double Mean(const std::vector<double>& values) {
  if (values.empty()) return kNaN;
  double sum = 0.0;
  for (double v : values) sum += v;
  return sum / static_cast<double>(values.size());
}

nlohmann::json Number(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr); }

BatteryPolicyFlight Summarise(const BatteryFlightResult& result) {
  BatteryPolicyFlight flight;
  flight.outcome = result.outcome;
  flight.end_time_s = result.end_time_s;
  flight.switches = CountSwitches(result);
  flight.charge_left_ah = result.charge_left_ah[0] + result.charge_left_ah[1];
  flight.energy_used_wh = result.energy_used_wh;
  return flight;
}

BatteryPolicySummary SummariseFlights(const std::string& label, const std::vector<const BatteryPolicyFlight*>& flights) {
  BatteryPolicySummary out;
  out.label = label;
  std::vector<double> failure_times, charge_left, switches;
  for (const BatteryPolicyFlight* f : flights) {
    ++out.runs;
    if (f->completed()) {
      ++out.completions;
      charge_left.push_back(f->charge_left_ah);
    } else {
      ++out.failures;  // every outcome but completion: the battery flights fail only on the battery (Table 4.1)
      failure_times.push_back(f->end_time_s);
    }
    switches.push_back(f->switches);
    out.max_switches = std::max(out.max_switches, f->switches);
  }
  out.completion_wilson = WilsonInterval(out.completions, out.runs);
  out.median_failure_time_s = Median(failure_times);
  out.mean_charge_left_ah = Mean(charge_left);
  out.median_switches = Median(switches);
  out.mean_switches = Mean(switches);
  return out;
}

nlohmann::json SummaryJson(const BatteryPolicySummary& s) {
  return {{"policy", s.label},
          {"runs", s.runs},
          {"completions", s.completions},
          {"failures", s.failures},
          {"completion_rate", s.runs > 0 ? Number(static_cast<double>(s.completions) / static_cast<double>(s.runs)) : nullptr},
          {"completion_wilson_low", Number(s.completion_wilson.low)},
          {"completion_wilson_high", Number(s.completion_wilson.high)},
          {"median_failure_time_s", Number(s.median_failure_time_s)},
          {"mean_charge_left_ah_completed", Number(s.mean_charge_left_ah)},
          {"median_switches", Number(s.median_switches)},
          {"mean_switches", Number(s.mean_switches)},
          {"max_switches", s.max_switches}};
}

}  // namespace

// ================================ policies ========================================================
std::vector<BatteryPolicySpec> ParseBatteryPolicies(const std::string& text, const std::string& option) {
  std::vector<BatteryPolicySpec> specs;
  std::set<std::string> seen;
  std::size_t begin = 0;
  while (begin <= text.size()) {
    const std::size_t end = std::min(text.find(',', begin), text.size());
    const std::string item = text.substr(begin, end - begin);
    begin = end + 1;
    BatteryPolicySpec spec;
    const std::size_t colon = item.find(':');
    const std::string name = item.substr(0, colon);
    const std::string argument = colon == std::string::npos ? "" : item.substr(colon + 1);
    if (name == "useboth" && argument.empty()) {
      spec.kind = BatteryPolicyKind::kUseBoth;
    } else if (name == "rule" && (argument == "voltage" || argument.rfind("voltage:", 0) == 0)) {
      spec.kind = BatteryPolicyKind::kVoltageRule;
      if (argument != "voltage") {
        const std::string value = argument.substr(std::string("voltage:").size());
        try {
          std::size_t used = 0;
          spec.drop_voltage_v = std::stod(value, &used);
          if (used != value.size()) throw std::invalid_argument("trailing characters");
        } catch (const std::exception&) {
          throw InputError(option, item, fmt::format("rule:voltage:V with V a number of volts, got '{}'", value));
        }
        // Between the 3.3 V cut-off (Table 4.1) and a full cell (4.2 V).
        if (!(spec.drop_voltage_v >= models::kCutoffVoltage && spec.drop_voltage_v <= 4.2)) {
          throw InputError(option, item, fmt::format("a drop voltage in [3.3, 4.2] V, got {}", spec.drop_voltage_v));
        }
      }
    } else if ((name == "pistar" || name == "ours") && !argument.empty()) {
      spec.kind = name == "pistar" ? BatteryPolicyKind::kPiStar : BatteryPolicyKind::kOurs;
      spec.file = argument;
      auto policies = std::make_shared<decision::BatteryPolicySet>(decision::ReadBatteryPolicyFile(spec.file));
      const auto wanted =
          name == "pistar" ? decision::BatteryFormulation::kDissertation : decision::BatteryFormulation::kOurs;
      if (policies->formulation != wanted) {
        throw InputError(spec.file.string(), "formulation",
                         fmt::format("'{}' for {}: (battery solve{}), got '{}'", decision::BatteryFormulationName(wanted),
                                     name, name == "ours" ? " --formulation ours" : "",
                                     decision::BatteryFormulationName(policies->formulation)));
      }
      spec.policies = std::move(policies);
    } else {
      throw InputError(option, item.empty() ? "(empty)" : item,
                       "useboth | pistar:POLICY.json | ours:POLICY.json | rule:voltage[:V], separated by commas");
    }
    spec.label = KindName(spec.kind);
    if (!seen.insert(spec.label).second) throw InputError(option, item, "each policy once");
    specs.push_back(std::move(spec));
    if (end == text.size()) break;
  }
  return specs;
}

BatteryFlightController MakeBatteryController(const BatteryPolicySpec& spec, const BatteryContext& context) {
  BatteryFlightController out;
  out.initial_switches = PackAction::kUseBoth;
  switch (spec.kind) {
    case BatteryPolicyKind::kUseBoth:
      out.controller = [](double, const decision::BatteryObservation&, StateIndex) { return PackAction::kUseBoth; };
      break;
    case BatteryPolicyKind::kPiStar: {
      UASCMA_CHECK(spec.policies != nullptr, "a policy file read for pistar");
      auto executor = std::make_shared<decision::BatteryPolicyExecutor>(*spec.policies, context);
      out.controller = [executor](double, const decision::BatteryObservation&, StateIndex s) {
        return executor->Decide(s);
      };
      break;
    }
    case BatteryPolicyKind::kOurs: {
      UASCMA_CHECK(spec.policies != nullptr, "a policy file read for ours");
      auto executor = std::make_shared<decision::BatteryPolicyExecutor>(*spec.policies, context);
      out.observe_pair_eod = true;
      out.controller = [executor](double, const decision::BatteryObservation& observation, StateIndex s) {
        if (const auto guard = OursImminentFailureGuard(observation)) return *guard;
        return executor->Decide(s);
      };
      break;
    }
    case BatteryPolicyKind::kVoltageRule: {
      // The pack dropped (−1: none), kept across epochs of this one flight.
      auto dropped = std::make_shared<int>(-1);
      const double drop_v = spec.drop_voltage_v;
      out.controller = [dropped, drop_v](double, const decision::BatteryObservation& observation, StateIndex) {
        if (*dropped < 0) {
          for (int j = 0; j < models::kBranchCount; ++j) {
            const double v = observation.actual_min_cell_voltage_v[j];
            if (observation.switch_on[j] && v >= 0.0 && v < drop_v) {
              *dropped = j;
              break;
            }
          }
        }
        if (*dropped == 0) return PackAction::kUseBatt2;
        if (*dropped == 1) return PackAction::kUseBatt1;
        return PackAction::kUseBoth;
      };
      break;
    }
  }
  return out;
}

std::optional<PackAction> OursImminentFailureGuard(const decision::BatteryObservation& observation) {
  if (!(observation.switch_on[0] && observation.switch_on[1])) return std::nullopt;  // already one pack
  const double eod_s = observation.pair_eod_s;
  const int limiting = observation.pair_limiting_branch;
  if (!std::isfinite(eod_s) || limiting < 0) return std::nullopt;
  // FAILURE (Table 4.1) before the end of the plan and within the safety margin t_sf: drop the limiting pack.
  if (eod_s < observation.remaining_flight_s && eod_s < observation.safety_margin_s) {
    return limiting == 0 ? PackAction::kUseBatt2 : PackAction::kUseBatt1;
  }
  return std::nullopt;
}

std::string SwitchSchedule::Describe() const {
  std::string out;
  for (const auto& [time_s, action] : steps) {
    out += fmt::format("{}{}@{:.0f}", out.empty() ? "" : " ", models::PackActionName(action), time_s);
  }
  return out;
}

BatteryFlightController ScheduleController(const SwitchSchedule& schedule) {
  UASCMA_CHECK(!schedule.steps.empty() && schedule.steps.front().first <= 0.0, "a schedule from 0 s");
  auto steps = std::make_shared<const std::vector<std::pair<double, PackAction>>>(schedule.steps);
  BatteryFlightController out;
  out.initial_switches = PackAction::kUseBoth;
  out.controller = [steps](double time_s, const decision::BatteryObservation&, StateIndex) {
    PackAction action = steps->front().second;
    for (const auto& [from_s, step_action] : *steps) {
      if (time_s + 1e-9 >= from_s) action = step_action;
    }
    return action;
  };
  return out;
}

int CountSwitches(const BatteryFlightResult& result) {
  int count = 0;
  PackAction previous = PackAction::kUseBoth;
  for (const auto& [time_s, action] : result.switches) {
    if (action != previous) ++count;
    previous = action;
  }
  return count;
}

// ================================ evaluation ======================================================
BatteryEvaluation EvaluateBatteryPolicies(const std::vector<BatteryPolicySpec>& policies,
                                          const BatteryEvaluationOptions& options) {
  if (policies.empty()) throw InputError("--policies", "value", "at least one policy");
  if (options.runs < 1) throw InputError("--runs", "value", fmt::format("at least 1 flight, got {}", options.runs));
  if (options.jobs < 1) throw InputError("--jobs", "value", fmt::format("at least 1 thread, got {}", options.jobs));
  const auto start = std::chrono::steady_clock::now();
  BatteryEvaluation out;
  out.seed = options.seed;
  for (const auto& p : policies) out.labels.push_back(p.label);
  out.runs.resize(static_cast<std::size_t>(options.runs));
  std::atomic<std::int64_t> next_run{0}, done{0};
  auto worker = [&] {
    std::vector<BatteryFlightController> controllers;
    for (std::int64_t r = next_run++; r < options.runs; r = next_run++) {
      BatteryEvaluationRun& run = out.runs[static_cast<std::size_t>(r)];
      run.run = r;
      run.params = SampleBatteryFlight(options.ranges, options.seed, r);
      controllers.clear();
      for (const auto& p : policies) controllers.push_back(MakeBatteryController(p, run.params.context()));
      // Every policy on the one flight: the same params value, flown together (bit-identical to alone).
      const std::vector<BatteryFlightResult> results = FlyBatteryFlights(run.params, controllers);
      for (const auto& result : results) run.flights.push_back(Summarise(result));
      const std::int64_t count = ++done;
      if (options.on_run_done) options.on_run_done(count);
    }
  };
  std::vector<std::thread> threads;
  for (int j = 1; j < options.jobs; ++j) threads.emplace_back(worker);
  worker();
  for (auto& thread : threads) thread.join();

  const std::size_t n = policies.size();
  auto column = [&](std::size_t k, const std::function<bool(const BatteryEvaluationRun&)>& keep) {
    std::vector<const BatteryPolicyFlight*> flights;
    for (const auto& run : out.runs) {
      if (keep(run)) flights.push_back(&run.flights[k]);
    }
    return flights;
  };
  for (std::size_t k = 0; k < n; ++k) {
    out.overall.push_back(SummariseFlights(out.labels[k], column(k, [](const BatteryEvaluationRun&) { return true; })));
  }
  for (int c = 0; c < decision::kBatteryNumContexts; ++c) {
    const BatteryContext context = decision::BatteryContextFromIndex(c);
    BatteryContextSummary group;
    group.context = context;
    for (std::size_t k = 0; k < n; ++k) {
      group.policies.push_back(SummariseFlights(
          out.labels[k], column(k, [&context](const BatteryEvaluationRun& run) { return run.params.context() == context; })));
    }
    if (group.policies.front().runs > 0) out.by_context.push_back(std::move(group));
  }
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t b = a + 1; b < n; ++b) {
      BatteryPairComparison cmp;
      cmp.first = out.labels[a];
      cmp.second = out.labels[b];
      for (const auto& run : out.runs) {
        const bool first = run.flights[a].completed(), second = run.flights[b].completed();
        ++cmp.pairs;
        if (first && second) ++cmp.both_completed;
        else if (!first && !second) ++cmp.neither_completed;
        else if (first) ++cmp.only_first_completed;
        else ++cmp.only_second_completed;
      }
      cmp.exact_p = CalcMcNemarTest(cmp.only_first_completed, cmp.only_second_completed).exact_p;
      out.comparisons.push_back(cmp);
    }
  }
  out.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

nlohmann::json BatteryEvaluationJson(const BatteryEvaluation& evaluation, bool with_runs) {
  nlohmann::json overall = nlohmann::json::array(), contexts = nlohmann::json::array(),
                 comparisons = nlohmann::json::array();
  for (const auto& s : evaluation.overall) overall.push_back(SummaryJson(s));
  for (const auto& group : evaluation.by_context) {
    nlohmann::json per_policy = nlohmann::json::array();
    for (const auto& s : group.policies) per_policy.push_back(SummaryJson(s));
    contexts.push_back({{"context", decision::BatteryContextLabel(group.context)},
                        {"b1", decision::BatteryHealthName(group.context.b1)},
                        {"b2", decision::BatteryHealthName(group.context.b2)},
                        {"temperature", decision::TemperatureClassName(group.context.temperature)},
                        {"policies", per_policy}});
  }
  for (const auto& c : evaluation.comparisons) {
    comparisons.push_back({{"policies", {c.first, c.second}},
                           {"pairs", c.pairs},
                           {"both_completed", c.both_completed},
                           {"neither_completed", c.neither_completed},
                           {"only_first_completed", c.only_first_completed},
                           {"only_second_completed", c.only_second_completed},
                           {"mcnemar_exact_p", c.exact_p}});
  }
  nlohmann::json json = {{"policies", evaluation.labels},
                         {"seed", evaluation.seed},
                         {"runs", evaluation.runs.size()},
                         {"confidence_level", kConfidenceLevel},
                         {"overall", overall},
                         {"by_context", contexts},
                         {"paired_comparisons", comparisons},
                         {"wall_time_s", evaluation.wall_time_s}};
  if (with_runs) {
    nlohmann::json runs = nlohmann::json::array();
    for (const auto& run : evaluation.runs) {
      nlohmann::json flights = nlohmann::json::array();
      for (const auto& f : run.flights) {
        flights.push_back({{"outcome", sim::OutcomeName(f.outcome)},
                           {"end_time_s", f.end_time_s},
                           {"switches", f.switches},
                           {"charge_left_ah", f.charge_left_ah},
                           {"energy_used_wh", f.energy_used_wh}});
      }
      runs.push_back({{"run", run.run},
                      {"context", decision::BatteryContextLabel(run.params.context())},
                      {"plan_duration_s", run.params.plan_duration_s},
                      {"flights", flights}});
    }
    json["runs_detail"] = runs;
  }
  return json;
}

std::string BatteryEvaluationText(const BatteryEvaluation& evaluation) {
  std::string out = fmt::format(
      "battery policies on {} paired flights of Table 4.4's draw (seed {}), every policy on the same flight\n\n",
      evaluation.runs.size(), evaluation.seed);
  out += "policy        completed   95% Wilson        failed  median failure s  charge left Ah  switches median/mean/max\n";
  for (const auto& s : evaluation.overall) {
    out += fmt::format("{:<13} {:>4}/{:<5} [{:5.1f}%, {:5.1f}%]  {:>6}  {:>16.0f}  {:>14.3f}  {:>6.0f} / {:.1f} / {}\n", s.label,
                       s.completions, s.runs, 100.0 * s.completion_wilson.low, 100.0 * s.completion_wilson.high,
                       s.failures, s.median_failure_time_s, s.mean_charge_left_ah, s.median_switches, s.mean_switches,
                       s.max_switches);
  }
  out += "\npaired completions (McNemar, exact two-sided p): only A completed / only B completed\n";
  for (const auto& c : evaluation.comparisons) {
    out += fmt::format("  {:<13} vs {:<13} {:>4} / {:<4} both {:>4}, neither {:>4}   p = {:.4g}\n", c.first, c.second,
                       c.only_first_completed, c.only_second_completed, c.both_completed, c.neither_completed, c.exact_p);
  }
  out += "\ncompleted per health pair and temperature (Table 4.2), runs in brackets\ncontext    ";
  for (const auto& label : evaluation.labels) out += fmt::format(" {:>13}", label);
  out += "\n";
  for (const auto& group : evaluation.by_context) {
    out += fmt::format("{:<10} ", decision::BatteryContextLabel(group.context));
    for (const auto& s : group.policies) out += fmt::format(" {:>7}/{:<5}", s.completions, fmt::format("{}", s.runs));
    out += "\n";
  }
  out += fmt::format("\n{:.1f} s wall\n", evaluation.wall_time_s);
  return out;
}

// ================================ case studies ====================================================
namespace {

models::PerCell<models::CellHealth> CellHealthOf(const models::PerBranch<HealthClass>& health) {
  models::PerCell<models::CellHealth> cells{};
  for (int j = 0; j < models::kBranchCount; ++j) {
    for (auto& cell : cells[j]) cell = models::CellHealthForClass(health[j]);
  }
  return cells;
}

std::string PairName(HealthClass b1, HealthClass b2) {
  return fmt::format("({},{})", decision::BatteryHealthName(b1), decision::BatteryHealthName(b2));
}

// Best of the family in hindsight: a completed flight first (then the most charge left, then the fewest switches),
// else the latest failure.
bool Better(const BatteryFlightResult& a, const BatteryFlightResult& b) {
  const bool ac = a.outcome == sim::Outcome::kCompleted, bc = b.outcome == sim::Outcome::kCompleted;
  if (ac != bc) return ac;
  if (ac) {
    const double qa = a.charge_left_ah[0] + a.charge_left_ah[1], qb = b.charge_left_ah[0] + b.charge_left_ah[1];
    if (qa != qb) return qa > qb;
    return CountSwitches(a) < CountSwitches(b);
  }
  return a.end_time_s > b.end_time_s;
}

}  // namespace

BatteryFlightParams CaseFlightParams(const BatteryContext& context, double plan_duration_s) {
  // One representative package drop (§4.3.3, Fig. 4.6), the same for every scenario: Table 4.4's middle
  // values, cells at 4.1 V (ours); the context's temperature (77 °F warm, 40 °F cold as the learning draw).
  BatteryFlightParams p;
  p.seed = 1;
  p.safety_margin_s = 7.5;
  p.initial_cell_voltage_v = {{{4.1, 4.1, 4.1}, {4.1, 4.1, 4.1}}};
  p.cruise_speed_mps = 5.0;
  p.wind_speed_mps = 2.0;
  p.wind_direction_rad = 1.0;
  p.turbulence = models::TurbulenceCategory::kLowLight;
  p.health = {context.b1, context.b2};
  p.cells = CellHealthOf(p.health);
  const BatteryFlightRanges ranges;
  p.ambient_temp_degf = context.temperature == decision::TemperatureClass::kLow ? ranges.cold_temp_degf : ranges.warm_temp_degf;
  p.plan_duration_s = plan_duration_s;
  return p;
}

StateIndex TakeoffState(const BatteryFlightParams& params) {
  // What FlyBatteryFlights' first epoch sees: the initial state with the take-off switches (UseBoth).
  const sim::FlightModel model(MakeBatteryScenario(params));
  sim::FlightState state = sim::MakeInitialState(model, params.seed);
  sim::SwitchPacks(state, PackAction::kUseBoth);
  return decision::AbstractBatteryState(ObserveBatteryFlight(model, state));
}

std::vector<SwitchSchedule> HindsightSchedules(double plan_duration_s, double window_grid_s, double switch_grid_s) {
  UASCMA_CHECK(window_grid_s > 0.0 && switch_grid_s > 0.0 && plan_duration_s > 0.0, "positive grids and plan");
  std::vector<SwitchSchedule> out;
  out.push_back({{{0.0, PackAction::kUseBoth}}});
  // (a) UseBoth, then pack k alone for good from t (t > 0 on the fine grid).
  for (PackAction alone : {PackAction::kUseBatt1, PackAction::kUseBatt2}) {
    for (double t = switch_grid_s; t < plan_duration_s; t += switch_grid_s) {
      out.push_back({{{0.0, PackAction::kUseBoth}, {t, alone}}});
    }
  }
  // (b) UseBoth with one window [t1, t2) of pack k alone on the coarse grid (t2 = the end: for good, from t1 = 0
  // only, the rest being in (a)).
  std::vector<double> times;
  for (double t = 0.0; t < plan_duration_s; t += window_grid_s) times.push_back(t);
  for (PackAction alone : {PackAction::kUseBatt1, PackAction::kUseBatt2}) {
    for (std::size_t i = 0; i < times.size(); ++i) {
      for (std::size_t j = i + 1; j <= times.size(); ++j) {
        if (j == times.size() && i > 0) continue;  // in (a)
        SwitchSchedule s;
        if (times[i] > 0.0) s.steps.emplace_back(0.0, PackAction::kUseBoth);
        s.steps.emplace_back(times[i], alone);
        if (j < times.size()) s.steps.emplace_back(times[j], PackAction::kUseBoth);
        out.push_back(std::move(s));
      }
    }
  }
  return out;
}

std::vector<CaseScenario> RunCaseStudy(int number, const CaseStudyOptions& options) {
  if (number < 1 || number > 4) throw InputError("case-study", "N", fmt::format("1, 2, 3 or 4 (Table 4.5), got {}", number));
  const bool uses_policy = number == 2 || number == 4;
  if (uses_policy && options.pistar == nullptr) throw InputError("case-study", "--policy", "a battery policy file for pi*");
  std::vector<std::pair<HealthClass, HealthClass>> pairs;
  double plan_duration_s = 0.0;
  if (number <= 2) {
    // "battery pack EOD time is twice the flight time": the plan lasts one healthy pack's EOD.
    plan_duration_s = ReferenceBatteryEod(PackAction::kUseBatt1);
    for (int b1 = 0; b1 < 3; ++b1) {
      for (int b2 = 0; b2 < 3; ++b2) pairs.emplace_back(static_cast<HealthClass>(b1), static_cast<HealthClass>(b2));
    }
  } else {
    plan_duration_s = kCaseFlightFraction * ReferenceBatteryEod(PackAction::kUseBoth);  // decision 26
    if (number == 3) {
      pairs = {{HealthClass::kG, HealthClass::kM}, {HealthClass::kG, HealthClass::kP}, {HealthClass::kP, HealthClass::kP}};
    } else {
      pairs = {{HealthClass::kM, HealthClass::kG}};
    }
  }
  std::vector<CaseScenario> scenarios;
  for (const auto& [b1, b2] : pairs) {
    BatteryFlightParams params = CaseFlightParams({b1, b2, decision::TemperatureClass::kHigh}, plan_duration_s);
    params.seed = options.seed;
    if (number == 4) {
      // Fig. 4.11's caption: "Batt1 has one cell with capacity fade and Batt2 is healthy" (an F2 pack of
      // Table 4.2); the other cases' packs are as their captions say, every cell faded (Figs. 4.9, 4.10).
      params.cells[0] = {};
      params.cells[0][0].capacity_fade = true;
    }
    // UseBoth (§4.3.3: "a similar scenario can be set up with a single action of UseBoth"), then each learned
    // policy beside it on the same flight.
    std::vector<std::pair<std::string, BatteryFlightController>> flown;
    BatteryPolicySpec useboth;
    flown.emplace_back("UseBoth", MakeBatteryController(useboth, params.context()));
    if (uses_policy) {
      BatteryPolicySpec pistar;
      pistar.kind = BatteryPolicyKind::kPiStar;
      pistar.policies = std::shared_ptr<const decision::BatteryPolicySet>(options.pistar, [](const auto*) {});
      flown.emplace_back("pi*", MakeBatteryController(pistar, params.context()));
      BatteryPolicySpec rule;
      rule.kind = BatteryPolicyKind::kVoltageRule;
      flown.emplace_back("rule:voltage", MakeBatteryController(rule, params.context()));
      if (options.ours != nullptr) {
        BatteryPolicySpec ours;
        ours.kind = BatteryPolicyKind::kOurs;
        ours.policies = std::shared_ptr<const decision::BatteryPolicySet>(options.ours, [](const auto*) {});
        flown.emplace_back("ours", MakeBatteryController(ours, params.context()));
      }
    }
    std::vector<BatteryFlightController> controllers;
    for (const auto& f : flown) controllers.push_back(f.second);
    const std::vector<BatteryFlightResult> results = FlyBatteryFlights(params, controllers);
    for (std::size_t k = 0; k < flown.size(); ++k) {
      CaseScenario scenario;
      scenario.name = PairName(b1, b2);
      scenario.params = params;
      scenario.controller = flown[k].first;
      scenario.result = results[k];
      scenarios.push_back(std::move(scenario));
    }
    if (number == 4 && options.hindsight) {
      const std::vector<SwitchSchedule> family = HindsightSchedules(plan_duration_s);
      std::vector<BatteryFlightController> schedules;
      for (const auto& s : family) schedules.push_back(ScheduleController(s));
      const std::vector<BatteryFlightResult> tried = FlyBatteryFlights(params, schedules);
      std::size_t best = 0;
      for (std::size_t k = 1; k < tried.size(); ++k) {
        if (Better(tried[k], tried[best])) best = k;
      }
      CaseScenario scenario;
      scenario.name = PairName(b1, b2);
      scenario.params = params;
      scenario.controller = "hindsight-best";
      scenario.schedule = family[best].Describe();
      scenario.schedules_flown = static_cast<int>(family.size());
      scenario.result = tried[best];
      scenarios.push_back(std::move(scenario));
    }
  }
  return scenarios;
}

nlohmann::json CaseStudyJson(int number, const std::vector<CaseScenario>& scenarios) {
  nlohmann::json out = nlohmann::json::array();
  for (const CaseScenario& scenario : scenarios) {
    nlohmann::json switches = nlohmann::json::array();
    for (const auto& [time_s, action] : scenario.result.switches) {
      switches.push_back({{"time_s", time_s}, {"action", models::PackActionName(action)}});
    }
    const BatteryContext context = scenario.params.context();
    nlohmann::json entry = {{"name", scenario.name},
                            {"b1", decision::BatteryHealthName(context.b1)},
                            {"b2", decision::BatteryHealthName(context.b2)},
                            {"temperature", decision::TemperatureClassName(context.temperature)},
                            {"controller", scenario.controller},
                            {"seed", scenario.params.seed},
                            {"plan_duration_s", scenario.params.plan_duration_s},
                            {"outcome", sim::OutcomeName(scenario.result.outcome)},
                            {"end_time_s", scenario.result.end_time_s},
                            {"switch_count", CountSwitches(scenario.result)},
                            {"charge_left_ah", scenario.result.charge_left_ah[0] + scenario.result.charge_left_ah[1]},
                            {"switches", switches}};
    if (!scenario.schedule.empty()) {
      entry["schedule"] = scenario.schedule;
      entry["family"] = fmt::format("UseBoth; UseBoth then one pack alone for good from t ({:.0f} s grid); UseBoth with "
                                    "one window [t1, t2) of one pack alone ({:.0f} s grid)",
                                    kHindsightSwitchGridS, kHindsightWindowGridS);
      entry["schedules_flown"] = scenario.schedules_flown;
    }
    out.push_back(std::move(entry));
  }
  return {{"case", number}, {"flight_fraction", number >= 3 ? nlohmann::json(kCaseFlightFraction) : nlohmann::json(nullptr)},
          {"scenarios", out}};
}

}  // namespace uascma::campaign
