#include "uascma/campaign/battery_case_studies.h"

#include <cstddef>
#include <memory>
#include <utility>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/sim/act.h"
#include "uascma/sim/initial_state.h"

namespace uascma::campaign {

using decision::BatteryContext;
using decision::StateIndex;
using models::HealthClass;
using models::PackAction;

// ================================ case studies ====================================================
namespace {

models::PerCell<models::CellHealth> CellHealthOf(const models::PerBranch<HealthClass>& health) {
  models::PerCell<models::CellHealth> cells{};
  for (int j = 0; j < models::kBranchCount; ++j) {
    for (auto& cell : cells[j]) cell = models::CellHealthForClass(health[j]);
  }
  return cells;
}

std::string HealthPairName(HealthClass b1, HealthClass b2) {
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
  p.ambient_temp_degf =
      context.temperature == decision::TemperatureClass::kLow ? ranges.cold_temp_degf : ranges.warm_temp_degf;
  p.plan_duration_s = plan_duration_s;
  return p;
}

double CaseFlightTimeS() { return kCaseFlightFraction * ReferenceBatteryEod(PackAction::kUseBoth); }

std::vector<StateIndex> CaseTakeoffStates(double plan_duration_s) {
  std::vector<StateIndex> takeoff(decision::kBatteryNumContexts);
  for (int c = 0; c < decision::kBatteryNumContexts; ++c) {
    takeoff[static_cast<std::size_t>(c)] =
        TakeoffState(CaseFlightParams(decision::BatteryContextFromIndex(c), plan_duration_s));
  }
  return takeoff;
}

std::string CaseEpochsCsv(const BatteryFlightResult& result) {
  std::string out =
      "time_s,state,action,total_current_a,branch1_current_a,branch2_current_a,eod1_s,eod2_s,remaining_flight_s,"
      "min_cell1_v,min_cell2_v\n";
  for (const BatteryEpoch& e : result.epochs) {
    out += fmt::format("{:.1f},{},{},{:.4f},{:.4f},{:.4f},{:.2f},{:.2f},{:.2f},{:.4f},{:.4f}\n", e.time_s,
                       decision::BatteryStateLabel(e.state), models::PackActionName(e.action), e.total_current_a,
                       e.branch_current_a[0], e.branch_current_a[1], e.eod_s[0], e.eod_s[1], e.remaining_flight_s,
                       e.min_cell_voltage_v[0], e.min_cell_voltage_v[1]);
  }
  return out;
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

namespace {

// The health pairs and the flight time of case `number` (Table 4.5).
struct CaseDefinition {
  std::vector<std::pair<HealthClass, HealthClass>> pairs;
  double plan_duration_s = 0.0;
};

CaseDefinition DefineCase(int number) {
  CaseDefinition out;
  if (number <= 2) {
    // "battery pack EOD time is twice the flight time": the plan lasts one healthy pack's EOD.
    out.plan_duration_s = ReferenceBatteryEod(PackAction::kUseBatt1);
    for (int b1 = 0; b1 < 3; ++b1) {
      for (int b2 = 0; b2 < 3; ++b2) out.pairs.emplace_back(static_cast<HealthClass>(b1), static_cast<HealthClass>(b2));
    }
  } else {
    // docs/modelling-choices.md#battery-case-study-flight-time
    out.plan_duration_s = CaseFlightTimeS();
    if (number == 3) {
      out.pairs = {
          {HealthClass::kG, HealthClass::kM}, {HealthClass::kG, HealthClass::kP}, {HealthClass::kP, HealthClass::kP}};
    } else {
      out.pairs = {{HealthClass::kM, HealthClass::kG}};
    }
  }
  return out;
}

// UseBoth (§4.3.3: "a similar scenario can be set up with a single action of UseBoth"), then, in the cases that
// use a policy, each learned policy and the voltage rule beside it on the same flight.
std::vector<std::pair<std::string, BatteryFlightController>> CaseControllers(bool uses_policy,
                                                                             const CaseStudyOptions& options,
                                                                             const BatteryContext& context) {
  std::vector<std::pair<std::string, BatteryFlightController>> flown;
  BatteryPolicySpec useboth;
  flown.emplace_back("UseBoth", MakeBatteryController(useboth, context));
  if (!uses_policy) return flown;
  BatteryPolicySpec pistar;
  pistar.kind = BatteryPolicyKind::kPiStar;
  pistar.policies = std::shared_ptr<const decision::BatteryPolicySet>(options.pistar, [](const auto*) {});
  flown.emplace_back("pi*", MakeBatteryController(pistar, context));
  BatteryPolicySpec rule;
  rule.kind = BatteryPolicyKind::kVoltageRule;
  flown.emplace_back("rule:voltage", MakeBatteryController(rule, context));
  if (options.ours != nullptr) {
    BatteryPolicySpec ours;
    ours.kind = BatteryPolicyKind::kOurs;
    ours.policies = std::shared_ptr<const decision::BatteryPolicySet>(options.ours, [](const auto*) {});
    flown.emplace_back("ours", MakeBatteryController(ours, context));
  }
  return flown;
}

// The best of the hindsight family (HindsightSchedules), every member flown on the case's flight.
CaseScenario HindsightBest(const std::string& name, const BatteryFlightParams& params) {
  const std::vector<SwitchSchedule> family = HindsightSchedules(params.plan_duration_s);
  std::vector<BatteryFlightController> schedules;
  for (const auto& s : family) schedules.push_back(ScheduleController(s));
  const std::vector<BatteryFlightResult> tried = FlyBatteryFlights(params, schedules);
  std::size_t best = 0;
  for (std::size_t k = 1; k < tried.size(); ++k) {
    if (Better(tried[k], tried[best])) best = k;
  }
  CaseScenario scenario;
  scenario.name = name;
  scenario.params = params;
  scenario.controller = "hindsight-best";
  scenario.schedule = family[best].Describe();
  scenario.schedules_flown = static_cast<int>(family.size());
  scenario.result = tried[best];
  return scenario;
}

}  // namespace

std::vector<CaseScenario> RunCaseStudy(int number, const CaseStudyOptions& options) {
  if (number < 1 || number > 4)
    throw InputError("case-study", "N", fmt::format("1, 2, 3 or 4 (Table 4.5), got {}", number));
  const bool uses_policy = number == 2 || number == 4;
  if (uses_policy && options.pistar == nullptr)
    throw InputError("case-study", "--policy", "a battery policy file for pi*");
  const CaseDefinition definition = DefineCase(number);
  std::vector<CaseScenario> scenarios;
  for (const auto& [b1, b2] : definition.pairs) {
    BatteryFlightParams params =
        CaseFlightParams({b1, b2, decision::TemperatureClass::kHigh}, definition.plan_duration_s);
    params.seed = options.seed;
    if (number == 4) {
      // Fig. 4.11's caption: "Batt1 has one cell with capacity fade and Batt2 is healthy" (an F2 pack of
      // Table 4.2); the other cases' packs are as their captions say, every cell faded (Figs. 4.9, 4.10).
      params.cells[0] = {};
      params.cells[0][0].capacity_fade = true;
    }
    const auto flown = CaseControllers(uses_policy, options, params.context());
    std::vector<BatteryFlightController> controllers;
    for (const auto& f : flown) controllers.push_back(f.second);
    const std::vector<BatteryFlightResult> results = FlyBatteryFlights(params, controllers);
    for (std::size_t k = 0; k < flown.size(); ++k) {
      CaseScenario scenario;
      scenario.name = HealthPairName(b1, b2);
      scenario.params = params;
      scenario.controller = flown[k].first;
      scenario.result = results[k];
      scenarios.push_back(std::move(scenario));
    }
    if (number == 4 && options.hindsight) scenarios.push_back(HindsightBest(HealthPairName(b1, b2), params));
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
      entry["family"] = fmt::format(
          "UseBoth; UseBoth then one pack alone for good from t ({:.0f} s grid); UseBoth with "
          "one window [t1, t2) of one pack alone ({:.0f} s grid)",
          kHindsightSwitchGridS, kHindsightWindowGridS);
      entry["schedules_flown"] = scenario.schedules_flown;
    }
    out.push_back(std::move(entry));
  }
  return {{"case", number},
          {"flight_fraction", number >= 3 ? nlohmann::json(kCaseFlightFraction) : nlohmann::json(nullptr)},
          {"scenarios", out}};
}

}  // namespace uascma::campaign
