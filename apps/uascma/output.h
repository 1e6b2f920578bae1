#pragma once
// Output helpers shared by the commands.
#include <nlohmann/json.hpp>

#include <string>

namespace uascma::cli {

// Prints a JSON document on stdout, pretty, followed by a newline.
void PrintJson(const nlohmann::json& document);

// Writes `content` to `path` atomically, or to stdout when `path` is empty or "-".
void WriteOutput(const std::string& path, const std::string& content);

// An output file is checked before any work: its folder exists and is writable, and the path is not a
// folder. Throws InputError(option, path, …) otherwise (exit 2, nothing written). An empty path passes.
void CheckOutputFile(const std::string& path, const char* option);

}  // namespace uascma::cli
