// The companion's decision log (companion_log.h): written as CSV, read back for `uascma plot companion`.
#include "uascma/mavlink/companion_log.h"

#include <cmath>
#include <string>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "uascma/common/csv.h"
#include "uascma/common/error.h"
#include "uascma/mavlink/companion.h"

namespace uascma::mavlink {
namespace {

// A text field, quoted, its quotes doubled (RFC 4180).
std::string Quoted(const std::string& text) {
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

double Number(const CsvRecord& record, std::size_t column, const std::string& source) {
  const std::string& text = record.fields[column];
  std::size_t used = 0;
  double value = NAN;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  // inf is a value of the log (the RUL before a spall, sim::Observe); nan is none.
  if (used == 0 || used != text.size() || std::isnan(value)) {
    throw InputError(source, fmt::format("line {} {}", record.line, kCompanionLogColumns[column]),
                     fmt::format("a number (inf allowed), got \"{}\"", text.substr(0, 40)));
  }
  return value;
}

}  // namespace

std::string CompanionLogCsv(const std::vector<CompanionDecision>& log) {
  std::string csv = fmt::format("{}\n", fmt::join(kCompanionLogColumns, ","));
  for (const CompanionDecision& r : log) {
    csv += fmt::format("{:.3f},{},{},{},{:.3f},{:.3f},{:.3f},{:.5f},{:.5f},{:.3f},{}\n", r.time_s, Quoted(r.state),
                       r.decided, r.taken, r.eod_s, r.rul_s, r.flight_time_remaining_s, r.reach_margin, r.motor_margin,
                       r.decision_ms, Quoted(r.note));
  }
  return csv;
}

std::vector<CompanionDecision> ParseCompanionLogCsv(std::string_view text, const std::string& source) {
  const std::vector<CsvRecord> records = SplitCsv(text, source);
  const std::string header = fmt::format("{}", fmt::join(kCompanionLogColumns, ","));
  if (records.empty() || fmt::format("{}", fmt::join(records.front().fields, ",")) != header) {
    throw InputError(source, "line 1 (header)", "the columns of `uascma companion --log`: " + header);
  }
  std::vector<CompanionDecision> log;
  for (std::size_t k = 1; k < records.size(); ++k) {
    const CsvRecord& record = records[k];
    if (record.fields.size() != kCompanionLogColumns.size()) {
      throw InputError(source, fmt::format("line {}", record.line),
                       fmt::format("{} fields, got {}", kCompanionLogColumns.size(), record.fields.size()));
    }
    CompanionDecision row;
    row.time_s = Number(record, 0, source);
    row.state = record.fields[1];
    row.decided = record.fields[2];
    row.taken = record.fields[3];
    row.eod_s = Number(record, 4, source);
    row.rul_s = Number(record, 5, source);
    row.flight_time_remaining_s = Number(record, 6, source);
    row.reach_margin = Number(record, 7, source);
    row.motor_margin = Number(record, 8, source);
    row.decision_ms = Number(record, 9, source);
    row.note = record.fields[10];
    if (!log.empty() && !(row.time_s > log.back().time_s)) {
      throw InputError(
          source, fmt::format("line {} time_s", record.line),
          fmt::format("a time after the row before's {:.3f} s, got {:.3f} s", log.back().time_s, row.time_s));
    }
    log.push_back(std::move(row));
  }
  return log;
}

}  // namespace uascma::mavlink
