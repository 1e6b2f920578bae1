#include "uascma/mavlink/mission_server.h"

#include <cmath>

namespace uascma::mavlink {

planning::MissionItem ToMissionItem(const MissionItemInt& item) {
  return {item.command,
          item.frame,
          {item.param1, item.param2, item.param3, item.param4, item.x * 1e-7, item.y * 1e-7, item.z}};
}

MissionItemInt ToMissionItemInt(const planning::MissionItem& item, Address target, std::uint16_t seq) {
  MissionItemInt out;
  out.target_system = target.system_id;
  out.target_component = target.component_id;
  out.seq = seq;
  out.frame = static_cast<std::uint8_t>(item.frame);
  out.command = static_cast<std::uint16_t>(item.command);
  out.current = seq == 0 ? 1 : 0;
  out.autocontinue = 1;
  out.param1 = static_cast<float>(item.params[0]);
  out.param2 = static_cast<float>(item.params[1]);
  out.param3 = static_cast<float>(item.params[2]);
  out.param4 = static_cast<float>(item.params[3]);
  const auto degrees_e7 = [](double degrees) {
    return std::isfinite(degrees) ? static_cast<std::int32_t>(std::llround(degrees * 1e7)) : 0;
  };
  out.x = degrees_e7(item.params[4]);
  out.y = degrees_e7(item.params[5]);
  out.z = static_cast<float>(item.params[6]);
  out.mission_type = static_cast<std::uint8_t>(kMavMissionTypeMission);
  return out;
}

bool MissionServer::ForUs(std::uint8_t target_system, std::uint8_t mission_type) const {
  return (target_system == self_.system_id || target_system == 0) && mission_type == kMavMissionTypeMission;
}

void MissionServer::Ack(Address partner, std::uint8_t result, std::vector<Outgoing>& out) const {
  MissionAck ack;
  ack.target_system = partner.system_id;
  ack.target_component = partner.component_id;
  ack.type = result;
  ack.mission_type = static_cast<std::uint8_t>(kMavMissionTypeMission);
  out.push_back(MakeOutgoing(ack));
}

void MissionServer::Request(double now_s, std::vector<Outgoing>& out) {
  MissionRequestInt request;
  request.target_system = upload_->partner.system_id;
  request.target_component = upload_->partner.component_id;
  request.seq = static_cast<std::uint16_t>(upload_->received.size());
  request.mission_type = static_cast<std::uint8_t>(kMavMissionTypeMission);
  upload_->last_request_s = now_s;
  out.push_back(MakeOutgoing(request));
}

bool MissionServer::OnItem(const Frame& frame, double now_s, std::vector<Outgoing>& out) {
  const MissionItemInt item = frame.As<MissionItemInt>();
  if (!ForUs(item.target_system, item.mission_type)) {
    ++counts_.ignored;
    return false;
  }
  if (!upload_ || frame.sender != upload_->partner) {
    ++counts_.ignored;
    return false;
  }
  if (item.seq != upload_->received.size()) {  // a repeat or an item out of order: ask again for the expected one
    ++counts_.out_of_order_items;
    Request(now_s, out);
    return false;
  }
  upload_->received.push_back(item);
  upload_->retries = 0;
  if (upload_->received.size() < upload_->count) {
    Request(now_s, out);
    return false;
  }
  if (check_) {
    if (std::optional<std::string> why = check_(upload_->received)) {
      Ack(upload_->partner, static_cast<std::uint8_t>(kMavMissionInvalid), out);
      upload_.reset();
      refusal_ = std::move(why);
      ++counts_.refused;
      return false;
    }
  }
  items_ = std::move(upload_->received);
  current_ = 0;
  Ack(upload_->partner, static_cast<std::uint8_t>(kMavMissionAccepted), out);
  upload_.reset();
  ++counts_.uploads;
  return true;
}

void MissionServer::OnRequest(const Frame& frame, std::uint16_t seq, std::vector<Outgoing>& out) {
  if (seq >= items_.size()) {
    Ack(frame.sender, static_cast<std::uint8_t>(kMavMissionInvalidSequence), out);
    return;
  }
  MissionItemInt item = items_[seq];
  item.target_system = frame.sender.system_id;
  item.target_component = frame.sender.component_id;
  item.current = seq == current_ ? 1 : 0;
  out.push_back(MakeOutgoing(item));
}

bool MissionServer::Handle(const Frame& frame, double now_s, std::vector<Outgoing>& out) {
  if (frame.Is<MissionCount>()) {
    const MissionCount count = frame.As<MissionCount>();
    if (!ForUs(count.target_system, count.mission_type)) return ++counts_.ignored, false;
    if (count.count == 0) {  // an empty upload clears the mission
      items_.clear();
      current_ = 0;
      Ack(frame.sender, static_cast<std::uint8_t>(kMavMissionAccepted), out);
      return true;
    }
    upload_ = Upload{frame.sender, count.count, {}, now_s, 0};
    Request(now_s, out);
    return false;
  }
  if (frame.Is<MissionItemInt>()) return OnItem(frame, now_s, out);
  if (frame.Is<MissionRequestList>()) {
    const MissionRequestList list = frame.As<MissionRequestList>();
    if (!ForUs(list.target_system, list.mission_type)) return ++counts_.ignored, false;
    MissionCount count;
    count.target_system = frame.sender.system_id;
    count.target_component = frame.sender.component_id;
    count.count = static_cast<std::uint16_t>(items_.size());
    count.mission_type = static_cast<std::uint8_t>(kMavMissionTypeMission);
    out.push_back(MakeOutgoing(count));
    ++counts_.downloads;
    return false;
  }
  if (frame.Is<MissionRequestInt>() || frame.Is<MissionRequest>()) {
    // MISSION_REQUEST (deprecated) is answered with MISSION_ITEM_INT too, as the protocol recommends.
    const auto request = frame.Is<MissionRequestInt>() ? frame.As<MissionRequestInt>() : [&] {
      const MissionRequest old = frame.As<MissionRequest>();
      return MissionRequestInt{old.target_system, old.target_component, old.seq, old.mission_type};
    }();
    if (!ForUs(request.target_system, request.mission_type)) return ++counts_.ignored, false;
    OnRequest(frame, request.seq, out);
    return false;
  }
  if (frame.Is<MissionClearAll>()) {
    const MissionClearAll clear = frame.As<MissionClearAll>();
    if (!ForUs(clear.target_system, clear.mission_type)) return ++counts_.ignored, false;
    items_.clear();
    current_ = 0;
    upload_.reset();
    Ack(frame.sender, static_cast<std::uint8_t>(kMavMissionAccepted), out);
    return true;
  }
  if (frame.Is<MissionSetCurrent>()) {
    const MissionSetCurrent set = frame.As<MissionSetCurrent>();
    if (!ForUs(set.target_system, kMavMissionTypeMission)) return ++counts_.ignored, false;
    if (set.seq < items_.size()) current_ = set.seq;
    MissionCurrent announce;
    announce.seq = current_;
    announce.total = static_cast<std::uint16_t>(items_.size());
    out.push_back(MakeOutgoing(announce));
    return false;
  }
  return false;
}

void MissionServer::Tick(double now_s, std::vector<Outgoing>& out) {
  if (!upload_ || now_s - upload_->last_request_s < kTimeoutS) return;
  if (upload_->retries >= kRetries) {
    Ack(upload_->partner, static_cast<std::uint8_t>(kMavMissionOperationCancelled), out);
    upload_.reset();
    ++counts_.cancelled;
    return;
  }
  ++upload_->retries;
  ++counts_.retries;
  Request(now_s, out);
}

}  // namespace uascma::mavlink
