#pragma once
// JSON documents read the one way every uascma file reader reports them: a malformed text is an InputError naming
// the source and the byte where parsing stopped; a number out of double's range (1e999) names the source too.
#include <filesystem>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace uascma {

// Parses `text`; InputError(source, "byte N", "valid JSON") on a syntax error, InputError(source, "JSON", …)
// on any other parser error.
nlohmann::json ParseJsonText(std::string_view text, const std::string& source);

// ReadFile (common/files.h) then ParseJsonText, the path as the source.
nlohmann::json ReadJsonFile(const std::filesystem::path& path);

}  // namespace uascma
