// At the library level: text that is not UTF-8 and keys given twice are refused where
// YAML and JSON enter (naming the line, both lines for a duplicate), and a write that fails inside an output
// folder's staging copy names the user's path, not the hidden staging folder.
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "../under_asan.h"

#include <filesystem>
#include <string>

#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/common/json_io.h"
#include "uascma/common/json_reader.h"
#include "uascma/common/text.h"
#include "uascma/common/yaml_io.h"

namespace uascma {
namespace {

std::string ErrorOf(const auto& call) {
  try {
    call();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Utf8Test, WellFormedSequencesPassAndEveryKindOfIllFormedByteIsFound) {
  EXPECT_TRUE(IsValidUtf8("plain ASCII"));
  EXPECT_TRUE(IsValidUtf8("\xC3\xA9t\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x9A\x81"));  // été € 🚁
  // (text, offset of the first bad byte)
  const std::pair<std::string, std::size_t> bad[] = {
      {"a\xFF", 1},             // never in UTF-8
      {"ab\x80", 2},            // a lone continuation byte
      {"\xC0\xAF", 0},          // overlong '/'
      {"\xE0\x80\xAF", 0},      // overlong, 3 bytes
      {"\xED\xA0\x80", 0},      // a surrogate, U+D800
      {"\xF4\x90\x80\x80", 0},  // above U+10FFFF
      {"ok\xE2\x82", 2},        // truncated at the end
  };
  for (const auto& [text, offset] : bad) {
    ASSERT_TRUE(FirstInvalidUtf8(text).has_value()) << EscapeInvalidUtf8(text);
    EXPECT_EQ(*FirstInvalidUtf8(text), offset) << EscapeInvalidUtf8(text);
  }
  EXPECT_EQ(EscapeInvalidUtf8("a\xFF\xC3\xA9"), "a\\xFF\xC3\xA9");
  const std::string message = ErrorOf([] { RequireUtf8("n\xFF", "s.yaml", "name"); });
  EXPECT_EQ(message, "s.yaml: name: text in UTF-8, but byte 1 (0xFF) of 'n\\xFF' is not");
}

TEST(Utf8Test, APrefixEndsBetweenCharacters) {
  const std::string text = "ab\xC3\xA9\xE2\x82\xAC";  // "abé€": 1 + 1 + 2 + 3 bytes
  EXPECT_EQ(Utf8Prefix(text, 3), "ab");               // é would need bytes 2-3
  EXPECT_EQ(Utf8Prefix(text, 4), "ab\xC3\xA9");
  EXPECT_EQ(Utf8Prefix(text, 6), "ab\xC3\xA9");  // € would need bytes 4-6
  EXPECT_EQ(Utf8Prefix(text, 7), text);
  EXPECT_EQ(Utf8Prefix(text, 100), text);
  const std::string stray_bytes{'a', '\xFF', '\xFF', 'b'};  // four bytes (in a literal, "\xFFb" is one escape)
  ASSERT_EQ(stray_bytes.size(), 4u);
  EXPECT_EQ(Utf8Prefix(stray_bytes, 2), "a\xFF");  // a byte that starts nothing counts as one
  for (std::size_t n = 0; n <= text.size(); ++n) EXPECT_TRUE(IsValidUtf8(Utf8Prefix(text, n))) << n;
}

TEST(YamlTextTest, AKeyGivenTwiceIsRefusedNamingBothLines) {
  EXPECT_EQ(ErrorOf([] { ParseYamlText("name: a\nwind:\n  speed_mps: 1\nname: b\n", "s.yaml"); }),
            "s.yaml: line 4: each key once per mapping, but 'name' is also given on line 1 (YAML tools disagree on "
            "which value counts: remove one)");
  // Nested mappings, flow mappings and mappings inside lists are checked too; the same key in two mappings is not
  // a duplicate.
  EXPECT_NE(ErrorOf([] { ParseYamlText("wind:\n  speed_mps: 1\n  speed_mps: 2\n", "s.yaml"); }).find("line 3"),
            std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseYamlText("map: {a: 1, a: 2}\n", "s.yaml"); }).find("'a' is also given on line 1"),
            std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseYamlText("l:\n  - {x: 1}\n  - x: 1\n    x: 2\n", "s.yaml"); }).find("line 4"),
            std::string::npos);
  EXPECT_EQ(ErrorOf([] { ParseYamlText("a: {x: 1}\nb: {x: 1}\n", "s.yaml"); }), "");
}

TEST(YamlTextTest, TextThatIsNotUtf8IsRefusedNamingItsLine) {
  EXPECT_EQ(ErrorOf([] { ParseYamlText("seed: 1\nname: \"a\xFF\"\n", "s.yaml"); }),
            "s.yaml: line 2: text in UTF-8 (YAML 1.2 §5.2), but column 9 holds byte 0xFF");
  EXPECT_EQ(ErrorOf([] { ParseYamlText("seed: 1\n# \xFF\xFE in a comment\n", "s.yaml"); }),
            "s.yaml: line 2: text in UTF-8 (YAML 1.2 §5.2), but column 3 holds byte 0xFF");
  EXPECT_EQ(ErrorOf([] { ParseYamlText("name: \xC3\xA9t\xC3\xA9\n", "s.yaml"); }), "");
}

TEST(YamlTextTest, NestedAliasesCostTheirTextNotTheirExpansion) {
  // A "billion laughs" document: 2^30 leaves expanded, 30 mappings as written. The walk visits each once.
  std::string text = "a0: &a0 {x: 1}\n";
  for (int i = 1; i <= 30; ++i) {
    text += "a" + std::to_string(i) + ": &a" + std::to_string(i) + " [*a" + std::to_string(i - 1) + ", *a" +
            std::to_string(i - 1) + "]\n";
  }
  EXPECT_EQ(ErrorOf([&] { ParseYamlText(text, "laughs.yaml"); }), "");
}

TEST(JsonTextTest, AKeyGivenTwiceIsRefusedNamingBothLines) {
  EXPECT_EQ(ErrorOf([] { ParseJsonText("{\n  \"name\": \"a\",\n  \"x\": 1,\n  \"name\": \"b\"\n}", "p.json"); }),
            "p.json: line 4: each key once per object, but \"name\" is also given on line 2 (JSON tools disagree on "
            "which value counts: remove one)");
  // Escapes are decoded before keys are compared; strings that hold braces, quotes and keys' names are values.
  EXPECT_NE(ErrorOf([] { ParseJsonText("{\"a\": 1, \"\\u0061\": 2}", "p.json"); }).find("\"a\" is also given"),
            std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseJsonText("[{\"k\": [1, {\"j\": 1, \"j\": 2}]}]", "p.json"); }).find("\"j\""),
            std::string::npos);
  EXPECT_EQ(
      ErrorOf([] { ParseJsonText("{\"a\": \"{\\\"a\\\": 1}\", \"b\": {\"a\": 1}, \"c\": [\"a\", \"a\"]}", "p.json"); }),
      "");
  // The syntax errors are reported as before.
  EXPECT_EQ(ErrorOf([] { ParseJsonText("{\"a\": ", "p.json"); }).rfind("p.json: byte", 0), 0u);
}

// A document nested 100,000 deep crashed the message writer (a recursive dump of the value, on the stack): every
// JSON reader now refuses nesting beyond kMaxJsonDepth, naming the source and the path where it passed it.
TEST(JsonTextTest, NestingBeyondTheBoundIsRefusedNamingThePath) {
  const auto nested = [](std::size_t depth) { return std::string(depth, '[') + std::string(depth, ']'); };
  EXPECT_EQ(ErrorOf([&] { ParseJsonText(nested(kMaxJsonDepth), "p.json"); }), "");
  EXPECT_EQ(ErrorOf([&] { ParseJsonText(nested(kMaxJsonDepth + 1), "p.json"); }),
            fmt::format("p.json: [0][0][0][0][0][0][0][0]… ({0} levels): JSON nested at most {1} levels deep, but "
                        "line 1 opens level {0}",
                        kMaxJsonDepth + 1, kMaxJsonDepth));
  EXPECT_NE(ErrorOf([&] {
              ParseJsonText("{\"states\": [1, {\"q\": " + nested(100000) + "}]}", "p.json");
            }).rfind("p.json: states[1].q[0][0][0][0][0]… (", 0),
            std::string::npos);
}

// nlohmann's "number overflow parsing '1e999'" named neither the field nor the file's path to it.
TEST(JsonTextTest, ANumberBeyondDoublesRangeIsRefusedNamingItsPath) {
  EXPECT_EQ(ErrorOf([] { ParseJsonText("{\"gamma\": 0.9, \"rows\": [1, 2, {\"v\": -1e999}]}", "p.json"); }),
            "p.json: rows[2].v: a number within double's range (magnitude below 1.8e308), got -1e999");
  EXPECT_EQ(ErrorOf([] { ParseJsonText("[1e-999, 1.7e308]", "p.json"); }), "");  // underflow to 0 is a number
}

// The value quoted by a message costs its 60 characters, not its size, and carries no control character.
TEST(JsonTextTest, AMessageQuotesAShortEscapedPartOfTheValue) {
  std::string text = "{\"a\": [";
  for (int i = 0; i < 20000; ++i) text += "[\"x\\u001b[31m\", 1],";
  text += "0]}";
  const JsonDocument document = JsonDocument::Parse(text, "p.json");
  const std::string error = ErrorOf([&] { document.root().Member("a").String(); });
  EXPECT_EQ(error,
            "p.json: a: a string, got [[\"x\\u001b[31m\",1],[\"x\\u001b[31m\",1],[\"x\\u001b[31m\",1],[\"...");
  EXPECT_EQ(error.find('\x1b'), std::string::npos);
  EXPECT_EQ(JsonDocument::Parse("{\"k\": {\"b\": [1, 2.5, \"s\"]}}", "p.json").root().Member("k").Brief(),
            "{\"b\":[1,2.5,\"s\"]}");  // a short value whole, as nlohmann writes it
}

TEST(TextTest, MessagesEscapeControlCharactersAndBytesThatAreNotUtf8) {
  EXPECT_EQ(EscapeForMessage("a\x1b[2Jb\r\n\x7F\xFF \xC3\xA9"), "a\\x1B[2Jb\\x0D\\x0A\\x7F\\xFF \xC3\xA9");
  EXPECT_EQ(BriefForMessage(std::string(100, 'z')), std::string(57, 'z') + "...");
  EXPECT_EQ(BriefForMessage("\t"), "\\x09");
}

// A second document after `---` was silently ignored (the vehicle flew the first): refused naming its line.
TEST(YamlTextTest, ASecondDocumentIsRefusedNamingItsLine) {
  const std::string expected =
      "s.yaml: line 3: one YAML document, but a second one starts here (uascma would read the first only: remove the "
      "second or make it a file of its own)";
  EXPECT_EQ(ErrorOf([] { ParseYamlText("seed: 1\nname: a\n---\nseed: 2\n", "s.yaml"); }), expected);
  EXPECT_EQ(ErrorOf([] { ParseYamlText("seed: 1\nname: a\n---\n", "s.yaml"); }), expected);
  EXPECT_EQ(ErrorOf([] { ParseYamlText("---\nseed: 1\n...\n", "s.yaml"); }), "");  // one document, marked
  EXPECT_TRUE(ParseYamlText("", "s.yaml").IsNull());
}

// A ',' at the top level made yaml-cpp 0.7's parser report an empty document there again and again (YAML::LoadAll
// filled the memory: 17 GB in 10 s for a 1.6 kB scenario the fuzzer wrote). Parsed in a child process with 2 GB of
// address space and 20 s of CPU, so that the old loop ends as a failed test, not a stalled machine. Under
// AddressSanitizer, whose shadow memory is terabytes of address space reserved at start, an address-space limit
// fails the child's first allocation: there the child has 3 s of CPU and no memory limit (the parse takes
// milliseconds; the old loop would reach a few GB).
TEST(YamlTextTest, AFlowIndicatorOutsideAnyCollectionIsRefusedNamingItsLine) {
  int pipe_fds[2];
  ASSERT_EQ(::pipe(pipe_fds), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::close(pipe_fds[0]);
#ifdef UASCMA_UNDER_ASAN
    const rlimit cpu{3, 3};
#else
    const rlimit memory{2'000'000'000, 2'000'000'000};
    const rlimit cpu{20, 20};
    ::setrlimit(RLIMIT_AS, &memory);
#endif
    ::setrlimit(RLIMIT_CPU, &cpu);
    std::string messages;
    for (const char* text : {",", "seed: 1\n,\n", "]\n", "seed: 1\n---\n,\n", "[1]\n,\n"}) {
      messages += ErrorOf([&] { ParseYamlText(text, "s.yaml"); }) + "\n";
    }
    const ssize_t written = ::write(pipe_fds[1], messages.data(), messages.size());
    ::_exit(written == static_cast<ssize_t>(messages.size()) ? 0 : 1);
  }
  ::close(pipe_fds[1]);
  std::string messages;
  char buffer[4096];
  for (ssize_t n; (n = ::read(pipe_fds[0], buffer, sizeof buffer)) > 0;) messages.append(buffer, n);
  ::close(pipe_fds[0]);
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "the child ran out of memory or CPU time";
  EXPECT_EQ(messages,
            "s.yaml: line 1: valid YAML (',' at column 1 belongs to no sequence or mapping)\n"
            "s.yaml: line 2: valid YAML (end of map not found)\n"
            "s.yaml: line 1: valid YAML (illegal flow end)\n"
            "s.yaml: line 2: one YAML document, but a second one starts here (uascma would read the first only: "
            "remove the second or make it a file of its own)\n"
            "s.yaml: line 2: valid YAML (',' at column 1 belongs to no sequence or mapping)\n");
}

// A NUL in a comment passed unseen, and one in a flow sequence sent yaml-cpp into documents it could not place
// ("a second one starts" on a comment line): characters outside YAML 1.2's printable set are refused where they are.
TEST(YamlTextTest, ACharacterYamlDoesNotAllowIsRefusedNamingItsLineAndColumn) {
  using namespace std::string_literals;
  EXPECT_EQ(ErrorOf([] { ParseYamlText("seed: 1\n# a comment\0\n"s, "s.yaml"); }),
            "s.yaml: line 2: printable characters only (YAML 1.2 §5.1), but column 12 holds byte 0x00");
  EXPECT_EQ(ErrorOf([] { ParseYamlText("home_ne_m: [0, \0\0]\n"s, "s.yaml"); }),
            "s.yaml: line 1: printable characters only (YAML 1.2 §5.1), but column 16 holds byte 0x00");
  EXPECT_EQ(ErrorOf([] { ParseYamlText("name: \"a\x1b[2J\"\n", "s.yaml"); }),
            "s.yaml: line 1: printable characters only (YAML 1.2 §5.1), but column 9 holds byte 0x1B");
  EXPECT_EQ(ErrorOf([] { ParseYamlText("name: a\xc2\x9b\n", "s.yaml"); }),
            "s.yaml: line 1: printable characters only (YAML 1.2 §5.1), but column 8 holds U+009B");
  EXPECT_EQ(ErrorOf([] { ParseYamlText("name:\t\"caf\xc3\xa9 \xc2\x85\"\r\nseed: 1\n", "s.yaml"); }), "");  // tab, CR, é, NEL
}

// A 10 MB scalar cost 7.5 CPU s in yaml-cpp's scanner before any check: the size is checked first.
TEST(YamlTextTest, AnOversizedTextOrLineIsRefusedBeforeParsing) {
  const std::string long_line = "name: \"" + std::string(kMaxYamlLineBytes, 'a') + "\"\n";
  EXPECT_EQ(ErrorOf([&] { ParseYamlText("seed: 1\n" + long_line, "s.yaml"); }),
            fmt::format("s.yaml: line 2: lines of at most {} bytes (no uascma key or value is longer), but it holds {}",
                        kMaxYamlLineBytes, long_line.size() - 1));
  std::string big;
  while (big.size() <= kMaxYamlBytes) big += "# a comment line of a big file\n";
  EXPECT_EQ(ErrorOf([&] { ParseYamlText(big, "s.yaml"); }),
            fmt::format("s.yaml: file: a YAML file of at most {} bytes, but it holds {}", kMaxYamlBytes, big.size()));
  EXPECT_EQ(ErrorOf([] { ParseYamlText("name: \"" + std::string(1000, 'a') + "\"\n", "s.yaml"); }), "");
}

TEST(OutputDirectoryMessagesTest, AFailedWriteInsideTheStagingFolderNamesTheUsersPath) {
  const std::filesystem::path root =
      std::filesystem::temp_directory_path() / ("uascma_input_text_test_" + std::to_string(::getpid()));
  std::filesystem::remove_all(root);
  std::filesystem::create_directories(root);
  const std::filesystem::path user = root / "results";
  // A child process with a file-size limit of 64 bytes stands for a full disk (EFBIG on the write, SIGXFSZ
  // ignored); it reports the message through a pipe.
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  const pid_t child = ::fork();
  if (child == 0) {
    ::close(fds[0]);
    std::string message = "no error";
    {
      OutputDirectory out("--out", user);  // its marker file is smaller than the limit
      ::signal(SIGXFSZ, SIG_IGN);
      const rlimit limit{64, 64};
      ::setrlimit(RLIMIT_FSIZE, &limit);
      try {
        WriteFileAtomically(out.staging() / "telemetry.csv", std::string(4096, 'x'));
      } catch (const InputError& e) {
        message = e.what();
      }
    }
    (void)!::write(fds[1], message.data(), message.size());
    ::close(fds[1]);
    ::_exit(0);
  }
  ::close(fds[1]);
  std::string message;
  char buffer[512];
  for (ssize_t n; (n = ::read(fds[0], buffer, sizeof buffer)) > 0;) message.append(buffer, static_cast<std::size_t>(n));
  ::close(fds[0]);
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_EQ(message.rfind((user / "telemetry.csv").string() + ": path: room to write the file", 0), 0u) << message;
  EXPECT_EQ(message.find(".tmp."), std::string::npos) << message;
  EXPECT_FALSE(std::filesystem::exists(user));  // nothing was committed
  std::filesystem::remove_all(root);
}

}  // namespace
}  // namespace uascma
