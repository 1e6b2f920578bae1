#include "uascma/campaign/record.h"

#include <cstring>
#include <type_traits>

#include "uascma/common/error.h"

namespace uascma::campaign {
namespace {

template <typename T>
void ReadField(const nlohmann::json& json, const char* name, T& field, const std::string& source) {
  if (!json.contains(name)) throw InputError(source, name, "a value, but the key is missing");
  const nlohmann::json& value = json.at(name);
  if constexpr (std::is_same_v<T, std::optional<double>>) {
    if (value.is_null()) {
      field.reset();
    } else if (value.is_number()) {
      field = value.get<double>();
    } else {
      throw InputError(source, name, "a number or null");
    }
  } else if constexpr (std::is_same_v<T, std::string>) {
    if (!value.is_string()) throw InputError(source, name, "a string");
    field = value.get<std::string>();
  } else if constexpr (std::is_same_v<T, bool>) {
    if (!value.is_boolean()) throw InputError(source, name, "true or false");
    field = value.get<bool>();
  } else if constexpr (std::is_same_v<T, double>) {
    if (!value.is_number()) throw InputError(source, name, "a number");
    field = value.get<double>();
  } else {
    if (!value.is_number_integer()) throw InputError(source, name, "an integer");
    field = value.get<T>();
  }
}

template <typename T>
bool SameValue(const T& a, const T& b) {
  if constexpr (std::is_same_v<T, double>) {
    return std::memcmp(&a, &b, sizeof a) == 0;
  } else if constexpr (std::is_same_v<T, std::optional<double>>) {
    if (a.has_value() != b.has_value()) return false;
    return !a.has_value() || std::memcmp(&*a, &*b, sizeof(double)) == 0;
  } else {
    return a == b;
  }
}

}  // namespace

nlohmann::json RecordToJson(const RunRecord& record) {
  nlohmann::json json = nlohmann::json::object();
  VisitRecordFields(record, [&json](const char* name, const auto& field) {
    using T = std::decay_t<decltype(field)>;
    if constexpr (std::is_same_v<T, std::optional<double>>) {
      json[name] = field ? nlohmann::json(*field) : nlohmann::json(nullptr);
    } else {
      json[name] = field;
    }
  });
  return json;
}

RunRecord RecordFromJson(const nlohmann::json& json, const std::string& source) {
  if (!json.is_object()) throw InputError(source, "record", "a JSON object");
  RunRecord record;
  VisitRecordFields(record, [&](const char* name, auto& field) { ReadField(json, name, field, source); });
  return record;
}

std::optional<std::string> FirstDifference(const RunRecord& a, const RunRecord& b) {
  std::optional<std::string> difference;
  // For each field of a, find the field of b with the same name and compare (42 × 42 visits).
  VisitRecordFields(a, [&](const char* name, const auto& field_a) {
    if (difference || std::strcmp(name, "wall_time_s") == 0) return;
    using T = std::decay_t<decltype(field_a)>;
    bool found = false;
    VisitRecordFields(b, [&](const char* other, const auto& field_b) {
      if (found || std::strcmp(name, other) != 0) return;
      found = true;
      if constexpr (std::is_same_v<T, std::decay_t<decltype(field_b)>>) {
        if (!SameValue(field_a, field_b)) difference = name;
      }
    });
  });
  return difference;
}

}  // namespace uascma::campaign
