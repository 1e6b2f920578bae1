#pragma once
// JSON documents read the one way every uascma file reader reports them: a malformed text is an InputError naming
// the source and the byte where parsing stopped; a number out of double's range (1e999) names the source too.
#include <filesystem>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace uascma {

// Parses `text`; InputError(source, "byte N", "valid JSON") on a syntax error, InputError(source, "JSON", …)
// on any other parser error, and the CheckJsonKeysUnique error on a key given twice in one object.
// (nlohmann's lexer already refuses strings that are not UTF-8.)
nlohmann::json ParseJsonText(std::string_view text, const std::string& source);

// For text that nlohmann::json::parse accepted: InputError(source, "line N", …) naming both lines when an
// object holds one key twice (RFC 8259 §4 leaves the meaning to each tool: nlohmann keeps
// the last value, others the first or refuse). Keys are compared after their escapes are decoded
// ("a" and "\u0061" are the same key).
void CheckJsonKeysUnique(std::string_view text, const std::string& source);

// ReadFile (common/files.h) then ParseJsonText, the path as the source.
nlohmann::json ReadJsonFile(const std::filesystem::path& path);

}  // namespace uascma
