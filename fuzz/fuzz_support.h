#pragma once
// Shared by the libFuzzer harnesses of fuzz/. A harness feeds one input to one parser; the
// only outcome a parser may have on bad input is uascma::InputError (exit code 2 in the CLI). Any other
// exception escapes the harness, so libFuzzer reports it as a crash, like a sanitizer finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>

namespace uascma::fuzz {

inline std::string_view AsText(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// Parsers that take only a path read the input from this per-process scratch file (the name ends in
// `suffix`, which is how the map importers pick the format). Created under $TMPDIR, or /tmp.
inline std::filesystem::path WriteScratchFile(const std::uint8_t* data, std::size_t size, const char* suffix) {
  const char* folder = std::getenv("TMPDIR");
  const std::filesystem::path path = std::filesystem::path(folder != nullptr ? folder : "/tmp") /
                                     ("uascma-fuzz-" + std::to_string(::getpid()) + suffix);
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) std::abort();  // the harness itself is broken, not the parser
  if (size > 0 && std::fwrite(data, 1, size, file) != size) std::abort();
  std::fclose(file);
  return path;
}

}  // namespace uascma::fuzz
