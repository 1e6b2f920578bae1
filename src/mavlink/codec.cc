#include "uascma/mavlink/codec.h"

#include <algorithm>

namespace uascma::mavlink {

std::uint16_t CrcAccumulate(std::uint8_t byte, std::uint16_t crc) {
  // The X.25 CRC one byte at a time, as the MAVLink specification writes it (checksum.h of the reference library
  // computes the same function): tmp = byte ^ low(crc); tmp ^= tmp << 4 (8 bits);
  // crc = (crc >> 8) ^ (tmp << 8) ^ (tmp << 3) ^ (tmp >> 4).
  std::uint8_t tmp = static_cast<std::uint8_t>(byte ^ static_cast<std::uint8_t>(crc & 0xFF));
  tmp = static_cast<std::uint8_t>(tmp ^ static_cast<std::uint8_t>(tmp << 4));
  return static_cast<std::uint16_t>((crc >> 8) ^ (static_cast<std::uint16_t>(tmp) << 8) ^
                                    (static_cast<std::uint16_t>(tmp) << 3) ^ (static_cast<std::uint16_t>(tmp) >> 4));
}

std::uint16_t CalcCrc(std::span<const std::uint8_t> bytes, std::uint16_t crc) {
  for (std::uint8_t byte : bytes) crc = CrcAccumulate(byte, crc);
  return crc;
}

const MessageInfo* FindMessageInfo(std::uint32_t id) {
  const auto it = std::lower_bound(kMessageInfos.begin(), kMessageInfos.end(), id,
                                   [](const MessageInfo& info, std::uint32_t key) { return info.id < key; });
  return (it != kMessageInfos.end() && it->id == id) ? &*it : nullptr;
}

std::vector<std::uint8_t> EncodeFrame(const MessageInfo& info, const Payload& payload, Address sender,
                                      std::uint8_t sequence) {
  std::vector<std::uint8_t> frame;
  frame.reserve(kHeaderLength + payload.length + kChecksumLength);
  frame.push_back(kStx);
  frame.push_back(static_cast<std::uint8_t>(payload.length));
  frame.push_back(0);  // INC_FLAGS: unsigned
  frame.push_back(0);  // CMP_FLAGS
  frame.push_back(sequence);
  frame.push_back(sender.system_id);
  frame.push_back(sender.component_id);
  frame.push_back(static_cast<std::uint8_t>(info.id & 0xFF));
  frame.push_back(static_cast<std::uint8_t>((info.id >> 8) & 0xFF));
  frame.push_back(static_cast<std::uint8_t>((info.id >> 16) & 0xFF));
  frame.insert(frame.end(), payload.bytes.begin(), payload.bytes.begin() + static_cast<std::ptrdiff_t>(payload.length));
  std::uint16_t crc = CalcCrc(std::span(frame).subspan(1));
  crc = CrcAccumulate(info.crc_extra, crc);
  frame.push_back(static_cast<std::uint8_t>(crc & 0xFF));
  frame.push_back(static_cast<std::uint8_t>(crc >> 8));
  return frame;
}

void FrameParser::NoteSequence(const Frame& frame) {
  const auto [it, first] = last_sequence_.try_emplace(frame.sender, frame.sequence);
  if (!first) {
    const std::uint8_t expected = static_cast<std::uint8_t>(it->second + 1);
    if (frame.sequence != expected) ++counts_.sequence_gaps;
    it->second = frame.sequence;
  }
}

std::size_t FrameParser::TryFrame(std::size_t start, std::vector<Frame>& out) {
  const std::size_t available = pending_.size() - start;
  if (available < kHeaderLength) return 0;
  const std::uint8_t* p = pending_.data() + start;
  const std::size_t length = p[1];
  const std::uint8_t incompat = p[2];
  if ((incompat & ~kIncompatSigned) != 0) {
    ++counts_.unsupported_flags;
    ++counts_.skipped_bytes;
    return 1;
  }
  const bool is_signed = (incompat & kIncompatSigned) != 0;
  const std::size_t total = kHeaderLength + length + kChecksumLength + (is_signed ? kSignatureLength : 0);
  if (available < total) return 0;
  const std::uint32_t id = p[7] | (static_cast<std::uint32_t>(p[8]) << 8) | (static_cast<std::uint32_t>(p[9]) << 16);
  const MessageInfo* info = FindMessageInfo(id);
  if (info == nullptr) {  // the checksum cannot be checked, so nor can LEN: resynchronise after the STX
    ++counts_.unknown_message;
    ++counts_.skipped_bytes;
    return 1;
  }
  std::uint16_t crc = CalcCrc(std::span(p + 1, kHeaderLength - 1 + length));
  crc = CrcAccumulate(info->crc_extra, crc);
  const std::uint16_t sent = static_cast<std::uint16_t>(p[kHeaderLength + length] |
                                                        (p[kHeaderLength + length + 1] << 8));
  if (crc != sent) {
    ++counts_.bad_checksum;
    ++counts_.skipped_bytes;
    return 1;
  }
  if (is_signed) {
    ++counts_.signed_frames;
    counts_.skipped_bytes += total;
    return total;
  }
  Frame frame;
  frame.sequence = p[4];
  frame.sender = Address{p[5], p[6]};
  frame.message_id = id;
  frame.compat_flags = p[3];
  std::copy(p + kHeaderLength, p + kHeaderLength + length, frame.payload.bytes.begin());
  frame.payload.length = length;
  NoteSequence(frame);
  ++counts_.frames;
  out.push_back(frame);
  return total;
}

void FrameParser::Parse(std::span<const std::uint8_t> bytes, std::vector<Frame>& out) {
  pending_.insert(pending_.end(), bytes.begin(), bytes.end());
  std::size_t position = 0;
  while (position < pending_.size()) {
    if (pending_[position] != kStx) {
      ++counts_.skipped_bytes;
      ++position;
      continue;
    }
    const std::size_t consumed = TryFrame(position, out);
    if (consumed == 0) break;  // wait for the rest of the frame
    position += consumed;
  }
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(position));
}

void FrameParser::ParseDatagram(std::span<const std::uint8_t> datagram, std::vector<Frame>& out) {
  Parse(datagram, out);
  // What is left is the start of a frame the datagram did not hold whole: rescan it byte by byte after its STX,
  // since a shorter frame may start inside it.
  if (!pending_.empty()) ++counts_.truncated;
  while (!pending_.empty()) {
    ++counts_.skipped_bytes;
    std::vector<std::uint8_t> rest(pending_.begin() + 1, pending_.end());
    pending_.clear();
    Parse(rest, out);
  }
}

}  // namespace uascma::mavlink
