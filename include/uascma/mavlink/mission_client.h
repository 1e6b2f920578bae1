#pragma once
// The ground station's (or companion's) side of the MAVLink mission protocol (mavlink.io "Mission Protocol"), for
// mission_type MISSION: an upload (MISSION_COUNT, each MISSION_ITEM_INT the vehicle requests, its MISSION_ACK) and a
// download (MISSION_REQUEST_LIST → MISSION_COUNT, MISSION_REQUEST_INT n → MISSION_ITEM_INT n …, MISSION_ACK). Pure
// state machines, as MissionServer: frames and the wall time in, messages out; the caller owns the link. A message not
// answered within the protocol's timeout (MissionServer::kTimeoutS) is sent again, at most MissionServer::kRetries
// times; then the transfer fails.
#include <optional>
#include <vector>

#include "uascma/mavlink/mission_server.h"

namespace uascma::mavlink {

// How a transfer ended.
enum class TransferStatus { kActive, kDone, kRefused, kNoAnswer };

class MissionUpload {
 public:
  void Start(std::vector<MissionItemInt> items, Address vehicle, double now_s, std::vector<Outgoing>& out);
  // A frame from the link: a request is answered with its item; the MISSION_ACK ends the upload (kDone when
  // accepted, kRefused with any other type). kActive while it goes on or for frames of no concern.
  TransferStatus Handle(const Frame& frame, double now_s, std::vector<Outgoing>& out);
  // The count again after the timeout; kNoAnswer once the retries are spent.
  TransferStatus Tick(double now_s, std::vector<Outgoing>& out);
  bool active() const { return active_; }

 private:
  void SendCount(double now_s, std::vector<Outgoing>& out);
  std::vector<MissionItemInt> items_;
  Address vehicle_;
  double last_s_ = 0.0;
  int retries_ = 0;
  bool active_ = false;
};

class MissionDownload {
 public:
  void Start(Address vehicle, double now_s, std::vector<Outgoing>& out);
  // The items once the last one came (the download acknowledged to the vehicle), nothing before.
  std::optional<std::vector<MissionItemInt>> Handle(const Frame& frame, double now_s, std::vector<Outgoing>& out);
  // The last request again after the timeout; kNoAnswer once the retries are spent.
  TransferStatus Tick(double now_s, std::vector<Outgoing>& out);
  bool active() const { return active_; }

 private:
  void Request(double now_s, std::vector<Outgoing>& out);
  Address vehicle_;
  std::optional<std::uint16_t> count_;  // from MISSION_COUNT
  std::vector<MissionItemInt> items_;
  double last_s_ = 0.0;
  int retries_ = 0;
  bool active_ = false;
};

}  // namespace uascma::mavlink
