// JsonDocument / JsonValue (common/json_reader.h): every failed typed access names the source, the field's full
// path and what was expected; numbers are checked against Bounds; the parser's checks (syntax, duplicate keys,
// UTF-8) are json_io's.
#include "uascma/common/json_reader.h"

#include <cstdint>
#include <string>

#include <gtest/gtest.h>

#include "uascma/common/error.h"
#include "uascma/common/text.h"

namespace uascma {
namespace {

// The message of the InputError `read` throws, or "" when it throws none.
template <typename Fn>
std::string ErrorOf(Fn read) {
  try {
    read();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

constexpr char kText[] = R"({"name": "a", "gamma": 0.95, "count": 3, "flag": true, "nothing": null,
  "items": [{"params": [1, 2.5, null]}, {"params": "x"}], "big": 18446744073709551615, "negative": -4})";

TEST(JsonReaderTest, ReadsTypedMembers) {
  const JsonDocument document = JsonDocument::Parse(kText, "plan.json");
  const JsonValue root = document.root();
  EXPECT_EQ(root.Member("name").String(), "a");
  EXPECT_DOUBLE_EQ(root.Member("gamma").Number(), 0.95);  // the literal's double, exactly
  EXPECT_EQ(root.Member("count").Integer<int>(), 3);
  EXPECT_TRUE(root.Member("flag").Bool());
  EXPECT_FALSE(root.Member("nothing").OptionalNumber().has_value());
  EXPECT_FALSE(root.Member("absent").OptionalString().has_value());
  EXPECT_TRUE(root.Member("absent").IsMissing());
  const auto params = root.Member("items").Elements()[0].Member("params").Elements(3, "three numbers");
  EXPECT_DOUBLE_EQ(params[1].Number(), 2.5);
  EXPECT_TRUE(params[2].IsNull());
  EXPECT_EQ(params[2].path(), "items[0].params[2]");
}

TEST(JsonReaderTest, NamesSourceFullPathAndExpectation) {
  const JsonDocument document = JsonDocument::Parse(kText, "plan.json");
  const JsonValue root = document.root();
  EXPECT_EQ(ErrorOf([&] { root.Member("items").Elements()[1].Member("params").Elements(); }),
            "plan.json: items[1].params: an array, got \"x\"");
  EXPECT_EQ(ErrorOf([&] { root.Member("items").Elements()[0].Member("params").Elements()[2].Number(); }),
            "plan.json: items[0].params[2]: a number, got null");
  EXPECT_EQ(ErrorOf([&] { root.Member("model").String("a model name"); }),
            "plan.json: model: a model name, but it is missing");
  EXPECT_EQ(ErrorOf([&] { root.Member("name").Member("x"); }), "plan.json: name: an object, got \"a\"");
  EXPECT_EQ(ErrorOf([&] { root.Member("count").RequireString("Plan"); }), "plan.json: count: \"Plan\", got 3");
  EXPECT_EQ(ErrorOf([&] { root.Elements(); }).rfind("plan.json: (top level): an array, got {", 0), 0u);
}

TEST(JsonReaderTest, AShortenedValueInAMessageIsNotCutInsideACharacter) {
  // The dump is '"' + 55 'a' + "é"...: a cut at 57 bytes would split the first é (bytes 56-57).
  std::string value(55, 'a');
  for (int k = 0; k < 10; ++k) value += "\xC3\xA9";
  const JsonDocument document = JsonDocument::Parse("{\"name\": \"" + value + "\"}", "plan.json");
  const std::string message = ErrorOf([&] { document.root().Member("name").Number(); });
  EXPECT_TRUE(IsValidUtf8(message)) << message;
  EXPECT_EQ(message, "plan.json: name: a number, got \"" + std::string(55, 'a') + "...");
}

TEST(JsonReaderTest, ChecksBoundsAndIntegerRanges) {
  const JsonDocument document = JsonDocument::Parse(kText, "plan.json");
  const JsonValue root = document.root();
  constexpr Bounds kUnit{0.0, 0.9, ""};
  EXPECT_EQ(ErrorOf([&] { root.Member("gamma").Number(kUnit); }), "plan.json: gamma: from 0 to 0.9, got 0.95");
  EXPECT_DOUBLE_EQ(root.Member("gamma").Number(Bounds{0.0, 1.0, ""}), 0.95);
  // 2^64-1 fits no signed type; -4 no unsigned one; 0.95 is no integer.
  EXPECT_EQ(ErrorOf([&] { root.Member("big").Integer<std::int64_t>(); }),
            "plan.json: big: an integer, got 18446744073709551615");
  EXPECT_EQ(ErrorOf([&] { root.Member("negative").Integer<std::uint32_t>(); }),
            "plan.json: negative: an integer, got -4");
  EXPECT_EQ(root.Member("negative").Integer<std::int8_t>(), -4);
  EXPECT_EQ(root.Member("big").Integer<std::uint64_t>(), 18446744073709551615ull);  // a seed's whole range
  EXPECT_EQ(root.Member("count").Integer<std::uint8_t>(), 3);
  EXPECT_EQ(ErrorOf([&] { root.Member("big").Integer<std::uint32_t>(); }),
            "plan.json: big: an integer, got 18446744073709551615");
  EXPECT_NE(ErrorOf([&] { root.Member("gamma").Integer<int>(); }), "");
}

TEST(JsonReaderTest, ParsingRefusesDuplicateKeysAndBadSyntaxNamingTheSource) {
  EXPECT_NE(ErrorOf([] { JsonDocument::Parse("{\"a\": 1, \"a\": 2}", "dup.json"); }).find("dup.json: line 1"),
            std::string::npos);
  EXPECT_EQ(ErrorOf([] { JsonDocument::Parse("{\"a\": ", "bad.json"); }).rfind("bad.json: byte", 0), 0u);
  EXPECT_EQ(ErrorOf([] { JsonDocument::Parse("\"\xff\"", "utf.json"); }).rfind("utf.json:", 0), 0u);
}

TEST(JsonReaderTest, ASubDocumentKeepsItsPathPrefix) {
  const JsonDocument document(nlohmann::json::parse(R"([{"state": 1}])"), "policy.json", "model_config.counts");
  EXPECT_EQ(ErrorOf([&] { document.root().Elements()[0].Member("state").String(); }),
            "policy.json: model_config.counts[0].state: a string, got 1");
}

}  // namespace
}  // namespace uascma
