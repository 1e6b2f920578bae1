// The MPI backend of distributed campaigns (Open MPI): the only file that includes <mpi.h>. It is its own library,
// uascma::campaign_mpi, linked by the MPI launcher uascma-mpi alone, so that `uascma` and every other program
// start without loading MPI (libmpi and its ~20 dependencies cost most of the tool's start-up).
#include <mpi.h>

#include <optional>
#include <string>

#include "../mpi_transport.h"
#include "uascma/campaign/mpi_session.h"

namespace uascma::campaign {
namespace {

void Init(int& rank, int& size) {
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
}

void Finalize() { MPI_Finalize(); }

void Abort(int code) { MPI_Abort(MPI_COMM_WORLD, code); }

void Broadcast(std::string& bytes, int root) {
  unsigned long long size = bytes.size();
  MPI_Bcast(&size, 1, MPI_UNSIGNED_LONG_LONG, root, MPI_COMM_WORLD);
  bytes.resize(size);
  if (size > 0) MPI_Bcast(bytes.data(), static_cast<int>(size), MPI_BYTE, root, MPI_COMM_WORLD);
}

void Send(const std::string& bytes, int destination, int tag) {
  MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, destination, tag, MPI_COMM_WORLD);
}

std::optional<std::string> TryReceive(int tag) {
  int waiting = 0;
  MPI_Status status;
  MPI_Iprobe(MPI_ANY_SOURCE, tag, MPI_COMM_WORLD, &waiting, &status);
  if (!waiting) return std::nullopt;
  int size = 0;
  MPI_Get_count(&status, MPI_BYTE, &size);
  std::string bytes(static_cast<std::size_t>(size), '\0');
  MPI_Recv(bytes.data(), size, MPI_BYTE, status.MPI_SOURCE, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return bytes;
}

constexpr mpi::Backend kOpenMpi{Init, Finalize, Abort, Broadcast, Send, TryReceive};

}  // namespace

void UseMpi() { mpi::RegisterBackend(&kOpenMpi); }

}  // namespace uascma::campaign
