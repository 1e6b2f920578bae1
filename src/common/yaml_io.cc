#include "uascma/common/yaml_io.h"

#include <cmath>

#include "uascma/common/error.h"

namespace uascma {
namespace {

std::string Join(const std::string& where, const std::string& key) {
  return where.empty() ? key : where + "." + key;
}

double ParseNumber(const YAML::Node& value, const std::string& source, const std::string& field) {
  if (!value.IsScalar()) throw InputError(source, field, "a number, got a non-scalar");
  double number = 0.0;
  try {
    number = value.as<double>();
  } catch (const YAML::Exception&) {
    throw InputError(source, field, "a number, got '" + value.Scalar() + "'");
  }
  if (!std::isfinite(number)) throw InputError(source, field, "a finite number, got '" + value.Scalar() + "'");
  return number;
}

}  // namespace

YAML::Node LoadYamlFile(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(path.string(), "file", "an existing YAML file");
  }
  try {
    YAML::Node root = YAML::LoadFile(path.string());
    if (!root.IsMap()) throw InputError(path.string(), "(top level)", "a YAML mapping");
    return root;
  } catch (const YAML::Exception& e) {
    throw InputError(path.string(), "line " + std::to_string(e.mark.line + 1),
                     "valid YAML (" + e.msg + ")");
  }
}

double RequireNumber(const YAML::Node& node, const std::string& key, const std::string& source,
                     const std::string& where) {
  const YAML::Node value = node[key];
  if (!value) throw InputError(source, Join(where, key), "a number, but the key is missing");
  return ParseNumber(value, source, Join(where, key));
}

double OptionalNumber(const YAML::Node& node, const std::string& key, double fallback,
                      const std::string& source, const std::string& where) {
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
  if (!node.IsMap()) throw InputError(source, where.empty() ? "(top level)" : where, "a mapping");
  for (const auto& entry : node) {
    if (!entry.first.IsScalar()) throw InputError(source, where.empty() ? "(top level)" : where, "names as keys");
    const std::string key = entry.first.as<std::string>();
    bool known = false;
    std::string list;
    for (const char* name : allowed) {
      known = known || key == name;
      list += (list.empty() ? "" : ", ") + std::string(name);
    }
    if (!known) throw InputError(source, Join(where, key), "no such key here; expected one of: " + list);
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
    throw InputError(source, Join(where, key), "true or false, got '" + (value.IsScalar() ? value.Scalar() : "?") + "'");
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
  for (std::size_t i = 0; i < size; ++i) numbers.push_back(ParseNumber(value[i], source, field + "[" + std::to_string(i) + "]"));
  return numbers;
}

}  // namespace uascma
