#include "uascma/campaign/battery_controllers.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/decision/battery_mdp_file.h"

namespace uascma::campaign {
namespace {

using decision::BatteryContext;
using decision::StateIndex;
using models::PackAction;

const char* KindName(BatteryPolicyKind kind) {
  switch (kind) {
    case BatteryPolicyKind::kUseBoth:
      return "useboth";
    case BatteryPolicyKind::kVoltageRule:
      return "rule:voltage";
    case BatteryPolicyKind::kPiStar:
      return "pistar";
    case BatteryPolicyKind::kOurs:
      return "ours";
    case BatteryPolicyKind::kFaultRule:
      return "rule:fault";
  }
  return "?";
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
    } else if (name == "rule" && argument == "fault") {
      spec.kind = BatteryPolicyKind::kFaultRule;
    } else if ((name == "pistar" || name == "ours") && !argument.empty()) {
      spec.kind = name == "pistar" ? BatteryPolicyKind::kPiStar : BatteryPolicyKind::kOurs;
      spec.file = argument;
      auto policies = std::make_shared<decision::BatteryPolicySet>(decision::ReadBatteryPolicyFile(spec.file));
      const auto wanted =
          name == "pistar" ? decision::BatteryFormulation::kDissertation : decision::BatteryFormulation::kOurs;
      if (policies->formulation != wanted) {
        throw InputError(
            spec.file.string(), "formulation",
            fmt::format("'{}' for {}: (battery solve{}), got '{}'", decision::BatteryFormulationName(wanted), name,
                        name == "ours" ? " --formulation ours" : "",
                        decision::BatteryFormulationName(policies->formulation)));
      }
      spec.policies = std::move(policies);
    } else {
      throw InputError(
          option, item.empty() ? "(empty)" : item,
          "useboth | pistar:POLICY.json | ours:POLICY.json | rule:voltage[:V] | rule:fault, separated by commas");
    }
    spec.label = KindName(spec.kind);
    if (!seen.insert(spec.label).second) throw InputError(option, item, "each policy once");
    specs.push_back(std::move(spec));
    if (end == text.size()) break;
  }
  return specs;
}

PackAction HeldSwitches(const decision::BatteryObservation& observation) {
  if (observation.switch_on[0] && !observation.switch_on[1]) return PackAction::kUseBatt1;
  if (observation.switch_on[1] && !observation.switch_on[0]) return PackAction::kUseBatt2;
  return PackAction::kUseBoth;
}

namespace {

// An action that takes a pack out while both are in.
bool IsIsolation(const decision::BatteryObservation& observation, PackAction action) {
  return observation.switch_on[0] && observation.switch_on[1] && action != PackAction::kUseBoth;
}

// The same, of a pack the pack-fault indicator flags.
bool IsFaultIsolation(const decision::BatteryObservation& observation, PackAction action) {
  if (!IsIsolation(observation, action)) return false;
  return observation.pack_fault[action == PackAction::kUseBatt1 ? 1 : 0];
}

// Ours (decision/battery_mdp.h): the table in ours' abstraction, item 9's drop check, item 8's guard as a last line.
BatteryFlightController OursController(const BatteryPolicySpec& spec, const BatteryContext& context) {
  BatteryFlightController out;
  out.initial_switches = PackAction::kUseBoth;
  UASCMA_CHECK(spec.policies != nullptr, "a policy file read for ours");
  auto executor = std::make_shared<decision::BatteryPolicyExecutor>(*spec.policies, context);
  auto counts = std::make_shared<BatteryDecisionCounts>();
  out.decisions = counts;
  out.observe_pair_eod = true;
  out.controller = [executor, counts](double, const decision::BatteryObservation& observation, StateIndex) {
    const StateIndex s = executor->Abstract(observation);  // ours' abstraction: the pack-fault flags read
    if (s == decision::kBatteryFailureState) {
      ++counts->failure_rows_held;
      return HeldSwitches(observation);
    }
    // The table first (item 10: its flagged states isolate a flagged pack), with item 9's drop check on an
    // unflagged state's drop (a flagged state's drop is onto the only pack not known faulted).
    const PackAction table = executor->Decide(s);
    const PackAction action =
        decision::IsFlaggedBatteryState(s) ? table : OursDropCheck(table, observation, executor->thresholds());
    if (IsIsolation(observation, action)) {
      ++counts->table_isolations;
      if (IsFaultIsolation(observation, action)) ++counts->table_fault_isolations;
      return action;
    }
    // The imminent-failure guard (item 8), a last line: only where the table keeps both packs in.
    if (const auto guard = OursImminentFailureGuard(observation)) {
      if (IsIsolation(observation, *guard)) ++counts->guard_isolations;
      if (IsFaultIsolation(observation, *guard)) ++counts->guard_fault_isolations;
      return *guard;
    }
    return action;
  };
  return out;
}

}  // namespace

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
      auto counts = std::make_shared<BatteryDecisionCounts>();
      out.decisions = counts;
      out.controller = [executor, counts](double, const decision::BatteryObservation& observation, StateIndex s) {
        if (s == decision::kBatteryFailureState) {
          ++counts->failure_rows_held;
          return HeldSwitches(observation);
        }
        const PackAction action = executor->Decide(s);
        if (IsIsolation(observation, action)) ++counts->table_isolations;
        if (IsFaultIsolation(observation, action)) ++counts->table_fault_isolations;
        return action;
      };
      break;
    }
    case BatteryPolicyKind::kOurs:
      out = OursController(spec, context);
      break;
    case BatteryPolicyKind::kFaultRule: {
      // UseBoth; the first pack the pack-fault indicator flags is switched off for good (the other stays in).
      auto dropped = std::make_shared<int>(-1);
      out.controller = [dropped](double, const decision::BatteryObservation& observation, StateIndex) {
        for (int j = 0; j < models::kBranchCount && *dropped < 0; ++j) {
          if (observation.pack_fault[j] && observation.switch_on[j]) *dropped = j;
        }
        if (*dropped == 0) return PackAction::kUseBatt2;
        if (*dropped == 1) return PackAction::kUseBatt1;
        return PackAction::kUseBoth;
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

PackAction OursDropCheck(PackAction table_action, const decision::BatteryObservation& observation,
                         const decision::BatteryThresholds& thresholds) {
  if (!(observation.switch_on[0] && observation.switch_on[1]) || table_action == PackAction::kUseBoth) {
    return table_action;
  }
  const int k = table_action == PackAction::kUseBatt1 ? 0 : 1;
  const double eod_s = observation.alone_power_eod_s[k];
  const double min_cell_v = observation.alone_power_min_cell_voltage_v[k];
  if (std::isnan(eod_s) || std::isnan(min_cell_v)) return PackAction::kUseBoth;  // not observed: no evidence
  const bool can_finish = decision::ClassifyEnergy(eod_s, observation.remaining_flight_s,
                                                   observation.safety_margin_s) == decision::EnergyState::kS1;
  const bool above_critical = decision::ClassifyVoltage(min_cell_v, thresholds) == decision::VoltageState::kC0;
  return can_finish && above_critical ? table_action : PackAction::kUseBoth;
}

std::string SwitchSchedule::Describe() const {
  std::string out;
  for (const auto& [time_s, action] : steps) {
    out += fmt::format("{}{}@{:.0f}", out.empty() ? "" : " ", models::PackActionName(action), time_s);
  }
  return out;
}

double SwitchSchedule::FirstDepartureS() const {
  for (const auto& [time_s, action] : steps) {
    if (action != PackAction::kUseBoth) return time_s;
  }
  return std::numeric_limits<double>::infinity();
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

}  // namespace uascma::campaign
