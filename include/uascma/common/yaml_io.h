#pragma once
// Typed reads from YAML with errors that name the file and the key path (style habit 8).
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <string>

namespace uascma {

// Parses a YAML file; a missing file or a syntax error becomes an InputError naming the file.
YAML::Node LoadYamlFile(const std::filesystem::path& path);

// A required finite number at `node[key]`; `where` is the key path of `node` used in messages
// ("weights.actions"), `source` the file name.
double RequireNumber(const YAML::Node& node, const std::string& key, const std::string& source,
                     const std::string& where);

// The same, but returns `fallback` when the key is absent.
double OptionalNumber(const YAML::Node& node, const std::string& key, double fallback,
                      const std::string& source, const std::string& where);

// A required map at node[key].
YAML::Node RequireMap(const YAML::Node& node, const std::string& key, const std::string& source,
                      const std::string& where);

}  // namespace uascma
