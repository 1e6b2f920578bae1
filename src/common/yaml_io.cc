#include "uascma/common/yaml_io.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <yaml-cpp/eventhandler.h>

#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/common/text.h"

namespace uascma {
namespace {

std::string Join(const std::string& where, const std::string& key) { return where.empty() ? key : where + "." + key; }

double ParseNumber(const YAML::Node& value, const std::string& source, const std::string& field) {
  if (!value.IsScalar()) throw InputError(source, field, "a number, got a non-scalar");
  double number = 0.0;
  try {
    number = value.as<double>();
  } catch (const YAML::Exception&) {
    throw InputError(source, field, "a number, got '" + EscapeForMessage(value.Scalar()) + "'");
  }
  if (!std::isfinite(number))
    throw InputError(source, field, "a finite number, got '" + EscapeForMessage(value.Scalar()) + "'");
  return number;
}

std::string LineOf(const YAML::Node& node) { return "line " + std::to_string(node.Mark().line + 1); }

// Walks the document once: every mapping's keys unique, every scalar UTF-8. An alias shares the node it
// refers to, so containers already walked (known by their start in the text) are skipped: a document of
// nested aliases ("billion laughs") costs its own size, not the size of its expansion.
class DocumentCheck {
 public:
  explicit DocumentCheck(const std::string& source) : source_(source) {}

  void Walk(const YAML::Node& node) {
    if (node.IsScalar()) {
      CheckUtf8(node);
      return;
    }
    if (!node.IsMap() && !node.IsSequence()) return;
    const YAML::Mark mark = node.Mark();
    if (!visited_.insert({mark.pos, node.IsMap()}).second) return;
    if (node.IsSequence()) {
      for (const auto& item : node) Walk(item);
      return;
    }
    std::map<std::string, int> lines;  // scalar key -> its line (0-based)
    for (const auto& entry : node) {
      Walk(entry.first);
      Walk(entry.second);
      if (!entry.first.IsScalar()) continue;
      const int line = entry.first.Mark().line;
      const auto [it, inserted] = lines.emplace(entry.first.Scalar(), line);
      if (!inserted) {
        throw InputError(source_, fmt::format("line {}", line + 1),
                         fmt::format("each key once per mapping, but '{}' is also given on line {} (YAML tools "
                                     "disagree on which value counts: remove one)",
                                     EscapeForMessage(entry.first.Scalar()), it->second + 1));
      }
    }
  }

 private:
  void CheckUtf8(const YAML::Node& node) const {
    const std::string& text = node.Scalar();
    if (IsValidUtf8(text)) return;
    RequireUtf8(text, source_, LineOf(node));
  }

  const std::string& source_;
  std::set<std::pair<std::size_t, bool>> visited_;  // (start offset, is a mapping) of containers walked
};

}  // namespace

namespace {

// YAML 1.2 §5.1: a stream holds printable characters only: tab, line feed, carriage return, 0x20-0x7E and Unicode
// above, less the C1 controls but NEL (U+0080-U+009F, UTF-8 0xC2 0x80-0x9F). yaml-cpp does not check it: a NUL or
// a terminal escape in a comment passed unseen, and one in a value reached the messages raw.
void CheckPrintable(const std::string& text, std::size_t begin, std::size_t end, int line, const std::string& source) {
  // UTF-8 first (uascma's encoding, YAML 1.2 §5.2): bytes such as 0xFF 0xFE read as a UTF-16 mark send yaml-cpp's
  // reader astray, and a comment is text too.
  if (const auto bad = FirstInvalidUtf8(std::string_view(text).substr(begin, end - begin))) {
    throw InputError(source, fmt::format("line {}", line),
                     fmt::format("text in UTF-8 (YAML 1.2 §5.2), but column {} holds byte 0x{:02X}", *bad + 1,
                                 static_cast<unsigned char>(text[begin + *bad])));
  }
  for (std::size_t i = begin; i < end; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    const bool c0 = (c < 0x20 && c != '\t' && c != '\r') || c == 0x7F;
    const bool c1 = c == 0xC2 && i + 1 < end && static_cast<unsigned char>(text[i + 1]) >= 0x80 &&
                    static_cast<unsigned char>(text[i + 1]) <= 0x9F && static_cast<unsigned char>(text[i + 1]) != 0x85;
    if (c0 || c1) {
      throw InputError(source, fmt::format("line {}", line),
                       fmt::format("printable characters only (YAML 1.2 §5.1), but column {} holds {}", i - begin + 1,
                                   c1 ? fmt::format("U+00{:02X}", static_cast<unsigned char>(text[i + 1]))
                                      : fmt::format("byte 0x{:02X}", c)));
    }
  }
}

// Before yaml-cpp sees the text: its size and its longest line within their bounds, its characters printable.
void CheckYamlSize(const std::string& text, const std::string& source) {
  if (text.size() > kMaxYamlBytes) {
    throw InputError(source, "file",
                     fmt::format("a YAML file of at most {} bytes, but it holds {}", kMaxYamlBytes, text.size()));
  }
  std::size_t line_start = 0;
  for (int line = 1; line_start < text.size(); ++line) {
    const std::size_t end = std::min(text.find('\n', line_start), text.size());
    if (end - line_start > kMaxYamlLineBytes) {
      throw InputError(source, fmt::format("line {}", line),
                       fmt::format("lines of at most {} bytes (no uascma key or value is longer), but it holds {}",
                                   kMaxYamlLineBytes, end - line_start));
    }
    CheckPrintable(text, line_start, end, line, source);
    line_start = end + 1;
  }
}

// The 1-based line of the `---` that starts the document yaml-cpp marks on 0-based line `mark_line` (its first
// node; the line after the text for an empty one).
int DocumentStartLine(const std::string& text, int mark_line) {
  std::vector<std::size_t> starts{0};
  for (std::size_t i = 0; i < text.size(); ++i)
    if (text[i] == '\n') starts.push_back(i + 1);
  for (int line = std::min<int>(mark_line, static_cast<int>(starts.size()) - 1); line >= 0; --line) {
    if (text.compare(starts[line], 3, "---") == 0) return line + 1;
  }
  return mark_line + 1;
}

// Where each document of a YAML stream starts, from yaml-cpp's parser events (no nodes built).
class DocumentStarts final : public YAML::EventHandler {
 public:
  void OnDocumentStart(const YAML::Mark& mark) override { marks.push_back(mark); }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t, const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}

  std::vector<YAML::Mark> marks;
};

[[noreturn]] void ThrowYamlError(const YAML::Exception& e, const std::string& source) {
  throw InputError(source, "line " + std::to_string(e.mark.line + 1), "valid YAML (" + EscapeForMessage(e.msg) + ")");
}

// The stream holds one document at most. yaml-cpp 0.7's parser, given a token no document can start with (a ',' at
// the top level), reports an empty document there again and again without moving on (YAML::LoadAll then fills the
// memory): a document that starts where the one before it did is that token, named with its line and column.
void CheckOneDocument(const std::string& text, const std::string& source) {
  std::istringstream stream(text);
  YAML::Parser parser(stream);
  DocumentStarts starts;
  try {
    while (starts.marks.size() < 3 && parser.HandleNextDocument(starts)) {
    }
  } catch (const YAML::Exception& e) {
    if (starts.marks.size() < 2) ThrowYamlError(e, source);
  }
  const std::vector<YAML::Mark>& marks = starts.marks;
  for (std::size_t k = 1; k < marks.size(); ++k) {
    if (marks[k].pos != marks[k - 1].pos) continue;
    const char c = static_cast<std::size_t>(marks[k].pos) < text.size() ? text[marks[k].pos] : ' ';
    throw InputError(source, fmt::format("line {}", marks[k].line + 1),
                     fmt::format("valid YAML ('{}' at column {} belongs to no sequence or mapping)",
                                 EscapeForMessage(std::string(1, c)), marks[k].column + 1));
  }
  if (marks.size() < 2) return;
  const YAML::Mark& second = marks[1];
  throw InputError(source, fmt::format("line {}", DocumentStartLine(text, second.line)),
                   "one YAML document, but a second one starts here (uascma would read the first only: remove "
                   "the second or make it a file of its own)");
}

}  // namespace

YAML::Node ParseYamlText(const std::string& text, const std::string& source) {
  CheckYamlSize(text, source);
  CheckOneDocument(text, source);
  YAML::Node root;
  try {
    root = YAML::Load(text);
    DocumentCheck(source).Walk(root);
  } catch (const YAML::Exception& e) {
    ThrowYamlError(e, source);
  }
  return root;
}

YAML::Node LoadYamlFile(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(path.string(), "file", "an existing YAML file");
  }
  YAML::Node root = ParseYamlText(ReadFile(path), path.string());
  if (!root.IsMap()) throw InputError(path.string(), "(top level)", "a YAML mapping");
  return root;
}

double RequireNumber(const YAML::Node& node, const std::string& key, const std::string& source,
                     const std::string& where) {
  const YAML::Node value = node[key];
  if (!value) throw InputError(source, Join(where, key), "a number, but the key is missing");
  return ParseNumber(value, source, Join(where, key));
}

double OptionalNumber(const YAML::Node& node, const std::string& key, double fallback, const std::string& source,
                      const std::string& where) {
  if (!node[key]) return fallback;
  return RequireNumber(node, key, source, where);
}

YAML::Node RequireMap(const YAML::Node& node, const std::string& key, const std::string& source,
                      const std::string& where) {
  const YAML::Node value = node[key];
  if (!value) throw InputError(source, Join(where, key), "a mapping, but the key is missing");
  if (!value.IsMap()) throw InputError(source, Join(where, key), "a mapping");
  return value;
}

void RequireOnlyKeys(const YAML::Node& node, std::initializer_list<const char*> allowed, const std::string& source,
                     const std::string& where) {
  RequireOnlyKeys(node, std::vector<std::string>(allowed.begin(), allowed.end()), source, where);
}

void RequireOnlyKeys(const YAML::Node& node, const std::vector<std::string>& allowed, const std::string& source,
                     const std::string& where) {
  if (!node.IsMap()) throw InputError(source, where.empty() ? "(top level)" : where, "a mapping");
  for (const auto& entry : node) {
    if (!entry.first.IsScalar()) throw InputError(source, where.empty() ? "(top level)" : where, "names as keys");
    const std::string key = entry.first.as<std::string>();
    bool known = false;
    std::string list;
    for (const std::string& name : allowed) {
      known = known || key == name;
      list += (list.empty() ? "" : ", ") + name;
    }
    if (!known) {
      throw InputError(source, Join(where, EscapeForMessage(key)), "no such key here; expected one of: " + list);
    }
  }
}

std::string RequireString(const YAML::Node& node, const std::string& key, const std::string& source,
                          const std::string& where) {
  const YAML::Node value = node[key];
  if (!value) throw InputError(source, Join(where, key), "a string, but the key is missing");
  if (!value.IsScalar()) throw InputError(source, Join(where, key), "a string");
  return value.Scalar();
}

bool OptionalBool(const YAML::Node& node, const std::string& key, bool fallback, const std::string& source,
                  const std::string& where) {
  const YAML::Node value = node[key];
  if (!value) return fallback;
  try {
    return value.as<bool>();
  } catch (const YAML::Exception&) {
    throw InputError(source, Join(where, key),
                     "true or false, got '" + (value.IsScalar() ? EscapeForMessage(value.Scalar()) : "?") + "'");
  }
}

std::vector<double> RequireNumberList(const YAML::Node& node, const std::string& key, std::size_t size,
                                      const std::string& source, const std::string& where) {
  const YAML::Node value = node[key];
  const std::string field = Join(where, key);
  if (!value || !value.IsSequence() || value.size() != size) {
    throw InputError(source, field, "a list of " + std::to_string(size) + " numbers");
  }
  std::vector<double> numbers;
  for (std::size_t i = 0; i < size; ++i)
    numbers.push_back(ParseNumber(value[i], source, field + "[" + std::to_string(i) + "]"));
  return numbers;
}

}  // namespace uascma
