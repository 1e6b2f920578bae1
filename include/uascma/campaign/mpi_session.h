#pragma once
// MPI for distributed campaigns (Open MPI, scripts/install-deps.sh), optional at build time
// (CMake option UASCMA_WITH_MPI) and at run time: `uascma campaign` never needs MPI unless it was
// launched by mpirun/mpiexec, which LaunchedUnderMpi() detects from the launcher's environment
// (OMPI_COMM_WORLD_SIZE for Open MPI; PMI_SIZE / PMIX_RANK for other launchers).
// MPI itself lives in the library uascma::campaign_mpi (src/campaign/mpi/), which a program links and
// enables with UseMpi() before its first session; the MPI launcher uascma-mpi does, and `uascma` hands
// over to it when started by mpirun, so that the plain tool never loads libmpi.
//
// The session is owned by the program (the CLI command): MPI can be initialised and finalised once per
// process. Only the thread that created the session calls MPI (MPI_THREAD_FUNNELED).
#include <string>

#include "uascma/common/error.h"

namespace uascma::campaign {

// True when this program has MPI (UseMpi() was called).
bool BuiltWithMpi();
// Gives this program MPI: later sessions call MPI_Init_thread. Defined in uascma::campaign_mpi only.
void UseMpi();
// True when the environment says an MPI launcher started this process.
bool LaunchedUnderMpi();

// The input error rank 0 found and sent to every rank with the campaign's plan (runner.cc): rank 0 reports it, so
// the other ranks leave without a word and with exit code 0 (campaign_command.cc says why).
class RankZeroInputError : public InputError {
 public:
  using InputError::InputError;
};

class MpiSession {
 public:
  // Initialises MPI when `enable` (normally LaunchedUnderMpi()); InputError when enabled in a build
  // without MPI and the launcher started more than one process. Inactive otherwise (rank 0 of 1).
  explicit MpiSession(bool enable);
  ~MpiSession();  // MPI_Finalize when active
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  bool active() const { return active_; }
  int rank() const { return rank_; }
  int size() const { return size_; }
  // Ranks sharing this node (for the default number of threads per rank).
  int local_size() const { return local_size_; }
  // Ends every rank at once (MPI_Abort) after printing `message` on this rank's stderr.
  [[noreturn]] void Abort(const std::string& message, int code = 1) const;

 private:
  bool active_ = false;
  int rank_ = 0;
  int size_ = 1;
  int local_size_ = 1;
};

}  // namespace uascma::campaign
