#include "uascma/decision/cma_mdp.h"

#include <cmath>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "uascma/common/error.h"
#include "uascma/common/yaml_io.h"

namespace uascma::decision {
namespace {

const std::vector<std::string> kActionNames = {"NoOp", "Terminate", "LandASAP", "LandPract"};
const std::vector<DiscreteFeature> kFeatures = {
    {"FS", {"N", "ELASAP", "ELPRACT"}},
    {"MH", {"NF", "SF", "JF"}},
    {"MM", {"MM0", "MM1"}},
    {"BH", {"G", "M", "P"}},
    {"RM", {"RM0", "RM1"}},
};
const std::vector<std::string> kTerminalNames = {"C", "T", "FL", "E"};

// A row as the dissertation prints it (cma_mdp.h).
ConditionalRow Printed(std::string next, std::vector<std::string> parents, double noop, double land_asap,
                       double land_pract, double terminate) {
  return PrintedCmaRow(std::move(next), std::move(parents), noop, land_asap, land_pract, terminate);
}
// A row of a table that does not depend on the action (Tables 5.2, 5.4).
ConditionalRow Any(std::string next, std::vector<std::string> parents, double p) {
  return {std::move(next), std::move(parents), {p, p, p, p}};
}

// Table 5.1: P(FS_{t+1} | FS_t, A_t).
ConditionalTable FlightStatusTable() {
  return {"Table 5.1",
          "FS",
          {"FS"},
          {
              Printed("N", {"N"}, 1, 0, 0, 0),
              Printed("ELASAP", {"N"}, 0, 1, 0, 0),
              Printed("ELPRACT", {"N"}, 0, 0, 1, 0),
              Printed("N", {"ELASAP"}, 0, 0, 0, 0),
              Printed("ELASAP", {"ELASAP"}, 1, 0, 0, 0),
              Printed("ELPRACT", {"ELASAP"}, 0, 0, 0, 0),
              Printed("N", {"ELPRACT"}, 0, 0, 0, 0),
              Printed("ELASAP", {"ELPRACT"}, 0, 1, 0, 0),
              Printed("ELPRACT", {"ELPRACT"}, 1, 0, 0, 0),
          }};
}

// Table 5.2: P(BH_{t+1} | BH_t): health is constant during a flight.
ConditionalTable BatteryHealthTable() {
  ConditionalTable table{"Table 5.2", "BH", {"BH"}, {}};
  for (const char* from : {"G", "M", "P"}) {
    for (const char* to : {"G", "M", "P"}) {
      table.rows.push_back(Any(to, {from}, std::string(from) == to ? 1.0 : 0.0));
    }
  }
  return table;
}

// Table 5.3: P(RM_{t+1} | RM_t, BH_t, MM_t, A_t), values as printed (some pairs sum to 1.001 or
// more; the composed rows are normalised, docs/modelling-choices.md#transition-composition).
ConditionalTable ReachMarginTable() {
  return {"Table 5.3",
          "RM",
          {"RM", "BH", "MM"},
          {
              Printed("RM0", {"RM0", "G", "MM0"}, 1, 0.003, 0.0025, 0),
              Printed("RM1", {"RM0", "G", "MM0"}, 0, 0.997, 0.9975, 0),
              Printed("RM0", {"RM0", "M", "MM0"}, 1, 0.004, 0.0045, 0),
              Printed("RM1", {"RM0", "M", "MM0"}, 0, 0.996, 0.9955, 0),
              Printed("RM0", {"RM0", "P", "MM0"}, 1, 0.005, 0.0055, 0),
              Printed("RM1", {"RM0", "P", "MM0"}, 0, 0.995, 0.9945, 0),
              Printed("RM0", {"RM1", "G", "MM0"}, 0.005, 0.0003, 0.00035, 0),
              Printed("RM1", {"RM1", "G", "MM0"}, 0.995, 0.9997, 0.99965, 0),
              Printed("RM0", {"RM1", "M", "MM0"}, 0.01, 0.0004, 0.00045, 0),
              Printed("RM1", {"RM1", "M", "MM0"}, 0.99, 0.9996, 0.99955, 0),
              Printed("RM0", {"RM1", "P", "MM0"}, 0.05, 0.005, 0.0055, 0),
              Printed("RM1", {"RM1", "P", "MM0"}, 0.95, 0.9995, 0.9945, 0),
              Printed("RM0", {"RM0", "G", "MM1"}, 1, 0.0035, 0.004, 0),
              Printed("RM1", {"RM0", "G", "MM1"}, 0, 0.9975, 0.996, 0),
              Printed("RM0", {"RM0", "M", "MM1"}, 1, 0.0045, 0.005, 0),
              Printed("RM1", {"RM0", "M", "MM1"}, 0, 0.9965, 0.995, 0),
              Printed("RM0", {"RM0", "P", "MM1"}, 1, 0.0055, 0.006, 0),
              Printed("RM1", {"RM0", "P", "MM1"}, 0, 0.9955, 0.994, 0),
              Printed("RM0", {"RM1", "G", "MM1"}, 5e-05, 5e-06, 5.5e-06, 0),
              Printed("RM1", {"RM1", "G", "MM1"}, 0.99995, 0.99999, 0.99999, 0),
              Printed("RM0", {"RM1", "M", "MM1"}, 0.0005, 5e-05, 5.5e-05, 0),
              Printed("RM1", {"RM1", "M", "MM1"}, 0.9995, 0.99995, 0.99994, 0),
              Printed("RM0", {"RM1", "P", "MM1"}, 0.005, 0.0004, 0.00045, 0),
              Printed("RM1", {"RM1", "P", "MM1"}, 0.995, 0.9996, 0.99955, 0),
          }};
}

// Table 5.4: P(MH_{t+1} | MH_t). The printed SF → JF value 0.002809 is the NoOp one; under the
// landing actions the dissertation's complete tables use 0.008583 (docs/modelling-choices.md#landing-loads-motor).
// Terminate never reaches these rows (it exits to T), so it carries the NoOp values.
constexpr double kSpallToJamNoOp = 0.002809;
constexpr double kSpallToJamLanding = 0.008583;
ConditionalTable MotorHealthTable() {
  return {"Table 5.4",
          "MH",
          {"MH"},
          {
              Any("NF", {"NF"}, 0.99995),
              Any("SF", {"NF"}, 4.75e-05),
              Any("JF", {"NF"}, 0),
              Any("NF", {"SF"}, 0),
              Printed("SF", {"SF"}, 0.99719, 1.0 - kSpallToJamLanding, 1.0 - kSpallToJamLanding, 0.99719),
              Printed("JF", {"SF"}, kSpallToJamNoOp, kSpallToJamLanding, kSpallToJamLanding, kSpallToJamNoOp),
              Any("NF", {"JF"}, 0),
              Any("SF", {"JF"}, 0),
              Any("JF", {"JF"}, 1),
          }};
}

}  // namespace

ConditionalRow PrintedCmaRow(std::string next, std::vector<std::string> parents, double noop, double land_asap,
                             double land_pract, double terminate) {
  return {std::move(next), std::move(parents), {noop, terminate, land_asap, land_pract}};
}

// Table 5.5: P(MM_{t+1} | MM_t, MH_t, A_t).
ConditionalTable CmaMotorMarginTable() {
  return {"Table 5.5",
          "MM",
          {"MM", "MH"},
          {
              Printed("MM0", {"MM0", "NF"}, 0, 0, 0, 0),
              Printed("MM1", {"MM0", "NF"}, 1, 1, 1, 0),
              Printed("MM0", {"MM0", "SF"}, 0.995, 0.9, 0.89, 0),
              Printed("MM1", {"MM0", "SF"}, 0.005, 0.1, 0.11, 0),
              Printed("MM0", {"MM0", "JF"}, 1, 1, 1, 0),
              Printed("MM1", {"MM0", "JF"}, 0, 0, 0, 0),
              Printed("MM0", {"MM1", "NF"}, 0, 0, 0, 0),
              Printed("MM1", {"MM1", "NF"}, 1, 1, 1, 0),
              Printed("MM0", {"MM1", "SF"}, 0.002809, 0.002, 0.0025, 0),
              Printed("MM1", {"MM1", "SF"}, 0.99719, 0.998, 0.9975, 0),
              Printed("MM0", {"MM1", "JF"}, 1, 1, 1, 0),
              Printed("MM1", {"MM1", "JF"}, 0, 0, 0, 0),
          }};
}

namespace {

// Table 5.6: P(C_{t+1} | FS_t, RM_t, MM_t, A_t).
ExitTable CompleteTable() {
  return {"Table 5.6",
          "C",
          {"FS", "RM", "MM"},
          {
              Printed("", {"N", "RM0", "MM0"}, 0, 0, 0, 0),
              Printed("", {"N", "RM0", "MM1"}, 0, 0, 0, 0),
              Printed("", {"N", "RM1", "MM0"}, 0.08, 0.0095, 0.009, 0),
              Printed("", {"N", "RM1", "MM1"}, 0.1, 0.01, 0.015, 0),
              Printed("", {"ELASAP", "RM0", "MM0"}, 0, 0, 0, 0),
              Printed("", {"ELASAP", "RM0", "MM1"}, 0, 0, 0, 0),
              Printed("", {"ELASAP", "RM1", "MM0"}, 0.095, 0, 0, 0),
              Printed("", {"ELASAP", "RM1", "MM1"}, 0.2, 0, 0, 0),
              Printed("", {"ELPRACT", "RM0", "MM0"}, 0, 0, 0, 0),
              Printed("", {"ELPRACT", "RM0", "MM1"}, 0, 0, 0, 0),
              Printed("", {"ELPRACT", "RM1", "MM0"}, 0.09, 0.0095, 0, 0),
              Printed("", {"ELPRACT", "RM1", "MM1"}, 0.15, 0.01, 0, 0),
          }};
}

// Table 5.7: P(FL_{t+1} | FS_t, RM_t, MM_t, A_t).
ExitTable FailureTable() {
  return {"Table 5.7",
          "FL",
          {"FS", "RM", "MM"},
          {
              Printed("", {"N", "RM0", "MM0"}, 1, 0.0002, 0.0002, 0),
              Printed("", {"N", "RM0", "MM1"}, 1, 0.0001, 0.0003, 0),
              Printed("", {"N", "RM1", "MM0"}, 0.01, 0, 0, 0),
              Printed("", {"N", "RM1", "MM1"}, 0.001, 0, 0, 0),
              Printed("", {"ELASAP", "RM0", "MM0"}, 1, 0, 0, 0),
              Printed("", {"ELASAP", "RM0", "MM1"}, 1, 0, 0, 0),
              Printed("", {"ELASAP", "RM1", "MM0"}, 0.009, 0, 0, 0),
              Printed("", {"ELASAP", "RM1", "MM1"}, 0.0001, 0, 0, 0),
              Printed("", {"ELPRACT", "RM0", "MM0"}, 1, 1, 0, 0),
              Printed("", {"ELPRACT", "RM0", "MM1"}, 1, 1, 0, 0),
              Printed("", {"ELPRACT", "RM1", "MM0"}, 0.0095, 0.00085, 0, 0),
              Printed("", {"ELPRACT", "RM1", "MM1"}, 0.0005, 0.00075, 0, 0),
          }};
}

// Feature scores of eqs. 5.23–5.27.
constexpr std::array<double, 3> kScoreFS = {1.0, -1.0, -1.0};             // N, ELASAP, ELPRACT (eq. 5.25)
constexpr std::array<double, 3> kScoreMH = {1.0, 0.0, -1.0};              // NF, SF, JF (eq. 5.25)
constexpr std::array<double, 2> kScoreMM = {-1.0, 1.0};                   // MM0, MM1 (eq. 5.26)
constexpr std::array<double, 3> kScoreBH = {1.0, 0.0, -1.0};              // G, M, P (eq. 5.26)
constexpr std::array<double, 2> kScoreRM = {-1.0, 1.0};                   // RM0, RM1 (eq. 5.27)
constexpr std::array<double, 4> kScoreTerminal = {1.0, -0.1, -1.0, 0.0};  // C, T, FL, E (eq. 5.23)
constexpr std::array<double, 4> kScoreAction = {1.0, -1.0, -0.5, 0.5};    // NoOp, Terminate,
                                                                          // LandASAP, LandPract

int Radix(int feature) { return static_cast<int>(kFeatures[feature].values.size()); }

}  // namespace

StateIndex CmaStateIndex(const CmaState& state) {
  const std::array<int, 5> values = {static_cast<int>(state.fs), static_cast<int>(state.mh), static_cast<int>(state.mm),
                                     static_cast<int>(state.bh), static_cast<int>(state.rm)};
  StateIndex index = 0;
  for (int f = 0; f < 5; ++f) index = index * Radix(f) + values[f];
  return index;
}

StateIndex CmaTerminalIndex(CmaTerminal terminal) { return kCmaNumTupleStates + static_cast<int>(terminal); }

const std::string& CmaFeatureValueName(int feature, int value) { return kFeatures.at(feature).values.at(value); }

std::string CmaStateLabel(const CmaState& state) {
  return fmt::format(
      "{},{},{},{},{}", CmaFeatureValueName(0, static_cast<int>(state.fs)),
      CmaFeatureValueName(1, static_cast<int>(state.mh)), CmaFeatureValueName(2, static_cast<int>(state.mm)),
      CmaFeatureValueName(3, static_cast<int>(state.bh)), CmaFeatureValueName(4, static_cast<int>(state.rm)));
}

const char* CmaActionName(CmaAction action) { return kActionNames[static_cast<int>(action)].c_str(); }

CmaState ParseCmaState(const std::string& label, const std::string& source) {
  std::array<int, 5> values{};
  std::size_t start = 0;
  for (int f = 0; f < 5; ++f) {
    const std::size_t comma = label.find(',', start);
    const bool last = f == 4;
    if (last != (comma == std::string::npos)) {
      throw InputError(source, "state", "five comma-separated features FS,MH,MM,BH,RM, got '" + label + "'");
    }
    const std::string token = label.substr(start, last ? std::string::npos : comma - start);
    values[f] = -1;
    for (int v = 0; v < Radix(f); ++v) {
      if (kFeatures[f].values[v] == token) values[f] = v;
    }
    if (values[f] < 0) {
      std::string allowed;
      for (const auto& v : kFeatures[f].values) allowed += (allowed.empty() ? "" : "|") + v;
      throw InputError(source, "state feature " + kFeatures[f].name,
                       "one of " + allowed + ", got '" + token + "' in '" + label + "'");
    }
    start = comma + 1;
  }
  return {static_cast<FlightStatus>(values[0]), static_cast<MotorHealth>(values[1]),
          static_cast<MotorMargin>(values[2]), static_cast<BatteryHealth>(values[3]),
          static_cast<ReachMargin>(values[4])};
}

CmaAction ParseCmaAction(const std::string& name, const std::string& source) {
  for (std::size_t a = 0; a < kActionNames.size(); ++a) {
    if (kActionNames[a] == name) return static_cast<CmaAction>(a);
  }
  throw InputError(source, "action", "one of NoOp|Terminate|LandASAP|LandPract, got '" + name + "'");
}

const std::vector<std::string>& CmaWeights::Names() {
  static const std::vector<std::string> names = {"C",         "FL", "T",  "E",  "NoOp", "Terminate", "LandASAP",
                                                 "LandPract", "FS", "MH", "MM", "BH",   "RM"};
  return names;
}

namespace {
double* WeightSlot(CmaWeights& w, const std::string& name) {
  double* slots[] = {&w.C,         &w.FL, &w.T,  &w.E,  &w.NoOp, &w.Terminate, &w.LandASAP,
                     &w.LandPract, &w.FS, &w.MH, &w.MM, &w.BH,   &w.RM};
  const auto& names = CmaWeights::Names();
  std::string bare = name.rfind("w_", 0) == 0 ? name.substr(2) : name;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i] == bare) return slots[i];
  }
  std::string allowed;
  for (const auto& n : names) allowed += (allowed.empty() ? "" : "|") + n;
  throw InputError("--weight", "name", "one of " + allowed + ", got '" + name + "'");
}
}  // namespace

double CmaWeights::Get(const std::string& name) const { return *WeightSlot(const_cast<CmaWeights&>(*this), name); }

void CmaWeights::Set(const std::string& name, double value) { *WeightSlot(*this, name) = value; }

double CmaWeights::Sum() const {
  double sum = 0.0;
  for (const auto& name : Names()) sum += Get(name);
  return sum;
}

bool CmaWeights::IsValid(std::string* error) const {
  for (const auto& name : Names()) {
    if (!CheckWithin(Get(name), kCmaWeightBounds, "weight " + name, error)) return false;
  }
  return true;
}

CmaWeights CmaWeights::WithRenormalised(const std::string& name, double value) const {
  if (!(value >= 0.0 && value <= 1.0)) {
    throw InputError("--weight " + name, "value", fmt::format("a weight in [0, 1], got {}", value));
  }
  CmaWeights result = *this;
  const double others = Sum() - Get(name);
  if (!(others > 0.0)) {
    throw InputError("--weight " + name, "other weights", "a positive sum to rescale");
  }
  const double scale = (1.0 - value) / others;
  for (const auto& n : Names()) result.Set(n, Get(n) * scale);
  result.Set(name, value);
  return result;
}

CmaConfig LoadCmaConfig(const std::filesystem::path& path) {
  const std::string source = path.string();
  const YAML::Node root = LoadYamlFile(path);
  CmaConfig config;
  RequireOnlyKeys(root, {"gamma", "weights"}, source, "");
  config.gamma = OptionalNumber(root, "gamma", config.gamma, source, "");
  RequireWithin(config.gamma, kGammaBounds, source, "gamma");
  const YAML::Node weights = RequireMap(root, "weights", source, "");
  RequireOnlyKeys(weights, {"end_states", "actions", "state_features"}, source, "weights");
  const struct {
    const char* group;
    std::vector<std::string> names;
  } groups[] = {{"end_states", {"C", "FL", "T", "E"}},
                {"actions", {"NoOp", "Terminate", "LandASAP", "LandPract"}},
                {"state_features", {"FS", "MH", "MM", "BH", "RM"}}};
  for (const auto& group : groups) {
    const std::string where = std::string("weights.") + group.group;
    const YAML::Node node = RequireMap(weights, group.group, source, "weights");
    for (const auto& name : group.names) {
      const double value = RequireNumber(node, name, source, where);
      RequireWithin(value, kCmaWeightBounds, source, where + "." + name);
      config.weights.Set(name, value);
    }
    for (const auto& entry : node) {
      if (!entry.first.IsScalar()) throw InputError(source, where, "weight names as keys");
      const std::string key = entry.first.as<std::string>();
      if (std::find(group.names.begin(), group.names.end(), key) == group.names.end()) {
        throw InputError(source, where + "." + key, "no such weight (a misspelling?)");
      }
    }
  }
  return config;
}

std::string CmaConfigYaml(const CmaConfig& config) {
  const CmaWeights& w = config.weights;
  return fmt::format(
      "# CMA MDP reward weights (eqs. 5.28-5.29) and discount factor.\n"
      "gamma: {}\n"
      "weights:\n"
      "  end_states: {{C: {}, FL: {}, T: {}, E: {}}}\n"
      "  actions: {{NoOp: {}, Terminate: {}, LandASAP: {}, LandPract: {}}}\n"
      "  state_features: {{FS: {}, MH: {}, MM: {}, BH: {}, RM: {}}}\n",
      config.gamma, w.C, w.FL, w.T, w.E, w.NoOp, w.Terminate, w.LandASAP, w.LandPract, w.FS, w.MH, w.MM, w.BH, w.RM);
}

FactoredMdpBuilder MakeCmaFactoredModel() {
  FactoredMdpBuilder model(kFeatures, kActionNames);
  model.AddTerminalState("C", "E");
  model.AddTerminalState("T", "E");
  model.AddTerminalState("FL", "E");
  model.AddTerminalState("E", "E");
  model.SetTransitionTable(FlightStatusTable());
  model.SetTransitionTable(MotorHealthTable());
  model.SetTransitionTable(CmaMotorMarginTable());
  model.SetTransitionTable(BatteryHealthTable());
  model.SetTransitionTable(ReachMarginTable());
  model.AddExitTable(CompleteTable());
  model.AddExitTable(FailureTable());
  model.SetForcedExit("Terminate", "T");  // eq. 5.18: P(T | S, Terminate) = 1
  // §5.3.2.1 and docs/modelling-choices.md#action-availability.
  model.RestrictActions("FS", "ELPRACT", {"NoOp", "Terminate", "LandASAP"});
  model.RestrictActions("FS", "ELASAP", {"NoOp", "Terminate"});
  return model;
}

double CmaReward(const CmaWeights& w, const FactoredState& state, ActionIndex action) {
  const std::array<double, 4> action_weight = {w.NoOp, w.Terminate, w.LandASAP, w.LandPract};
  const double reward_action = action_weight[action] * kScoreAction[action];  // eq. 5.21
  if (state.is_terminal()) {
    const std::array<double, 4> terminal_weight = {w.C, w.T, w.FL, w.E};
    return terminal_weight[state.terminal] * kScoreTerminal[state.terminal] + reward_action;
  }
  const auto& v = state.values;
  const double reward_state = w.FS * kScoreFS[v[0]] + w.MH * kScoreMH[v[1]] + w.MM * kScoreMM[v[2]] +
                              w.BH * kScoreBH[v[3]] + w.RM * kScoreRM[v[4]];  // eq. 5.21, w_S^T f_S
  return reward_state + reward_action;
}

FiniteMdp BuildCmaMdp(const CmaWeights& weights) {
  std::string error;
  if (!weights.IsValid(&error)) throw InputError("CMA weights: " + error);
  const FactoredMdpBuilder model = MakeCmaFactoredModel();
  return model.Build([&weights](const FactoredState& s, ActionIndex a) { return CmaReward(weights, s, a); });
}

CmaState QuadrantState(FlightStatus fs, MotorHealth mh, BatteryHealth bh, int quadrant) {
  // Quad I: RM1, MM1; II: RM1, MM0; III: RM0, MM0; IV: RM0, MM1 (§5.3.2.5).
  constexpr std::array<ReachMargin, 4> rm = {ReachMargin::kRM1, ReachMargin::kRM1, ReachMargin::kRM0,
                                             ReachMargin::kRM0};
  constexpr std::array<MotorMargin, 4> mm = {MotorMargin::kMM1, MotorMargin::kMM0, MotorMargin::kMM0,
                                             MotorMargin::kMM1};
  return {fs, mh, mm[quadrant], bh, rm[quadrant]};
}

std::vector<QuadrantRow> CmaQuadrantView(const std::vector<ActionIndex>& action, const std::vector<double>& value) {
  std::vector<QuadrantRow> rows;
  for (int fs = 0; fs < 3; ++fs) {
    for (int mh = 0; mh < 3; ++mh) {
      for (int bh = 0; bh < 3; ++bh) {
        QuadrantRow row{
            static_cast<FlightStatus>(fs), static_cast<MotorHealth>(mh), static_cast<BatteryHealth>(bh), {}};
        for (int q = 0; q < 4; ++q) {
          const CmaState state = QuadrantState(row.fs, row.mh, row.bh, q);
          const StateIndex s = CmaStateIndex(state);
          row.quadrants[q] = {state, action[s], value[s]};
        }
        rows.push_back(row);
      }
    }
  }
  return rows;
}

}  // namespace uascma::decision
