#pragma once
// Why a landing was unnecessary. A flight's landing is unnecessary when its NoOp twin completed with its reserve
// (campaign/statistics.h IsUnnecessaryLanding); its cause is read from the record of the landing flight: the time of
// its first emergency action, the abstract CMA state its policy read then (RunRecord::first_action_state: for
// `cma-vehicle` the vehicle-level motor margin's state; for `cma-vehicle-risk` the state whose action it took, for
// `cma-vehicle-qmdp` its belief's most probable state, sim/belief_policy.cc), and the truth of the fault (onset, jam,
// isolation). In order:
//   after a jam          a rotor was already isolated (or the motor jammed) at the first action;
//   battery margin       the state read RM0 (docs/modelling-choices.md#margins);
//   false fault reading  the state read a spall (MH = SF) that the motor did not have then (no fault in the flight,
//                        or its onset after the action): the noisy indicator's false alarm (sim/sensing.h);
//   motor margin         the state read MM0 for a real spall (eq. 5.14's RUL, or the vehicle-level margin);
//   other                anything else (a belief policy deciding on P(EOD short) or b(SF), a record without a state).
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "uascma/campaign/record.h"

namespace uascma::campaign {

enum class LandingCause { kAfterJam = 0, kBatteryMargin = 1, kFalseFaultReading = 2, kMotorMargin = 3, kOther = 4 };
inline constexpr int kLandingCauseCount = 5;
const char* LandingCauseName(LandingCause cause);  // "after_jam", "battery_margin", …

// The cause of a landing flight's landing (header); the record need not be an unnecessary landing.
LandingCause ClassifyLandingCause(const RunRecord& record);

// Unnecessary landings by cause, per policy and battery-health group (G, M, P, all).
struct LandingCauseCounts {
  std::string policy;
  std::string battery_health;  // "G" | "M" | "P" | "all"
  std::array<std::int64_t, kLandingCauseCount> count{};
  std::int64_t total() const;
};
// Over the runs with a NoOp twin; empty when the campaign has no NoOp policy.
std::vector<LandingCauseCounts> CountUnnecessaryLandingCauses(const std::vector<RunRecord>& records,
                                                              const std::vector<std::string>& policy_order);
// {"cma": {"all": {"after_jam": n, …}, "G": {…}, …}, …}
nlohmann::json LandingCausesJson(const std::vector<LandingCauseCounts>& counts);
// One line per policy and group with a landing: "cma        all  after_jam 3  battery_margin 1  …".
std::string LandingCausesTable(const std::vector<LandingCauseCounts>& counts);

}  // namespace uascma::campaign
