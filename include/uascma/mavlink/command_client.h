#pragma once
// The sender's side of the MAVLink command protocol (mavlink.io "Command Protocol"): COMMAND_LONG and COMMAND_INT
// sent one at a time, in order, each until its COMMAND_ACK. A command not acknowledged within kTimeoutS is sent
// again (a COMMAND_LONG with `confirmation` incremented, as the protocol asks; COMMAND_INT has no such field), at most
// kRetries times; then it ends unanswered. MAV_RESULT_IN_PROGRESS waits for the final ACK without resending. The
// commands queued behind one that failed are dropped with it: they belonged to the same action (DO_REPOSITION then
// NAV_LAND). A pure state machine: frames and the wall time in, messages out, as MissionServer.
//
// Timeout and retries (docs/modelling-choices.md#companion-command-retries): the mission protocol's defaults, 1.5 s
// and 5 (mavlink.io "Mission Protocol", "Timeouts and Retries"); the command protocol leaves them to the sender.
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "uascma/mavlink/mission_server.h"

namespace uascma::mavlink {

// How one command ended.
struct CommandOutcome {
  std::uint16_t command = 0;           // MAV_CMD
  std::optional<std::uint8_t> result;  // MAV_RESULT of the final COMMAND_ACK; nothing when none came
  int attempts = 0;                    // sends, the first included
  bool accepted() const { return result && *result == kMavResultAccepted; }
  // "NAV_LAND DENIED", "MISSION_START not acknowledged after 6 sends", …
  std::string Describe() const;
};

class CommandClient {
 public:
  static constexpr double kTimeoutS = 1.5;  // s, see above
  static constexpr int kRetries = 5;

  // Queues the command; it is sent at once when nothing waits for an ACK.
  void Send(const CommandLong& command, double now_s, std::vector<Outgoing>& out);
  void Send(const CommandInt& command, double now_s, std::vector<Outgoing>& out);
  // A COMMAND_ACK from `vehicle` for the command in flight: the outcome once it is final (the next one sent).
  std::optional<CommandOutcome> Handle(const Frame& frame, Address vehicle, double now_s, std::vector<Outgoing>& out);
  // The command in flight again after the timeout; its outcome (unanswered) once the retries are spent.
  std::optional<CommandOutcome> Tick(double now_s, std::vector<Outgoing>& out);
  bool idle() const { return queue_.empty(); }
  int resent() const { return resent_; }

 private:
  struct Pending {
    std::variant<CommandLong, CommandInt> message;
    int attempts = 0;
    double sent_s = 0.0;
    bool in_progress = false;
  };
  void Transmit(Pending& pending, double now_s, std::vector<Outgoing>& out);
  CommandOutcome Finish(std::optional<std::uint8_t> result, bool drop_queue, double now_s, std::vector<Outgoing>& out);
  std::uint16_t CommandOf(const Pending& pending) const;
  std::deque<Pending> queue_;
  int resent_ = 0;
};

// "NAV_LAND", "MISSION_START", … for the commands the companion sends; "command N" otherwise.
std::string CommandName(std::uint16_t command);
// "ACCEPTED", "DENIED", … ; "result N" otherwise.
std::string ResultName(std::uint8_t result);

}  // namespace uascma::mavlink
