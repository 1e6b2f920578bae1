#pragma once
// Byte messages between the ranks of an active MpiSession (private to src/campaign). Only the thread that
// created the session calls these. They go through the MPI backend of the process (uascma::campaign::UseMpi,
// linked only into the MPI launcher uascma-mpi); without one they are never reached (an
// MpiSession cannot be active there) and abort if they are.
#include <optional>
#include <string>

namespace uascma::campaign::mpi {

inline constexpr int kTagRecords = 11;

// `bytes` of rank `root` arrive in `bytes` on every rank.
void Broadcast(std::string& bytes, int root);
void Send(const std::string& bytes, int destination, int tag);
// A message with `tag` from any rank if one is waiting; nothing otherwise (never blocks).
std::optional<std::string> TryReceive(int tag);

// The MPI calls of a session, supplied by src/campaign/mpi/ (the only code that includes <mpi.h>), so that
// the library, and every program that does not distribute campaigns, links no MPI.
struct Backend {
  void (*init)(int& rank, int& size);  // MPI_Init_thread (MPI_THREAD_FUNNELED), then rank and size of the world
  void (*finalize)();
  void (*abort)(int code);
  void (*broadcast)(std::string& bytes, int root);
  void (*send)(const std::string& bytes, int destination, int tag);
  std::optional<std::string> (*try_receive)(int tag);
};
// Makes `backend` (static storage) the process's MPI; called by UseMpi().
void RegisterBackend(const Backend* backend);

}  // namespace uascma::campaign::mpi
