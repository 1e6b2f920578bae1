#include "uascma/mavlink/mission_client.h"

namespace uascma::mavlink {
namespace {

enum class Retry { kWait, kSendAgain, kGiveUp };
// Whether a transfer's last message (sent at `last_s`) is due again at `now_s`: after the protocol's timeout, at most
// MissionServer::kRetries times (counted in `retries`); then the transfer ends (`active` false).
Retry RetryDue(bool& active, int& retries, double last_s, double now_s) {
  if (!active || now_s - last_s < MissionServer::kTimeoutS) return Retry::kWait;
  if (++retries > MissionServer::kRetries) {
    active = false;
    return Retry::kGiveUp;
  }
  return Retry::kSendAgain;
}

}  // namespace

void MissionUpload::Start(std::vector<MissionItemInt> items, Address vehicle, double now_s,
                          std::vector<Outgoing>& out) {
  items_ = std::move(items);
  vehicle_ = vehicle;
  retries_ = 0;
  active_ = true;
  SendCount(now_s, out);
}

TransferStatus MissionUpload::Handle(const Frame& frame, double now_s, std::vector<Outgoing>& out) {
  if (!active_ || frame.sender != vehicle_) return TransferStatus::kActive;
  std::optional<std::uint16_t> seq;
  if (frame.Is<MissionRequestInt>()) seq = frame.As<MissionRequestInt>().seq;
  if (frame.Is<MissionRequest>()) seq = frame.As<MissionRequest>().seq;
  if (seq && *seq < items_.size()) {
    out.push_back(MakeOutgoing(items_[*seq]));
    last_s_ = now_s;
  }
  if (!frame.Is<MissionAck>()) return TransferStatus::kActive;
  active_ = false;
  return frame.As<MissionAck>().type == kMavMissionAccepted ? TransferStatus::kDone : TransferStatus::kRefused;
}

TransferStatus MissionUpload::Tick(double now_s, std::vector<Outgoing>& out) {
  const Retry retry = RetryDue(active_, retries_, last_s_, now_s);
  if (retry == Retry::kSendAgain) SendCount(now_s, out);
  return retry == Retry::kGiveUp ? TransferStatus::kNoAnswer : TransferStatus::kActive;
}

void MissionUpload::SendCount(double now_s, std::vector<Outgoing>& out) {
  MissionCount count;
  count.target_system = vehicle_.system_id;
  count.target_component = vehicle_.component_id;
  count.count = static_cast<std::uint16_t>(items_.size());
  count.mission_type = static_cast<std::uint8_t>(kMavMissionTypeMission);
  out.push_back(MakeOutgoing(count));
  last_s_ = now_s;
}

void MissionDownload::Start(Address vehicle, double now_s, std::vector<Outgoing>& out) {
  vehicle_ = vehicle;
  count_.reset();
  items_.clear();
  retries_ = 0;
  active_ = true;
  Request(now_s, out);
}

std::optional<std::vector<MissionItemInt>> MissionDownload::Handle(const Frame& frame, double now_s,
                                                                   std::vector<Outgoing>& out) {
  if (!active_ || frame.sender != vehicle_) return std::nullopt;
  if (frame.Is<MissionCount>() && !count_) {
    const MissionCount count = frame.As<MissionCount>();
    if (count.mission_type != kMavMissionTypeMission) return std::nullopt;
    count_ = count.count;
  } else if (frame.Is<MissionItemInt>() && count_) {
    const MissionItemInt item = frame.As<MissionItemInt>();
    // An item other than the one asked for (a repeat, out of order) is not stored: the request is repeated.
    if (item.mission_type != kMavMissionTypeMission || item.seq != items_.size()) return std::nullopt;
    items_.push_back(item);
  } else {
    return std::nullopt;
  }
  retries_ = 0;
  if (items_.size() < *count_) {
    Request(now_s, out);
    return std::nullopt;
  }
  MissionAck ack;  // the vehicle's download ends at our MISSION_ACK
  ack.target_system = vehicle_.system_id;
  ack.target_component = vehicle_.component_id;
  ack.type = static_cast<std::uint8_t>(kMavMissionAccepted);
  ack.mission_type = static_cast<std::uint8_t>(kMavMissionTypeMission);
  out.push_back(MakeOutgoing(ack));
  active_ = false;
  return std::move(items_);
}

TransferStatus MissionDownload::Tick(double now_s, std::vector<Outgoing>& out) {
  const Retry retry = RetryDue(active_, retries_, last_s_, now_s);
  if (retry == Retry::kSendAgain) Request(now_s, out);
  return retry == Retry::kGiveUp ? TransferStatus::kNoAnswer : TransferStatus::kActive;
}

void MissionDownload::Request(double now_s, std::vector<Outgoing>& out) {
  last_s_ = now_s;
  if (!count_) {
    MissionRequestList list;
    list.target_system = vehicle_.system_id;
    list.target_component = vehicle_.component_id;
    list.mission_type = static_cast<std::uint8_t>(kMavMissionTypeMission);
    out.push_back(MakeOutgoing(list));
    return;
  }
  MissionRequestInt request;
  request.target_system = vehicle_.system_id;
  request.target_component = vehicle_.component_id;
  request.seq = static_cast<std::uint16_t>(items_.size());
  request.mission_type = static_cast<std::uint8_t>(kMavMissionTypeMission);
  out.push_back(MakeOutgoing(request));
}

}  // namespace uascma::mavlink
