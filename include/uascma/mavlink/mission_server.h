#pragma once
// The vehicle's side of the MAVLink mission protocol (mavlink.io "Mission Protocol"), for mission_type MISSION
// (0): upload (MISSION_COUNT → MISSION_REQUEST_INT n → MISSION_ITEM_INT n … → MISSION_ACK), download
// (MISSION_REQUEST_LIST → MISSION_COUNT → MISSION_REQUEST_INT/MISSION_REQUEST n → MISSION_ITEM_INT n … →
// MISSION_ACK), MISSION_CLEAR_ALL, MISSION_SET_CURRENT. A pure state machine: frames and the time in, replies out;
// the caller owns the link and the clock.
//
// Hostile or lossy links: an item with another sequence number than the one requested is not stored (counted,
// and the expected one requested again); a request that gets no item within the timeout is repeated, and after
// the retries the upload is cancelled (MISSION_ACK OPERATION_CANCELLED) and the stored mission kept as it was.
// The protocol's default timeout is 1500 ms and retries 5 (mavlink.io, Mission Protocol, "Timeouts and Retries").
#include <cstdint>
#include <optional>
#include <vector>

#include "uascma/mavlink/codec.h"

namespace uascma::mavlink {

// A message to send: its id's info and its payload.
struct Outgoing {
  MessageInfo info;
  Payload payload;
};
template <class M>
Outgoing MakeOutgoing(const M& message) {
  return Outgoing{MessageInfo{M::kId, M::kName, M::kCrcExtra, M::kMinLength, M::kMaxLength}, EncodePayload(message)};
}

struct MissionServerCounts {
  int uploads = 0, downloads = 0;
  int out_of_order_items = 0;  // items with another seq than requested: not stored
  int retries = 0;             // requests repeated after a timeout
  int cancelled = 0;           // uploads given up after the retries
  int ignored = 0;             // mission messages for another system or another mission type
};

class MissionServer {
 public:
  static constexpr double kTimeoutS = 1.5;  // s, the protocol's default (see above)
  static constexpr int kRetries = 5;

  explicit MissionServer(Address self) : self_(self) {}
  // Handles a mission message (other messages are ignored) received at wall time `now_s`; replies go to `out`.
  // Returns true when the stored mission changed (an upload completed, or a clear).
  bool Handle(const Frame& frame, double now_s, std::vector<Outgoing>& out);
  // Repeats a request whose item is overdue, or cancels the upload after the retries.
  void Tick(double now_s, std::vector<Outgoing>& out);

  const std::vector<MissionItemInt>& items() const { return items_; }
  std::uint16_t current() const { return current_; }
  void set_current(std::uint16_t seq) { current_ = seq; }
  bool uploading() const { return upload_.has_value(); }
  const MissionServerCounts& counts() const { return counts_; }

 private:
  struct Upload {
    Address partner;
    std::uint16_t count = 0;
    std::vector<MissionItemInt> received;
    double last_request_s = 0.0;
    int retries = 0;
  };
  bool ForUs(std::uint8_t target_system, std::uint8_t mission_type) const;
  void Request(double now_s, std::vector<Outgoing>& out);
  void Ack(Address partner, std::uint8_t result, std::vector<Outgoing>& out) const;
  bool OnItem(const Frame& frame, double now_s, std::vector<Outgoing>& out);
  void OnRequest(const Frame& frame, std::uint16_t seq, std::vector<Outgoing>& out);

  Address self_;
  std::vector<MissionItemInt> items_;
  std::uint16_t current_ = 0;
  std::optional<Upload> upload_;
  MissionServerCounts counts_;
};

}  // namespace uascma::mavlink
