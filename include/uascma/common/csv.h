#pragma once
// Comma-separated values as RFC 4180 defines them: the one reader of every CSV input (landing sites, map_sites_csv.h;
// drag tables, models/drag.h; OCV tables, models/ocv_table.h; bench data). Records end at a line break (CRLF or LF);
// fields are separated by commas; a field may be enclosed in double quotes, and then may contain commas, line breaks
// and double quotes (written twice: "" is one "). We are lenient in two ways the RFC leaves open: spaces and tabs
// around a field (outside its quotes) are dropped, and blank lines are skipped. With CsvOptions::comment_lines, a line
// whose first non-blank character is '#' is a comment and skipped whole (whatever it holds, quotes too). A quote that
// is never closed, or text after a closing quote other than spaces before the next comma, is an InputError naming the
// source and the line.
#include <string>
#include <string_view>
#include <vector>

namespace uascma {

struct CsvRecord {
  int line = 0;                     // the line on which the record starts, from 1
  std::vector<std::string> fields;  // unquoted and unescaped
};

struct CsvOptions {
  bool comment_lines = false;  // skip lines starting (after blanks) with '#'
};

// Every record of `text`; `source` names it in messages.
std::vector<CsvRecord> SplitCsv(std::string_view text, const std::string& source, const CsvOptions& options = {});

}  // namespace uascma
