#include "uascma/common/json_io.h"

#include <string>
#include <unordered_map>
#include <vector>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/files.h"

namespace uascma {

void CheckJsonKeysUnique(std::string_view text, const std::string& source) {
  // One pass over the (valid) text: a stack of open containers, each object with its keys and their lines.
  struct Container {
    bool is_object = false;
    bool expect_key = false;
    std::unordered_map<std::string, int> key_lines;
  };
  std::vector<Container> open;
  int line = 1;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    switch (c) {
      case '\n':
        ++line;
        break;
      case '{':
        open.push_back({true, true, {}});
        break;
      case '[':
        open.push_back({false, false, {}});
        break;
      case '}':
      case ']':
        if (!open.empty()) open.pop_back();
        break;
      case ',':
        if (!open.empty() && open.back().is_object) open.back().expect_key = true;
        break;
      case '"': {
        // A string token: up to the next quote not escaped (strings hold no raw newline in valid JSON).
        const std::size_t start = i;
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
        if (open.empty() || !open.back().is_object || !open.back().expect_key) break;
        open.back().expect_key = false;
        const std::string_view token = text.substr(start, i + 1 - start);
        std::string key;
        if (token.find('\\') == std::string_view::npos) {
          key = std::string(token.substr(1, token.size() - 2));
        } else {
          try {
            key = nlohmann::json::parse(token).get<std::string>();
          } catch (const nlohmann::json::exception&) {
            throw InputError(source, fmt::format("line {}", line), "valid JSON");
          }
        }
        const auto [it, inserted] = open.back().key_lines.emplace(std::move(key), line);
        if (!inserted) {
          throw InputError(source, fmt::format("line {}", line),
                           fmt::format("each key once per object, but \"{}\" is also given on line {} (JSON tools "
                                       "disagree on which value counts: remove one)",
                                       it->first, it->second));
        }
        break;
      }
      default:
        break;
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
  } catch (const nlohmann::json::exception& e) {  // out_of_range: a number like 1e999
    throw InputError(source, "JSON", fmt::format("valid JSON ({})", e.what()));
  }
}

nlohmann::json ReadJsonFile(const std::filesystem::path& path) { return ParseJsonText(ReadFile(path), path.string()); }

}  // namespace uascma
