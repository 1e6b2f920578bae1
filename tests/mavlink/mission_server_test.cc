// The vehicle's side of the mission protocol, driven message by message: upload, download, retries, a hostile
// partner (items out of order, another system's messages), clear.
#include <gtest/gtest.h>

#include <vector>

#include "uascma/mavlink/mission_server.h"

namespace uascma::mavlink {
namespace {

constexpr Address kVehicle{1, 1};
constexpr Address kGround{255, 190};

template <class M>
Frame FrameOf(const M& message, Address sender = kGround) {
  Frame frame;
  frame.sender = sender;
  frame.message_id = M::kId;
  frame.payload = EncodePayload(message);
  return frame;
}

template <class M>
M Only(const std::vector<Outgoing>& out) {
  EXPECT_EQ(out.size(), 1u);
  EXPECT_EQ(out.at(0).info.id, M::kId);
  return DecodePayload<M>(out.at(0).payload.view());
}

MissionItemInt Item(std::uint16_t seq) {
  MissionItemInt item;
  item.target_system = kVehicle.system_id;
  item.seq = seq;
  item.frame = static_cast<std::uint8_t>(kMavFrameGlobalRelativeAltInt);
  item.command = static_cast<std::uint16_t>(kMavCmdNavWaypoint);
  item.x = 407700000 + seq;
  item.y = -739600000 - seq;
  item.z = 30.0f + seq;
  item.autocontinue = 1;
  return item;
}

MissionCount Count(std::uint16_t n) {
  MissionCount count;
  count.target_system = kVehicle.system_id;
  count.count = n;
  return count;
}

TEST(MissionServerTest, UploadThenDownloadGivesTheSameItems) {
  MissionServer server(kVehicle);
  std::vector<Outgoing> out;
  server.Handle(FrameOf(Count(3)), 0.0, out);
  for (std::uint16_t seq = 0; seq < 3; ++seq) {
    EXPECT_EQ(Only<MissionRequestInt>(out).seq, seq);
    out.clear();
    server.Handle(FrameOf(Item(seq)), 0.1 * seq, out);
  }
  EXPECT_EQ(Only<MissionAck>(out).type, kMavMissionAccepted);
  out.clear();
  MissionRequestList list;
  list.target_system = 1;
  server.Handle(FrameOf(list), 1.0, out);
  EXPECT_EQ(Only<MissionCount>(out).count, 3);
  for (std::uint16_t seq = 0; seq < 3; ++seq) {
    out.clear();
    MissionRequestInt request;
    request.target_system = 1;
    request.seq = seq;
    server.Handle(FrameOf(request), 1.0, out);
    MissionItemInt expected = Item(seq);
    expected.target_system = kGround.system_id;
    expected.target_component = kGround.component_id;
    expected.current = seq == 0 ? 1 : 0;
    EXPECT_EQ(Only<MissionItemInt>(out), expected);
  }
}

TEST(MissionServerTest, ItemsOutOfOrderAreNotStoredAndTheExpectedOneIsAskedAgain) {
  MissionServer server(kVehicle);
  std::vector<Outgoing> out;
  server.Handle(FrameOf(Count(2)), 0.0, out);
  out.clear();
  server.Handle(FrameOf(Item(1)), 0.1, out);  // 1 before 0
  EXPECT_EQ(Only<MissionRequestInt>(out).seq, 0);
  out.clear();
  server.Handle(FrameOf(Item(0)), 0.2, out);
  server.Handle(FrameOf(Item(0)), 0.3, out);  // a duplicate
  out.clear();
  server.Handle(FrameOf(Item(1)), 0.4, out);
  EXPECT_EQ(Only<MissionAck>(out).type, kMavMissionAccepted);
  ASSERT_EQ(server.items().size(), 2u);
  EXPECT_EQ(server.items()[1].seq, 1);
  EXPECT_EQ(server.counts().out_of_order_items, 2);
}

TEST(MissionServerTest, AnotherSystemsMissionMessagesAreIgnored) {
  MissionServer server(kVehicle);
  std::vector<Outgoing> out;
  MissionCount count = Count(1);
  count.target_system = 2;
  server.Handle(FrameOf(count), 0.0, out);
  MissionClearAll clear;
  clear.target_system = 9;
  server.Handle(FrameOf(clear), 0.0, out);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(server.counts().ignored, 2);
  // An item from a third party in the middle of an upload is not taken.
  server.Handle(FrameOf(Count(1)), 0.0, out);
  out.clear();
  server.Handle(FrameOf(Item(0), Address{42, 1}), 0.1, out);
  EXPECT_TRUE(out.empty());
  EXPECT_TRUE(server.uploading());
}

TEST(MissionServerTest, ALostItemIsRequestedAgainThenTheUploadIsCancelled) {
  MissionServer server(kVehicle);
  std::vector<Outgoing> out;
  server.Handle(FrameOf(Count(2)), 0.0, out);
  out.clear();
  server.Tick(MissionServer::kTimeoutS - 0.01, out);  // not yet overdue
  EXPECT_TRUE(out.empty());
  double t = 0.0;
  for (int retry = 1; retry <= MissionServer::kRetries; ++retry) {
    t += MissionServer::kTimeoutS;
    server.Tick(t, out);
    EXPECT_EQ(Only<MissionRequestInt>(out).seq, 0);
    out.clear();
  }
  t += MissionServer::kTimeoutS;
  server.Tick(t, out);
  EXPECT_EQ(Only<MissionAck>(out).type, kMavMissionOperationCancelled);
  EXPECT_FALSE(server.uploading());
  EXPECT_EQ(server.counts().retries, MissionServer::kRetries);
}

TEST(MissionServerTest, ClearAndAnInvalidRequest) {
  MissionServer server(kVehicle);
  std::vector<Outgoing> out;
  server.Handle(FrameOf(Count(1)), 0.0, out);
  server.Handle(FrameOf(Item(0)), 0.0, out);
  ASSERT_EQ(server.items().size(), 1u);
  out.clear();
  MissionRequestInt request;
  request.target_system = 1;
  request.seq = 5;
  server.Handle(FrameOf(request), 0.0, out);
  EXPECT_EQ(Only<MissionAck>(out).type, kMavMissionInvalidSequence);
  out.clear();
  MissionClearAll clear;
  clear.target_system = 1;
  EXPECT_TRUE(server.Handle(FrameOf(clear), 0.0, out));
  EXPECT_EQ(Only<MissionAck>(out).type, kMavMissionAccepted);
  EXPECT_TRUE(server.items().empty());
}

}  // namespace
}  // namespace uascma::mavlink

namespace uascma::mavlink {
namespace {

// An upload the vehicle cannot fly (MissionServer::set_check): refused at its MISSION_ACK with MAV_MISSION_INVALID,
// the stored mission kept, the reason given once.
TEST(MissionServerTest, AnUploadTheCheckRefusesIsAnsweredInvalidAndNotStored) {
  MissionServer server(kVehicle);
  server.Load({Item(0)});
  server.set_check([](const std::vector<MissionItemInt>& items) -> std::optional<std::string> {
    if (items.size() == 2) return std::string("two items are refused");
    return std::nullopt;
  });
  std::vector<Outgoing> out;
  server.Handle(FrameOf(Count(2)), 0.0, out);
  out.clear();
  server.Handle(FrameOf(Item(0)), 0.1, out);
  out.clear();
  server.Handle(FrameOf(Item(1)), 0.2, out);
  EXPECT_EQ(Only<MissionAck>(out).type, kMavMissionInvalid);
  ASSERT_EQ(server.items().size(), 1u);  // the one held before
  EXPECT_EQ(server.counts().refused, 1);
  EXPECT_EQ(server.counts().uploads, 0);
  EXPECT_EQ(server.TakeRefusal(), std::optional<std::string>("two items are refused"));
  EXPECT_FALSE(server.TakeRefusal());
  out.clear();
  server.Handle(FrameOf(Count(3)), 1.0, out);  // a mission the check accepts is stored as before
  for (std::uint16_t seq = 0; seq < 3; ++seq) {
    out.clear();
    server.Handle(FrameOf(Item(seq)), 1.1 + seq, out);
  }
  EXPECT_EQ(Only<MissionAck>(out).type, kMavMissionAccepted);
  EXPECT_EQ(server.items().size(), 3u);
}

}  // namespace
}  // namespace uascma::mavlink
