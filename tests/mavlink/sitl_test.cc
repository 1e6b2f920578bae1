// `uascma sitl` end to end on loopback: a client (our own codec; the independent implementation is the node-mavlink
// test) connects, sees the telemetry, uploads and downloads a mission, sends commands (its own, another system's,
// unsupported ones, garbage), and reads the flight's events as STATUSTEXT: the same events as the in-process
// simulator's flight of the same scenario.
#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <map>
#include <optional>
#include <thread>

#include "uascma/mavlink/sitl.h"
#include "uascma/sim/simulator.h"

namespace uascma::mavlink {
namespace {

constexpr Address kSitlGround{255, 190};

class Client {
 public:
  explicit Client(std::uint16_t port) : link_({LinkAddress{LinkAddress::Kind::kSendTo, "127.0.0.1", port}}) {}
  template <class M>
  void Send(const M& message) {
    link_.Send(EncodeFrame(message, kSitlGround, sequence_++));
  }
  void SendRaw(const std::vector<std::uint8_t>& bytes) { link_.Send(bytes); }
  // Receives until a frame of M for which `accept` holds (returned) or `timeout_s` (nothing).
  template <class M, class Accept>
  std::optional<M> Await(Accept accept, double timeout_s = 5.0) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (std::chrono::steady_clock::now() < end) {
      for (const ReceivedFrame& received : link_.Receive(0.02)) {
        Record(received.frame);
        if (received.frame.Is<M>() && !found_) {
          const M message = received.frame.As<M>();
          if (accept(message)) found_ = true, pending_ = received.frame;
        }
      }
      if (found_) {
        found_ = false;
        return pending_.As<M>();
      }
    }
    return std::nullopt;
  }
  void Drain(double seconds) {
    Await<Heartbeat>([](const Heartbeat&) { return false; }, seconds);
  }
  std::map<std::uint32_t, int> received;  // frames per message id
  std::vector<std::string> texts;         // STATUSTEXT in order
  ParserCounts counts() const { return link_.counts(); }

 private:
  void Record(const Frame& frame) {
    ++received[frame.message_id];
    if (frame.Is<Statustext>()) {
      const Statustext text = frame.As<Statustext>();
      texts.emplace_back(text.text.data(), strnlen(text.text.data(), text.text.size()));
    }
  }
  UdpLink link_;
  std::uint8_t sequence_ = 0;
  bool found_ = false;
  Frame pending_;
};

MissionItemInt Waypoint(std::uint16_t seq) {
  MissionItemInt item;
  item.target_system = 1;
  item.target_component = 1;
  item.seq = seq;
  item.frame = static_cast<std::uint8_t>(kMavFrameGlobalRelativeAltInt);
  item.command = static_cast<std::uint16_t>(kMavCmdNavWaypoint);
  item.x = 407800000 + 1000 * seq;
  item.y = -739700000;
  item.z = 40.0f;
  item.autocontinue = 1;
  return item;
}

// The sitl's flight is the simulator's: the same outcome, duration and events, each at the same time (bit for bit).
void ExpectSameFlight(const SitlSummary& summary, const sim::SimResult& reference) {
  EXPECT_EQ(summary.outcome, reference.outcome);
  EXPECT_EQ(summary.sim_time_s, reference.sim_time_s);
  ASSERT_EQ(summary.events.size(), reference.events.size());
  for (std::size_t i = 0; i < summary.events.size(); ++i) {
    EXPECT_EQ(summary.events[i].what, reference.events[i].what);
    EXPECT_EQ(summary.events[i].time_s, reference.events[i].time_s);
  }
}

TEST(SitlTest, AClientFliesScenarioOneAndSeesTheSimulatorsEvents) {
  const sim::ScenarioFile file = sim::LoadScenarioFile(std::string(UASCMA_SOURCE_DIR) + "/examples/scenario-1.yaml", {});
  auto policy = sim::MakePolicy(file.policy, "scenario-1.yaml");
  std::promise<std::uint16_t> port;
  SitlOptions options;
  options.links = {ParseLinkAddress("udp:127.0.0.1:0", "test")};
  options.speed = 1000.0;  // as fast as the machine steps
  options.linger_s = 6.0;
  options.on_ready = [&](const UdpLink& link) { port.set_value(link.bound_port(0)); };
  auto run = std::async(std::launch::async, [&] { return RunSitl(file.scenario, *policy, options); });
  Client client(port.get_future().get());
  client.Send(Heartbeat{});  // makes the client a peer
  ASSERT_TRUE(client.Await<Heartbeat>([](const Heartbeat& h) { return h.type == kMavTypeHexarotor; }).has_value());
  // Garbage and another system's command first: ignored, no acknowledgement.
  client.SendRaw({0xFD, 0xFF, 0x00, 0x00, 0x01, 0x02});
  client.SendRaw({0xFD, 3, 0, 0, 0, 255, 190, 77, 0, 0, 1, 2, 3, 0xBA, 0xD0});  // COMMAND_ACK with a wrong checksum
  CommandLong foreign;
  foreign.target_system = 2;
  foreign.command = static_cast<std::uint16_t>(kMavCmdDoFlighttermination);
  foreign.param1 = 1.0f;
  client.Send(foreign);
  CommandLong unsupported;
  unsupported.target_system = 1;
  unsupported.command = static_cast<std::uint16_t>(kMavCmdDoReposition);
  client.Send(unsupported);
  const auto ack = client.Await<CommandAck>([](const CommandAck& a) { return a.command != 0; });
  ASSERT_TRUE(ack.has_value());
  EXPECT_EQ(ack->command, kMavCmdDoReposition);
  EXPECT_EQ(ack->result, kMavResultUnsupported);
  // Mission upload.
  MissionCount count;
  count.target_system = 1;
  count.count = 3;
  client.Send(count);
  for (std::uint16_t seq = 0; seq < 3; ++seq) {
    const auto request = client.Await<MissionRequestInt>([&](const MissionRequestInt& r) { return r.seq == seq; });
    ASSERT_TRUE(request.has_value()) << seq;
    client.Send(Waypoint(seq));
  }
  const auto accepted = client.Await<MissionAck>([](const MissionAck&) { return true; });
  ASSERT_TRUE(accepted.has_value());
  EXPECT_EQ(accepted->type, kMavMissionAccepted);
  // Download.
  MissionRequestList list;
  list.target_system = 1;
  client.Send(list);
  const auto listed = client.Await<MissionCount>([](const MissionCount&) { return true; });
  ASSERT_TRUE(listed.has_value());
  ASSERT_EQ(listed->count, 3);
  for (std::uint16_t seq = 0; seq < 3; ++seq) {
    MissionRequestInt request;
    request.target_system = 1;
    request.seq = seq;
    client.Send(request);
    const auto item = client.Await<MissionItemInt>([&](const MissionItemInt& i) { return i.seq == seq; });
    ASSERT_TRUE(item.has_value());
    EXPECT_EQ(item->x, Waypoint(seq).x);
    EXPECT_EQ(item->z, Waypoint(seq).z);
    EXPECT_EQ(item->command, Waypoint(seq).command);
  }
  // A flood: 10,000 commands in one second (30 frames a datagram), each with its own command number (40000 + i: none
  // that the vehicle carries out). Every one is answered UNSUPPORTED, and the answers come back in the order sent.
  constexpr int kFlood = 10000;
  std::vector<std::uint8_t> burst;
  for (int i = 0; i < kFlood; ++i) {
    CommandLong command;
    command.target_system = 1;
    command.command = static_cast<std::uint16_t>(40000 + i);
    const auto frame = EncodeFrame(command, kSitlGround, static_cast<std::uint8_t>(i));
    burst.insert(burst.end(), frame.begin(), frame.end());
    if ((i + 1) % 30 == 0 || i + 1 == kFlood) {
      client.SendRaw(burst);
      burst.clear();
    }
    if ((i + 1) % 1000 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(100));  // 10,000 frames a second
  }
  int last_acked = -1;
  bool in_order = true;
  while (client.Await<CommandAck>([&](const CommandAck& a) {
    const int i = a.command - 40000;
    if (i >= 0 && i < kFlood) {
      in_order = in_order && i > last_acked;
      last_acked = i;
    }
    return i == kFlood - 1;
  }, 3.0)) {
  }
  EXPECT_TRUE(in_order);
  client.Drain(0.5);
  while (run.wait_for(std::chrono::milliseconds(0)) != std::future_status::ready) client.Drain(0.2);
  const SitlSummary summary = run.get();
  client.Drain(0.3);

  // The flight is the simulator's: the same outcome and events as Simulator::Run with telemetry recorded.
  const sim::Simulator simulator(file.scenario);
  auto reference_policy = sim::MakePolicy(file.policy, "scenario-1.yaml");
  const sim::SimResult reference = simulator.Run(*reference_policy);
  ExpectSameFlight(summary, reference);
  // The client read every event as a STATUSTEXT (its first 50 bytes, cut at a character boundary), in order.
  ASSERT_EQ(client.texts.size(), summary.events.size());
  for (std::size_t i = 0; i < client.texts.size(); ++i) {
    const std::string& what = summary.events[i].what;
    EXPECT_EQ(client.texts[i], what.substr(0, client.texts[i].size()));
    EXPECT_GE(client.texts[i].size(), std::min<std::size_t>(what.size(), 49));  // at most one 2-byte character short
  }
  // "speed capped at 8.2 m/s airspeed (four rotors, §4.4.2)": the 50-byte cut falls inside "§" and stops before it.
  EXPECT_EQ(MakeStatustext(kMavSeverityInfo, std::string(49, 'a') + "\u00a7").text[49], '\0');
  // Telemetry: one HEARTBEAT per simulated second (plus the start and the linger), two BATTERY_STATUS each time.
  EXPECT_GE(client.received[Heartbeat::kId], static_cast<int>(reference.sim_time_s) - 1);
  EXPECT_EQ(client.received[BatteryStatus::kId], 2 * client.received[Heartbeat::kId]);
  EXPECT_EQ(client.received[GlobalPositionInt::kId], client.received[Heartbeat::kId]);
  EXPECT_EQ(client.counts().sequence_gaps, 0u);
  EXPECT_EQ(client.counts().bad_checksum, 0u);
  // The hostile frames were counted and ignored.
  EXPECT_EQ(summary.commands.foreign_commands, 1);
  EXPECT_EQ(summary.commands.unsupported_commands, 1 + kFlood);  // every command of the flood was handled
  EXPECT_GE(summary.link.bad_checksum, 1u);
  EXPECT_GE(summary.link.truncated, 1u);
  EXPECT_EQ(summary.missions.uploads, 1);
  EXPECT_EQ(summary.missions.downloads, 1);
}

// With the CMA external and no companion on the link, nothing decides: the vehicle flies the scenario as the
// simulator flies it under NoOp (the scenario's own policy, here `cma`, is not consulted), event for event.
TEST(SitlTest, WithTheCmaExternalAndNoCommandsTheFlightIsTheNoOpFlight) {
  const sim::ScenarioFile file = sim::LoadScenarioFile(std::string(UASCMA_SOURCE_DIR) + "/examples/scenario-1.yaml", {});
  auto policy = sim::MakePolicy(file.policy, "scenario-1.yaml");
  SitlOptions options;
  options.links = {ParseLinkAddress("udp:127.0.0.1:0", "test")};
  options.speed = 1000.0;
  options.linger_s = 0.0;
  options.external_cma = true;
  const SitlSummary summary = RunSitl(file.scenario, *policy, options);
  const sim::Simulator simulator(file.scenario);
  sim::NoOpPolicy noop;
  const sim::SimResult reference = simulator.Run(noop);
  EXPECT_EQ(reference.outcome, sim::Outcome::kFailedBattery);  // Scenario I under NoOp (§5.5.1)
  ExpectSameFlight(summary, reference);
}

}  // namespace
}  // namespace uascma::mavlink

namespace uascma::mavlink {
namespace {

// A long STATUSTEXT in chunks (the common set's id and chunk_seq): every chunk but the last full (a NUL would end the
// text for the receiver), the whole text again when joined, a UTF-8 character across two chunks restored, and a last
// chunk holding a NUL (empty when the text fills the one before).
TEST(StatustextTest, ALongTextIsChunkedWholeAndJoinsBack) {
  std::string text;
  for (int k = 0; k < 40; ++k) text += "é-";  // 3 bytes each: 120 bytes, the 2-byte é across the 50th byte
  const std::vector<Statustext> chunks = StatustextChunks(kMavSeverityError, text, 7);
  ASSERT_EQ(chunks.size(), 3u);
  std::string joined;
  for (std::size_t k = 0; k < chunks.size(); ++k) {
    EXPECT_EQ(chunks[k].id, 7);
    EXPECT_EQ(chunks[k].chunk_seq, k);
    const std::string part(chunks[k].text.data(), strnlen(chunks[k].text.data(), chunks[k].text.size()));
    if (k + 1 < chunks.size()) {
      EXPECT_EQ(part.size(), chunks[k].text.size()) << "chunk " << k << " cut short";
    }
    joined += part;
  }
  EXPECT_EQ(joined, text);
  EXPECT_LT(strnlen(chunks.back().text.data(), chunks.back().text.size()), chunks.back().text.size());
  const std::vector<Statustext> exact = StatustextChunks(kMavSeverityInfo, std::string(50, 'x'), 8);
  ASSERT_EQ(exact.size(), 2u);
  EXPECT_EQ(exact[1].text[0], '\0');
}

}  // namespace
}  // namespace uascma::mavlink
