#pragma once
// File helpers shared by every command: output is written whole or not at all.
#include <filesystem>
#include <string>
#include <string_view>

namespace uascma {

// Writes `content` to `path` through a temporary file in the same folder and an atomic rename,
// so a reader (or a crash) never sees half a file. Throws InputError naming the path on failure.
void WriteFileAtomically(const std::filesystem::path& path, std::string_view content);

// The folder `file` is in: its parent path, or "." for a bare file name.
std::filesystem::path ContainingFolder(const std::filesystem::path& file);

// Reads a whole file; throws InputError naming the path when it cannot be read.
std::string ReadFile(const std::filesystem::path& path);

// An output folder written whole or not at all: after a command with `--out DIR`, DIR holds
// exactly this run's files, never a mix with an earlier run's.
//
//   OutputDirectory out("--out", user_path);   // checks the rule below, makes a fresh staging folder
//   WriteFileAtomically(out.staging() / "telemetry.csv", …);   // fill it
//   out.Commit();                               // swaps it in atomically
//
// The staging folder is a hidden sibling of DIR (same filesystem, so the swap is one rename(2), or
// renameat2(RENAME_EXCHANGE) when DIR exists). Without Commit (an exception) the destructor removes it
// and DIR is untouched. The staging folder and so DIR after Commit carry a marker file, kOutputMarker.
//
// The rule for an existing DIR: it is replaced when it is empty or carries the marker (uascma made it);
// any other folder, or a file, is refused with InputError so that `--out ~/Documents` never wipes a folder
// of the user's. Missing parent folders are created. Every error names `user_path` as the user typed it,
// never the staging folder.
inline constexpr const char* kOutputMarker = ".uascma-output";

class OutputDirectory {
 public:
  // `option` names the source in errors ("--out", "--plots").
  OutputDirectory(std::string option, std::filesystem::path user_path);
  OutputDirectory(const OutputDirectory&) = delete;
  OutputDirectory& operator=(const OutputDirectory&) = delete;
  ~OutputDirectory();

  // Where to write this run's files until Commit.
  const std::filesystem::path& staging() const { return staging_; }
  const std::filesystem::path& path() const { return user_path_; }
  // Replaces DIR by the staging folder atomically, then removes the previous contents.
  void Commit();

 private:
  std::string option_;
  std::filesystem::path user_path_;
  std::filesystem::path target_;  // the folder itself: absolute, links resolved
  std::filesystem::path staging_;
  bool committed_ = false;
};

}  // namespace uascma
