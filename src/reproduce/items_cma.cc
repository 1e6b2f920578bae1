// Items of Chapter V's decision model and scenarios: the CMA transition model composed from Tables 5.1-5.7, its
// policy by quadrant (Fig. 5.9), the reward-weight sensitivity (Figs. 5.10-5.12), Scenarios I and II (§5.5.1-2),
// and the battery MDP's state count (§4.3.2).
#include "items_cma.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "uascma/decision/battery_mdp.h"
#include "uascma/decision/cma_mdp.h"
#include "uascma/decision/solvers.h"
#include "uascma/reproduce/reproduce.h"
#include "uascma/sim/outcome.h"
#include "uascma/sim/policy.h"
#include "uascma/sim/scenario.h"
#include "uascma/sim/simulator.h"

namespace uascma::reproduce {
namespace {

using decision::FiniteMdp;
using decision::Policy;

// The marginal probability that the motor health of the next tuple state is `to`, within the row's tuple
// successors (C and FL apart), of `state` under `action`.
double MotorHealthMarginal(const FiniteMdp& mdp, const std::string& state, const std::string& action,
                           const std::string& to) {
  const std::int64_t c = mdp.FindChoice(mdp.FindState(state), mdp.FindAction(action));
  double tuple = 0.0, hit = 0.0;
  const auto next = mdp.choice_next_states(c);
  const auto p = mdp.choice_probabilities(c);
  for (std::size_t k = 0; k < next.size(); ++k) {
    const std::string& label = mdp.state_label(next[k]);
    if (label.find(',') == std::string::npos) continue;
    tuple += p[k];
    if (label.find("," + to + ",") != std::string::npos) hit += p[k];
  }
  return hit / tuple;
}

std::string ActionAt(const FiniteMdp& mdp, const Policy& policy, const std::string& state) {
  return mdp.action_name(policy.action[mdp.FindState(state)]);
}

const std::vector<std::string> kFs = {"N", "ELPRACT", "ELASAP"}, kMh = {"NF", "SF", "JF"}, kBh = {"G", "M", "P"};
// Quadrants of Fig. 5.9 (§5.3.2.5): I safe RM1 MM1, II hazardous RM1 MM0, III hyper-critical RM0 MM0, IV critical
// RM0 MM1.
const std::vector<std::pair<std::string, std::string>> kQuadrants = {
    {"I", "MM1,{},RM1"}, {"II", "MM0,{},RM1"}, {"III", "MM0,{},RM0"}, {"IV", "MM1,{},RM0"}};

std::string State(const std::string& fs, const std::string& mh, const std::string& quadrant_pattern,
                  const std::string& bh) {
  return fs + "," + mh + "," + fmt::format(fmt::runtime(quadrant_pattern), bh);
}

nlohmann::json QuadrantGrid(const FiniteMdp& mdp, const Policy& policy) {
  nlohmann::json rows = nlohmann::json::array(), cells = nlohmann::json::array();
  for (const auto& fs : kFs) {
    for (const auto& mh : kMh) {
      for (const auto& bh : kBh) {
        rows.push_back(fs + "," + mh + "," + bh);
        nlohmann::json row = nlohmann::json::array();
        for (const auto& [name, pattern] : kQuadrants) row.push_back(ActionAt(mdp, policy, State(fs, mh, pattern, bh)));
        cells.push_back(row);
      }
    }
  }
  return {{"kind", "grid"}, {"rows", rows}, {"cols", {"Quad I", "Quad II", "Quad III", "Quad IV"}}, {"cells", cells}};
}

}  // namespace

Item ReproduceCmaTables(const Context&) {
  Item item;
  item.source = "§5.3.2.3, Tables 5.1-5.7, eqs. 5.16-5.19";
  const FiniteMdp mdp = decision::BuildCmaMdp({});
  // §5.3.2.1: FS 3, MH 3, MM 2, BH 3, RM 2 values, and the terminal C, T, FL, E.
  item.quantities.push_back(CompareAbsolute("states", mdp.num_states(), 3 * 3 * 2 * 3 * 2 + 4, "", 0.0,
                                            "the product of the features' printed values (§5.3.2.1) plus 4 terminals",
                                            "The state space is not the dissertation's.", 4));
  double worst = 0.0;
  for (std::int64_t c = 0; c < mdp.num_choices(); ++c) {
    double sum = 0.0;
    for (double p : mdp.choice_probabilities(c)) sum += p;
    worst = std::max(worst, std::abs(sum - 1.0));
  }
  item.quantities.push_back(CompareAbsolute(
      "largest |row sum - 1| after normalising", worst, 0.0, "", 1e-12,
      "docs/modelling-choices.md#transition-composition: the printed factors (some RM rows sum to 1.001) are "
      "composed, then each row normalised, as the dissertation says it did",
      "A composed row does not sum to one.", 3));
  item.quantities.push_back(
      CompareAbsolute("P(JF | SF) under NoOp", MotorHealthMarginal(mdp, "N,SF,MM1,P,RM1", "NoOp", "JF"), 0.002809, "",
                      2e-6, "Table 5.4 prints 0.002809; its row sums to 0.999999, so normalising moves it by 1e-6",
                      "The composed NoOp rows do not carry Table 5.4's factor."));
  item.quantities.push_back(CompareAbsolute(
      "P(JF | SF) under LandPract", MotorHealthMarginal(mdp, "N,SF,MM1,P,RM0", "LandPract", "JF"), 0.008583, "", 2e-6,
      "docs/modelling-choices.md#landing-loads-motor: the dissertation's complete tables use 0.008583 under the "
      "landing actions",
      "The landing rows do not carry the complete tables' factor."));
  std::map<std::string, int> choices;
  for (decision::StateIndex s = 0; s < mdp.num_states(); ++s) {
    const std::string& label = mdp.state_label(s);
    if (label.find(',') == std::string::npos) continue;
    choices[label.substr(0, label.find(','))] += static_cast<int>(mdp.choice_end(s) - mdp.choice_begin(s));
  }
  item.quantities.push_back(CompareText(
      "available actions per state (N / ELPRACT / ELASAP)",
      fmt::format("{} / {} / {}", choices["N"] / 36, choices["ELPRACT"] / 36, choices["ELASAP"] / 36), "4 / 3 / 2",
      "docs/modelling-choices.md#action-availability (§5.3.2.2's availability by flight status)",
      "The availability differs from docs/modelling-choices.md#action-availability."));
  item.data["choices"] = mdp.num_choices();
  item.data["transitions"] = mdp.num_transitions();
  return item;
}

Item ReproduceCmaPolicy(const Context&) {
  Item item;
  item.source = "§5.3.2.5, Fig. 5.9, Fig. 5.13";
  const FiniteMdp mdp = decision::BuildCmaMdp({});
  const Policy policy = decision::SolveValueIteration(mdp, {});
  // §5.3.2.5's expected behaviour per quadrant, read as the sets of actions the text allows.
  int as_described = 0, total = 0;
  for (const auto& mh : kMh) {
    for (const auto& bh : kBh) {
      for (const auto& fs : kFs) {  // Quad I: "continue the current flight plan"
        total += 1;
        as_described += ActionAt(mdp, policy, State(fs, mh, kQuadrants[0].second, bh)) == "NoOp" ? 1 : 0;
      }
      const std::string quad2 = ActionAt(mdp, policy, State("N", mh, kQuadrants[1].second, bh));
      total += 1;  // Quad II: "either continue the current flight plan or execute an emergency landing"
      as_described += quad2 != "Terminate" ? 1 : 0;
      for (int q : {2, 3}) {  // Quad III and IV: "an emergency landing or flight termination"
        total += 1;
        as_described += ActionAt(mdp, policy, State("N", mh, kQuadrants[q].second, bh)) != "NoOp" ? 1 : 0;
      }
    }
  }
  item.quantities.push_back(CompareAbsolute(
      "nominal-flight states whose action §5.3.2.5 allows", as_described, total, "states", 0.0,
      "Fig. 5.9 is a picture; its text names the allowed actions per quadrant (I: NoOp; II: NoOp or a landing; "
      "III, IV: a landing or Terminate)",
      "Some quadrant actions are not those §5.3.2.5 describes.", 4));
  item.quantities.push_back(CompareText("action at N,NF,MM0,G,RM0", ActionAt(mdp, policy, "N,NF,MM0,G,RM0"),
                                        "LandPract", "Fig. 5.13 prints this state's optimal action",
                                        "The solved policy differs from Fig. 5.13."));
  item.data["policy"] = QuadrantGrid(mdp, policy)["cells"];
  nlohmann::json grid = QuadrantGrid(mdp, policy);
  item.figures.push_back({"cma-policy.png",
                          "The solved CMA policy by quadrant (Fig. 5.9's view), γ 0.95, eqs. "
                          "5.28-5.29's weights",
                          grid});
  item.notes.push_back(
      "Value iteration, γ = 0.95 (docs/modelling-choices.md#discount), residual 1e-10, as `uascma policy solve --model "
      "cma`.");
  return item;
}

Item ReproduceSensitivity(const Context&) {
  Item item;
  item.source = "§5.3.2.5, Figs. 5.10-5.12";
  const decision::CmaWeights base;
  nlohmann::json weights_series = nlohmann::json::array();
  std::map<std::string, nlohmann::json> lines;
  nlohmann::json xs = nlohmann::json::array(), quad2_landings = nlohmann::json::array(),
                 quad1_asap = nlohmann::json::array();
  for (int k = 0; k <= 20; ++k) {
    const double w = 0.01 * k;  // w_MM from 0 to 0.2 (ours: Fig. 5.10's axis values are not printed)
    const decision::CmaWeights weights = base.WithRenormalised("MM", w);
    xs.push_back(w);
    for (const std::string name : {"RM", "MM", "BH", "NoOp", "C", "FL"}) lines[name].push_back(weights.Get(name));
    const FiniteMdp mdp = decision::BuildCmaMdp(weights);
    const Policy policy = decision::SolveValueIteration(mdp, {});
    int landings = 0, asap = 0;
    for (const auto& fs : kFs) {
      for (const auto& mh : kMh) {
        for (const auto& bh : kBh) {
          landings += ActionAt(mdp, policy, State(fs, mh, kQuadrants[1].second, bh)).rfind("Land", 0) == 0 ? 1 : 0;
          asap += ActionAt(mdp, policy, State(fs, mh, kQuadrants[0].second, bh)) == "LandASAP" ? 1 : 0;
        }
      }
    }
    quad2_landings.push_back(landings);
    quad1_asap.push_back(asap);
  }
  for (auto& [name, ys] : lines) weights_series.push_back({{"label", "w_" + name}, {"x", xs}, {"y", ys}});
  // Fig. 5.11 (green line, larger w_MM; its value is not printed: 0.1 ours) and Fig. 5.12 (w_MM = 0).
  const FiniteMdp high = decision::BuildCmaMdp(base.WithRenormalised("MM", 0.1));
  const Policy high_policy = decision::SolveValueIteration(high, {});
  int asap_quad2 = 0;
  for (const std::string bh : {"G", "M"})
    asap_quad2 += ActionAt(high, high_policy, "ELPRACT,SF,MM0," + bh + ",RM1") == "LandASAP";
  item.quantities.push_back(
      CompareAbsolute("Fig. 5.11 (w_MM 0.1): LandASAP in Quad II, G and M", asap_quad2, 2, "of 2", 0.0,
                      "§5.3.2.5: 'LandASAP is also included in Quad II for Good and Medium battery health'",
                      "The larger w_MM does not add LandASAP to Quad II.", 3));
  const FiniteMdp zero = decision::BuildCmaMdp(base.WithRenormalised("MM", 0.0));
  const Policy zero_policy = decision::SolveValueIteration(zero, {});
  int quad2_nominal = 0, quad1 = 0;
  for (const auto& mh : kMh) {
    for (const auto& bh : kBh) {
      quad2_nominal += ActionAt(zero, zero_policy, State("N", mh, kQuadrants[1].second, bh)) != "NoOp";
      for (const auto& fs : kFs)
        quad1 += ActionAt(zero, zero_policy, State(fs, mh, kQuadrants[0].second, bh)) == "LandASAP";
    }
  }
  item.quantities.push_back(CompareAbsolute(
      "Fig. 5.12 (w_MM 0): landings in nominal Quad II", quad2_nominal, 0, "states", 0.0,
      "§5.3.2.5: 'no consideration of emergency landing is made in Quad II'", "w_MM = 0 still lands in Quad II.", 3));
  item.quantities.push_back(CompareText("Fig. 5.12 (w_MM 0): LandASAP appears in Quad I", quad1 > 0 ? "yes" : "no",
                                        "yes", "§5.3.2.5: 'LandASAP is recommended in Quad I'",
                                        "w_MM = 0 does not put LandASAP in Quad I."));
  item.data["w_mm"] = xs;
  item.data["quad2_landing_states"] = quad2_landings;
  item.data["quad1_landasap_states"] = quad1_asap;
  item.figures.push_back({"sensitivity-weights.png",
                          "Fig. 5.10: the weights renormalised as w_MM varies (eq. 5.22)",
                          {{"kind", "lines"},
                           {"xlabel", "w_MM (before renormalising)"},
                           {"ylabel", "weight"},
                           {"series", weights_series},
                           {"vline", base.MM}}});
  item.figures.push_back(
      {"sensitivity-policy.png",
       "Quadrant actions against w_MM (Figs. 5.11-5.12): landing states in Quad II, LandASAP in Quad I",
       {{"kind", "lines"},
        {"xlabel", "w_MM (before renormalising)"},
        {"ylabel", "states (of 27)"},
        {"series",
         {{{"label", "Quad II: LandPract/LandASAP"}, {"x", xs}, {"y", quad2_landings}},
          {{"label", "Quad I: LandASAP"}, {"x", xs}, {"y", quad1_asap}}}},
        {"vline", base.MM}}});
  return item;
}

namespace {

struct ScenarioExpectation {
  std::string file;
  std::string source;
  double spall_s, jam_s;
  std::string actions;
  std::optional<double> first_action_s;
};

std::string ActionList(const sim::SimResult& r) {
  std::string out;
  for (const auto& [t, a] : r.actions) out += (out.empty() ? "" : ", ") + std::string(decision::CmaActionName(a));
  return out.empty() ? "none" : out;
}

Item ReproduceScenario(const Context& context, const ScenarioExpectation& expect) {
  Item item;
  item.source = expect.source;
  const sim::ScenarioFile file = sim::LoadScenarioFile(context.options.source_dir / "examples" / expect.file);
  const sim::Simulator simulator(file.scenario);
  auto cma = sim::MakePolicy("cma", "reproduce");
  auto noop = sim::MakePolicy("noop", "reproduce");
  const sim::SimResult r = simulator.Run(*cma, {}, {.record_telemetry = false});
  const sim::SimResult n = simulator.Run(*noop, {}, {.record_telemetry = false});
  item.quantities.push_back(CompareAbsolute("spall onset", r.spall_onset_s.value_or(NAN), expect.spall_s, "s", 1e-9,
                                            "the scenario's own setting (examples/" + expect.file + ")",
                                            "The scenario file does not place the spall as the dissertation does.", 4));
  item.quantities.push_back(CompareAbsolute(
      "jam", r.jam_time_s.value_or(NAN), expect.jam_s, "s", 5.0,
      "the spall's growth is stochastic (eq. 3.8's noise); ±5 s, a third of the ~17 s spall-to-jam time",
      fmt::format("The jam comes {:.1f} s after the spall where the dissertation has {:.0f} s: the growth's time "
                  "scale (0.7128 s per step, examples/) is ours, the dissertation prints none.",
                  r.jam_time_s.value_or(NAN) - expect.spall_s, expect.jam_s - expect.spall_s),
      4));
  if (expect.first_action_s) {
    const double first = r.actions.empty() ? NAN : r.actions.front().first;
    item.quantities.push_back(CompareAbsolute("first action", first, *expect.first_action_s, "s", 1.0,
                                              "one 1 Hz decision epoch (§5.4)",
                                              "The first action is not at the spall's epoch.", 4));
  }
  item.quantities.push_back(CompareText("CMA actions", ActionList(r), expect.actions,
                                        "the sequence the section narrates", "The CMA takes other actions."));
  item.quantities.push_back(CompareText("CMA outcome", sim::OutcomeName(r.outcome), "emergency_landing",
                                        "'landed safely' / 'the final execution of the emergency landing'",
                                        "The CMA does not land safely: " + r.reason));
  item.quantities.push_back(CompareText("NoOp fails", sim::IsFailure(n.outcome) ? "yes" : "no", "yes",
                                        "the CMA 'prevented the crash due to insufficient energy'",
                                        std::string("NoOp ") + sim::OutcomeName(n.outcome) + "."));
  // The headline is the action sequence: the scenario's own spall setting goes last.
  std::rotate(item.quantities.begin(), item.quantities.begin() + 1, item.quantities.end());
  nlohmann::json ours = nlohmann::json::array(), theirs = nlohmann::json::array();
  if (r.spall_onset_s) ours.push_back({{"t", *r.spall_onset_s}, {"label", "spall"}});
  if (r.jam_time_s) ours.push_back({{"t", *r.jam_time_s}, {"label", "jam"}});
  if (r.isolation_time_s) ours.push_back({{"t", *r.isolation_time_s}, {"label", "isolated"}});
  for (const auto& [t, a] : r.actions) ours.push_back({{"t", t}, {"label", decision::CmaActionName(a)}});
  ours.push_back({{"t", r.sim_time_s}, {"label", sim::OutcomeName(r.outcome)}});
  theirs.push_back({{"t", expect.spall_s}, {"label", "spall"}});
  theirs.push_back({{"t", expect.jam_s}, {"label", "jam"}});
  if (expect.first_action_s) theirs.push_back({{"t", *expect.first_action_s}, {"label", "LandPract"}});
  item.data["cma_sim_time_s"] = r.sim_time_s;
  item.data["noop_outcome"] = sim::OutcomeName(n.outcome);
  item.data["noop_sim_time_s"] = n.sim_time_s;
  item.data["cma_events"] = nlohmann::json::array();
  for (const auto& e : r.events) item.data["cma_events"].push_back({{"t", e.time_s}, {"what", e.what}});
  item.figures.push_back(
      {"timeline-" + expect.file.substr(0, expect.file.find('.')) + ".png",
       "Event timeline, ours (CMA) against the times the dissertation prints",
       {{"kind", "timeline"},
        {"rows", {{{"label", "ours (CMA)"}, {"events", ours}}, {{"label", "dissertation"}, {"events", theirs}}}}}});
  item.notes.push_back("Flown as `uascma simulate examples/" + expect.file + " --policy cma|noop`.");
  return item;
}

}  // namespace

Item ReproduceScenarioOne(const Context& context) {
  // §5.5.1: spall in motor 3 at 175 s, "no action at this time-step", jam at 192 s, then LandPract, landed safely.
  return ReproduceScenario(context, {"scenario-1.yaml", "§5.5.1, Figs. 5.18-5.24", 175.0, 192.0, "LandPract", {}});
}

Item ReproduceScenarioTwo(const Context& context) {
  // §5.5.2: spall at 525 s triggering LandPract, jam at 542 s, then LandASAP, an emergency landing.
  return ReproduceScenario(context,
                           {"scenario-2.yaml", "§5.5.2, Figs. 5.25-5.29", 525.0, 542.0, "LandPract, LandASAP", 525.0});
}

Item ReproduceBatteryMdpSize(const Context&) {
  Item item;
  item.source = "§4.3.2, Table 4.1, Fig. 4.4";
  item.quantities.push_back(
      CompareAbsolute("battery MDP states", static_cast<double>(decision::BatteryStateLabels().size()), 289.0, "", 0.0,
                      "§4.3.2: |S| = 9 x 4 x 4 x 2 + 1 = 289, printed", "The abstraction's state count differs.", 4));
  int distinct = 0;
  for (decision::StateIndex s = 0; s < decision::kBatteryNumStates; ++s) {
    distinct += decision::ParseBatteryState(decision::BatteryStateLabel(s), "reproduce") == s ? 1 : 0;
  }
  item.quantities.push_back(CompareAbsolute("labels that parse back to their state", distinct, 289.0, "", 0.0,
                                            "every state has its own label (Fig. 4.4's IL/IH, ON/OFF, S1-S3, C0/C1)",
                                            "Two states share a label.", 4));
  item.quantities.push_back(CompareAbsolute("actions", decision::kBatteryNumActions, 3.0, "", 0.0,
                                            "Table 4.3: UseBatt1, UseBatt2, UseBoth", "The action set differs.", 3));
  item.quantities.push_back(CompareAbsolute("policy contexts (Fig. 4.5's leaves)", decision::kBatteryNumContexts, 18.0,
                                            "", 0.0, "Fig. 4.5: B1 health (3) x B2 health (3) x temperature (2)",
                                            "The decision tree has another number of leaves.", 3));
  return item;
}

}  // namespace uascma::reproduce
