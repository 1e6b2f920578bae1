#include "uascma/decision/battery_mdp.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "uascma/common/error.h"

namespace uascma::decision {
namespace {

using models::HealthClass;
using models::PackAction;

constexpr int kNonFailureStates = kBatteryNumStates - 1;  // 288

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

std::string FeaturesLabel(const BatteryFeatures& f) {
  const auto pack = [](const PackFeatures& p) {
    return p.flagged ? fmt::format("{}FLT", p.switch_on ? "ON" : "OFF") : PackLabel(p);
  };
  return fmt::format("{}{}{}", f.current == CurrentLevel::kHigh ? "IH" : "IL", pack(f.pack[0]), pack(f.pack[1]));
}

// Ours' labels: the dissertation's 289, COMPLETE, then the flagged states (the first 289 are BatteryStateLabels()).
std::vector<std::string> MakeOursStateLabels() {
  std::vector<std::string> labels;
  labels.reserve(kOursNumStates);
  for (StateIndex s = 0; s < kNonFailureStates; ++s) labels.push_back(FeaturesLabel(BatteryStateFeatures(s)));
  labels.emplace_back("FAILURE");
  labels.emplace_back("COMPLETE");
  for (StateIndex s = kBatteryFirstFlaggedState; s < kOursNumStates; ++s) {
    labels.push_back(FeaturesLabel(BatteryStateFeatures(s)));
  }
  return labels;
}

// A flagged pack's energy and voltage are not read: S3 and C1, the worst (decision/battery_mdp.h ours item 10).
PackFeatures FlaggedPack(bool switch_on) { return {switch_on, EnergyState::kS3, VoltageState::kC1, true}; }

// Ours' flagged states (item 10), after COMPLETE: one flagged pack j (96), index
//   290 + ((j·2 + I)·2 + Sw_j)·12 + the other pack's code;  both flagged (8): 386 + (I·2 + Sw1)·2 + Sw2.
constexpr StateIndex kFirstBothFlagged = kBatteryFirstFlaggedState + 96;

StateIndex FlaggedStateIndex(const BatteryFeatures& f) {
  const int current = static_cast<int>(f.current);
  if (f.pack[0].flagged && f.pack[1].flagged) {
    return kFirstBothFlagged + (current * 2 + (f.pack[0].switch_on ? 1 : 0)) * 2 + (f.pack[1].switch_on ? 1 : 0);
  }
  const int j = f.pack[0].flagged ? 0 : 1;
  return kBatteryFirstFlaggedState + ((j * 2 + current) * 2 + (f.pack[j].switch_on ? 1 : 0)) * 12 +
         PackCode(f.pack[1 - j]);
}

BatteryFeatures FlaggedStateFeatures(StateIndex state) {
  BatteryFeatures f;
  if (state >= kFirstBothFlagged) {
    const int code = state - kFirstBothFlagged;
    f.current = static_cast<CurrentLevel>(code / 4);
    f.pack[0] = FlaggedPack((code / 2) % 2 == 1);
    f.pack[1] = FlaggedPack(code % 2 == 1);
    return f;
  }
  const int code = state - kBatteryFirstFlaggedState;
  const int j = code / 48;
  f.current = static_cast<CurrentLevel>((code / 24) % 2);
  f.pack[j] = FlaggedPack((code / 12) % 2 == 1);
  f.pack[1 - j] = PackFromCode(code % 12);
  return f;
}

// R_BiS of eq. 4.5 (docs/modelling-choices.md#battery-mdp-rewards): health "at least as good" = class index not larger
// (F1 < F2 < F3).
double EnergyReward(EnergyState energy, HealthClass own, HealthClass other) {
  const bool at_least_as_good = static_cast<int>(own) <= static_cast<int>(other);
  switch (energy) {
    case EnergyState::kS1:
      return 0.0;
    case EnergyState::kS2:
      return at_least_as_good ? -5.0 : -10.0;
    case EnergyState::kS3:
      return at_least_as_good ? -20.0 : -25.0;
  }
  return 0.0;
}
double VoltageReward(VoltageState voltage) { return voltage == VoltageState::kC1 ? -10.0 : 0.0; }  // eq. 4.6
double SwitchReward(bool on) { return on ? 1.0 : 0.0; }                                            // eq. 4.7

}  // namespace

// ================================ states ==========================================================
StateIndex BatteryStateIndex(const BatteryFeatures& features) {
  if (features.pack[0].flagged || features.pack[1].flagged) return FlaggedStateIndex(features);
  return (static_cast<int>(features.current) * 12 + PackCode(features.pack[0])) * 12 + PackCode(features.pack[1]);
}

BatteryFeatures BatteryStateFeatures(StateIndex state) {
  if (IsFlaggedBatteryState(state)) return FlaggedStateFeatures(state);
  UASCMA_CHECK(state >= 0 && state < kNonFailureStates, "a non-failure battery state");
  BatteryFeatures features;
  features.pack[1] = PackFromCode(state % 12);
  features.pack[0] = PackFromCode((state / 12) % 12);
  features.current = static_cast<CurrentLevel>(state / 144);
  return features;
}

const std::vector<std::string>& BatteryStateLabels() {
  static const std::vector<std::string> labels(BatteryFormulationStateLabels(BatteryFormulation::kOurs).begin(),
                                               BatteryFormulationStateLabels(BatteryFormulation::kOurs).begin() +
                                                   kBatteryNumStates);
  return labels;
}

int BatteryPolicyStates(BatteryFormulation formulation) {
  return formulation == BatteryFormulation::kOurs ? kOursNumStates : kBatteryNumStates;
}

const std::vector<std::string>& BatteryFormulationStateLabels(BatteryFormulation formulation) {
  static const std::vector<std::string> ours = MakeOursStateLabels();
  return formulation == BatteryFormulation::kOurs ? ours : BatteryStateLabels();
}

const std::vector<std::string>& BatteryActionNames() {
  static const std::vector<std::string> names = {models::PackActionName(PackAction::kUseBatt1),
                                                 models::PackActionName(PackAction::kUseBatt2),
                                                 models::PackActionName(PackAction::kUseBoth)};
  return names;
}

std::string BatteryStateLabel(StateIndex state) {
  UASCMA_CHECK(state >= 0 && state < kOursNumStates, "a battery state index");
  return BatteryFormulationStateLabels(BatteryFormulation::kOurs)[static_cast<std::size_t>(state)];
}

StateIndex ParseBatteryState(const std::string& label, const std::string& source) {
  const auto& labels = BatteryFormulationStateLabels(BatteryFormulation::kOurs);
  const auto it = std::find(labels.begin(), labels.end(), label);
  if (it == labels.end()) {
    throw InputError(source, "state",
                     fmt::format("a battery MDP state such as ILONS1C0OFFS2C0 or FAILURE, got '{}'", label));
  }
  return static_cast<StateIndex>(it - labels.begin());
}

StateIndex ApplySwitches(StateIndex state, PackAction action) {
  if (state == kBatteryFailureState || state == kBatteryCompleteState) return state;
  BatteryFeatures features = BatteryStateFeatures(state);
  const models::PerBranch<bool> on = models::SwitchesFor(action);
  features.pack[0].switch_on = on[0];
  features.pack[1].switch_on = on[1];
  return BatteryStateIndex(features);
}

bool SwitchesMatch(StateIndex state, PackAction action) { return ApplySwitches(state, action) == state; }

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
    case HealthClass::kG:
      return "F1";
    case HealthClass::kM:
      return "F2";
    case HealthClass::kP:
      return "F3";
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
    case PackAction::kUseBatt1:
      return weights.w1 * energy[0] + weights.w2 * voltage[0] - weights.w3 * on[1];  // 4.1
    case PackAction::kUseBatt2:
      return weights.w1 * energy[1] + weights.w2 * voltage[1] - weights.w3 * on[0];  // 4.2
    case PackAction::kUseBoth:                                                       // 4.3
      return weights.w1 * (energy[0] + energy[1]) / 2.0 + weights.w2 * (voltage[0] + voltage[1]) / 2.0 -
             weights.w3 * ((on[0] + on[1]) / 2.0 - 1.0);
  }
  return 0.0;
}

// ================================ ours ================================================
const char* BatteryFormulationName(BatteryFormulation formulation) {
  return formulation == BatteryFormulation::kOurs ? "ours" : "dissertation";
}

int SwitchToggles(StateIndex state, PackAction action) {
  UASCMA_CHECK((state >= 0 && state < kBatteryFailureState) || IsFlaggedBatteryState(state),
               "a non-failure battery state");
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
  const double energy =
      EnergyReward(f.pack[0].energy, context.b1, context.b2) + EnergyReward(f.pack[1].energy, context.b2, context.b1);
  const double voltage = VoltageReward(f.pack[0].voltage) + VoltageReward(f.pack[1].voltage);
  return weights.w1 * energy / 2.0 + weights.w2 * voltage / 2.0 -
         weights.w3 * static_cast<double>(SwitchToggles(state, action));
}

PackAction HoldSwitchesAction(const BatteryFeatures& f) {
  if (f.pack[0].switch_on && !f.pack[1].switch_on) return PackAction::kUseBatt1;
  if (!f.pack[0].switch_on && f.pack[1].switch_on) return PackAction::kUseBatt2;
  return PackAction::kUseBoth;
}

bool OursOffers(const BatteryFeatures& f, PackAction action) {
  const bool both_on = f.pack[0].switch_on && f.pack[1].switch_on;
  if (f.pack[0].flagged != f.pack[1].flagged) {  // item 10: one pack flagged
    const int flagged = f.pack[0].flagged ? 0 : 1;
    const PackAction other_alone = flagged == 0 ? PackAction::kUseBatt2 : PackAction::kUseBatt1;
    return action == HoldSwitchesAction(f) || action == other_alone;
  }
  if (!both_on) return action == HoldSwitchesAction(f);  // item 6: a dropped pack stays dropped
  if (f.pack[0].flagged) return true;                    // both flagged, both in: the features cannot tell them apart
  if (action == PackAction::kUseBoth) return true;
  const int k = action == PackAction::kUseBatt1 ? 0 : 1;
  // Item 7: only onto a pack that can finish alone with t_sf (S1) and is not critical alone (C0).
  return f.pack[k].energy == EnergyState::kS1 && f.pack[k].voltage == VoltageState::kC0;
}

}  // namespace uascma::decision
