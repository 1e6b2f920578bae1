#include "output.h"

#include <cstdio>

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

}  // namespace uascma::cli
