#include "uascma/common/yaml_io.h"

#include <cmath>

#include "uascma/common/error.h"

namespace uascma {
namespace {

std::string Join(const std::string& where, const std::string& key) {
  return where.empty() ? key : where + "." + key;
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
  if (!value.IsScalar()) throw InputError(source, Join(where, key), "a number, got a non-scalar");
  double number = 0.0;
  try {
    number = value.as<double>();
  } catch (const YAML::Exception&) {
    throw InputError(source, Join(where, key), "a number, got '" + value.Scalar() + "'");
  }
  if (!std::isfinite(number)) {
    throw InputError(source, Join(where, key), "a finite number, got '" + value.Scalar() + "'");
  }
  return number;
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

}  // namespace uascma
