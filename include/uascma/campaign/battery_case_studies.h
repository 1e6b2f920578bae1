#pragma once
// The case studies of dissertation §4.3.3 (Table 4.5, Figs. 4.8–4.11), each flown in the simulator
// (campaign/battery_flights.h) with the controllers of campaign/battery_controllers.h.
// Case studies (Table 4.5) at the case studies' flight time (docs/modelling-choices.md#battery-case-study-flight-time),
// every learned policy beside UseBoth, and the hindsight best of a stated family of switch schedules, each flown in the
// simulator (HindsightSchedules).
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "uascma/campaign/battery_controllers.h"
#include "uascma/campaign/battery_flights.h"
#include "uascma/decision/battery_mdp.h"
#include "uascma/decision/battery_policy.h"

namespace uascma::campaign {

// Cases 3 and 4 fly kCaseFlightFraction of the healthy pair's reference EOD
// (docs/modelling-choices.md#battery-case-study-flight-time; ours: 0.82, the middle of the 0.815-0.825 band in which
// the four case-3/4 outcomes of the dissertation hold together, chosen so).
inline constexpr double kCaseFlightFraction = 0.82;
// s: that flight time, kCaseFlightFraction · ReferenceBatteryEod(UseBoth).
double CaseFlightTimeS();

// The hindsight family (ours), every member flown in the simulator: (a) UseBoth throughout; (b) UseBoth, then pack
// k alone (UseBatt_k, k = 1, 2) for good from t, t on a 5 s grid (the late drop of a collapsing pack); (c) UseBoth
// with one window [t1, t2) of pack k alone, t1 and t2 on a 60 s grid (a rest, Fig. 4.11's shape), t2 = the end only
// from t1 = 0. The best: completed first (then most charge left, then fewest switches), else the latest failure.
inline constexpr double kHindsightSwitchGridS = 5.0;
inline constexpr double kHindsightWindowGridS = 60.0;
std::vector<SwitchSchedule> HindsightSchedules(double plan_duration_s, double window_grid_s = kHindsightWindowGridS,
                                               double switch_grid_s = kHindsightSwitchGridS);

struct CaseScenario {
  std::string name;  // e.g. "(F1,F2)"
  BatteryFlightParams params;
  std::string controller;   // "UseBoth", "pi*", "rule:voltage", "ours", "hindsight-best"
  std::string schedule;     // the hindsight schedule (SwitchSchedule::Describe)
  int schedules_flown = 0;  // hindsight: the family's size
  BatteryFlightResult result;
};

struct CaseStudyOptions {
  const decision::BatteryPolicySet* pistar = nullptr;  // required for cases 2 and 4
  const decision::BatteryPolicySet* ours = nullptr;    // optional: flown beside
  std::uint64_t seed = 1;                              // the vehicle's seed (gusts, noise)
  bool hindsight = true;                               // case 4: the hindsight-best schedule
};
// Case 1: flight time = one healthy pack's EOD, UseBoth, nine health pairs. Case 2: the same flights with UseBoth,
// π*, the voltage rule and ours (when given). Case 3: the case studies' flight time, UseBoth, (F1,F2), (F1,F3),
// (F3,F3). Case 4: the same flight time, (F2,F1) with Fig. 4.11's pack 1 (one capacity-faded cell): UseBoth, π*, the
// voltage rule, ours (when given) and the hindsight best. InputError when a case needs π* and none is given.
std::vector<CaseScenario> RunCaseStudy(int number, const CaseStudyOptions& options);
nlohmann::json CaseStudyJson(int number, const std::vector<CaseScenario>& scenarios);
// A scenario's 1 Hz epochs as CSV (time, state, action, currents, EODs, flight left, lowest cells): one file per
// scenario of `battery case-study --out`.
std::string CaseEpochsCsv(const BatteryFlightResult& result);

// The case-study flight of a context at `plan_duration_s` (Table 4.4's middle values, cells at 4.1 V, seed 1).
BatteryFlightParams CaseFlightParams(const decision::BatteryContext& context, double plan_duration_s);
// The abstract state that flight starts in (its first 1 Hz epoch, before any switch): what `battery show` reads
// the decision tree at (Fig. 4.5).
decision::StateIndex TakeoffState(const BatteryFlightParams& params);
// TakeoffState of every context's case-study flight at `plan_duration_s`, by decision::BatteryContextIndex.
std::vector<decision::StateIndex> CaseTakeoffStates(double plan_duration_s);

}  // namespace uascma::campaign
