#pragma once
// The companion's decision log (mavlink/companion.h CompanionSummary::log, src/mavlink/companion_log.cc): written as
// CSV by `uascma companion`, read back for `uascma plot companion`.
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "uascma/mavlink/companion.h"

namespace uascma::mavlink {

// The decision log as CSV (RFC 4180, common/csv.h): the header kCompanionLogColumns, then one row per epoch; the
// texts quoted.
inline constexpr std::array<const char*, 11> kCompanionLogColumns = {
    "time_s",       "cma_state",    "decided",     "taken", "eod_s", "rul_s", "flight_time_remaining_s",
    "reach_margin", "motor_margin", "decision_ms", "note"};
std::string CompanionLogCsv(const std::vector<CompanionDecision>& log);
// Reads a decision log back (`uascma plot companion`): InputError naming `source`, the line and column, and what was
// expected (the header above; a number in each numeric column; times rising).
std::vector<CompanionDecision> ParseCompanionLogCsv(std::string_view text, const std::string& source);

}  // namespace uascma::mavlink
