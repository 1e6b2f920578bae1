// The companion's command sender (mavlink/command_client.h) on loopback against scripted peers: one that drops the
// first command (it comes again after the timeout, confirmation 1), one that denies it (the outcome says so, and the
// command queued behind it is never sent), one that never answers (given up after the retries). The peers' clock is
// the test's: the times passed are wall seconds as the caller would give them.
#include "uascma/mavlink/command_client.h"

#include <gtest/gtest.h>

#include <optional>
#include <vector>

#include "uascma/mavlink/mission_client.h"
#include "uascma/mavlink/udp_link.h"

namespace uascma::mavlink {
namespace {

constexpr Address kCompanion{1, 191};
constexpr Address kClientVehicle{1, 1};
constexpr double kLoopbackWaitS = 1.0;  // s: the longest a datagram on loopback is waited for (ours, generous)

// A vehicle on loopback and a companion sending to it.
struct Loopback {
  UdpLink vehicle{{LinkAddress{LinkAddress::Kind::kListen, "127.0.0.1", 0}}};
  UdpLink companion{{LinkAddress{LinkAddress::Kind::kSendTo, "127.0.0.1", vehicle.bound_port(0)}}};
  FrameSender companion_sender{companion, kCompanion};
  FrameSender vehicle_sender{vehicle, kClientVehicle};

  // The next frame of M the vehicle receives, or nothing within kLoopbackWaitS.
  template <class M>
  std::optional<M> VehicleReceives() {
    for (int k = 0; k < 50; ++k) {
      for (const ReceivedFrame& received : vehicle.Receive(kLoopbackWaitS / 50)) {
        if (received.frame.Is<M>()) return received.frame.As<M>();
      }
    }
    return std::nullopt;
  }
  void VehicleAcks(std::uint16_t command, std::uint8_t result) {
    CommandAck ack;
    ack.command = command;
    ack.result = result;
    ack.target_system = kCompanion.system_id;
    ack.target_component = kCompanion.component_id;
    std::vector<Outgoing> out{MakeOutgoing(ack)};
    vehicle_sender.Flush(out);
  }
  // The companion's client fed with what arrives until an outcome or kLoopbackWaitS.
  std::optional<CommandOutcome> CompanionReads(CommandClient& client, double now_s) {
    std::vector<Outgoing> out;
    for (int k = 0; k < 50; ++k) {
      for (const ReceivedFrame& received : companion.Receive(kLoopbackWaitS / 50)) {
        if (auto outcome = client.Handle(received.frame, kClientVehicle, now_s, out)) {
          companion_sender.Flush(out);
          return outcome;
        }
      }
    }
    return std::nullopt;
  }
};

// A message as the peer receives it from `sender`.
Frame DecodeForTest(const Outgoing& message, Address sender) {
  Frame frame;
  frame.sender = sender;
  frame.message_id = message.info.id;
  frame.payload = message.payload;
  return frame;
}

CommandLong Land() {
  CommandLong command;
  command.target_system = kClientVehicle.system_id;
  command.target_component = kClientVehicle.component_id;
  command.command = static_cast<std::uint16_t>(kMavCmdNavLand);
  return command;
}

TEST(CommandClientTest, ACommandDroppedOnceComesAgainWithConfirmationOneAndIsAccepted) {
  Loopback link;
  CommandClient client;
  std::vector<Outgoing> out;
  client.Send(Land(), 0.0, out);
  link.companion_sender.Flush(out);
  const std::optional<CommandLong> first = link.VehicleReceives<CommandLong>();
  ASSERT_TRUE(first);
  EXPECT_EQ(first->confirmation, 0);  // dropped: no ACK
  EXPECT_FALSE(client.Tick(CommandClient::kTimeoutS - 0.1, out));
  EXPECT_TRUE(out.empty()) << "sent again before the timeout";
  EXPECT_FALSE(client.Tick(CommandClient::kTimeoutS + 0.1, out));
  link.companion_sender.Flush(out);
  const std::optional<CommandLong> again = link.VehicleReceives<CommandLong>();
  ASSERT_TRUE(again);
  EXPECT_EQ(again->command, kMavCmdNavLand);
  EXPECT_EQ(again->confirmation, 1);
  link.VehicleAcks(kMavCmdNavLand, kMavResultAccepted);
  const std::optional<CommandOutcome> outcome = link.CompanionReads(client, CommandClient::kTimeoutS + 0.2);
  ASSERT_TRUE(outcome);
  EXPECT_TRUE(outcome->accepted());
  EXPECT_EQ(outcome->attempts, 2);
  EXPECT_EQ(client.resent(), 1);
  EXPECT_TRUE(client.idle());
}

TEST(CommandClientTest, ADeniedCommandIsReportedAndTheRestOfItsActionIsNotSent) {
  Loopback link;
  CommandClient client;
  std::vector<Outgoing> out;
  CommandInt reposition;
  reposition.command = static_cast<std::uint16_t>(kMavCmdDoReposition);
  client.Send(reposition, 0.0, out);
  client.Send(Land(), 0.0, out);  // queued behind the reposition: not sent yet
  link.companion_sender.Flush(out);
  ASSERT_TRUE(link.VehicleReceives<CommandInt>());
  link.VehicleAcks(kMavCmdDoReposition, kMavResultDenied);
  const std::optional<CommandOutcome> outcome = link.CompanionReads(client, 0.1);
  ASSERT_TRUE(outcome);
  EXPECT_FALSE(outcome->accepted());
  EXPECT_EQ(outcome->Describe(), "DO_REPOSITION DENIED");
  EXPECT_TRUE(client.idle());
  EXPECT_FALSE(link.VehicleReceives<CommandLong>()) << "NAV_LAND sent after its DO_REPOSITION was denied";
}

TEST(CommandClientTest, ACommandNeverAnsweredIsGivenUpAfterTheRetries) {
  CommandClient client;
  std::vector<Outgoing> out;
  client.Send(Land(), 0.0, out);
  std::optional<CommandOutcome> outcome;
  double now_s = 0.0;
  for (int tick = 0; tick < 100 && !outcome; ++tick) outcome = client.Tick(now_s += 0.5, out);
  ASSERT_TRUE(outcome);
  EXPECT_EQ(outcome->attempts, 1 + CommandClient::kRetries);
  EXPECT_EQ(out.size(), static_cast<std::size_t>(1 + CommandClient::kRetries));
  EXPECT_EQ(outcome->Describe(), "NAV_LAND not acknowledged after 6 sends");
  // The first timeout after the last send: (1 + retries) timeouts of 1.5 s, ticked every 0.5 s.
  EXPECT_NEAR(now_s, (1 + CommandClient::kRetries) * CommandClient::kTimeoutS, 0.5);
}

// The download (mission_client.h) against the vehicle's server (mission_server.h): the items the server holds, in
// order, and the server's download acknowledged.
TEST(MissionDownloadTest, TheVehiclesHeldMissionDownloadsWhole) {
  MissionServer server(kClientVehicle);
  std::vector<MissionItemInt> held;
  for (std::uint16_t seq = 0; seq < 4; ++seq) {
    planning::MissionItem item{kMavCmdNavWaypoint, kMavFrameGlobalRelativeAltInt, {0, 0, 0, 0, 1.0 + seq, 1.0, 30}};
    held.push_back(ToMissionItemInt(item, kClientVehicle, seq));
  }
  server.Load(held);
  MissionDownload download;
  std::vector<Outgoing> to_vehicle, to_companion;
  download.Start(kClientVehicle, 0.0, to_vehicle);
  std::optional<std::vector<MissionItemInt>> items;
  for (int round = 0; round < 20 && !items; ++round) {
    for (const Outgoing& message : to_vehicle) {
      server.Handle(DecodeForTest(message, kCompanion), 0.0, to_companion);
    }
    to_vehicle.clear();
    for (const Outgoing& message : to_companion) {
      if (auto done = download.Handle(DecodeForTest(message, kClientVehicle), 0.0, to_vehicle)) items = done;
    }
    to_companion.clear();
  }
  ASSERT_TRUE(items);
  ASSERT_EQ(items->size(), held.size());
  for (std::size_t k = 0; k < held.size(); ++k) {
    EXPECT_EQ((*items)[k].x, held[k].x) << k;
    EXPECT_EQ((*items)[k].seq, k);
  }
  EXPECT_EQ(server.counts().downloads, 1);
}

}  // namespace
}  // namespace uascma::mavlink
