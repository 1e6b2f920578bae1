#pragma once
// Byte messages between the ranks of an active MpiSession (private to src/campaign). Only the thread that
// created the session calls these. In a build without MPI they are never reached (an MpiSession cannot
// be active there) and abort if they are.
#include <optional>
#include <string>

namespace uascma::campaign::mpi {

inline constexpr int kTagRecords = 11;

// `bytes` of rank `root` arrive in `bytes` on every rank.
void Broadcast(std::string& bytes, int root);
void Send(const std::string& bytes, int destination, int tag);
// A message with `tag` from any rank if one is waiting; nothing otherwise (never blocks).
std::optional<std::string> TryReceive(int tag);

}  // namespace uascma::campaign::mpi
