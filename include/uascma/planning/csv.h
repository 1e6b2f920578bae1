#pragma once
// Comma-separated values as RFC 4180 defines them, for the landing-site reader (map_import.h) and any other CSV
// input: records end at a line break (CRLF or LF); fields are separated by commas; a field may be enclosed in
// double quotes, and then may contain commas, line breaks and double quotes (written twice: "" is one "). We are
// lenient in two ways the RFC leaves open: spaces and tabs around a field (outside its quotes) are dropped, and
// blank lines are skipped. A quote that is never closed, or text after a closing quote other than spaces before the
// next comma, is an InputError naming the source and the line.
#include <string>
#include <string_view>
#include <vector>

namespace uascma::planning {

struct CsvRecord {
  int line = 0;                     // the line on which the record starts, from 1
  std::vector<std::string> fields;  // unquoted and unescaped
};

// Every record of `text`; `source` names it in messages.
std::vector<CsvRecord> SplitCsv(std::string_view text, const std::string& source);

}  // namespace uascma::planning
