#pragma once
// Typed reading of a JSON document: every value knows the file it came from and its path in the
// document ("mission.items[3].params[2]"), and every typed access that fails throws
// InputError(source, path, what was expected), so a reader never checks a member by hand and never lets a
// nlohmann type_error escape as an internal error.
//
//   const JsonDocument document = JsonDocument::ReadFile(path);      // syntax, duplicate keys: common/json_io.h
//   const JsonValue root = document.root();
//   root.Member("format").RequireString(kPolicyFormat);
//   const double gamma = root.Member("gamma").Number(kGammaBounds);  // "policy.json: gamma: from 0 to … , got 2"
//   for (const JsonValue& entry : root.Member("states").Elements()) {
//     labels.push_back(entry.Member("state").String());            // "policy.json: states[4].state: a string, …"
//   }
//
// A member that is absent is a JsonValue too (IsMissing()): reading it as a type says "<expected>, but it is
// missing"; Optional… accessors give nullopt for it (and for null). The document owns the parsed JSON; a JsonValue
// is a view into it and must not outlive it.
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "uascma/common/bounds.h"

namespace uascma {

class JsonValue {
 public:
  // A view of `json` (nullptr: a missing member) at `path` ("" for the top level) of the document `source`.
  JsonValue(const nlohmann::json* json, const std::string* source, std::string path)
      : json_(json), source_(source), path_(std::move(path)) {}

  const std::string& source() const { return *source_; }
  // The path for messages: "(top level)" for the root.
  std::string field() const { return path_.empty() ? "(top level)" : path_; }
  const std::string& path() const { return path_; }
  // The underlying value (UASCMA_CHECK: not missing), for writers that keep a sub-document as it is.
  const nlohmann::json& json() const;

  bool IsMissing() const { return json_ == nullptr; }
  bool IsNull() const { return json_ != nullptr && json_->is_null(); }
  bool IsMissingOrNull() const { return json_ == nullptr || json_->is_null(); }
  bool IsObject() const { return json_ != nullptr && json_->is_object(); }
  bool IsArray() const { return json_ != nullptr && json_->is_array(); }
  bool IsString() const { return json_ != nullptr && json_->is_string(); }
  bool IsNumber() const { return json_ != nullptr && json_->is_number(); }
  bool IsInteger() const { return json_ != nullptr && json_->is_number_integer(); }
  bool IsBool() const { return json_ != nullptr && json_->is_boolean(); }

  // Throws InputError(source, path, expected + ", but it is missing" / ", got <the value>").
  [[noreturn]] void Fail(std::string_view expected) const;
  // The same with `expected` as it is (no "got").
  [[noreturn]] void FailExactly(std::string_view expected) const;
  // A member of this object: throws "an object" unless it is one (`expected` says what the object holds).
  JsonValue Member(std::string_view key, std::string_view expected = "an object") const;
  bool Has(std::string_view key) const;  // an object holding `key`
  // The elements of this array (throws `expected` unless it is an array), each with its path "…[i]".
  std::vector<JsonValue> Elements(std::string_view expected = "an array") const;
  // An array of exactly `count` elements, else throws `expected`.
  std::vector<JsonValue> Elements(std::size_t count, std::string_view expected) const;
  // The members of this object in the document's key order (nlohmann's: sorted), each with its path "….key".
  std::vector<std::pair<std::string, JsonValue>> Members(std::string_view expected = "an object") const;
  void RequireObject(std::string_view expected = "an object") const;
  void RequireArray(std::string_view expected = "an array") const;
  std::size_t size() const { return json_ != nullptr ? json_->size() : 0; }

  std::string String(std::string_view expected = "a string") const;
  // A string equal to `value`, else throws expected (default "\"value\"").
  void RequireString(std::string_view value, std::string_view expected = {}) const;
  bool Bool(std::string_view expected = "true or false") const;
  double Number(std::string_view expected = "a number") const;
  // A number within `bounds` (common/bounds.h): "from 0 to 1, got 2" outside.
  double Number(const Bounds& bounds, std::string_view expected = "a number") const;
  // An integer (a JSON number without fraction or exponent) within T's range.
  template <typename T>
  T Integer(std::string_view expected = "an integer") const {
    static_assert(std::is_integral_v<T> && !std::is_same_v<T, bool>);
    if constexpr (std::is_unsigned_v<T>) {
      return static_cast<T>(UnsignedUpTo(std::numeric_limits<T>::max(), expected));
    } else {
      return static_cast<T>(SignedIn(std::numeric_limits<T>::min(), std::numeric_limits<T>::max(), expected));
    }
  }

  // Absent or null: nullopt; otherwise as the accessors above.
  std::optional<std::string> OptionalString(std::string_view expected = "a string") const;
  std::optional<double> OptionalNumber(std::string_view expected = "a number or null") const;
  std::optional<bool> OptionalBool(std::string_view expected = "true or false") const;

  // A short JSON text of the value for messages (at most ~60 characters), "nothing" when missing.
  std::string Brief() const;

 private:
  std::int64_t SignedIn(std::int64_t low, std::int64_t high, std::string_view expected) const;
  std::uint64_t UnsignedUpTo(std::uint64_t high, std::string_view expected) const;
  std::string ChildPath(std::string_view key) const;

  const nlohmann::json* json_;
  const std::string* source_;
  std::string path_;
};

// A parsed document and its source (a file's path). Not copyable: the JsonValues point into it.
class JsonDocument {
 public:
  // ParseJsonText (common/json_io.h): InputError naming the source on a syntax error, a number out of range or a
  // key given twice in one object; nlohmann's lexer refuses strings that are not UTF-8.
  static JsonDocument Parse(std::string_view text, std::string source);
  static JsonDocument ReadFile(const std::filesystem::path& path);
  // A document already parsed (e.g. a member of another one) under `source`, its paths starting at `path`.
  JsonDocument(nlohmann::json json, std::string source, std::string path = "")
      : json_(std::move(json)), source_(std::move(source)), path_(std::move(path)) {}
  JsonDocument(const JsonDocument&) = delete;
  JsonDocument& operator=(const JsonDocument&) = delete;

  JsonValue root() const { return JsonValue(&json_, &source_, path_); }
  const nlohmann::json& json() const { return json_; }
  const std::string& source() const { return source_; }

 private:
  nlohmann::json json_;
  std::string source_;
  std::string path_;
};

}  // namespace uascma
