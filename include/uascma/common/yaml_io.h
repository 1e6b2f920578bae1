#pragma once
// Typed reads from YAML with errors that name the file and the key path (bad input names file, field and expectation).
#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <vector>

namespace uascma {

// The largest YAML text uascma reads (ours: 270 times the largest example file, 3.9 KB) and its longest line
// (ours: no key or value of uascma's YAML files is longer; a path is at most 4 KiB on Linux).
inline constexpr std::size_t kMaxYamlBytes = 1 << 20;
inline constexpr std::size_t kMaxYamlLineBytes = 1 << 16;

// Parses a YAML file; a missing file or a syntax error becomes an InputError naming the file, and the
// document is checked as ParseYamlText does.
YAML::Node LoadYamlFile(const std::filesystem::path& path);

// Parses YAML text (`source` names it in errors) and refuses, with an InputError naming the line(s):
//   - a syntax error;
//   - a key given twice in one mapping: YAML 1.2 requires keys to be unique, and tools
//     disagree on which value counts (yaml-cpp's node[key] returns the first, PyYAML keeps the last), so
//     the file is refused naming both lines rather than read one way;
//   - a scalar that is not UTF-8, naming its line;
//   - a second document (after `---`), naming the line it starts on: the file would mean its first document
//     only, silently;
//   - before parsing, a text above kMaxYamlBytes or a line above kMaxYamlLineBytes (yaml-cpp's scanner costs
//     about 0.4 µs per byte of a scalar, measured: a 10 MB value would take seconds before any check).
// An empty document gives a null node.
YAML::Node ParseYamlText(const std::string& text, const std::string& source);

// A required finite number at `node[key]`; `where` is the key path of `node` used in messages
// ("weights.actions"), `source` the file name.
double RequireNumber(const YAML::Node& node, const std::string& key, const std::string& source,
                     const std::string& where);

// The same, but returns `fallback` when the key is absent.
double OptionalNumber(const YAML::Node& node, const std::string& key, double fallback, const std::string& source,
                      const std::string& where);

// A required map at node[key].
YAML::Node RequireMap(const YAML::Node& node, const std::string& key, const std::string& source,
                      const std::string& where);

// Throws InputError naming the first key of the mapping `node` that is not in `allowed` (catches typos
// such as "turbulance" that would otherwise be silently ignored).
void RequireOnlyKeys(const YAML::Node& node, std::initializer_list<const char*> allowed, const std::string& source,
                     const std::string& where);
// The same for a list made at run time (the keys of a field table: campaign/config_fields.h, sim/scenario_fields.h).
void RequireOnlyKeys(const YAML::Node& node, const std::vector<std::string>& allowed, const std::string& source,
                     const std::string& where);

// A required string at node[key].
std::string RequireString(const YAML::Node& node, const std::string& key, const std::string& source,
                          const std::string& where);

// A boolean at node[key], or `fallback` when absent.
bool OptionalBool(const YAML::Node& node, const std::string& key, bool fallback, const std::string& source,
                  const std::string& where);

// A list of exactly `size` numbers at node[key].
std::vector<double> RequireNumberList(const YAML::Node& node, const std::string& key, std::size_t size,
                                      const std::string& source, const std::string& where);

}  // namespace uascma
