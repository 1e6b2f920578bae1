#include "uascma/campaign/record.h"

#include <cstring>
#include <type_traits>

#include "uascma/common/error.h"
#include "uascma/common/json_reader.h"

namespace uascma::campaign {
namespace {

// One field of a record from its member of the same name (common/json_reader.h names the source and field).
template <typename T>
void ReadField(const JsonValue& value, T& field) {
  if constexpr (std::is_same_v<T, std::optional<double>>) {
    if (value.IsMissing()) value.Fail("a number or null");
    field = value.OptionalNumber("a number or null");
  } else if constexpr (std::is_same_v<T, std::string>) {
    field = value.String();
  } else if constexpr (std::is_same_v<T, bool>) {
    field = value.Bool();
  } else if constexpr (std::is_same_v<T, double>) {
    field = value.Number();
  } else {
    field = value.Integer<T>();
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
  const JsonValue root(&json, &source, "");
  if (!root.IsObject()) throw InputError(source, "record", "a JSON object");
  RunRecord record;
  VisitRecordFields(record, [&](const char* name, auto& field) { ReadField(root.Member(name), field); });
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
