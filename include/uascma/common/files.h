#pragma once
// File helpers shared by every command: output is written whole or not at all.
#include <filesystem>
#include <string>
#include <string_view>

namespace uascma {

// Writes `content` to `path` through a temporary file in the same folder and an atomic rename,
// so a reader (or a crash) never sees half a file. Throws InputError naming the path on failure.
void WriteFileAtomically(const std::filesystem::path& path, std::string_view content);

// Reads a whole file; throws InputError naming the path when it cannot be read.
std::string ReadFile(const std::filesystem::path& path);

}  // namespace uascma
