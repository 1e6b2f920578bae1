// RFC 4180 splitting (include/uascma/common/csv.h): one pass over the text, a small state machine per field.
#include "uascma/common/csv.h"

#include <fmt/format.h>

#include "uascma/common/error.h"

namespace uascma {
namespace {

// Spaces and tabs around fields, and a lone carriage return at the end of a line.
bool IsBlank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

// Drops spaces and tabs at both ends of an unquoted field.
std::string TrimBlanks(const std::string& text) {
  std::size_t begin = 0, end = text.size();
  while (begin < end && IsBlank(text[begin])) ++begin;
  while (end > begin && IsBlank(text[end - 1])) --end;
  return text.substr(begin, end - begin);
}

// The quoted field whose opening quote is at *i: its text ("" read as one quote). Moves *i past the closing
// quote and the blanks after it, counts the line breaks inside into *line, and requires a comma, a line break
// or the end next.
std::string ReadQuotedField(std::string_view text, const std::string& source, std::size_t* i, int* line) {
  const int opened = *line;
  std::string field;
  ++*i;
  while (true) {
    if (*i >= text.size()) {
      throw InputError(source, fmt::format("line {}", opened), "a closing double quote for the field opened here");
    }
    if (text[*i] == '"') {
      if (*i + 1 < text.size() && text[*i + 1] == '"') {
        field += '"';
        *i += 2;
        continue;
      }
      ++*i;
      break;
    }
    if (text[*i] == '\n') ++*line;
    field += text[(*i)++];
  }
  // After the closing quote: blanks, then a comma, a line break or the end.
  while (*i < text.size() && IsBlank(text[*i])) ++*i;
  if (*i < text.size() && text[*i] != ',' && text[*i] != '\n' && text[*i] != '\r') {
    throw InputError(source, fmt::format("line {}", *line), "a comma or the end of the line after a closing quote");
  }
  return field;
}

// With comment lines: *i at the start of a record, past blanks, on a '#': moves *i to the line break ending it.
bool SkipComment(std::string_view text, const CsvOptions& options, std::size_t* i) {
  if (!options.comment_lines) return false;
  std::size_t j = *i;
  while (j < text.size() && (text[j] == ' ' || text[j] == '\t')) ++j;
  if (j >= text.size() || text[j] != '#') return false;
  const std::size_t end = text.find('\n', j);
  *i = end == std::string_view::npos ? text.size() : end;
  return true;
}

}  // namespace

std::vector<CsvRecord> SplitCsv(std::string_view text, const std::string& source, const CsvOptions& options) {
  std::vector<CsvRecord> records;
  CsvRecord record;
  std::string field;
  bool quoted = false;       // the current field was quoted (its text is final, not trimmed)
  bool any_content = false;  // the record has a comma, a quote or a non-blank character (not a blank line)
  int line = 1;
  record.line = 1;

  auto end_field = [&] {
    record.fields.push_back(quoted ? field : TrimBlanks(field));
    field.clear();
    quoted = false;
  };
  auto end_record = [&] {
    end_field();
    if (any_content) records.push_back(std::move(record));
    record = CsvRecord{};
    any_content = false;
  };

  std::size_t i = 0;
  while (i < text.size()) {
    const bool record_start = record.fields.empty() && field.empty() && !quoted && !any_content;
    if (record_start && SkipComment(text, options, &i)) continue;  // on the line break: the record stays blank
    const char c = text[i];
    if (c == '"') {
      // A quoted field: only blanks may precede the opening quote.
      if (quoted || !TrimBlanks(field).empty()) {
        throw InputError(source, fmt::format("line {}", line),
                         "a double quote only at the start of a field (write \"\" inside a quoted field)");
      }
      field = ReadQuotedField(text, source, &i, &line);
      quoted = true;
      any_content = true;
      continue;
    }
    if (c == ',') {
      any_content = true;
      end_field();
      ++i;
      continue;
    }
    if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') {
      ++i;
      continue;  // the LF ends the record
    }
    if (c == '\r' && i + 1 < text.size()) {  // a lone CR would make the whole file one line
      throw InputError(source, fmt::format("line {}", line),
                       "lines ending in LF or CRLF (RFC 4180), but this line holds a carriage return alone (classic "
                       "Mac line endings? convert them to LF)");
    }
    if (c == '\n') {
      end_record();
      ++line;
      record.line = line;
      ++i;
      continue;
    }
    if (quoted) {  // only blanks may follow a quoted field (checked above), so this is unreachable
      throw InputError(source, fmt::format("line {}", line), "a comma or the end of the line after a closing quote");
    }
    if (!IsBlank(c)) any_content = true;
    field += c;
    ++i;
  }
  if (any_content || !field.empty() || quoted) end_record();
  return records;
}

}  // namespace uascma
