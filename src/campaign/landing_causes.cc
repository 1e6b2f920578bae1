#include "uascma/campaign/landing_causes.h"

#include <algorithm>
#include <optional>

#include <fmt/format.h>

#include "uascma/campaign/statistics.h"
#include "uascma/common/error.h"
#include "uascma/decision/cma_mdp.h"

namespace uascma::campaign {
namespace {

constexpr std::array<const char*, kLandingCauseCount> kCauseNames = {"after_jam", "battery_margin",
                                                                     "false_fault_reading", "motor_margin", "other"};
constexpr std::array<const char*, 4> kLandingCauseHealthGroups = {"all", "G", "M", "P"};

// The recorded state, or none when the record has none (no action, or a record written without the column).
std::optional<decision::CmaState> StateAtFirstAction(const RunRecord& record) {
  if (record.first_action_state.empty()) return std::nullopt;
  try {
    return decision::ParseCmaState(record.first_action_state, "first_action_state");
  } catch (const InputError&) {
    return std::nullopt;
  }
}

}  // namespace

const char* LandingCauseName(LandingCause cause) { return kCauseNames[static_cast<std::size_t>(cause)]; }

std::int64_t LandingCauseCounts::total() const {
  std::int64_t sum = 0;
  for (std::int64_t n : count) sum += n;
  return sum;
}

LandingCause ClassifyLandingCause(const RunRecord& record) {
  if (!record.first_emergency_action_s) return LandingCause::kOther;
  const double action_s = *record.first_emergency_action_s;
  const auto at_or_before = [action_s](const std::optional<double>& t) { return t && *t <= action_s; };
  if (at_or_before(record.isolation_time_s) || at_or_before(record.jam_time_s)) return LandingCause::kAfterJam;
  const std::optional<decision::CmaState> state = StateAtFirstAction(record);
  if (!state) return LandingCause::kOther;
  if (state->rm == decision::ReachMargin::kRM0) return LandingCause::kBatteryMargin;
  const bool spall_then = record.fault && record.fault_onset_s && *record.fault_onset_s <= action_s;
  if (state->mh == decision::MotorHealth::kSF && !spall_then) return LandingCause::kFalseFaultReading;
  if (state->mm == decision::MotorMargin::kMM0) return LandingCause::kMotorMargin;
  return LandingCause::kOther;
}

std::vector<LandingCauseCounts> CountUnnecessaryLandingCauses(const std::vector<RunRecord>& records,
                                                              const std::vector<std::string>& policy_order) {
  const std::map<std::int64_t, const RunRecord*> noop = NoOpFlightsByRun(records);
  std::vector<LandingCauseCounts> counts;
  if (noop.empty()) return counts;
  for (const std::string& policy : policy_order) {
    if (policy == kNoOpPolicy) continue;
    for (const char* group : kLandingCauseHealthGroups) counts.push_back({policy, group, {}});
  }
  for (const RunRecord& r : records) {
    if (!IsUnnecessaryLanding(r, noop)) continue;
    const auto cause = static_cast<std::size_t>(ClassifyLandingCause(r));
    for (LandingCauseCounts& c : counts) {
      if (c.policy == r.policy && (c.battery_health == "all" || c.battery_health == r.battery_health)) {
        ++c.count[cause];
      }
    }
  }
  return counts;
}

nlohmann::json LandingCausesJson(const std::vector<LandingCauseCounts>& counts) {
  nlohmann::json json = nlohmann::json::object();
  for (const LandingCauseCounts& c : counts) {
    nlohmann::json causes = nlohmann::json::object();
    for (int k = 0; k < kLandingCauseCount; ++k) causes[kCauseNames[k]] = c.count[k];
    json[c.policy][c.battery_health] = causes;
  }
  return json;
}

std::string LandingCausesTable(const std::vector<LandingCauseCounts>& counts) {
  if (counts.empty()) return "";
  std::string out =
      "Unnecessary landings by cause (the NoOp twin completed; the state the policy read at its first "
      "action):\n";
  // The policy column: the widest name, at least 14 characters, so any policy name keeps the columns aligned.
  std::size_t w = 14;
  for (const LandingCauseCounts& c : counts) w = std::max(w, c.policy.size());
  out += fmt::format("  {:<{}} {:<4} {:>6} {:>9} {:>9} {:>12} {:>7} {:>6}\n", "policy", w, "BH", "total", "after_jam",
                     "battery", "false_fault", "motor", "other");
  for (const LandingCauseCounts& c : counts) {
    out += fmt::format("  {:<{}} {:<4} {:>6} {:>9} {:>9} {:>12} {:>7} {:>6}\n", c.policy, w, c.battery_health,
                       c.total(), c.count[0], c.count[1], c.count[2], c.count[3], c.count[4]);
  }
  return out;
}

}  // namespace uascma::campaign
