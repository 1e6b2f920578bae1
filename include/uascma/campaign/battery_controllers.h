#pragma once
// The battery switch controllers a battery flight (campaign/battery_flights.h) is flown with: the policies
// judged by the evaluation (campaign/battery_evaluation.h) and the case studies (campaign/battery_case_studies.h),
// and fixed switch schedules.
//
// Policies (ParseBatteryPolicies, "--policies useboth,pistar:P.json,rule:voltage,ours:P.json"):
//   useboth        UseBoth throughout (the dissertation's fixed rule, Table 4.5 cases 1 and 3);
//   pistar:FILE    the dissertation's π* (a policy file solved with the dissertation's formulation);
//   ours:FILE      ours (a policy file solved with formulation "ours", decision/battery_mdp.h);
//   rule:voltage[:V]  UseBoth; a pack whose worst cell, as it is loaded now, falls below V (default 3.31 V, the
//                  rule the issue states: 10 mV above the 3.3 V cut-off of Table 4.1) is switched off for good,
//                  unless the other pack was already dropped;
//   rule:fault     UseBoth; the first pack the pack-fault indicator flags (prognostics/pack_fault_monitor.h) is
//                  switched off for good: what isolating on detection is worth, a rule outside any table.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "uascma/campaign/battery_flights.h"
#include "uascma/decision/battery_abstraction.h"
#include "uascma/decision/battery_mdp.h"
#include "uascma/decision/battery_policy.h"

namespace uascma::campaign {

// --- policies ----------------------------------------------------------------------------------------------------
enum class BatteryPolicyKind { kUseBoth, kVoltageRule, kPiStar, kOurs, kFaultRule };
inline constexpr double kVoltageRuleDropVoltage = 3.31;  // V, the rule (Table 4.1's 3.3 V + 10 mV)

struct BatteryPolicySpec {
  BatteryPolicyKind kind = BatteryPolicyKind::kUseBoth;
  std::string label;                                           // "useboth", "pistar", "ours", "rule:voltage"
  std::filesystem::path file;                                  // pistar, ours
  double drop_voltage_v = kVoltageRuleDropVoltage;             // rule:voltage
  std::shared_ptr<const decision::BatteryPolicySet> policies;  // pistar, ours: the file, read
};

// Parses and reads every policy (files too) before any flight: InputError naming `option` for an unknown name,
// a policy named twice, a drop voltage outside [3.3, 4.2] V, a missing or bad file, or a file of the other
// formulation (pistar must be the dissertation's, ours ours).
std::vector<BatteryPolicySpec> ParseBatteryPolicies(const std::string& text, const std::string& option);

// A fresh controller for one flight of `context` (the rule remembers the pack it dropped), starting on UseBoth. The
// table policies (pistar, ours) never execute their FAILURE row: in FAILURE (a switched-in cell at the 3.3 V cut-off,
// Table 4.1) the switches are held (HeldSwitches); they count their isolations (BatteryFlightController::decisions).
BatteryFlightController MakeBatteryController(const BatteryPolicySpec& spec, const decision::BatteryContext& context);

// Ours' imminent-failure guard (item 8 of decision/battery_mdp.h's ours): with both packs switched in,
// when the packs as switched would bring a cell to the 3.3 V cut-off (the pair's EOD at the present load,
// BatteryObservation::pair_eod_s) before the plan ends and within the safety margin t_sf, the pack holding that cell
// is dropped (for good: ours' MDP keeps a dropped pack dropped). Why: the abstraction cannot time that drop (case 4:
// dropping at 725-737 s completes, at 710-720 s fails, all one abstract state). Empty: the MDP decides.
std::optional<models::PackAction> OursImminentFailureGuard(const decision::BatteryObservation& observation);

// Ours' drop check: with both packs in, the table's UseBatt_k stands only when pack k alone,
// drawing the present bus power (BatteryObservation::alone_power_*), is still S1 and C0 (Table 4.1: its EOD covers
// the rest of the plan and t_sf; its worst cell is at or above the 3.4 V critical voltage); otherwise UseBoth. Why:
// the table's features read each pack alone at the present current, but the load is a power: alone, a pack holds a
// lower bus voltage and draws more (measured in the README). Any other action passes unchanged.
models::PackAction OursDropCheck(models::PackAction table_action, const decision::BatteryObservation& observation,
                                 const decision::BatteryThresholds& thresholds = {});

// The action that keeps the switches of `observation` as they are (UseBoth when both or neither are on).
models::PackAction HeldSwitches(const decision::BatteryObservation& observation);

// A fixed schedule: `steps` (time from, action), the first at 0 s.
struct SwitchSchedule {
  std::vector<std::pair<double, models::PackAction>> steps;
  std::string Describe() const;  // "UseBoth@0 UseBatt2@60 UseBoth@300"
  double FirstDepartureS() const;  // when it first leaves UseBoth (+inf when it never does)
};
BatteryFlightController ScheduleController(const SwitchSchedule& schedule);

// Switch changes of a flight started on UseBoth (the take-off switches are not a switch).
int CountSwitches(const BatteryFlightResult& result);

}  // namespace uascma::campaign
