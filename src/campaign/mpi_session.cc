#include "uascma/campaign/mpi_session.h"

#include <cstdio>
#include <cstdlib>
#include <string>

#include "mpi_transport.h"
#include "uascma/common/error.h"

#ifdef UASCMA_HAVE_MPI
#include <mpi.h>
#endif

namespace uascma::campaign {
namespace {

int EnvironmentInteger(const char* name, int fallback) {
  const char* value = std::getenv(name);
  if (value == nullptr) return fallback;
  char* end = nullptr;
  const long parsed = std::strtol(value, &end, 10);
  return end != value && parsed > 0 ? static_cast<int>(parsed) : fallback;
}

}  // namespace

bool BuiltWithMpi() {
#ifdef UASCMA_HAVE_MPI
  return true;
#else
  return false;
#endif
}

bool LaunchedUnderMpi() {
  return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMI_SIZE") != nullptr ||
         std::getenv("PMIX_RANK") != nullptr;
}

MpiSession::MpiSession(bool enable) {
  if (!enable) return;
#ifdef UASCMA_HAVE_MPI
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  active_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  local_size_ = EnvironmentInteger("OMPI_COMM_WORLD_LOCAL_SIZE", 1);
#else
  const int size = EnvironmentInteger("OMPI_COMM_WORLD_SIZE", EnvironmentInteger("PMI_SIZE", 1));
  if (size > 1) {
    throw InputError("mpirun", "uascma", "a build with MPI (CMake option UASCMA_WITH_MPI=ON); this one has none");
  }
#endif
}

MpiSession::~MpiSession() {
#ifdef UASCMA_HAVE_MPI
  if (active_) MPI_Finalize();
#endif
}

void MpiSession::Abort(const std::string& message, int code) const {
  std::fprintf(stderr, "uascma: rank %d: %s\n", rank_, message.c_str());
  std::fflush(stderr);
#ifdef UASCMA_HAVE_MPI
  if (active_) MPI_Abort(MPI_COMM_WORLD, code);
#endif
  std::exit(code);
}

namespace mpi {

#ifdef UASCMA_HAVE_MPI

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

#else

void Broadcast(std::string&, int) { UASCMA_CHECK(false, "MPI is not part of this build"); }
void Send(const std::string&, int, int) { UASCMA_CHECK(false, "MPI is not part of this build"); }
std::optional<std::string> TryReceive(int) {
  UASCMA_CHECK(false, "MPI is not part of this build");
  return std::nullopt;
}

#endif

}  // namespace mpi
}  // namespace uascma::campaign
