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
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "uascma/mavlink/codec.h"
#include "uascma/planning/mission_file.h"

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

// A MISSION_ITEM_INT as the mission reader takes it (x, y · 1e-7 degrees; z metres), and back for `target` at `seq`
// (latitude and longitude rounded to 1e-7 degrees, about a centimetre).
planning::MissionItem ToMissionItem(const MissionItemInt& item);
MissionItemInt ToMissionItemInt(const planning::MissionItem& item, Address target, std::uint16_t seq);

struct MissionServerCounts {
  int uploads = 0, downloads = 0;
  int out_of_order_items = 0;  // items with another seq than requested: not stored
  int retries = 0;             // requests repeated after a timeout
  int cancelled = 0;           // uploads given up after the retries
  int refused = 0;             // complete uploads the vehicle cannot fly (MissionServer::set_check)
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

  // A check of a completed upload before it is stored: the reason the mission cannot be flown, or nothing. A refused
  // upload is answered MISSION_ACK MAV_MISSION_INVALID, the stored mission kept, and the reason kept for
  // TakeRefusal. Without a check every complete upload is stored.
  using Check = std::function<std::optional<std::string>(const std::vector<MissionItemInt>&)>;
  void set_check(Check check) { check_ = std::move(check); }
  // The reason of the last refused upload, once.
  std::optional<std::string> TakeRefusal() { return std::exchange(refusal_, std::nullopt); }
  // Holds `items` as the stored mission (the vehicle's own plan, for a ground station to download).
  void Load(std::vector<MissionItemInt> items) {
    items_ = std::move(items);
    current_ = 0;
  }

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
  Check check_;
  std::optional<std::string> refusal_;
};

}  // namespace uascma::mavlink
