#include "uascma/common/json_reader.h"

#include <cmath>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/common/json_io.h"
#include "uascma/common/text.h"

namespace uascma {
namespace {

// Characters of a value's JSON text quoted in a message at most (ours: one line stays readable).
constexpr std::size_t kBriefCharacters = 60;

}  // namespace

const nlohmann::json& JsonValue::json() const {
  UASCMA_CHECK(json_ != nullptr, "a JSON value that is present");
  return *json_;
}

namespace {

// A JSON string of at most `limit` bytes of `text` (cut between characters).
std::string QuotedPrefix(std::string_view text, std::size_t limit) {
  const nlohmann::json prefix = std::string(Utf8Prefix(text, limit));
  return prefix.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

// Appends the JSON text of `value` to `out` until `out` holds more than `limit` bytes: the work is bounded by
// the limit, not by the value's size, and the recursion by the limit too (each level writes its bracket first).
void AppendBrief(const nlohmann::json& value, std::size_t limit, std::string& out) {
  if (out.size() > limit) return;
  if (value.is_object() || value.is_array()) {
    out += value.is_object() ? '{' : '[';
    bool first = true;
    for (auto it = value.begin(); it != value.end() && out.size() <= limit; ++it) {
      if (!first) out += ',';
      first = false;
      if (value.is_object()) out += QuotedPrefix(it.key(), limit) + ':';
      AppendBrief(it.value(), limit, out);
    }
    out += value.is_object() ? '}' : ']';
    return;
  }
  if (value.is_string()) {
    out += QuotedPrefix(value.get_ref<const std::string&>(), limit);
    return;
  }
  out += value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace

std::string JsonValue::Brief() const {
  if (json_ == nullptr) return "nothing";
  std::string text;
  AppendBrief(*json_, kBriefCharacters, text);
  // Cut between characters: a UTF-8 sequence split at the cut would make the message itself invalid text.
  if (text.size() > kBriefCharacters) text = std::string(Utf8Prefix(text, kBriefCharacters - 3)) + "...";
  return EscapeForMessage(text);
}

void JsonValue::Fail(std::string_view expected) const {
  if (json_ == nullptr) throw InputError(*source_, field(), fmt::format("{}, but it is missing", expected));
  throw InputError(*source_, field(), fmt::format("{}, got {}", expected, Brief()));
}

void JsonValue::FailExactly(std::string_view expected) const {
  throw InputError(*source_, field(), std::string(expected));
}

std::string JsonValue::ChildPath(std::string_view key) const {
  return path_.empty() ? std::string(key) : fmt::format("{}.{}", path_, key);
}

void JsonValue::RequireObject(std::string_view expected) const {
  if (!IsObject()) Fail(expected);
}

void JsonValue::RequireArray(std::string_view expected) const {
  if (!IsArray()) Fail(expected);
}

bool JsonValue::Has(std::string_view key) const { return IsObject() && json_->contains(key); }

JsonValue JsonValue::Member(std::string_view key, std::string_view expected) const {
  RequireObject(expected);
  const auto it = json_->find(key);
  return JsonValue(it == json_->end() ? nullptr : &*it, source_, ChildPath(key));
}

std::vector<JsonValue> JsonValue::Elements(std::string_view expected) const {
  RequireArray(expected);
  std::vector<JsonValue> elements;
  elements.reserve(json_->size());
  for (std::size_t i = 0; i < json_->size(); ++i) {
    elements.emplace_back(&(*json_)[i], source_, fmt::format("{}[{}]", path_, i));
  }
  return elements;
}

std::vector<JsonValue> JsonValue::Elements(std::size_t count, std::string_view expected) const {
  if (!IsArray() || json_->size() != count) Fail(expected);
  return Elements(expected);
}

std::vector<std::pair<std::string, JsonValue>> JsonValue::Members(std::string_view expected) const {
  RequireObject(expected);
  std::vector<std::pair<std::string, JsonValue>> members;
  for (auto it = json_->begin(); it != json_->end(); ++it) {
    members.emplace_back(it.key(), JsonValue(&it.value(), source_, ChildPath(it.key())));
  }
  return members;
}

std::string JsonValue::String(std::string_view expected) const {
  if (!IsString()) Fail(expected);
  return json_->get<std::string>();
}

void JsonValue::RequireString(std::string_view value, std::string_view expected) const {
  const std::string wanted = expected.empty() ? fmt::format("\"{}\"", value) : std::string(expected);
  if (!IsString() || json_->get_ref<const std::string&>() != value) Fail(wanted);
}

bool JsonValue::Bool(std::string_view expected) const {
  if (!IsBool()) Fail(expected);
  return json_->get<bool>();
}

double JsonValue::Number(std::string_view expected) const {
  if (!IsNumber()) Fail(expected);
  return json_->get<double>();
}

double JsonValue::Number(const Bounds& bounds, std::string_view expected) const {
  const double value = Number(expected);
  if (!bounds.Contains(value)) throw InputError(*source_, field(), OutsideBoundsMessage(bounds, value));
  return value;
}

// nlohmann keeps a non-negative integer as unsigned when it parsed it without sign: values above int64's range
// are refused (or, for an unsigned target, compared) before any cast, so nothing wraps (2^64-1 is no -1).
std::int64_t JsonValue::SignedIn(std::int64_t low, std::int64_t high, std::string_view expected) const {
  if (!IsInteger()) Fail(expected);
  if (json_->is_number_unsigned()) {
    const std::uint64_t value = json_->get<std::uint64_t>();
    if (high < 0 || value > static_cast<std::uint64_t>(high)) Fail(expected);
    return static_cast<std::int64_t>(value);
  }
  const std::int64_t value = json_->get<std::int64_t>();
  if (value < low || value > high) Fail(expected);
  return value;
}

std::uint64_t JsonValue::UnsignedUpTo(std::uint64_t high, std::string_view expected) const {
  if (!IsInteger()) Fail(expected);
  if (!json_->is_number_unsigned()) {
    const std::int64_t value = json_->get<std::int64_t>();
    if (value < 0 || static_cast<std::uint64_t>(value) > high) Fail(expected);
    return static_cast<std::uint64_t>(value);
  }
  const std::uint64_t value = json_->get<std::uint64_t>();
  if (value > high) Fail(expected);
  return value;
}

std::optional<std::string> JsonValue::OptionalString(std::string_view expected) const {
  if (IsMissingOrNull()) return std::nullopt;
  return String(expected);
}

std::optional<double> JsonValue::OptionalNumber(std::string_view expected) const {
  if (IsMissingOrNull()) return std::nullopt;
  return Number(expected);
}

std::optional<bool> JsonValue::OptionalBool(std::string_view expected) const {
  if (IsMissingOrNull()) return std::nullopt;
  return Bool(expected);
}

JsonDocument JsonDocument::Parse(std::string_view text, std::string source) {
  nlohmann::json json = ParseJsonText(text, source);
  return JsonDocument(std::move(json), std::move(source));
}

JsonDocument JsonDocument::ReadFile(const std::filesystem::path& path) {
  return Parse(uascma::ReadFile(path), path.string());
}

}  // namespace uascma
