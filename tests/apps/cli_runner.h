#pragma once
// Runs the built `uascma` binary in a shell and captures exit code, stdout and stderr. Shared by the
// command tests of every module.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace uascma::testing_support {

struct RunResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

inline std::string Slurp(const std::filesystem::path& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A fresh folder under the system temp folder, removed at the end of the test.
struct ScratchDir {
  explicit ScratchDir(const std::string& name)
      : path(std::filesystem::temp_directory_path() / ("uascma_test_" + name + "_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~ScratchDir() { std::filesystem::remove_all(path); }
  std::filesystem::path path;
};

// `arguments` is passed through the shell after the binary path.
inline RunResult RunCli(const std::string& arguments) {
  static int counter = 0;
  const auto base = std::filesystem::temp_directory_path() /
                    ("uascma_run_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  const std::string command =
      std::string(UASCMA_CLI_PATH) + " " + arguments + " >" + base.string() + ".out 2>" + base.string() + ".err";
  const int status = std::system(command.c_str());
  RunResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.out = Slurp(base.string() + ".out");
  result.err = Slurp(base.string() + ".err");
  std::filesystem::remove(base.string() + ".out");
  std::filesystem::remove(base.string() + ".err");
  return result;
}

inline int LineCount(const std::string& text) { return static_cast<int>(std::count(text.begin(), text.end(), '\n')); }

// Bad input: exit code 2, one line on stderr naming `option`, nothing on stdout.
inline void ExpectBadInput(const RunResult& result, const std::string& option) {
  EXPECT_EQ(result.exit_code, 2) << result.err;
  EXPECT_EQ(LineCount(result.err), 1) << result.err;
  EXPECT_NE(result.err.find(option), std::string::npos) << result.err;
  EXPECT_TRUE(result.out.empty()) << result.out;
}

}  // namespace uascma::testing_support
