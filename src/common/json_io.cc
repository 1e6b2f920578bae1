#include "uascma/common/json_io.h"

#include <cmath>
#include <cstdlib>
#include <string>
#include <unordered_map>
#include <vector>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/common/text.h"

namespace uascma {

namespace {

// One open container of the scan: an object with its keys and their lines, or an array with its element count.
struct OpenContainer {
  bool is_object = false;
  bool expect_key = false;
  std::unordered_map<std::string, int> key_lines;
  std::string key;        // an object's latest key
  std::size_t index = 0;  // an array's current element
};

// The path of the value being read ("states[4].values[0]"), its first kShownLevels levels when deeper.
std::string PathOf(const std::vector<OpenContainer>& open) {
  constexpr std::size_t kShownLevels = 8;
  std::string path;
  for (std::size_t level = 0; level < open.size() && level < kShownLevels; ++level) {
    const OpenContainer& c = open[level];
    if (c.is_object) {
      path += (path.empty() ? "" : ".") + c.key;
    } else {
      path += fmt::format("[{}]", c.index);
    }
  }
  if (open.size() > kShownLevels) path += fmt::format("… ({} levels)", open.size());
  return path.empty() ? "(top level)" : path;
}

// A string token starting at text[i] (a quote): returns the offset of its closing quote.
std::size_t StringTokenEnd(std::string_view text, std::size_t i) {
  bool escaped = false;
  for (++i; i < text.size(); ++i) {
    if (escaped) {
      escaped = false;
    } else if (text[i] == '\\') {
      escaped = true;
    } else if (text[i] == '"') {
      break;
    }
  }
  return i;
}

// The decoded text of a key token ("a" and "\u0061" are the same key).
std::string DecodedKey(std::string_view token, const std::string& source, int line) {
  if (token.find('\\') == std::string_view::npos) return std::string(token.substr(1, token.size() - 2));
  try {
    return nlohmann::json::parse(token).get<std::string>();
  } catch (const nlohmann::json::exception&) {
    throw InputError(source, fmt::format("line {}", line), "valid JSON");
  }
}

void RecordKey(OpenContainer& object, std::string key, int line, const std::string& source) {
  const auto [it, inserted] = object.key_lines.emplace(key, line);
  if (!inserted) {
    throw InputError(source, fmt::format("line {}", line),
                     fmt::format("each key once per object, but \"{}\" is also given on line {} (JSON tools "
                                 "disagree on which value counts: remove one)",
                                 it->first, it->second));
  }
  object.key = EscapeForMessage(key);
}

// A number token starting at text[i]: throws naming the path when it lies outside double's range (1e999).
std::size_t CheckNumberToken(std::string_view text, std::size_t i, const std::vector<OpenContainer>& open,
                             const std::string& source) {
  const std::size_t start = i;
  while (i < text.size() && std::string_view("0123456789+-.eE").find(text[i]) != std::string_view::npos) ++i;
  const std::string token(text.substr(start, i - start));
  if (!std::isfinite(std::strtod(token.c_str(), nullptr))) {
    throw InputError(source, PathOf(open),
                     fmt::format("a number within double's range (magnitude below 1.8e308), got {}",
                                 EscapeForMessage(Utf8Prefix(token, 40))));
  }
  return i - 1;
}

}  // namespace

void CheckJsonKeysUnique(std::string_view text, const std::string& source) {
  // One pass over the text nlohmann's (iterative) parser accepted: a stack of open containers with the path.
  std::vector<OpenContainer> open;
  int line = 1;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
    } else if (c == '{' || c == '[') {
      open.push_back({c == '{', c == '{', {}, {}, 0});
      if (open.size() > kMaxJsonDepth) {
        throw InputError(source, PathOf(open),
                         fmt::format("JSON nested at most {} levels deep, but line {} opens level {}", kMaxJsonDepth,
                                     line, open.size()));
      }
    } else if (c == '}' || c == ']') {
      if (!open.empty()) open.pop_back();
    } else if (c == ',') {
      if (!open.empty() && open.back().is_object) open.back().expect_key = true;
      if (!open.empty() && !open.back().is_object) ++open.back().index;
    } else if (c == '"') {
      const std::size_t start = i;
      i = StringTokenEnd(text, i);
      if (open.empty() || !open.back().is_object || !open.back().expect_key) continue;
      open.back().expect_key = false;
      RecordKey(open.back(), DecodedKey(text.substr(start, i + 1 - start), source, line), line, source);
    } else if (c == '-' || (c >= '0' && c <= '9')) {
      i = CheckNumberToken(text, i, open, source);
    }
  }
}

nlohmann::json ParseJsonText(std::string_view text, const std::string& source) {
  try {
    nlohmann::json document = nlohmann::json::parse(text);
    CheckJsonKeysUnique(text, source);
    return document;
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(source, fmt::format("byte {}", e.byte), "valid JSON");
  } catch (const nlohmann::json::exception& e) {
    // out_of_range: a number like 1e999. The scan names its path (it throws before reaching the end).
    CheckJsonKeysUnique(text, source);
    throw InputError(source, "JSON", fmt::format("valid JSON ({})", EscapeForMessage(e.what())));
  }
}

nlohmann::json ReadJsonFile(const std::filesystem::path& path) { return ParseJsonText(ReadFile(path), path.string()); }

}  // namespace uascma
