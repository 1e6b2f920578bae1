#include "uascma/decision/battery_mdp.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/json_io.h"
#include "uascma/common/hash.h"
#include "uascma/decision/policy_file.h"

namespace uascma::decision {
namespace {

using models::HealthClass;
using models::PackAction;

constexpr int kNonFailureStates = kBatteryNumStates - 1;  // 288
constexpr std::array<PackAction, 3> kActions = {PackAction::kUseBatt1, PackAction::kUseBatt2, PackAction::kUseBoth};

int ActionIndexOf(PackAction action) { return static_cast<int>(action); }

// --- state encoding -----------------------------------------------------------------------------
int PackCode(const PackFeatures& pack) {
  return ((pack.switch_on ? 1 : 0) * 3 + static_cast<int>(pack.energy)) * 2 + static_cast<int>(pack.voltage);
}

PackFeatures PackFromCode(int code) {
  PackFeatures pack;
  pack.voltage = static_cast<VoltageState>(code % 2);
  code /= 2;
  pack.energy = static_cast<EnergyState>(code % 3);
  pack.switch_on = code / 3 == 1;
  return pack;
}

std::string PackLabel(const PackFeatures& pack) {
  return fmt::format("{}S{}C{}", pack.switch_on ? "ON" : "OFF", static_cast<int>(pack.energy) + 1,
                     static_cast<int>(pack.voltage));
}

std::vector<std::string> MakeStateLabels() {
  std::vector<std::string> labels;
  labels.reserve(kBatteryNumStates);
  for (StateIndex s = 0; s < kNonFailureStates; ++s) {
    const BatteryFeatures f = BatteryStateFeatures(s);
    labels.push_back(fmt::format("{}{}{}", f.current == CurrentLevel::kHigh ? "IH" : "IL", PackLabel(f.pack[0]),
                                 PackLabel(f.pack[1])));
  }
  labels.emplace_back("FAILURE");
  return labels;
}

// R_BiS of eq. 4.5 (decisions item 22): health "at least as good" = class index not larger (F1 < F2 < F3).
double EnergyReward(EnergyState energy, HealthClass own, HealthClass other) {
  const bool at_least_as_good = static_cast<int>(own) <= static_cast<int>(other);
  switch (energy) {
    case EnergyState::kS1: return 0.0;
    case EnergyState::kS2: return at_least_as_good ? -5.0 : -10.0;
    case EnergyState::kS3: return at_least_as_good ? -20.0 : -25.0;
  }
  return 0.0;
}
double VoltageReward(VoltageState voltage) { return voltage == VoltageState::kC1 ? -10.0 : 0.0; }  // eq. 4.6
double SwitchReward(bool on) { return on ? 1.0 : 0.0; }                                              // eq. 4.7

// --- JSON helpers -------------------------------------------------------------------------------
const nlohmann::json& Member(const nlohmann::json& object, const char* key, const std::string& source,
                             const std::string& where, const char* expected) {
  const std::string field = where.empty() ? key : where + "." + key;
  if (!object.is_object() || !object.contains(key)) throw InputError(source, field, std::string(expected) + ", but it is missing");
  return object.at(key);
}

std::string StringMember(const nlohmann::json& object, const char* key, const std::string& source,
                         const std::string& where = "") {
  const auto& value = Member(object, key, source, where, "a string");
  if (!value.is_string()) throw InputError(source, where.empty() ? key : where + "." + key, "a string");
  return value.get<std::string>();
}

double NumberMember(const nlohmann::json& object, const char* key, const std::string& source,
                    const std::string& where = "") {
  const auto& value = Member(object, key, source, where, "a number");
  if (!value.is_number() || !std::isfinite(value.get<double>())) {
    throw InputError(source, where.empty() ? key : where + "." + key, "a finite number");
  }
  return value.get<double>();
}

std::int64_t CountValue(const nlohmann::json& value, const std::string& source, const std::string& field) {
  if (!value.is_number_integer() || value.get<std::int64_t>() < 0) {
    throw InputError(source, field, "a non-negative integer count");
  }
  return value.get<std::int64_t>();
}

void CheckFormat(const nlohmann::json& json, const char* format, const std::string& source) {
  if (!json.is_object()) throw InputError(source, "(top level)", "a JSON object");
  const std::string got = StringMember(json, "format", source);
  if (got != format) throw InputError(source, "format", fmt::format("'{}', got '{}'", format, got));
  const auto& version = Member(json, "version", source, "", "an integer");
  if (!version.is_number_integer() || version.get<std::int64_t>() != kBatteryFileVersion) {
    throw InputError(source, "version",
                     fmt::format("{} (this build's {} version), got {}", kBatteryFileVersion, format, version.dump()));
  }
}

nlohmann::json WeightsJson(const BatteryRewardWeights& weights) {
  return {{"w1", weights.w1}, {"w2", weights.w2}, {"w3", weights.w3}};
}

BatteryRewardWeights WeightsFromJson(const nlohmann::json& json, const std::string& source) {
  const auto& object = Member(json, "weights", source, "", "an object {w1, w2, w3}");
  BatteryRewardWeights weights;
  weights.w1 = NumberMember(object, "w1", source, "weights");
  weights.w2 = NumberMember(object, "w2", source, "weights");
  weights.w3 = NumberMember(object, "w3", source, "weights");
  std::string error;
  if (!weights.IsValid(&error)) throw InputError(source, "weights", error);
  return weights;
}

double GammaFromJson(const nlohmann::json& json, const std::string& source) {
  const double gamma = NumberMember(json, "gamma", source);
  if (!(gamma >= 0.0 && gamma < 1.0)) throw InputError(source, "gamma", fmt::format("in [0, 1), got {}", gamma));
  return gamma;
}

BatteryContext ContextFromJson(const nlohmann::json& entry, const std::string& source, const std::string& where) {
  BatteryContext context;
  context.b1 = ParseBatteryHealth(StringMember(entry, "b1", source, where), source + ": " + where + ".b1");
  context.b2 = ParseBatteryHealth(StringMember(entry, "b2", source, where), source + ": " + where + ".b2");
  context.temperature =
      ParseTemperatureClass(StringMember(entry, "temperature", source, where), source + ": " + where + ".temperature");
  return context;
}

PackAction ParseAction(const std::string& name, const std::string& source, const std::string& field) {
  return models::ParsePackAction(name, source + ": " + field);  // names the file and the field
}

}  // namespace

// ================================ states ==========================================================
StateIndex BatteryStateIndex(const BatteryFeatures& features) {
  return (static_cast<int>(features.current) * 12 + PackCode(features.pack[0])) * 12 + PackCode(features.pack[1]);
}

BatteryFeatures BatteryStateFeatures(StateIndex state) {
  UASCMA_CHECK(state >= 0 && state < kNonFailureStates, "a non-failure battery state");
  BatteryFeatures features;
  features.pack[1] = PackFromCode(state % 12);
  features.pack[0] = PackFromCode((state / 12) % 12);
  features.current = static_cast<CurrentLevel>(state / 144);
  return features;
}

const std::vector<std::string>& BatteryStateLabels() {
  static const std::vector<std::string> labels = MakeStateLabels();
  return labels;
}

const std::vector<std::string>& BatteryActionNames() {
  static const std::vector<std::string> names = {models::PackActionName(PackAction::kUseBatt1),
                                                 models::PackActionName(PackAction::kUseBatt2),
                                                 models::PackActionName(PackAction::kUseBoth)};
  return names;
}

std::string BatteryStateLabel(StateIndex state) {
  UASCMA_CHECK(state >= 0 && state < kBatteryNumStates, "a battery state index");
  return BatteryStateLabels()[static_cast<std::size_t>(state)];
}

StateIndex ParseBatteryState(const std::string& label, const std::string& source) {
  const auto& labels = BatteryStateLabels();
  const auto it = std::find(labels.begin(), labels.end(), label);
  if (it == labels.end()) {
    throw InputError(source, "state", fmt::format("a battery MDP state such as ILONS1C0OFFS2C0 or FAILURE, got '{}'", label));
  }
  return static_cast<StateIndex>(it - labels.begin());
}

StateIndex ApplySwitches(StateIndex state, PackAction action) {
  if (state == kBatteryFailureState) return state;
  BatteryFeatures features = BatteryStateFeatures(state);
  const models::PerBranch<bool> on = models::SwitchesFor(action);
  features.pack[0].switch_on = on[0];
  features.pack[1].switch_on = on[1];
  return BatteryStateIndex(features);
}

bool SwitchesMatch(StateIndex state, PackAction action) { return ApplySwitches(state, action) == state; }

// ================================ abstraction =====================================================
EnergyState ClassifyEnergy(double eod_s, double remaining_flight_s, double safety_margin_s) {
  if (eod_s > remaining_flight_s + safety_margin_s) return EnergyState::kS1;  // enough, with the margin
  if (eod_s < remaining_flight_s) return EnergyState::kS3;                     // depletes before the end
  return EnergyState::kS2;                                                      // enough, inside the margin
}

VoltageState ClassifyVoltage(double min_cell_voltage_v, const BatteryThresholds& thresholds) {
  return min_cell_voltage_v >= thresholds.critical_voltage_v ? VoltageState::kC0 : VoltageState::kC1;
}

CurrentLevel ClassifyCurrent(double total_current_a, const BatteryThresholds& thresholds) {
  return total_current_a > thresholds.high_current_fraction * thresholds.max_current_a ? CurrentLevel::kHigh
                                                                                       : CurrentLevel::kLow;
}

bool IsCellFailure(double min_cell_voltage_v, const BatteryThresholds& thresholds) {
  return min_cell_voltage_v <= thresholds.failure_voltage_v;
}

StateIndex AbstractBatteryState(const BatteryObservation& observation, const BatteryThresholds& thresholds) {
  BatteryFeatures features;
  features.current = ClassifyCurrent(observation.total_current_a, thresholds);
  for (int j = 0; j < models::kBranchCount; ++j) {
    const double actual_v = observation.actual_min_cell_voltage_v[j] >= 0.0 ? observation.actual_min_cell_voltage_v[j]
                                                                           : observation.min_cell_voltage_v[j];
    if (observation.switch_on[j] && IsCellFailure(actual_v, thresholds)) return kBatteryFailureState;
  }
  for (int j = 0; j < models::kBranchCount; ++j) {
    features.pack[j].switch_on = observation.switch_on[j];
    features.pack[j].energy =
        ClassifyEnergy(observation.eod_s[j], observation.remaining_flight_s, observation.safety_margin_s);
    features.pack[j].voltage = ClassifyVoltage(observation.min_cell_voltage_v[j], thresholds);
  }
  return BatteryStateIndex(features);
}

BatteryObservation ObserveBattery(const models::BatteryPack& pack, const models::PackState& state,
                                  double total_current_a, double remaining_flight_s, double safety_margin_s,
                                  const prognostics::EodOptions& eod_options) {
  BatteryObservation observation;
  observation.total_current_a = total_current_a;
  observation.remaining_flight_s = remaining_flight_s;
  observation.safety_margin_s = safety_margin_s;
  observation.switch_on = state.branch_on;
  const models::PackOutputs actual = pack.CalcOutputs(state, total_current_a);
  for (int j = 0; j < models::kBranchCount; ++j) {
    // Pack j alone carrying the whole present current: its EOD and its worst cell under that load.
    models::PackState alone = state;
    alone.branch_on = {j == 0, j == 1};
    observation.eod_s[j] = prognostics::CalcPackEod(pack, alone, total_current_a, eod_options).eod_s;
    const models::PackOutputs loaded = pack.CalcOutputs(alone, total_current_a);
    double min_loaded_v = std::numeric_limits<double>::infinity(), min_actual_v = min_loaded_v;
    for (int c = 0; c < models::kCellsPerBranch; ++c) {
      min_loaded_v = std::min(min_loaded_v, loaded.cell_voltage_v[j][c]);
      min_actual_v = std::min(min_actual_v, actual.cell_voltage_v[j][c]);
    }
    observation.min_cell_voltage_v[j] = min_loaded_v;
    observation.actual_min_cell_voltage_v[j] = min_actual_v;
  }
  return observation;
}

// ================================ context =========================================================
int BatteryContextIndex(const BatteryContext& context) {
  return (static_cast<int>(context.temperature) * 3 + static_cast<int>(context.b1)) * 3 + static_cast<int>(context.b2);
}

BatteryContext BatteryContextFromIndex(int index) {
  UASCMA_CHECK(index >= 0 && index < kBatteryNumContexts, "a battery context index");
  return {static_cast<HealthClass>((index / 3) % 3), static_cast<HealthClass>(index % 3),
          static_cast<TemperatureClass>(index / 9)};
}

std::string BatteryContextLabel(const BatteryContext& context) {
  return fmt::format("{},{},{}", BatteryHealthName(context.b1), BatteryHealthName(context.b2),
                     TemperatureClassName(context.temperature));
}

TemperatureClass ClassifyTemperature(double ambient_temp_degf) {
  return ambient_temp_degf < models::kColdThresholdDegf ? TemperatureClass::kLow : TemperatureClass::kHigh;
}

const char* TemperatureClassName(TemperatureClass temperature) {
  return temperature == TemperatureClass::kLow ? "TL" : "TH";
}

TemperatureClass ParseTemperatureClass(const std::string& name, const std::string& source) {
  if (name == "TH") return TemperatureClass::kHigh;
  if (name == "TL") return TemperatureClass::kLow;
  throw InputError(source, "temperature", fmt::format("TH | TL (Table 4.2), got '{}'", name));
}

const char* BatteryHealthName(HealthClass health) {
  switch (health) {
    case HealthClass::kG: return "F1";
    case HealthClass::kM: return "F2";
    case HealthClass::kP: return "F3";
  }
  return "?";
}

HealthClass ParseBatteryHealth(const std::string& name, const std::string& source) {
  if (name == "F1") return HealthClass::kG;
  if (name == "F2") return HealthClass::kM;
  if (name == "F3") return HealthClass::kP;
  throw InputError(source, "health", fmt::format("F1 | F2 | F3 (Table 4.2), got '{}'", name));
}

BatteryContext BatteryContextOf(const models::PerCell<models::CellHealth>& cell_health, double ambient_temp_degf) {
  return {models::ClassifyHealth(cell_health[0]), models::ClassifyHealth(cell_health[1]),
          ClassifyTemperature(ambient_temp_degf)};
}

// ================================ rewards =========================================================
bool BatteryRewardWeights::IsValid(std::string* error) const {
  for (double w : {w1, w2, w3}) {
    if (!(w >= 0.0 && std::isfinite(w))) {
      if (error) *error = fmt::format("w1, w2, w3 finite and >= 0, got {}, {}, {}", w1, w2, w3);
      return false;
    }
  }
  if (std::abs(w1 + w2 + w3 - 1.0) > 1e-9) {
    if (error) *error = fmt::format("w1 + w2 + w3 = 1 (eq. 4.9), got {}", w1 + w2 + w3);
    return false;
  }
  return true;
}

double BatteryReward(StateIndex state, PackAction action, const BatteryContext& context,
                     const BatteryRewardWeights& weights) {
  if (state == kBatteryFailureState) return kBatteryFailureReward;  // eq. 4.8
  const BatteryFeatures f = BatteryStateFeatures(state);
  const double energy[2] = {EnergyReward(f.pack[0].energy, context.b1, context.b2),
                            EnergyReward(f.pack[1].energy, context.b2, context.b1)};
  const double voltage[2] = {VoltageReward(f.pack[0].voltage), VoltageReward(f.pack[1].voltage)};
  const double on[2] = {SwitchReward(f.pack[0].switch_on), SwitchReward(f.pack[1].switch_on)};
  switch (action) {
    case PackAction::kUseBatt1: return weights.w1 * energy[0] + weights.w2 * voltage[0] - weights.w3 * on[1];  // 4.1
    case PackAction::kUseBatt2: return weights.w1 * energy[1] + weights.w2 * voltage[1] - weights.w3 * on[0];  // 4.2
    case PackAction::kUseBoth:                                                                                // 4.3
      return weights.w1 * (energy[0] + energy[1]) / 2.0 + weights.w2 * (voltage[0] + voltage[1]) / 2.0 -
             weights.w3 * ((on[0] + on[1]) / 2.0 - 1.0);
  }
  return 0.0;
}

// ================================ ours (issue 24) ================================================
const char* BatteryFormulationName(BatteryFormulation formulation) {
  return formulation == BatteryFormulation::kOurs ? "ours" : "dissertation";
}

int SwitchToggles(StateIndex state, PackAction action) {
  UASCMA_CHECK(state >= 0 && state < kBatteryFailureState, "a non-failure battery state");
  const BatteryFeatures f = BatteryStateFeatures(state);
  const models::PerBranch<bool> on = models::SwitchesFor(action);
  return (f.pack[0].switch_on != on[0] ? 1 : 0) + (f.pack[1].switch_on != on[1] ? 1 : 0);
}

double OursBatteryReward(StateIndex state, PackAction action, const BatteryContext& context,
                         const BatteryRewardWeights& weights) {
  if (state == kBatteryFailureState) return kBatteryFailureReward;  // eq. 4.8, per epoch
  if (state == kBatteryCompleteState) return 0.0;                   // the plan is flown: nothing more to lose
  const BatteryFeatures f = BatteryStateFeatures(state);
  // Both packs' state terms whatever the action (eq. 4.3's averages), and eq. 4.7's w3 per toggled switch.
  const double energy = EnergyReward(f.pack[0].energy, context.b1, context.b2) +
                        EnergyReward(f.pack[1].energy, context.b2, context.b1);
  const double voltage = VoltageReward(f.pack[0].voltage) + VoltageReward(f.pack[1].voltage);
  return weights.w1 * energy / 2.0 + weights.w2 * voltage / 2.0 -
         weights.w3 * static_cast<double>(SwitchToggles(state, action));
}

namespace {

// The action that keeps a state's switches (UseBoth for both ON, and for the impossible both OFF).
PackAction HoldAction(const BatteryFeatures& f) {
  if (f.pack[0].switch_on && !f.pack[1].switch_on) return PackAction::kUseBatt1;
  if (!f.pack[0].switch_on && f.pack[1].switch_on) return PackAction::kUseBatt2;
  return PackAction::kUseBoth;
}

}  // namespace

bool OursOffers(const BatteryFeatures& f, PackAction action) {
  const bool both_on = f.pack[0].switch_on && f.pack[1].switch_on;
  if (!both_on) return action == HoldAction(f);  // item 6: a dropped pack stays dropped
  if (action == PackAction::kUseBoth) return true;
  const int k = action == PackAction::kUseBatt1 ? 0 : 1;
  return f.pack[k].energy == EnergyState::kS1;  // item 7: only onto a pack that can finish alone with t_sf (S1)
}

FiniteMdp BuildOursBatteryMdp(const BatteryTransitionCounts& counts, const BatteryContext& context,
                              const BatteryRewardWeights& weights, BatteryModelStats* stats) {
  std::string error;
  if (!weights.IsValid(&error)) throw InputError("battery MDP", "weights", error);
  std::vector<std::string> labels = BatteryStateLabels();
  labels.emplace_back("COMPLETE");
  FiniteMdpBuilder builder(std::move(labels), BatteryActionNames());
  BatteryModelStats local;
  std::vector<Transition> row;
  for (StateIndex s = 0; s < kBatteryFailureState; ++s) {
    bool any = false;
    const BatteryFeatures features = BatteryStateFeatures(s);
    for (PackAction action : kActions) {
      const StateIndex switched = ApplySwitches(s, action);
      const bool learned = switched == s;
      if (learned) ++local.learned_rows;
      else ++local.switch_rows;
      if (!OursOffers(features, action)) continue;  // items 6-7
      const auto& observed = counts.Row(context, switched, action);
      const std::int64_t completed = counts.Completions(context, switched, action);
      std::int64_t total = completed;
      for (const auto& [next, count] : observed) total += count;
      if (total == 0) {  // no evidence: the action is not offered here (item 5)
        if (learned) ++local.unobserved_rows;
        continue;
      }
      row.clear();
      for (const auto& [next, count] : observed) {
        row.push_back({next, static_cast<double>(count) / static_cast<double>(total)});
      }
      if (completed > 0) row.push_back({kBatteryCompleteState, static_cast<double>(completed) / static_cast<double>(total)});
      if (learned) local.transitions += total;
      builder.AddRow(s, ActionIndexOf(action), OursBatteryReward(s, action, context, weights), row);
      any = true;
    }
    if (!any) {  // nothing offered was ever observed: hold the present switches (UseBoth at take-off), as a loop
      const PackAction hold = HoldAction(features);
      const Transition loop{ApplySwitches(s, hold), 1.0};
      builder.AddRow(s, ActionIndexOf(hold), OursBatteryReward(s, hold, context, weights),
                     std::span<const Transition>(&loop, 1));
    }
  }
  for (StateIndex absorbing : {kBatteryFailureState, kBatteryCompleteState}) {
    const Transition loop{absorbing, 1.0};
    for (PackAction action : kActions) {
      builder.AddRow(absorbing, ActionIndexOf(action), OursBatteryReward(absorbing, action, context, weights),
                     std::span<const Transition>(&loop, 1));
    }
  }
  if (stats) *stats = local;
  return builder.Build();
}

// ================================ counts ==========================================================
BatteryTransitionCounts::BatteryTransitionCounts()
    : rows_(static_cast<std::size_t>(kBatteryNumContexts) * kBatteryNumStates * kBatteryNumActions),
      completions_(rows_.size(), 0) {}

std::size_t BatteryTransitionCounts::RowIndex(const BatteryContext& context, StateIndex state, PackAction action) {
  UASCMA_CHECK(state >= 0 && state < kBatteryNumStates, "a battery state index");
  return (static_cast<std::size_t>(BatteryContextIndex(context)) * kBatteryNumStates + static_cast<std::size_t>(state)) *
             kBatteryNumActions +
         static_cast<std::size_t>(ActionIndexOf(action));
}

void BatteryTransitionCounts::Add(const BatteryContext& context, StateIndex state, PackAction action, StateIndex next,
                                  std::int64_t count) {
  UASCMA_CHECK(next >= 0 && next < kBatteryNumStates, "a battery next-state index");
  UASCMA_CHECK(count >= 0, "a non-negative count");
  if (count == 0) return;
  rows_[RowIndex(context, state, action)][next] += count;
}

void BatteryTransitionCounts::AddCompletion(const BatteryContext& context, StateIndex state, PackAction action,
                                            std::int64_t count) {
  UASCMA_CHECK(state != kBatteryFailureState, "a completion from a non-failure state");
  UASCMA_CHECK(count >= 0, "a non-negative count");
  completions_[RowIndex(context, state, action)] += count;
}

std::int64_t BatteryTransitionCounts::Completions(const BatteryContext& context, StateIndex state,
                                                 PackAction action) const {
  return completions_[RowIndex(context, state, action)];
}

void BatteryTransitionCounts::AddFlight(const BatteryContext& context, PackAction action,
                                        std::span<const StateIndex> states, bool completed) {
  for (std::size_t k = 0; k < states.size(); ++k) {
    if (states[k] < 0 || states[k] >= kBatteryNumStates) {
      throw InputError("battery flight", fmt::format("states[{}]", k), "a battery MDP state index");
    }
    if (!SwitchesMatch(states[k], action)) {
      throw InputError("battery flight", fmt::format("states[{}]", k),
                       fmt::format("the switches of {} (flown throughout), got {}", models::PackActionName(action),
                                   BatteryStateLabel(states[k])));
    }
  }
  for (std::size_t k = 0; k + 1 < states.size(); ++k) {
    if (states[k] == kBatteryFailureState) break;
    Add(context, states[k], action, states[k + 1]);
  }
  if (completed && !states.empty() && states.back() != kBatteryFailureState) {
    AddCompletion(context, states.back(), action);
  }
  flights_[static_cast<std::size_t>(BatteryContextIndex(context) * kBatteryNumActions + ActionIndexOf(action))] += 1;
}

void BatteryTransitionCounts::AddSwitchingFlight(const BatteryContext& context, std::span<const StateIndex> states,
                                                 std::span<const PackAction> actions, bool completed) {
  UASCMA_CHECK(!actions.empty() && actions.size() <= states.size(), "an action per epoch");
  for (std::size_t k = 0; k < states.size(); ++k) {
    if (states[k] < 0 || states[k] >= kBatteryNumStates) {
      throw InputError("battery flight", fmt::format("states[{}]", k), "a battery MDP state index");
    }
  }
  std::size_t last = 0;
  for (std::size_t k = 0; k + 1 < states.size() && k < actions.size(); ++k) {
    if (states[k] == kBatteryFailureState) break;
    Add(context, ApplySwitches(states[k], actions[k]), actions[k], states[k + 1]);
    last = k + 1;
  }
  const std::size_t end = std::min(last, actions.size() - 1);
  if (completed && states[end] != kBatteryFailureState) {
    AddCompletion(context, ApplySwitches(states[end], actions[end]), actions[end]);
  }
  flights_[static_cast<std::size_t>(BatteryContextIndex(context) * kBatteryNumActions + ActionIndexOf(actions.back()))] += 1;
}

void BatteryTransitionCounts::Merge(const BatteryTransitionCounts& other) {
  for (std::size_t r = 0; r < rows_.size(); ++r) {
    for (const auto& [next, count] : other.rows_[r]) rows_[r][next] += count;
    completions_[r] += other.completions_[r];
  }
  for (std::size_t i = 0; i < flights_.size(); ++i) flights_[i] += other.flights_[i];
}

const std::map<StateIndex, std::int64_t>& BatteryTransitionCounts::Row(const BatteryContext& context, StateIndex state,
                                                                       PackAction action) const {
  return rows_[RowIndex(context, state, action)];
}

std::int64_t BatteryTransitionCounts::RowTotal(const BatteryContext& context, StateIndex state,
                                               PackAction action) const {
  std::int64_t total = 0;
  for (const auto& [next, count] : Row(context, state, action)) total += count;
  return total;
}

std::int64_t BatteryTransitionCounts::flights(const BatteryContext& context, PackAction action) const {
  return flights_[static_cast<std::size_t>(BatteryContextIndex(context) * kBatteryNumActions + ActionIndexOf(action))];
}

void BatteryTransitionCounts::SetFlights(const BatteryContext& context, PackAction action, std::int64_t flights) {
  flights_[static_cast<std::size_t>(BatteryContextIndex(context) * kBatteryNumActions + ActionIndexOf(action))] = flights;
}

std::int64_t BatteryTransitionCounts::total_transitions() const {
  std::int64_t total = 0;
  for (const auto& row : rows_) {
    for (const auto& [next, count] : row) total += count;
  }
  return total;
}

std::int64_t BatteryTransitionCounts::total_flights() const {
  std::int64_t total = 0;
  for (std::int64_t f : flights_) total += f;
  return total;
}

// ================================ the MDP of one context ==========================================
FiniteMdp BuildBatteryMdp(const BatteryTransitionCounts& counts, const BatteryContext& context,
                          const BatteryRewardWeights& weights, BatteryModelStats* stats) {
  std::string error;
  if (!weights.IsValid(&error)) throw InputError("battery MDP", "weights", error);
  FiniteMdpBuilder builder(BatteryStateLabels(), BatteryActionNames());
  BatteryModelStats local;
  std::vector<Transition> row;
  for (StateIndex s = 0; s < kBatteryNumStates; ++s) {
    for (PackAction action : kActions) {
      const double reward = BatteryReward(s, action, context, weights);
      row.clear();
      if (s == kBatteryFailureState) {
        row.push_back({s, 1.0});  // absorbing
      } else {
        // The switch takes effect at once and with certainty (§4.3.2, decisions items 23-24): the epoch
        // then runs from the switched state, whose row under this action is what the flights counted.
        const StateIndex switched = ApplySwitches(s, action);
        const bool learned = switched == s;
        if (learned) ++local.learned_rows;
        else ++local.switch_rows;
        const auto& observed = counts.Row(context, switched, action);
        std::int64_t total = 0;
        for (const auto& [next, count] : observed) total += count;
        if (total == 0) {
          row.push_back({switched, 1.0});  // never observed: the switched state loops on itself (item 23)
          if (learned) ++local.unobserved_rows;
        } else {
          for (const auto& [next, count] : observed) {
            row.push_back({next, static_cast<double>(count) / static_cast<double>(total)});
          }
          if (learned) local.transitions += total;
        }
      }
      builder.AddRow(s, ActionIndexOf(action), reward, row);
    }
  }
  if (stats) *stats = local;
  return builder.Build();
}

// ================================ model files =====================================================
std::string BatteryModelHash(const BatteryModel& model) {
  Fingerprint fingerprint;
  fingerprint.Add(std::string_view(kBatteryModelFormat));
  fingerprint.Add(kBatteryFileVersion);
  fingerprint.Add(model.gamma);
  fingerprint.Add(model.weights.w1);
  fingerprint.Add(model.weights.w2);
  fingerprint.Add(model.weights.w3);
  fingerprint.Add(model.provenance.dump());
  for (int c = 0; c < kBatteryNumContexts; ++c) {
    const BatteryContext context = BatteryContextFromIndex(c);
    for (PackAction action : kActions) fingerprint.Add(model.counts.flights(context, action));
    for (StateIndex s = 0; s < kBatteryNumStates; ++s) {
      for (PackAction action : kActions) {
        const auto& row = model.counts.Row(context, s, action);
        const std::int64_t completed = model.counts.Completions(context, s, action);
        if (row.empty() && completed == 0) continue;
        fingerprint.Add(static_cast<std::int64_t>(BatteryContextIndex(context)));
        fingerprint.Add(static_cast<std::int64_t>(s));
        fingerprint.Add(ActionIndexOf(action));
        for (const auto& [next, count] : row) {
          fingerprint.Add(static_cast<std::int64_t>(next));
          fingerprint.Add(count);
        }
        // Completions only when counted, so a model without them keeps its hash.
        if (completed > 0) {
          fingerprint.Add(std::string_view("completed"));
          fingerprint.Add(completed);
        }
      }
    }
  }
  return fingerprint.Hex();
}

nlohmann::json BatteryModelToJson(const BatteryModel& model) {
  nlohmann::json contexts = nlohmann::json::array();
  for (int c = 0; c < kBatteryNumContexts; ++c) {
    const BatteryContext context = BatteryContextFromIndex(c);
    nlohmann::json flights = nlohmann::json::object();
    for (PackAction action : kActions) flights[models::PackActionName(action)] = model.counts.flights(context, action);
    nlohmann::json rows = nlohmann::json::array();
    for (StateIndex s = 0; s < kBatteryNumStates; ++s) {
      for (PackAction action : kActions) {
        const auto& row = model.counts.Row(context, s, action);
        const std::int64_t completed = model.counts.Completions(context, s, action);
        if (row.empty() && completed == 0) continue;
        nlohmann::json next = nlohmann::json::object();
        for (const auto& [state, count] : row) next[BatteryStateLabel(state)] = count;
        nlohmann::json entry = {{"state", BatteryStateLabel(s)}, {"action", models::PackActionName(action)}, {"next", next}};
        if (completed > 0) entry["completed"] = completed;
        rows.push_back(std::move(entry));
      }
    }
    contexts.push_back({{"b1", BatteryHealthName(context.b1)},
                        {"b2", BatteryHealthName(context.b2)},
                        {"temperature", TemperatureClassName(context.temperature)},
                        {"flights", flights},
                        {"rows", rows}});
  }
  return {{"format", kBatteryModelFormat},
          {"version", kBatteryFileVersion},
          {"hash", BatteryModelHash(model)},
          {"gamma", model.gamma},
          {"weights", WeightsJson(model.weights)},
          {"provenance", model.provenance},
          {"contexts", contexts}};
}

BatteryModel BatteryModelFromJson(const nlohmann::json& json, const std::string& source) {
  CheckFormat(json, kBatteryModelFormat, source);
  BatteryModel model;
  const std::string hash = StringMember(json, "hash", source);
  model.gamma = GammaFromJson(json, source);
  model.weights = WeightsFromJson(json, source);
  model.provenance = json.value("provenance", nlohmann::json::object());
  const auto& contexts = Member(json, "contexts", source, "", "an array of contexts");
  if (!contexts.is_array()) throw InputError(source, "contexts", "an array of contexts");
  std::array<bool, kBatteryNumContexts> seen{};
  for (std::size_t i = 0; i < contexts.size(); ++i) {
    const std::string where = fmt::format("contexts[{}]", i);
    const auto& entry = contexts[i];
    if (!entry.is_object()) throw InputError(source, where, "an object {b1, b2, temperature, flights, rows}");
    const BatteryContext context = ContextFromJson(entry, source, where);
    const int index = BatteryContextIndex(context);
    if (seen[static_cast<std::size_t>(index)]) throw InputError(source, where, "each (b1, b2, temperature) once");
    seen[static_cast<std::size_t>(index)] = true;
    const auto& flights = Member(entry, "flights", source, where, "an object of flights per action");
    for (PackAction action : kActions) {
      const char* name = models::PackActionName(action);
      const auto& value = Member(flights, name, source, where + ".flights", "a count");
      model.counts.SetFlights(context, action, CountValue(value, source, where + ".flights." + name));
    }
    const auto& rows = Member(entry, "rows", source, where, "an array of rows");
    if (!rows.is_array()) throw InputError(source, where + ".rows", "an array of rows");
    for (std::size_t r = 0; r < rows.size(); ++r) {
      const std::string row_where = fmt::format("{}.rows[{}]", where, r);
      const auto& row = rows[r];
      const StateIndex s = ParseBatteryState(StringMember(row, "state", source, row_where), source + ": " + row_where);
      const PackAction action = ParseAction(StringMember(row, "action", source, row_where), source, row_where + ".action");
      if (s == kBatteryFailureState || !SwitchesMatch(s, action)) {
        throw InputError(source, row_where, "a learned row: a non-failure state with the action's switches");
      }
      const auto& next = Member(row, "next", source, row_where, "an object next state → count");
      if (!next.is_object()) throw InputError(source, row_where + ".next", "an object next state → count");
      for (const auto& [label, count] : next.items()) {
        const StateIndex n = ParseBatteryState(label, source + ": " + row_where + ".next");
        model.counts.Add(context, s, action, n, CountValue(count, source, row_where + ".next." + label));
      }
      if (row.contains("completed")) {
        model.counts.AddCompletion(context, s, action, CountValue(row.at("completed"), source, row_where + ".completed"));
      }
    }
  }
  for (int c = 0; c < kBatteryNumContexts; ++c) {
    if (!seen[static_cast<std::size_t>(c)]) {
      throw InputError(source, "contexts", "every (b1, b2, temperature), missing " +
                                               BatteryContextLabel(BatteryContextFromIndex(c)));
    }
  }
  const std::string expected = BatteryModelHash(model);
  if (hash != expected) {
    throw InputError(source, "hash", fmt::format("{} (the fingerprint of the file's contents), got {}: the file was "
                                                 "edited or damaged",
                                                 expected, hash));
  }
  return model;
}

BatteryModel ReadBatteryModelFile(const std::filesystem::path& path) {
  return BatteryModelFromJson(ReadJsonFile(path), path.string());
}

// ================================ policies ========================================================
const BatteryContextPolicy& BatteryPolicySet::Select(const BatteryContext& context) const {
  // Fig. 4.5's tree: the temperature branch, then the B1 health branch, then the B2 health leaf. The
  // array is laid out in that order (BatteryContextIndex), so the walk is one index computation.
  return policies[static_cast<std::size_t>(BatteryContextIndex(context))];
}

BatteryPolicySet SolveBatteryPolicies(const BatteryModel& model) {
  BatteryPolicySet set;
  set.model_hash = BatteryModelHash(model);
  set.gamma = model.gamma;
  set.weights = model.weights;
  ValueIterationOptions options;
  options.gamma = model.gamma;  // 0.95, §4.3.2.1
  for (int c = 0; c < kBatteryNumContexts; ++c) {
    BatteryContextPolicy& out = set.policies[static_cast<std::size_t>(c)];
    out.context = BatteryContextFromIndex(c);
    const FiniteMdp mdp = BuildBatteryMdp(model.counts, out.context, model.weights, &out.stats);
    Policy policy = SolveValueIteration(mdp, options, &out.summary);
    out.action = std::move(policy.action);
    out.value = std::move(policy.value);
    out.mdp_hash = ModelHash(mdp);
    for (StateIndex s = 0; s < kBatteryFailureState; ++s) {
      for (PackAction action : kActions) {
        if (!SwitchesMatch(s, action) || model.counts.Row(out.context, s, action).empty()) continue;
        const std::int64_t choice = mdp.FindChoice(s, ActionIndexOf(action));
        BatteryLearnedRow row{s, action, {}};
        const auto next = mdp.choice_next_states(choice);
        const auto prob = mdp.choice_probabilities(choice);
        for (std::size_t k = 0; k < next.size(); ++k) row.next.push_back({next[k], prob[k]});
        out.observed_rows.push_back(std::move(row));
      }
    }
  }
  return set;
}

BatteryPolicySet SolveOursBatteryPolicies(const BatteryModel& model, double gamma) {
  if (!(gamma > 0.0 && gamma < 1.0)) throw InputError("battery MDP", "gamma", fmt::format("in (0, 1), got {}", gamma));
  BatteryPolicySet set;
  set.model_hash = BatteryModelHash(model);
  set.formulation = BatteryFormulation::kOurs;
  set.gamma = gamma;
  set.weights = model.weights;
  PolicyIterationOptions options;
  options.gamma = gamma;
  options.evaluation = EvaluationMethod::kDirect;  // 290 states: exact
  for (int c = 0; c < kBatteryNumContexts; ++c) {
    BatteryContextPolicy& out = set.policies[static_cast<std::size_t>(c)];
    out.context = BatteryContextFromIndex(c);
    const FiniteMdp mdp = BuildOursBatteryMdp(model.counts, out.context, model.weights, &out.stats);
    Policy policy = SolvePolicyIteration(mdp, options, &out.summary);
    out.action.assign(policy.action.begin(), policy.action.begin() + kBatteryNumStates);  // COMPLETE dropped
    out.value.assign(policy.value.begin(), policy.value.begin() + kBatteryNumStates);
    out.mdp_hash = ModelHash(mdp);
    // The counted rows (p over the counted next states, completions left out), for drawing Fig. 4.4.
    for (StateIndex s = 0; s < kBatteryFailureState; ++s) {
      for (PackAction action : kActions) {
        const auto& counted = model.counts.Row(out.context, s, action);
        if (!SwitchesMatch(s, action) || counted.empty()) continue;
        std::int64_t total = 0;
        for (const auto& [next, count] : counted) total += count;
        BatteryLearnedRow row{s, action, {}};
        for (const auto& [next, count] : counted) {
          row.next.push_back({next, static_cast<double>(count) / static_cast<double>(total)});
        }
        out.observed_rows.push_back(std::move(row));
      }
    }
  }
  return set;
}

namespace {

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
      fingerprint.Add(ActionIndexOf(row.action));
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

BatteryFormulation FormulationFromJson(const nlohmann::json& json, const std::string& source) {
  if (!json.contains("formulation")) return BatteryFormulation::kDissertation;
  const std::string name = StringMember(json, "formulation", source);
  if (name == "dissertation") return BatteryFormulation::kDissertation;
  if (name == "ours") return BatteryFormulation::kOurs;
  throw InputError(source, "formulation", fmt::format("dissertation | ours, got '{}'", name));
}

}  // namespace

nlohmann::json BatteryPolicyToJson(const BatteryPolicySet& set) {
  nlohmann::json policies = nlohmann::json::array();
  for (const BatteryContextPolicy& p : set.policies) {
    nlohmann::json actions = nlohmann::json::array();
    for (ActionIndex a : p.action) actions.push_back(BatteryActionNames()[static_cast<std::size_t>(a)]);
    nlohmann::json observed = nlohmann::json::array();
    for (const BatteryLearnedRow& row : p.observed_rows) {
      nlohmann::json next = nlohmann::json::object();
      for (const Transition& t : row.next) next[BatteryStateLabel(t.next_state)] = t.probability;
      observed.push_back({{"state", BatteryStateLabel(row.state)}, {"action", models::PackActionName(row.action)},
                          {"next", next}});
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
          {"states", BatteryStateLabels()},
          {"actions", BatteryActionNames()},
          {"policies", policies}};
}

BatteryPolicySet BatteryPolicyFromJson(const nlohmann::json& json, const std::string& source) {
  CheckFormat(json, kBatteryPolicyFormat, source);
  BatteryPolicySet set;
  const std::string hash = StringMember(json, "hash", source);
  set.model_hash = StringMember(json, "model_hash", source);
  set.formulation = FormulationFromJson(json, source);
  set.gamma = GammaFromJson(json, source);
  set.weights = WeightsFromJson(json, source);
  const auto& states = Member(json, "states", source, "", "the 289 state labels");
  if (states != nlohmann::json(BatteryStateLabels())) {
    throw InputError(source, "states", "the 289 battery MDP state labels in this build's order");
  }
  const auto& policies = Member(json, "policies", source, "", "an array of 18 policies");
  if (!policies.is_array()) throw InputError(source, "policies", "an array of 18 policies");
  std::array<bool, kBatteryNumContexts> seen{};
  for (std::size_t i = 0; i < policies.size(); ++i) {
    const std::string where = fmt::format("policies[{}]", i);
    const auto& entry = policies[i];
    if (!entry.is_object()) throw InputError(source, where, "an object {b1, b2, temperature, action, value}");
    const BatteryContext context = ContextFromJson(entry, source, where);
    const auto index = static_cast<std::size_t>(BatteryContextIndex(context));
    if (seen[index]) throw InputError(source, where, "each (b1, b2, temperature) once");
    seen[index] = true;
    BatteryContextPolicy& p = set.policies[index];
    p.context = context;
    p.mdp_hash = StringMember(entry, "mdp_hash", source, where);
    const auto& actions = Member(entry, "action", source, where, "289 action names");
    const auto& values = Member(entry, "value", source, where, "289 numbers");
    if (!actions.is_array() || actions.size() != static_cast<std::size_t>(kBatteryNumStates)) {
      throw InputError(source, where + ".action", "an array of 289 action names");
    }
    if (!values.is_array() || values.size() != static_cast<std::size_t>(kBatteryNumStates)) {
      throw InputError(source, where + ".value", "an array of 289 numbers");
    }
    for (int s = 0; s < kBatteryNumStates; ++s) {
      const std::string field = fmt::format("{}.action[{}]", where, s);
      if (!actions[static_cast<std::size_t>(s)].is_string()) throw InputError(source, field, "an action name");
      p.action.push_back(ActionIndexOf(ParseAction(actions[static_cast<std::size_t>(s)].get<std::string>(), source, field)));
      if (!values[static_cast<std::size_t>(s)].is_number()) {
        throw InputError(source, fmt::format("{}.value[{}]", where, s), "a number");
      }
      p.value.push_back(values[static_cast<std::size_t>(s)].get<double>());
    }
    const auto& observed = Member(entry, "observed_rows", source, where, "an array of observed rows");
    if (!observed.is_array()) throw InputError(source, where + ".observed_rows", "an array of observed rows");
    for (std::size_t r = 0; r < observed.size(); ++r) {
      const std::string row_where = fmt::format("{}.observed_rows[{}]", where, r);
      BatteryLearnedRow row;
      row.state = ParseBatteryState(StringMember(observed[r], "state", source, row_where), source + ": " + row_where);
      row.action = ParseAction(StringMember(observed[r], "action", source, row_where), source, row_where + ".action");
      const auto& next = Member(observed[r], "next", source, row_where, "an object next state → probability");
      if (!next.is_object()) throw InputError(source, row_where + ".next", "an object next state → probability");
      for (const auto& [label, probability] : next.items()) {
        if (!probability.is_number()) throw InputError(source, row_where + ".next." + label, "a probability");
        row.next.push_back({ParseBatteryState(label, source + ": " + row_where + ".next"), probability.get<double>()});
      }
      // JSON objects are ordered by key; the MDP's rows by state index.
      std::sort(row.next.begin(), row.next.end(),
                [](const Transition& a, const Transition& b) { return a.next_state < b.next_state; });
      p.observed_rows.push_back(std::move(row));
    }
    // The solver's report and the statistics: optional, but typed (a string status, counts in int's range, a
    // number residual); json::value() threw type_error on a mistyped one and cast 1e300 to int (issue 16).
    auto count = [&](const nlohmann::json& object, const char* key, const std::string& at) -> std::int64_t {
      const auto it = object.find(key);
      if (it == object.end()) return 0;
      if (!it->is_number_integer() || it->get<std::int64_t>() < 0 ||
          it->get<std::int64_t>() > std::numeric_limits<int>::max()) {
        throw InputError(source, at + "." + key, fmt::format("a count from 0 to {}, got {}", std::numeric_limits<int>::max(), it->dump()));
      }
      return it->get<std::int64_t>();
    };
    if (entry.contains("solver") && entry.at("solver").is_object()) {
      const auto& solver = entry.at("solver");
      const std::string at = where + ".solver";
      const std::string status = solver.contains("status") ? StringMember(solver, "status", source, at) : "";
      p.summary.status = status == "converged" ? SolverStatus::kConverged : SolverStatus::kMaxIterations;
      p.summary.iterations = static_cast<int>(count(solver, "iterations", at));
      p.summary.residual = solver.contains("residual") ? NumberMember(solver, "residual", source, at) : 0.0;
    }
    if (entry.contains("stats") && entry.at("stats").is_object()) {
      const auto& stats = entry.at("stats");
      const std::string at = where + ".stats";
      p.stats.learned_rows = static_cast<int>(count(stats, "learned_rows", at));
      p.stats.unobserved_rows = static_cast<int>(count(stats, "unobserved_rows", at));
      p.stats.switch_rows = static_cast<int>(count(stats, "switch_rows", at));
      p.stats.transitions = count(stats, "transitions", at);
    }
  }
  for (int c = 0; c < kBatteryNumContexts; ++c) {
    if (!seen[static_cast<std::size_t>(c)]) {
      throw InputError(source, "policies",
                       "a policy for every (b1, b2, temperature), missing " + BatteryContextLabel(BatteryContextFromIndex(c)));
    }
  }
  const std::string expected = PolicyFingerprint(set).Hex();
  if (hash != expected) {
    throw InputError(source, "hash",
                     fmt::format("{} (the fingerprint of the file's policies), got {}: the file was edited or damaged",
                                 expected, hash));
  }
  return set;
}

BatteryPolicySet ReadBatteryPolicyFile(const std::filesystem::path& path) {
  return BatteryPolicyFromJson(ReadJsonFile(path), path.string());
}

BatteryPolicyExecutor::BatteryPolicyExecutor(const BatteryPolicySet& policies, const BatteryContext& context)
    : context_(context), action_(policies.Select(context).action) {
  UASCMA_CHECK(action_.size() == static_cast<std::size_t>(kBatteryNumStates), "a policy of 289 actions");
}

PackAction BatteryPolicyExecutor::Decide(StateIndex state) const {
  UASCMA_CHECK(state >= 0 && state < kBatteryNumStates, "a battery state index");
  return static_cast<PackAction>(action_[static_cast<std::size_t>(state)]);
}

BatteryPolicyExecutor LoadBatteryPolicyExecutor(const std::filesystem::path& path, const BatteryContext& context) {
  return BatteryPolicyExecutor(ReadBatteryPolicyFile(path), context);
}

}  // namespace uascma::decision
