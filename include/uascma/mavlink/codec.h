#pragma once
// MAVLink v2 framing: the byte codec of a message payload and of a frame, and a frame parser that survives a
// hostile link. The messages themselves (fields, ids, CRC_EXTRA) are generated from the official XML definitions
// by scripts/mavlink_generate.py into uascma/mavlink/messages.h (data/mavlink/, SOURCE.md there).
//
// The wire format (MAVLink serialisation specification, mavlink.io "Serialization" and "Packet Format"):
//
//   byte 0      STX 0xFD (a v2 frame)
//   byte 1      LEN, the payload's length after truncation (0-255)
//   byte 2      INC_FLAGS (0x01: the frame is signed, 13 bytes of signature follow the checksum)
//   byte 3      CMP_FLAGS
//   byte 4      SEQ, the sender's frame counter (wraps at 256)
//   byte 5      SYSID, byte 6 COMPID
//   bytes 7-9   MSGID, 24 bits, little-endian
//   10 … 10+LEN the payload: the fields in wire order, little-endian, trailing zero bytes removed (at least one
//               byte kept)
//   then 2      CHECKSUM, the X.25 CRC of bytes 1 … 9+LEN and then the message's CRC_EXTRA, little-endian
//
// A receiver pads a truncated payload with zeros up to the message's length, and ignores bytes beyond it (a
// sender with newer definitions may send more extensions).
#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <map>
#include <span>
#include <utility>
#include <vector>
#include "uascma/mavlink/messages.h"

namespace uascma::mavlink {

inline constexpr std::uint8_t kStx = 0xFD;               // the v2 start byte
inline constexpr std::uint8_t kStxV1 = 0xFE;             // a MAVLink 1 frame's start byte (not spoken: skipped)
inline constexpr std::uint8_t kIncompatSigned = 0x01;    // INC_FLAGS: signed frame
inline constexpr std::size_t kHeaderLength = 10;         // bytes, STX to the end of MSGID
inline constexpr std::size_t kChecksumLength = 2;        // bytes
inline constexpr std::size_t kSignatureLength = 13;      // bytes
inline constexpr std::size_t kMaxPayloadLength = 255;    // bytes
inline constexpr std::size_t kMaxFrameLength = kHeaderLength + kMaxPayloadLength + kChecksumLength + kSignatureLength;

// The X.25 CRC (CRC-16/MCRF4XX) the checksum and CRC_EXTRA use: one byte, and a run of bytes.
std::uint16_t CrcAccumulate(std::uint8_t byte, std::uint16_t crc);
std::uint16_t CalcCrc(std::span<const std::uint8_t> bytes, std::uint16_t crc = 0xFFFF);

// The message's id, name, CRC_EXTRA and lengths; nullptr for an id the definitions do not hold.
const MessageInfo* FindMessageInfo(std::uint32_t id);

// ---- payloads ---------------------------------------------------------------------------------------------------
namespace detail {
template <class T>
void PutLittleEndian(T value, std::uint8_t*& out) {
  std::uint8_t bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(bytes, bytes + sizeof(T));
  std::memcpy(out, bytes, sizeof(T));
  out += sizeof(T);
}
template <class T>
void GetLittleEndian(T& value, const std::uint8_t*& in) {
  std::uint8_t bytes[sizeof(T)];
  std::memcpy(bytes, in, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(bytes, bytes + sizeof(T));
  std::memcpy(&value, bytes, sizeof(T));
  in += sizeof(T);
}
template <class T, std::size_t N>
void PutLittleEndian(const std::array<T, N>& values, std::uint8_t*& out) {
  for (const T& value : values) PutLittleEndian(value, out);
}
template <class T, std::size_t N>
void GetLittleEndian(std::array<T, N>& values, const std::uint8_t*& in) {
  for (T& value : values) GetLittleEndian(value, in);
}
}  // namespace detail

// A payload as sent: the fields in wire order with the trailing zeros removed (at least one byte kept).
struct Payload {
  std::array<std::uint8_t, kMaxPayloadLength> bytes{};
  std::size_t length = 0;
  std::span<const std::uint8_t> view() const { return {bytes.data(), length}; }
};

template <class M>
Payload EncodePayload(const M& message) {
  static_assert(M::kMaxLength <= kMaxPayloadLength);
  Payload payload;
  std::uint8_t* out = payload.bytes.data();
  message.VisitWire([&](const auto& field) { detail::PutLittleEndian(field, out); });
  std::size_t length = M::kMaxLength;
  while (length > 1 && payload.bytes[length - 1] == 0) --length;
  payload.length = length;
  return payload;
}

// The message from a received payload: zero-padded to its length, bytes beyond it ignored.
template <class M>
M DecodePayload(std::span<const std::uint8_t> payload) {
  std::array<std::uint8_t, kMaxPayloadLength> padded{};
  std::memcpy(padded.data(), payload.data(), std::min(payload.size(), M::kMaxLength));
  M message;
  const std::uint8_t* in = padded.data();
  message.VisitWire([&](auto& field) { detail::GetLittleEndian(field, in); });
  return message;
}

// ---- frames -----------------------------------------------------------------------------------------------------
// Who sent a frame (or sends one): MAVLink's system and component ids.
struct Address {
  std::uint8_t system_id = 0;
  std::uint8_t component_id = 0;
  auto operator<=>(const Address&) const = default;
};

// A frame received whole, its checksum checked against its message's CRC_EXTRA.
struct Frame {
  std::uint8_t sequence = 0;
  Address sender;
  std::uint32_t message_id = 0;
  std::uint8_t compat_flags = 0;
  Payload payload;
  template <class M>
  bool Is() const { return message_id == M::kId; }
  template <class M>
  M As() const { return DecodePayload<M>(payload.view()); }
};

// The bytes of one v2 frame (unsigned) carrying `payload` of the message `info`.
std::vector<std::uint8_t> EncodeFrame(const MessageInfo& info, const Payload& payload, Address sender,
                                      std::uint8_t sequence);
template <class M>
std::vector<std::uint8_t> EncodeFrame(const M& message, Address sender, std::uint8_t sequence) {
  static constexpr MessageInfo kInfo{M::kId, M::kName, M::kCrcExtra, M::kMinLength, M::kMaxLength};
  return EncodeFrame(kInfo, EncodePayload(message), sender, sequence);
}

// What a parser counted: every byte it was given is either part of a frame it delivered or counted here.
struct ParserCounts {
  std::uint64_t frames = 0;             // delivered
  std::uint64_t bad_checksum = 0;       // candidate frames whose checksum did not match
  std::uint64_t unknown_message = 0;    // candidates of an id the definitions do not hold (unverifiable)
  std::uint64_t signed_frames = 0;      // signed frames (signing is not supported: dropped whole)
  std::uint64_t unsupported_flags = 0;  // candidates with an incompatibility flag other than signing
  std::uint64_t truncated = 0;          // datagrams that ended inside a frame
  std::uint64_t skipped_bytes = 0;      // bytes outside any frame (noise, MAVLink 1, a rejected frame's bytes)
  std::uint64_t sequence_gaps = 0;      // frames missed by a sender, from its SEQ (lost or reordered on the link)
  bool operator==(const ParserCounts&) const = default;
};

// The frame parser: bytes in, frames out, in the order their bytes arrived. A candidate that fails (checksum,
// flags, an id the definitions do not hold, whose checksum and so whose LEN cannot be checked) costs one byte: the
// search for the next STX starts right after its STX, so a frame hidden behind noise or behind a truncated frame is
// still found (the reference parsers skip a failed frame whole, which lets a noise byte 0xFD swallow the next
// frame). Only a frame whose checksum holds is consumed whole. Memory is bounded: at most one frame's bytes wait.
class FrameParser {
 public:
  // Appends `bytes` of a stream (a serial port) and delivers every complete frame to `out`.
  void Parse(std::span<const std::uint8_t> bytes, std::vector<Frame>& out);
  // One datagram (UDP): its frames; whatever is left of an incomplete frame at its end is counted as truncated
  // and dropped, so one bad datagram cannot affect the next.
  void ParseDatagram(std::span<const std::uint8_t> datagram, std::vector<Frame>& out);
  const ParserCounts& counts() const { return counts_; }

 private:
  // Tries a frame at pending_[start] (an STX). Returns the bytes consumed, 0 when more bytes are needed.
  std::size_t TryFrame(std::size_t start, std::vector<Frame>& out);
  void NoteSequence(const Frame& frame);
  std::vector<std::uint8_t> pending_;
  ParserCounts counts_;
  std::map<Address, std::uint8_t> last_sequence_;
};

}  // namespace uascma::mavlink
