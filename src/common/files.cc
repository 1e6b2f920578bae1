#include "uascma/common/files.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>

#include <map>
#include <mutex>

#include "uascma/common/error.h"
#include "uascma/common/text.h"

namespace uascma {
namespace {

// The staging folders of the OutputDirectory objects alive in this process, each with the user's path it
// stands for: an error writing a file into one names the user's path, never the hidden
// staging folder the user did not ask for.
std::mutex& StagingMutex() {
  static std::mutex mutex;
  return mutex;
}
std::map<std::filesystem::path, std::filesystem::path>& StagingFolders() {
  static std::map<std::filesystem::path, std::filesystem::path> folders;
  return folders;
}

// `path` as the user knows it: inside a live staging folder, the same name under the user's folder.
std::string ShownPath(const std::filesystem::path& path) {
  const std::lock_guard lock(StagingMutex());
  for (std::filesystem::path folder = path; !folder.empty(); folder = folder.parent_path()) {
    const auto it = StagingFolders().find(folder);
    if (it != StagingFolders().end()) {
      return folder == path ? it->second.string() : (it->second / path.lexically_relative(folder)).string();
    }
    if (folder == folder.root_path() || folder.parent_path() == folder) break;
  }
  return path.string();
}

}  // namespace

std::filesystem::path ContainingFolder(const std::filesystem::path& file) {
  return file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
}

void WriteFileAtomically(const std::filesystem::path& path, std::string_view content) {
  namespace fs = std::filesystem;
  const fs::path folder = ContainingFolder(path);
  const std::string shown = ShownPath(path);
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) {
    throw InputError(shown, "path", "the folder '" + ShownPath(folder) + "' does not exist");
  }
  // The temporary name is unique per process and call, so parallel writers never collide.
  static thread_local std::mt19937_64 name_stream{std::random_device{}()};
  const fs::path temporary = folder / (".tmp." + path.filename().string() + "." + std::to_string(::getpid()) + "." +
                                       std::to_string(name_stream() % 1000000007ULL));
  {
    std::FILE* file = std::fopen(temporary.c_str(), "wb");
    if (file == nullptr) {
      throw InputError(shown, "path", std::string("a writable file (") + std::strerror(errno) + ")");
    }
    const bool written = std::fwrite(content.data(), 1, content.size(), file) == content.size();
    const bool flushed = std::fflush(file) == 0 && ::fsync(::fileno(file)) == 0;
    const bool closed = std::fclose(file) == 0;
    if (!written || !flushed || !closed) {
      const std::string reason = std::strerror(errno);
      fs::remove(temporary, ec);
      throw InputError(shown, "path", "room to write the file (" + reason + ")");
    }
  }
  fs::rename(temporary, path, ec);
  if (ec) {
    fs::remove(temporary, ec);
    throw InputError(shown, "path", "a path that can be replaced (" + ec.message() + ")");
  }
}

namespace {

std::string UniqueSuffix() {
  static thread_local std::mt19937_64 name_stream{std::random_device{}()};
  return std::to_string(::getpid()) + "." + std::to_string(name_stream() % 1000000007ULL);
}

}  // namespace

OutputDirectory::OutputDirectory(std::string option, std::filesystem::path user_path)
    : option_(std::move(option)), user_path_(std::move(user_path)) {
  namespace fs = std::filesystem;
  const std::string shown = user_path_.string();
  if (shown.empty()) throw InputError(option_, "path", "a folder name");
  // The folder's name reaches the files written into it (summaries, plots): UTF-8 or refused here.
  RequireUtf8(shown, option_, "folder name");
  std::error_code ec;
  // The folder itself, symbolic links resolved and a trailing "/" dropped, so that the staging folder is
  // its sibling on the same filesystem.
  fs::path target = fs::weakly_canonical(fs::absolute(user_path_, ec), ec);
  if (ec) throw InputError(option_, shown, "a usable folder path (" + ec.message() + ")");
  if (!target.has_filename()) target = target.parent_path();
  if (!target.has_filename() || target == target.root_path()) {
    throw InputError(option_, shown, "a folder other than the root of the filesystem");
  }
  const fs::file_status status = fs::status(target, ec);
  if (fs::exists(status)) {
    if (!fs::is_directory(status)) throw InputError(option_, shown, "a folder (it is an existing file)");
    const bool empty = fs::is_empty(target, ec);
    if (ec) throw InputError(option_, shown, "a readable folder (" + ec.message() + ")");
    if (!empty && !fs::exists(target / kOutputMarker, ec)) {
      throw InputError(option_, shown,
                       "a new or empty folder, or one an earlier uascma run wrote (it holds other files: nothing "
                       "was changed)");
    }
  }
  fs::create_directories(target.parent_path(), ec);
  if (ec) throw InputError(option_, shown, "a folder whose parent can be created (" + ec.message() + ")");
  staging_ = target.parent_path() / (".tmp." + target.filename().string() + "." + UniqueSuffix());
  if (!fs::create_directory(staging_, ec) || ec) {
    const std::string reason = ec ? ec.message() : "the name is taken";
    staging_.clear();
    throw InputError(option_, shown, "a folder it can write in (" + reason + ")");
  }
  try {
    WriteFileAtomically(staging_ / kOutputMarker,
                        "This folder was written by uascma and is replaced whole by its next run.\n");
  } catch (const InputError&) {
    fs::remove_all(staging_, ec);
    staging_.clear();
    throw InputError(option_, shown, "a folder it can write in");
  }
  target_ = target;
  const std::lock_guard lock(StagingMutex());
  StagingFolders()[staging_] = user_path_;
}

OutputDirectory::~OutputDirectory() {
  if (!staging_.empty()) {
    const std::lock_guard lock(StagingMutex());
    StagingFolders().erase(staging_);
  }
  if (!committed_ && !staging_.empty()) {
    std::error_code ec;
    std::filesystem::remove_all(staging_, ec);
  }
}

void OutputDirectory::Commit() {
  namespace fs = std::filesystem;
  UASCMA_CHECK(!committed_, "OutputDirectory committed twice");
  const std::string shown = user_path_.string();
  std::error_code ec;
  if (!fs::exists(target_, ec)) {
    fs::rename(staging_, target_, ec);
    if (ec) throw InputError(option_, shown, "a folder it can create (" + ec.message() + ")");
  } else if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) == 0) {
    // One atomic swap: the staging name now holds the previous run's files.
    fs::remove_all(staging_, ec);
  } else {
    // A filesystem without RENAME_EXCHANGE: move the old folder aside, then the new one in (two renames;
    // a crash in between leaves the old files under a hidden sibling name, never a mix).
    const fs::path old = target_.parent_path() / (".old." + target_.filename().string() + "." + UniqueSuffix());
    fs::rename(target_, old, ec);
    if (ec) throw InputError(option_, shown, "a folder it can replace (" + ec.message() + ")");
    fs::rename(staging_, target_, ec);
    if (ec) {
      std::error_code ignored;
      fs::rename(old, target_, ignored);
      throw InputError(option_, shown, "a folder it can replace (" + ec.message() + ")");
    }
    fs::remove_all(old, ec);
  }
  committed_ = true;
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
