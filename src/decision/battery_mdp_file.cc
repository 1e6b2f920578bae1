#include "uascma/decision/battery_mdp_file.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/hash.h"
#include "uascma/common/json_reader.h"

namespace uascma::decision {
namespace {

using models::PackAction;

// ================================ writing =========================================================
nlohmann::json WeightsJson(const BatteryRewardWeights& weights) {
  return {{"w1", weights.w1}, {"w2", weights.w2}, {"w3", weights.w3}};
}

Fingerprint PolicyFingerprint(const BatteryPolicySet& set) {
  Fingerprint fingerprint;
  fingerprint.Add(std::string_view(kBatteryPolicyFormat));
  fingerprint.Add(kBatteryFileVersion);
  fingerprint.Add(set.model_hash);
  // Only ours is marked, so a dissertation policy file keeps its hash.
  if (set.formulation == BatteryFormulation::kOurs) fingerprint.Add(std::string_view("formulation=ours"));
  fingerprint.Add(set.gamma);
  fingerprint.Add(set.weights.w1);
  fingerprint.Add(set.weights.w2);
  fingerprint.Add(set.weights.w3);
  for (const BatteryContextPolicy& p : set.policies) {
    fingerprint.Add(BatteryContextIndex(p.context));
    fingerprint.Add(p.mdp_hash);
    for (ActionIndex a : p.action) fingerprint.Add(a);
    for (double v : p.value) fingerprint.Add(v);
    for (const BatteryLearnedRow& row : p.observed_rows) {
      fingerprint.Add(static_cast<std::int64_t>(row.state));
      fingerprint.Add(BatteryActionIndex(row.action));
      for (const Transition& t : row.next) {
        fingerprint.Add(static_cast<std::int64_t>(t.next_state));
        fingerprint.Add(t.probability);
      }
    }
  }
  return fingerprint;
}

const char* StatusName(SolverStatus status) {
  return status == SolverStatus::kConverged ? "converged" : "max_iterations";
}

// ================================ reading (common/json_reader.h: every error names the file and the field) ====
void CheckFormat(const JsonValue& root, const char* format) {
  root.RequireObject("a JSON object");
  const JsonValue format_value = root.Member("format");
  const std::string got = format_value.String();
  if (got != format) format_value.FailExactly(fmt::format("'{}', got '{}'", format, got));
  const JsonValue version = root.Member("version");
  if (!version.IsInteger() || version.json() != kBatteryFileVersion) {
    version.Fail(fmt::format("{} (this build's {} version)", kBatteryFileVersion, format));
  }
}

double FiniteNumber(const JsonValue& value) {
  const double number = value.Number("a finite number");
  if (!std::isfinite(number)) value.Fail("a finite number");
  return number;
}

std::int64_t Count(const JsonValue& value) {
  const auto count = value.Integer<std::int64_t>("a non-negative integer count");
  if (count < 0) value.Fail("a non-negative integer count");
  return count;
}

// An optional count of the solver's report or the statistics, within int's range (1e300 was cast to int).
std::int64_t OptionalSmallCount(const JsonValue& value) {
  if (value.IsMissing()) return 0;
  const std::string expected = fmt::format("a count from 0 to {}", std::numeric_limits<int>::max());
  const int count = value.Integer<int>(expected);
  if (count < 0) value.Fail(expected);
  return count;
}

BatteryRewardWeights WeightsFrom(const JsonValue& root) {
  const JsonValue object = root.Member("weights");
  object.RequireObject("an object {w1, w2, w3}");
  BatteryRewardWeights weights;
  weights.w1 = FiniteNumber(object.Member("w1"));
  weights.w2 = FiniteNumber(object.Member("w2"));
  weights.w3 = FiniteNumber(object.Member("w3"));
  std::string error;
  if (!weights.IsValid(&error)) object.FailExactly(error);
  return weights;
}

double GammaFrom(const JsonValue& root) {
  const JsonValue value = root.Member("gamma");
  const double gamma = FiniteNumber(value);
  if (!(gamma >= 0.0 && gamma < 1.0)) value.FailExactly(fmt::format("in [0, 1), got {}", gamma));
  return gamma;
}

models::HealthClass HealthFrom(const JsonValue& value) {
  const std::string name = value.String();
  for (models::HealthClass health : {models::HealthClass::kG, models::HealthClass::kM, models::HealthClass::kP}) {
    if (name == BatteryHealthName(health)) return health;
  }
  value.FailExactly(fmt::format("F1 | F2 | F3 (Table 4.2), got '{}'", name));
}

TemperatureClass TemperatureFrom(const JsonValue& value) {
  const std::string name = value.String();
  for (TemperatureClass temperature : {TemperatureClass::kHigh, TemperatureClass::kLow}) {
    if (name == TemperatureClassName(temperature)) return temperature;
  }
  value.FailExactly(fmt::format("TH | TL (Table 4.2), got '{}'", name));
}

BatteryContext ContextFrom(const JsonValue& entry) {
  return {HealthFrom(entry.Member("b1")), HealthFrom(entry.Member("b2")), TemperatureFrom(entry.Member("temperature"))};
}

// The state labelled `label` (a member's key, or the value's own string); the failure names `value`'s path.
StateIndex StateFrom(const JsonValue& value, const std::string& label) {
  const auto& labels = BatteryFormulationStateLabels(BatteryFormulation::kOurs);
  const auto it = std::find(labels.begin(), labels.end(), label);
  if (it == labels.end()) {
    value.FailExactly(fmt::format("a battery MDP state such as ILONS1C0OFFS2C0 or FAILURE, got '{}'", label));
  }
  return static_cast<StateIndex>(it - labels.begin());
}
StateIndex StateFrom(const JsonValue& value) { return StateFrom(value, value.String()); }

PackAction ActionFrom(const JsonValue& value) {
  const std::string name = value.String("an action name");
  for (PackAction action : kBatteryActions) {
    if (name == models::PackActionName(action)) return action;
  }
  value.FailExactly(fmt::format("UseBatt1, UseBatt2 or UseBoth, got '{}'", name));
}

BatteryFormulation FormulationFrom(const JsonValue& root) {
  if (!root.Has("formulation")) return BatteryFormulation::kDissertation;
  const JsonValue value = root.Member("formulation");
  const std::string name = value.String();
  if (name == "dissertation") return BatteryFormulation::kDissertation;
  if (name == "ours") return BatteryFormulation::kOurs;
  value.FailExactly(fmt::format("dissertation | ours, got '{}'", name));
}

// The context of an entry, each once.
int ContextIndexOnce(const JsonValue& entry, const BatteryContext& context,
                     std::array<bool, kBatteryNumContexts>& seen) {
  const int index = BatteryContextIndex(context);
  if (seen[static_cast<std::size_t>(index)]) entry.FailExactly("each (b1, b2, temperature) once");
  seen[static_cast<std::size_t>(index)] = true;
  return index;
}

void RequireEveryContext(const JsonValue& array, const std::array<bool, kBatteryNumContexts>& seen,
                         const char* expected) {
  for (int c = 0; c < kBatteryNumContexts; ++c) {
    if (!seen[static_cast<std::size_t>(c)]) {
      array.FailExactly(std::string(expected) + BatteryContextLabel(BatteryContextFromIndex(c)));
    }
  }
}

void CheckHash(const JsonValue& value, const std::string& hash, const std::string& expected, const char* what) {
  if (hash != expected) {
    value.FailExactly(fmt::format("{} ({}), got {}: the file was edited or damaged", expected, what, hash));
  }
}

// `ours`: a row of ours' abstraction (its flagged states allowed), else of the dissertation's 289.
void ReadModelRow(const JsonValue& row, const BatteryContext& context, bool ours, BatteryTransitionCounts& counts) {
  const StateIndex s = StateFrom(row.Member("state", "an object {state, action, next}"));
  const PackAction action = ActionFrom(row.Member("action"));
  const bool known = s < kBatteryFailureState || (ours && IsFlaggedBatteryState(s));
  if (!known || !SwitchesMatch(s, action)) {
    row.FailExactly("a learned row: a non-failure state with the action's switches");
  }
  for (const auto& [label, count] : row.Member("next").Members("an object next state → count")) {
    const StateIndex next = StateFrom(count, label);
    if (next == kBatteryCompleteState || (!ours && next >= kBatteryNumStates)) {
      count.FailExactly(fmt::format("a next state of the {} abstraction, got '{}'", ours ? "ours" : "dissertation's",
                                    label));
    }
    counts.Add(context, s, action, next, Count(count));
  }
  if (row.Has("completed")) counts.AddCompletion(context, s, action, Count(row.Member("completed")));
}

void ReadModelContext(const JsonValue& entry, bool ours, BatteryTransitionCounts& counts,
                      std::array<bool, kBatteryNumContexts>& seen) {
  entry.RequireObject("an object {b1, b2, temperature, flights, rows}");
  const BatteryContext context = ContextFrom(entry);
  ContextIndexOnce(entry, context, seen);
  const JsonValue flights = entry.Member("flights");
  for (PackAction action : kBatteryActions) {
    const JsonValue value = flights.Member(models::PackActionName(action), "an object of flights per action");
    counts.SetFlights(context, action, Count(value));
  }
  for (const JsonValue& row : entry.Member("rows").Elements("an array of rows")) {
    ReadModelRow(row, context, ours, counts);
  }
}

nlohmann::json CountsJson(const BatteryTransitionCounts& counts) {
  nlohmann::json contexts = nlohmann::json::array();
  for (int c = 0; c < kBatteryNumContexts; ++c) {
    const BatteryContext context = BatteryContextFromIndex(c);
    nlohmann::json flights = nlohmann::json::object();
    for (PackAction action : kBatteryActions) flights[models::PackActionName(action)] = counts.flights(context, action);
    nlohmann::json rows = nlohmann::json::array();
    counts.ForEachRow(context, [&](StateIndex s, PackAction action, const auto& row, std::int64_t completed) {
      nlohmann::json next = nlohmann::json::object();
      for (const auto& [state, count] : row) next[BatteryStateLabel(state)] = count;
      nlohmann::json entry = {
          {"state", BatteryStateLabel(s)}, {"action", models::PackActionName(action)}, {"next", next}};
      if (completed > 0) entry["completed"] = completed;
      rows.push_back(std::move(entry));
    });
    contexts.push_back({{"b1", BatteryHealthName(context.b1)},
                        {"b2", BatteryHealthName(context.b2)},
                        {"temperature", TemperatureClassName(context.temperature)},
                        {"flights", flights},
                        {"rows", rows}});
  }
  return contexts;
}

// The contexts array `name` of a model file into `counts`.
void ReadCounts(const JsonValue& root, const char* name, bool ours, BatteryTransitionCounts& counts) {
  std::array<bool, kBatteryNumContexts> seen{};
  const JsonValue contexts = root.Member(name);
  for (const JsonValue& entry : contexts.Elements("an array of contexts")) ReadModelContext(entry, ours, counts, seen);
  RequireEveryContext(contexts, seen, "every (b1, b2, temperature), missing ");
}

BatteryLearnedRow ReadObservedRow(const JsonValue& entry) {
  BatteryLearnedRow row;
  row.state = StateFrom(entry.Member("state", "an object {state, action, next}"));
  row.action = ActionFrom(entry.Member("action"));
  for (const auto& [label, probability] : entry.Member("next").Members("an object next state → probability")) {
    row.next.push_back({StateFrom(probability, label), probability.Number("a probability")});
  }
  // JSON objects are ordered by key; the MDP's rows by state index.
  std::sort(row.next.begin(), row.next.end(),
            [](const Transition& a, const Transition& b) { return a.next_state < b.next_state; });
  return row;
}

// The solver's report and the statistics: optional, but typed (a string status, counts in int's range, a finite
// residual); json::value() threw type_error on a mistyped one and cast 1e300 to int.
void ReadSolverAndStats(const JsonValue& entry, BatteryContextPolicy& p) {
  if (entry.Has("solver")) {
    const JsonValue solver = entry.Member("solver");
    solver.RequireObject("an object {method, status, iterations, residual}");
    const std::string status = solver.Has("status") ? solver.Member("status").String() : "";
    p.summary.status = status == "converged" ? SolverStatus::kConverged : SolverStatus::kMaxIterations;
    p.summary.iterations = static_cast<int>(OptionalSmallCount(solver.Member("iterations")));
    p.summary.residual = solver.Has("residual") ? FiniteNumber(solver.Member("residual")) : 0.0;
  }
  if (entry.Has("stats")) {
    const JsonValue stats = entry.Member("stats");
    stats.RequireObject("an object {learned_rows, unobserved_rows, switch_rows, transitions}");
    p.stats.learned_rows = static_cast<int>(OptionalSmallCount(stats.Member("learned_rows")));
    p.stats.unobserved_rows = static_cast<int>(OptionalSmallCount(stats.Member("unobserved_rows")));
    p.stats.switch_rows = static_cast<int>(OptionalSmallCount(stats.Member("switch_rows")));
    p.stats.transitions = OptionalSmallCount(stats.Member("transitions"));
  }
}

void ReadContextPolicy(const JsonValue& entry, BatteryPolicySet& set, std::array<bool, kBatteryNumContexts>& seen) {
  entry.RequireObject("an object {b1, b2, temperature, action, value}");
  const BatteryContext context = ContextFrom(entry);
  BatteryContextPolicy& p = set.policies[static_cast<std::size_t>(ContextIndexOnce(entry, context, seen))];
  p.context = context;
  p.mdp_hash = entry.Member("mdp_hash").String();
  const auto states = static_cast<std::size_t>(BatteryPolicyStates(set.formulation));
  const std::vector<JsonValue> actions =
      entry.Member("action").Elements(states, fmt::format("an array of {} action names", states));
  const std::vector<JsonValue> values =
      entry.Member("value").Elements(states, fmt::format("an array of {} numbers", states));
  for (std::size_t s = 0; s < states; ++s) {
    p.action.push_back(BatteryActionIndex(ActionFrom(actions[s])));
    p.value.push_back(values[s].Number());
  }
  for (const JsonValue& row : entry.Member("observed_rows").Elements("an array of observed rows")) {
    p.observed_rows.push_back(ReadObservedRow(row));
  }
  ReadSolverAndStats(entry, p);
}

}  // namespace

// ================================ model files =====================================================
nlohmann::json BatteryModelToJson(const BatteryModel& model) {
  nlohmann::json json = {{"format", kBatteryModelFormat},
                         {"version", kBatteryFileVersion},
                         {"hash", BatteryModelHash(model)},
                         {"gamma", model.gamma},
                         {"weights", WeightsJson(model.weights)},
                         {"provenance", model.provenance},
                         {"contexts", CountsJson(model.counts)}};
  if (model.ours_counts) json["ours_contexts"] = CountsJson(*model.ours_counts);
  return json;
}

BatteryModel BatteryModelFromJson(const nlohmann::json& json, const std::string& source) {
  const JsonValue root(&json, &source, "");
  CheckFormat(root, kBatteryModelFormat);
  BatteryModel model;
  const std::string hash = root.Member("hash").String();
  model.gamma = GammaFrom(root);
  model.weights = WeightsFrom(root);
  model.provenance = root.Has("provenance") ? root.Member("provenance").json() : nlohmann::json::object();
  ReadCounts(root, "contexts", false, model.counts);
  if (root.Has("ours_contexts")) ReadCounts(root, "ours_contexts", true, model.ours_counts.emplace());
  CheckHash(root.Member("hash"), hash, BatteryModelHash(model), "the fingerprint of the file's contents");
  return model;
}

BatteryModel ReadBatteryModelFile(const std::filesystem::path& path) {
  const JsonDocument document = JsonDocument::ReadFile(path);
  return BatteryModelFromJson(document.json(), document.source());
}

// ================================ policy files ====================================================
nlohmann::json BatteryPolicyToJson(const BatteryPolicySet& set) {
  nlohmann::json policies = nlohmann::json::array();
  for (const BatteryContextPolicy& p : set.policies) {
    nlohmann::json actions = nlohmann::json::array();
    for (ActionIndex a : p.action) actions.push_back(BatteryActionNames()[static_cast<std::size_t>(a)]);
    nlohmann::json observed = nlohmann::json::array();
    for (const BatteryLearnedRow& row : p.observed_rows) {
      nlohmann::json next = nlohmann::json::object();
      for (const Transition& t : row.next) next[BatteryStateLabel(t.next_state)] = t.probability;
      observed.push_back(
          {{"state", BatteryStateLabel(row.state)}, {"action", models::PackActionName(row.action)}, {"next", next}});
    }
    policies.push_back({{"b1", BatteryHealthName(p.context.b1)},
                        {"b2", BatteryHealthName(p.context.b2)},
                        {"temperature", TemperatureClassName(p.context.temperature)},
                        {"mdp_hash", p.mdp_hash},
                        {"solver",
                         {{"method", set.formulation == BatteryFormulation::kOurs ? "pi" : "vi"},
                          {"status", StatusName(p.summary.status)},
                          {"iterations", p.summary.iterations},
                          {"residual", p.summary.residual}}},
                        {"stats",
                         {{"learned_rows", p.stats.learned_rows},
                          {"unobserved_rows", p.stats.unobserved_rows},
                          {"switch_rows", p.stats.switch_rows},
                          {"transitions", p.stats.transitions}}},
                        {"action", actions},
                        {"value", p.value},
                        {"observed_rows", observed}});
  }
  return {{"format", kBatteryPolicyFormat},
          {"version", kBatteryFileVersion},
          {"hash", PolicyFingerprint(set).Hex()},
          {"model_hash", set.model_hash},
          {"formulation", BatteryFormulationName(set.formulation)},
          {"gamma", set.gamma},
          {"weights", WeightsJson(set.weights)},
          {"states", BatteryFormulationStateLabels(set.formulation)},
          {"actions", BatteryActionNames()},
          {"policies", policies}};
}

BatteryPolicySet BatteryPolicyFromJson(const nlohmann::json& json, const std::string& source) {
  const JsonValue root(&json, &source, "");
  CheckFormat(root, kBatteryPolicyFormat);
  BatteryPolicySet set;
  const std::string hash = root.Member("hash").String();
  set.model_hash = root.Member("model_hash").String();
  set.formulation = FormulationFrom(root);
  set.gamma = GammaFrom(root);
  set.weights = WeightsFrom(root);
  const JsonValue states = root.Member("states");
  const std::size_t count = BatteryFormulationStateLabels(set.formulation).size();
  if (states.IsMissing()) states.Fail(fmt::format("the {} state labels", count));
  if (states.json() != nlohmann::json(BatteryFormulationStateLabels(set.formulation))) {
    states.FailExactly(fmt::format("the {} battery MDP state labels of the {} formulation in this build's order",
                                   count, BatteryFormulationName(set.formulation)));
  }
  std::array<bool, kBatteryNumContexts> seen{};
  const JsonValue policies = root.Member("policies");
  for (const JsonValue& entry : policies.Elements("an array of 18 policies")) ReadContextPolicy(entry, set, seen);
  RequireEveryContext(policies, seen, "a policy for every (b1, b2, temperature), missing ");
  CheckHash(root.Member("hash"), hash, PolicyFingerprint(set).Hex(), "the fingerprint of the file's policies");
  return set;
}

BatteryPolicySet ReadBatteryPolicyFile(const std::filesystem::path& path) {
  const JsonDocument document = JsonDocument::ReadFile(path);
  return BatteryPolicyFromJson(document.json(), document.source());
}

BatteryPolicyExecutor LoadBatteryPolicyExecutor(const std::filesystem::path& path, const BatteryContext& context) {
  return BatteryPolicyExecutor(ReadBatteryPolicyFile(path), context);
}

}  // namespace uascma::decision
