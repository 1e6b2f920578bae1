#pragma once
// The MPI launcher: `uascma` links no MPI, so that every command starts without loading
// libmpi; uascma-mpi is the same tool with MPI (uascma::campaign_mpi), built when UASCMA_WITH_MPI is ON.

namespace uascma::cli {

// When an MPI launcher (mpirun) started this process and it has no MPI, replaces it with uascma-mpi from
// the same folder, same arguments and environment (execv keeps the process, so the launcher sees no change).
// Returns otherwise, and when there is no uascma-mpi beside it: a campaign on more than one rank then stops
// with the InputError of a build without MPI (MpiSession).
void ContinueInMpiLauncher(char** argv);

}  // namespace uascma::cli
