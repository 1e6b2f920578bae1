// The frame parser on a hostile link: malformed, corrupted, truncated, oversized and unknown frames are counted
// and dropped, valid frames around them are still delivered, in their order; a flood of 10,000 frames.
#include <gtest/gtest.h>

#include <vector>

#include "uascma/common/random.h"
#include "uascma/mavlink/codec.h"

namespace uascma::mavlink {
namespace {

std::vector<std::uint8_t> Command(int index, Address sender = {255, 190}) {
  CommandLong command;
  command.target_system = 1;
  command.command = static_cast<std::uint16_t>(kMavCmdComponentArmDisarm);
  command.param1 = static_cast<float>(index);
  return EncodeFrame(command, sender, static_cast<std::uint8_t>(index));
}

void Append(std::vector<std::uint8_t>& to, const std::vector<std::uint8_t>& bytes) {
  to.insert(to.end(), bytes.begin(), bytes.end());
}

std::vector<int> Indices(const std::vector<Frame>& frames) {
  std::vector<int> indices;
  for (const Frame& frame : frames) {
    EXPECT_TRUE(frame.Is<CommandLong>());
    indices.push_back(static_cast<int>(frame.As<CommandLong>().param1));
  }
  return indices;
}

TEST(HostileLinkTest, AWrongChecksumIsCountedAndTheNextFrameIsFound) {
  std::vector<std::uint8_t> bytes = Command(1);
  bytes[12] ^= 0x40;  // a payload bit flipped on the link
  Append(bytes, Command(2));
  FrameParser parser;
  std::vector<Frame> frames;
  parser.ParseDatagram(bytes, frames);
  EXPECT_EQ(Indices(frames), std::vector<int>{2});
  EXPECT_EQ(parser.counts().bad_checksum, 1u);
}

TEST(HostileLinkTest, AFrameOfAnotherMessageSetIsCorruptedNotAccepted) {
  // A checksum computed with another CRC_EXTRA (a peer with different definitions of the same id) is refused.
  CommandLong command;
  const MessageInfo wrong{CommandLong::kId, "COMMAND_LONG", static_cast<std::uint8_t>(CommandLong::kCrcExtra + 1),
                          CommandLong::kMinLength, CommandLong::kMaxLength};
  FrameParser parser;
  std::vector<Frame> frames;
  parser.ParseDatagram(EncodeFrame(wrong, EncodePayload(command), Address{1, 1}, 0), frames);
  EXPECT_TRUE(frames.empty());
  EXPECT_EQ(parser.counts().bad_checksum, 1u);
}

TEST(HostileLinkTest, TruncatedDatagramsAreDroppedWithoutHarmingTheNext) {
  FrameParser parser;
  std::vector<Frame> frames;
  const std::vector<std::uint8_t> whole = Command(1);
  for (std::size_t cut = 1; cut < whole.size(); ++cut) {
    parser.ParseDatagram(std::span(whole.data(), cut), frames);  // every prefix of a frame
  }
  EXPECT_TRUE(frames.empty());
  EXPECT_GE(parser.counts().truncated, whole.size() - 1 - 1);  // a 1-byte "0xFD" prefix is truncated too
  parser.ParseDatagram(Command(2), frames);
  EXPECT_EQ(Indices(frames), std::vector<int>{2});
}

TEST(HostileLinkTest, UnknownIdsSignedFramesAndUnknownFlagsAreDropped) {
  std::vector<std::uint8_t> bytes;
  // An id no definition holds (3), with some payload and a checksum of 0: dropped whole, unverifiable.
  Append(bytes, {kStx, 4, 0, 0, 0, 9, 9, 3, 0, 0, 1, 2, 3, 4, 0, 0});
  Append(bytes, Command(1));
  // A signed frame (INC_FLAGS 0x01): its own checksum is right, the 13-byte signature follows; dropped whole.
  std::vector<std::uint8_t> signed_frame = Command(2);
  signed_frame[2] = kIncompatSigned;
  std::uint16_t crc = CalcCrc(std::span(signed_frame).subspan(1, signed_frame.size() - 3));
  crc = CrcAccumulate(CommandLong::kCrcExtra, crc);
  signed_frame[signed_frame.size() - 2] = static_cast<std::uint8_t>(crc & 0xFF);
  signed_frame[signed_frame.size() - 1] = static_cast<std::uint8_t>(crc >> 8);
  signed_frame.insert(signed_frame.end(), kSignatureLength, 0xAB);
  Append(bytes, signed_frame);
  // An unknown incompatibility flag: the frame cannot be understood.
  std::vector<std::uint8_t> flagged = Command(3);
  flagged[2] = 0x80;
  Append(bytes, flagged);
  Append(bytes, Command(4));
  FrameParser parser;
  std::vector<Frame> frames;
  parser.ParseDatagram(bytes, frames);
  EXPECT_EQ(Indices(frames), (std::vector<int>{1, 4}));
  // Counts are of candidates: a byte 0xFD inside a rejected frame (a checksum byte here) is one more candidate.
  EXPECT_GE(parser.counts().unknown_message, 1u);
  EXPECT_EQ(parser.counts().signed_frames, 1u);
  EXPECT_GE(parser.counts().unsupported_flags, 1u);
}

TEST(HostileLinkTest, OversizedPayloadsAndMavlink1AreHandledByTheRules) {
  // A HEARTBEAT with LEN 255 (a sender with many more extensions): valid, the extra bytes ignored.
  Heartbeat heartbeat;
  heartbeat.custom_mode = 77;
  Payload payload = EncodePayload(heartbeat);
  payload.length = kMaxPayloadLength;
  for (std::size_t i = Heartbeat::kMaxLength; i < kMaxPayloadLength; ++i) payload.bytes[i] = 0x5A;
  const MessageInfo& info = *FindMessageInfo(Heartbeat::kId);
  std::vector<std::uint8_t> bytes = EncodeFrame(info, payload, Address{1, 1}, 0);
  // A MAVLink 1 frame (0xFE): not spoken, skipped as noise.
  Append(bytes, {kStxV1, 9, 0, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x12, 0x34});
  FrameParser parser;
  std::vector<Frame> frames;
  parser.ParseDatagram(bytes, frames);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].As<Heartbeat>().custom_mode, 77u);
  EXPECT_EQ(parser.counts().skipped_bytes, 17u);
}

// Noise between frames, a frame's start hidden in noise, and frames corrupted at random: every intact frame is
// delivered, in order, and every byte is accounted for.
TEST(HostileLinkTest, RandomNoiseBetweenFramesLosesNoIntactFrame) {
  RandomStream random(4601);
  std::vector<std::uint8_t> stream;
  std::vector<int> intact;
  for (int i = 0; i < 2000; ++i) {
    const int noise = static_cast<int>(random.Next() % 12);
    for (int k = 0; k < noise; ++k) stream.push_back(k == 0 ? kStx : static_cast<std::uint8_t>(random.Next()));
    std::vector<std::uint8_t> frame = Command(i);
    if (random.Next() % 10 == 0) {
      frame[10 + random.Next() % (frame.size() - 12)] ^= static_cast<std::uint8_t>(1u << (random.Next() % 8));
    } else {
      intact.push_back(i);
    }
    Append(stream, frame);
  }
  FrameParser parser;
  std::vector<Frame> frames;
  // Fed in chunks of random sizes, as a serial port would deliver them.
  for (std::size_t at = 0; at < stream.size();) {
    const std::size_t n = std::min<std::size_t>(1 + random.Next() % 64, stream.size() - at);
    parser.Parse(std::span(stream.data() + at, n), frames);
    at += n;
  }
  parser.ParseDatagram({}, frames);  // the end of the stream: a noise STX that claimed more bytes is dropped
  const std::vector<int> got = Indices(frames);
  // A noise run may complete a corrupted frame by chance only with a 2^-16 checksum match: none in this stream.
  EXPECT_EQ(got, intact);
  EXPECT_GT(parser.counts().bad_checksum, 0u);
}

// A flood: 10,000 frames in 100 datagrams (one second of a 10 kHz sender), each a COMMAND_LONG numbered in order.
TEST(HostileLinkTest, AFloodOfTenThousandFramesIsParsedInOrder) {
  constexpr int kFrames = 10000;
  FrameParser parser;
  std::vector<Frame> frames;
  for (int datagram = 0; datagram < 100; ++datagram) {
    std::vector<std::uint8_t> bytes;
    for (int k = 0; k < kFrames / 100; ++k) Append(bytes, Command(datagram * 100 + k));
    parser.ParseDatagram(bytes, frames);
  }
  const std::vector<int> got = Indices(frames);
  ASSERT_EQ(got.size(), static_cast<std::size_t>(kFrames));
  for (int i = 0; i < kFrames; ++i) ASSERT_EQ(got[i], i);
  EXPECT_EQ(parser.counts().sequence_gaps, 0u);
  EXPECT_EQ(parser.counts().skipped_bytes, 0u);
}

TEST(HostileLinkTest, SequenceGapsAreCountedPerSender) {
  FrameParser parser;
  std::vector<Frame> frames;
  for (int i : {0, 1, 2, 5, 6}) parser.ParseDatagram(Command(i, Address{7, 1}), frames);
  for (int i : {10, 11}) parser.ParseDatagram(Command(i, Address{8, 1}), frames);  // another sender: its own count
  EXPECT_EQ(parser.counts().sequence_gaps, 1u);
  EXPECT_EQ(frames.size(), 7u);
}

}  // namespace
}  // namespace uascma::mavlink
