#include "uascma/campaign/mpi_session.h"

#include <cstdio>
#include <cstdlib>
#include <string>

#include "mpi_transport.h"
#include "uascma/common/error.h"

namespace uascma::campaign {
namespace {

// The process's MPI (mpi_transport.h): none unless the program called UseMpi() (uascma-mpi does).
constinit const mpi::Backend* backend = nullptr;

int EnvironmentInteger(const char* name, int fallback) {
  const char* value = std::getenv(name);
  if (value == nullptr) return fallback;
  char* end = nullptr;
  const long parsed = std::strtol(value, &end, 10);
  return end != value && parsed > 0 ? static_cast<int>(parsed) : fallback;
}

}  // namespace

bool BuiltWithMpi() { return backend != nullptr; }

bool LaunchedUnderMpi() {
  return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMI_SIZE") != nullptr ||
         std::getenv("PMIX_RANK") != nullptr;
}

MpiSession::MpiSession(bool enable) {
  if (!enable) return;
  if (backend != nullptr) {
    backend->init(rank_, size_);
    active_ = true;
    local_size_ = EnvironmentInteger("OMPI_COMM_WORLD_LOCAL_SIZE", 1);
    return;
  }
  const int size = EnvironmentInteger("OMPI_COMM_WORLD_SIZE", EnvironmentInteger("PMI_SIZE", 1));
  if (size > 1) {
    throw InputError("mpirun", "uascma", "a build with MPI (CMake option UASCMA_WITH_MPI=ON); this one has none");
  }
}

MpiSession::~MpiSession() {
  if (active_) backend->finalize();
}

void MpiSession::Abort(const std::string& message, int code) const {
  std::fprintf(stderr, "uascma: rank %d: %s\n", rank_, message.c_str());
  std::fflush(stderr);
  if (active_) backend->abort(code);
  std::exit(code);
}

namespace mpi {

void RegisterBackend(const Backend* registered) { backend = registered; }

void Broadcast(std::string& bytes, int root) {
  UASCMA_CHECK(backend != nullptr, "MPI is not part of this program");
  backend->broadcast(bytes, root);
}

void Send(const std::string& bytes, int destination, int tag) {
  UASCMA_CHECK(backend != nullptr, "MPI is not part of this program");
  backend->send(bytes, destination, tag);
}

std::optional<std::string> TryReceive(int tag) {
  UASCMA_CHECK(backend != nullptr, "MPI is not part of this program");
  return backend->try_receive(tag);
}

}  // namespace mpi
}  // namespace uascma::campaign
