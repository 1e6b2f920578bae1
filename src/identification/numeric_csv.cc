// Numeric columns of a CSV file (see numeric_csv.h).
#include "uascma/identification/numeric_csv.h"

#include <charconv>
#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/files.h"

namespace uascma::identification {
namespace {

std::string_view Trim(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\r')) text.remove_suffix(1);
  return text;
}

std::vector<std::string> SplitCells(std::string_view line) {
  std::vector<std::string> cells;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    cells.emplace_back(Trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  // A trailing comma (RCbenchmark's logs end every line with one) leaves an empty last cell.
  if (cells.size() > 1 && cells.back().empty()) cells.pop_back();
  return cells;
}

std::string HeaderList(const std::vector<std::string>& header) {
  std::string list;
  for (const std::string& name : header) {
    if (name.empty()) continue;
    if (!list.empty()) list += ", ";
    list += "\"" + name + "\"";
  }
  return list;
}

}  // namespace

NumericCsv NumericCsv::Parse(std::string_view text, std::string source) {
  NumericCsv csv;
  csv.source_ = std::move(source);
  constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";
  if (text.substr(0, kByteOrderMark.size()) == kByteOrderMark) text.remove_prefix(kByteOrderMark.size());
  int line_number = 0;
  std::size_t position = 0;
  bool have_header = false;
  while (position < text.size()) {
    const std::size_t end = text.find('\n', position);
    const std::string_view line = text.substr(position, end == std::string_view::npos ? std::string_view::npos : end - position);
    ++line_number;
    position = end == std::string_view::npos ? text.size() + 1 : end + 1;
    if (Trim(line).empty()) continue;
    if (!have_header) {
      csv.header_ = SplitCells(line);
      for (std::size_t a = 0; a < csv.header_.size(); ++a) {
        for (std::size_t b = a + 1; b < csv.header_.size(); ++b) {
          if (!csv.header_[a].empty() && csv.header_[a] == csv.header_[b]) {
            throw InputError(fmt::format("{}:{}", csv.source_, line_number), csv.header_[a],
                             "each column named once in the header, but it is given twice");
          }
        }
      }
      have_header = true;
      continue;
    }
    csv.rows_.push_back(SplitCells(line));
    csv.lines_.push_back(line_number);
  }
  if (!have_header) throw InputError(csv.source_, "header", "a header row naming the columns, but the file is empty");
  return csv;
}

NumericCsv NumericCsv::ReadFile(const std::string& path) { return Parse(uascma::ReadFile(path), path); }

std::optional<int> NumericCsv::FindColumn(std::string_view name) const {
  for (std::size_t c = 0; c < header_.size(); ++c) {
    if (header_[c] == name) return static_cast<int>(c);
  }
  return std::nullopt;
}

std::vector<double> NumericCsv::Column(std::string_view name) const {
  const std::optional<int> column = FindColumn(name);
  if (!column) {
    throw InputError(fmt::format("{}:1", source_), std::string(name),
                     fmt::format("a column of this name in the header, which has {}", HeaderList(header_)));
  }
  std::vector<double> values(rows_.size());
  for (std::size_t r = 0; r < rows_.size(); ++r) {
    const std::string cell = static_cast<std::size_t>(*column) < rows_[r].size() ? rows_[r][*column] : std::string();
    double value = 0.0;
    const auto [end, error] = std::from_chars(cell.data(), cell.data() + cell.size(), value);
    if (cell.empty() || error != std::errc() || end != cell.data() + cell.size() || !std::isfinite(value)) {
      throw InputError(fmt::format("{}:{}", source_, lines_[r]), std::string(name),
                       fmt::format("a finite number, got \"{}\"", cell));
    }
    values[r] = value;
  }
  return values;
}

std::string RowLocation(const NumericCsv& csv, int row) {
  return fmt::format("{}:{}", csv.source(), csv.line_of_row(row));
}

}  // namespace uascma::identification
