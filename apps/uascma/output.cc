#include "output.h"

#include <cstdio>

#include "uascma/common/files.h"

namespace uascma::cli {

void PrintJson(const nlohmann::json& document) {
  const std::string text = document.dump(2);
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
