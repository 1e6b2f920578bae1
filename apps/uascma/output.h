#pragma once
// Output helpers shared by the commands.
#include <nlohmann/json.hpp>

#include <string>

namespace uascma::cli {

// Prints a JSON document on stdout, pretty, followed by a newline.
void PrintJson(const nlohmann::json& document);

// Writes `content` to `path` atomically, or to stdout when `path` is empty or "-".
void WriteOutput(const std::string& path, const std::string& content);

}  // namespace uascma::cli
