#include "plotting.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "uascma/common/error.h"
#include "uascma/common/files.h"

extern char** environ;

namespace uascma::cli {
namespace {

constexpr const char* kPython = "/usr/bin/python3";

std::filesystem::path FindScript(const std::string& script) {
  std::vector<std::filesystem::path> candidates;
  if (const char* dir = std::getenv("UASCMA_PLOTS_DIR")) candidates.emplace_back(dir);
  candidates.emplace_back(UASCMA_SOURCE_PLOTS_DIR);
  candidates.emplace_back(UASCMA_INSTALLED_PLOTS_DIR);
  for (const auto& dir : candidates) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(dir / script, ec)) return dir / script;
  }
  throw InputError("plot", script,
                   "the plotting script in $UASCMA_PLOTS_DIR, " + std::string(UASCMA_SOURCE_PLOTS_DIR) + " or " +
                       UASCMA_INSTALLED_PLOTS_DIR);
}

}  // namespace

void RunPlotScript(const std::string& script, const std::vector<std::string>& arguments) {
  if (::access(kPython, X_OK) != 0) {
    throw InputError("plot", "python", "Debian's /usr/bin/python3 with matplotlib (make deps)");
  }
  const std::string path = FindScript(script).string();
  std::vector<std::string> argv_storage = {kPython, path};
  argv_storage.insert(argv_storage.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (auto& a : argv_storage) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (::posix_spawn(&pid, kPython, nullptr, nullptr, argv.data(), environ) != 0) {
    throw InputError("plot", script, "a runnable /usr/bin/python3");
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw InputError("plot", script, "the plotting script to succeed (see its message above)");
  }
}

void PlotJson(const std::string& script, const nlohmann::json& data, const std::string& target) {
  static int counter = 0;
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("uascma_plot_" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + ".json");
  WriteFileAtomically(path, data.dump());
  std::error_code ec;
  try {
    RunPlotScript(script, {path.string(), target});
  } catch (...) {
    std::filesystem::remove(path, ec);
    throw;
  }
  std::filesystem::remove(path, ec);
}

void PlotJsonWhole(const std::string& script, const nlohmann::json& data, const std::string& target) {
  const std::filesystem::path final_path(target);
  const std::filesystem::path staging =
      final_path.parent_path() / (".uascma-plot-" + std::to_string(::getpid()) + "-" + final_path.filename().string());
  try {
    PlotJson(script, data, staging.string());
    std::filesystem::rename(staging, final_path);
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(staging, ec);
    throw;
  }
}

}  // namespace uascma::cli
