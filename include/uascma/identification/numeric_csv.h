#pragma once
// Numeric columns of a CSV file with a header row, for the bench data that identification reads (thrust-stand logs,
// battery cycler exports). Only the columns asked for are parsed; other columns may hold anything (text, empty
// cells). Every error names the file, the line (1-based, the header is line 1) and the column.
//
// Accepted: a UTF-8 byte-order mark before the header, CR LF line ends, a trailing comma, blank lines (skipped),
// surrounding spaces in a cell. Not accepted: quoted cells holding commas (none of the layouts read here uses them).
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace uascma::identification {

class NumericCsv {
 public:
  // Parses the header and splits the rows; `source` names the file in errors. Throws InputError when there is no
  // header or a header cell is given twice.
  static NumericCsv Parse(std::string_view text, std::string source);
  static NumericCsv ReadFile(const std::string& path);

  const std::string& source() const { return source_; }
  const std::vector<std::string>& header() const { return header_; }
  bool HasColumn(std::string_view name) const { return FindColumn(name).has_value(); }
  std::optional<int> FindColumn(std::string_view name) const;
  int row_count() const { return static_cast<int>(rows_.size()); }
  // The file line (1-based) of row r.
  int line_of_row(int row) const { return lines_[row]; }

  // Column `name` as numbers, one per row. Throws InputError("<source>:<line>", "<name>", …) for a missing
  // column (naming the header's columns), an empty or non-numeric cell, NaN or infinity.
  std::vector<double> Column(std::string_view name) const;

 private:
  std::string source_;
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;  // [row][cell], cells trimmed
  std::vector<int> lines_;                      // [row], the file line of each row
};

// "<source>:<line>": the location used in messages about one row.
std::string RowLocation(const NumericCsv& csv, int row);

}  // namespace uascma::identification
