#include "uascma/mavlink/command_client.h"

#include <algorithm>
#include <iterator>

#include <fmt/format.h>

namespace uascma::mavlink {

std::string CommandName(std::uint16_t command) {
  switch (command) {
    case kMavCmdNavLand:
      return "NAV_LAND";
    case kMavCmdMissionStart:
      return "MISSION_START";
    case kMavCmdDoReposition:
      return "DO_REPOSITION";
    case kMavCmdDoFlighttermination:
      return "DO_FLIGHTTERMINATION";
    case kMavCmdComponentArmDisarm:
      return "COMPONENT_ARM_DISARM";
    default:
      return fmt::format("command {}", command);
  }
}

std::string ResultName(std::uint8_t result) {
  constexpr const char* kNames[] = {"ACCEPTED", "TEMPORARILY_REJECTED", "DENIED", "UNSUPPORTED",
                                    "FAILED",   "IN_PROGRESS"};
  return result < std::size(kNames) ? kNames[result] : fmt::format("result {}", result);
}

std::string CommandOutcome::Describe() const {
  if (!result) return fmt::format("{} not acknowledged after {} sends", CommandName(command), attempts);
  return fmt::format("{} {}", CommandName(command), ResultName(*result));
}

std::uint16_t CommandClient::CommandOf(const Pending& pending) const {
  return std::visit([](const auto& message) { return message.command; }, pending.message);
}

void CommandClient::Transmit(Pending& pending, double now_s, std::vector<Outgoing>& out) {
  if (auto* command = std::get_if<CommandLong>(&pending.message)) {
    // The command protocol: a repeat carries confirmation incremented (0 the first time).
    command->confirmation = static_cast<std::uint8_t>(std::min(pending.attempts, 255));
    out.push_back(MakeOutgoing(*command));
  } else {
    out.push_back(MakeOutgoing(std::get<CommandInt>(pending.message)));
  }
  if (pending.attempts > 0) ++resent_;
  ++pending.attempts;
  pending.sent_s = now_s;
}

void CommandClient::Send(const CommandLong& command, double now_s, std::vector<Outgoing>& out) {
  queue_.push_back({command});
  if (queue_.size() == 1) Transmit(queue_.front(), now_s, out);
}

void CommandClient::Send(const CommandInt& command, double now_s, std::vector<Outgoing>& out) {
  queue_.push_back({command});
  if (queue_.size() == 1) Transmit(queue_.front(), now_s, out);
}

CommandOutcome CommandClient::Finish(std::optional<std::uint8_t> result, bool drop_queue, double now_s,
                                     std::vector<Outgoing>& out) {
  CommandOutcome outcome{CommandOf(queue_.front()), result, queue_.front().attempts};
  queue_.pop_front();
  if (drop_queue) queue_.clear();
  if (!queue_.empty()) Transmit(queue_.front(), now_s, out);
  return outcome;
}

std::optional<CommandOutcome> CommandClient::Handle(const Frame& frame, Address vehicle, double now_s,
                                                    std::vector<Outgoing>& out) {
  if (queue_.empty() || !frame.Is<CommandAck>() || frame.sender != vehicle) return std::nullopt;
  const CommandAck ack = frame.As<CommandAck>();
  if (ack.command != CommandOf(queue_.front())) return std::nullopt;  // a late ACK of an earlier command
  if (ack.result == kMavResultInProgress) {
    queue_.front().in_progress = true;
    return std::nullopt;
  }
  return Finish(ack.result, ack.result != kMavResultAccepted, now_s, out);
}

std::optional<CommandOutcome> CommandClient::Tick(double now_s, std::vector<Outgoing>& out) {
  if (queue_.empty() || queue_.front().in_progress || now_s - queue_.front().sent_s < kTimeoutS) return std::nullopt;
  if (queue_.front().attempts > kRetries) return Finish(std::nullopt, true, now_s, out);
  Transmit(queue_.front(), now_s, out);
  return std::nullopt;
}

}  // namespace uascma::mavlink
