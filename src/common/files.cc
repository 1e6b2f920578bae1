#include "uascma/common/files.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>

#include "uascma/common/error.h"

namespace uascma {

void WriteFileAtomically(const std::filesystem::path& path, std::string_view content) {
  namespace fs = std::filesystem;
  const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) {
    throw InputError(path.string(), "path", "the folder '" + folder.string() + "' does not exist");
  }
  // The temporary name is unique per process and call, so parallel writers never collide.
  static thread_local std::mt19937_64 name_stream{std::random_device{}()};
  const fs::path temporary =
      folder / (".tmp." + path.filename().string() + "." + std::to_string(::getpid()) + "." +
                std::to_string(name_stream() % 1000000007ULL));
  {
    std::FILE* file = std::fopen(temporary.c_str(), "wb");
    if (file == nullptr) {
      throw InputError(path.string(), "path", std::string("a writable file (") +
                                                   std::strerror(errno) + ")");
    }
    const bool written = std::fwrite(content.data(), 1, content.size(), file) == content.size();
    const bool flushed = std::fflush(file) == 0 && ::fsync(::fileno(file)) == 0;
    const bool closed = std::fclose(file) == 0;
    if (!written || !flushed || !closed) {
      const std::string reason = std::strerror(errno);
      fs::remove(temporary, ec);
      throw InputError(path.string(), "path", "room to write the file (" + reason + ")");
    }
  }
  fs::rename(temporary, path, ec);
  if (ec) {
    fs::remove(temporary, ec);
    throw InputError(path.string(), "path", "a path that can be replaced (" + ec.message() + ")");
  }
}

std::string ReadFile(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(path.string(), "path", "an existing regular file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "path", "a readable file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

}  // namespace uascma
