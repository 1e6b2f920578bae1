#include "output.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/files.h"

namespace uascma::cli {

void PrintJson(const nlohmann::json& document) {
  // Strings from a file (a campaign name in a damaged results store) may hold invalid UTF-8: replace it
  // (U+FFFD) rather than throw json type_error 316 (found by results_store_fuzzer).
  const std::string text = document.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
  std::fwrite(text.data(), 1, text.size(), stdout);
  std::fputc('\n', stdout);
}

void WriteOutput(const std::string& path, const std::string& content) {
  if (path.empty() || path == "-") {
    std::fwrite(content.data(), 1, content.size(), stdout);
    return;
  }
  WriteFileAtomically(path, content);
}

void CheckOutputFile(const std::string& path, const char* option) {
  if (path.empty()) return;
  const std::filesystem::path file(path);
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) throw InputError(option, path, "a file path, got a folder");
  const std::filesystem::path folder = ContainingFolder(file);
  if (!std::filesystem::is_directory(folder, ec)) {
    throw InputError(option, path,
                     fmt::format("a file in an existing folder, but '{}' does not exist", folder.string()));
  }
  if (::access(folder.c_str(), W_OK) != 0) {
    throw InputError(option, path,
                     fmt::format("a file in a writable folder, but '{}' is not writable", folder.string()));
  }
}

}  // namespace uascma::cli
