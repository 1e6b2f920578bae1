#pragma once
// JSON documents read the one way every uascma file reader reports them: a malformed text is an InputError naming
// the source and the byte where parsing stopped; a number out of double's range (1e999) names the source too.
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace uascma {

// Parses `text`; InputError(source, "byte N", "valid JSON") on a syntax error, InputError(source, "JSON", …)
// on any other parser error, and the CheckJsonKeysUnique error on a key given twice in one object.
// (nlohmann's lexer already refuses strings that are not UTF-8.)
nlohmann::json ParseJsonText(std::string_view text, const std::string& source);

// The deepest nesting of arrays and objects a uascma JSON file may have (ours: our formats nest at most 6 levels,
// a GeoJSON MultiPolygon's coordinates 4 inside a feature; a deeper document is refused before anything walks it
// recursively: the message writers, copies and comparisons of nlohmann::json recurse once per level).
inline constexpr std::size_t kMaxJsonDepth = 64;

// For text that nlohmann::json::parse accepted (its parser and destructor are iterative), one pass that throws
// InputError naming the source and the path of the value ("states[4].q[2]") when:
// - an object holds one key twice (InputError(source, "line N", …) naming both lines; RFC 8259 §4 leaves the
//   meaning to each tool: nlohmann keeps the last value, others the first or refuse). Keys are compared after
//   their escapes are decoded ("a" and "\u0061" are the same key);
// - arrays and objects nest deeper than kMaxJsonDepth;
// - a number lies outside double's range (1e999; for text the parser refused with out_of_range).
void CheckJsonKeysUnique(std::string_view text, const std::string& source);

// ReadFile (common/files.h) then ParseJsonText, the path as the source.
nlohmann::json ReadJsonFile(const std::filesystem::path& path);

}  // namespace uascma
