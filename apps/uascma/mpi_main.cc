// uascma-mpi: the command-line tool with MPI, what mpirun runs for campaigns across ranks (`uascma` started by
// mpirun hands over to it, mpi_launcher.h). The same objects as `uascma` (main.cc and every command) plus the MPI
// backend, enabled here before main() runs: every MpiSession of this program then initialises MPI.
#include "uascma/campaign/mpi_session.h"

namespace {

[[maybe_unused]] const bool kMpiEnabled = (uascma::campaign::UseMpi(), true);

}  // namespace
