#include "mpi_launcher.h"

#include <unistd.h>

#include <filesystem>
#include <system_error>

#include "uascma/campaign/mpi_session.h"

namespace uascma::cli {

void ContinueInMpiLauncher(char** argv) {
  if (!campaign::LaunchedUnderMpi() || campaign::BuiltWithMpi()) return;
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) return;
  const std::filesystem::path launcher = self.parent_path() / "uascma-mpi";
  if (!std::filesystem::is_regular_file(launcher, error)) return;
  ::execv(launcher.c_str(), argv);  // returns only when it failed: go on without MPI
}

}  // namespace uascma::cli
