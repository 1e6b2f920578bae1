#pragma once
// MAVLink over UDP as ground stations address it (MAVProxy's and QGroundControl's notation):
//
//   udp:HOST:PORT     listen on HOST:PORT; every peer that sent a valid frame is answered (a ground station or
//                     a companion that connects to us)
//   udpout:HOST:PORT  send to a ground station listening on HOST:PORT (MAVProxy's --out); it is answered too
//
// One UDP datagram carries whole frames; each datagram is parsed apart (FrameParser::ParseDatagram), so a torn
// datagram cannot affect the next one.
#include <netinet/in.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "uascma/mavlink/codec.h"
#include "uascma/mavlink/mission_server.h"

namespace uascma::mavlink {

struct LinkAddress {
  enum class Kind { kListen, kSendTo };
  Kind kind = Kind::kListen;
  std::string host;
  std::uint16_t port = 0;
};

// Parses "udp:HOST:PORT" or "udpout:HOST:PORT" (HOST an IPv4 address or "localhost"); InputError naming `source`
// (the option) otherwise.
LinkAddress ParseLinkAddress(const std::string& text, const std::string& source);

// One frame received, with the endpoint it came from.
struct ReceivedFrame {
  Frame frame;
  sockaddr_in from{};
};

// A set of UDP endpoints. Not thread-safe; sockets are non-blocking and closed on destruction.
class UdpLink {
 public:
  explicit UdpLink(const std::vector<LinkAddress>& addresses);
  ~UdpLink();
  UdpLink(const UdpLink&) = delete;
  UdpLink& operator=(const UdpLink&) = delete;
  // Sends the bytes of one or more frames as one datagram to every known peer.
  void Send(std::span<const std::uint8_t> bytes);
  // Waits up to `timeout_s` for datagrams (0: only those already there) and returns the valid frames, in order of
  // arrival. A sender of a valid frame becomes a peer of the endpoint it reached.
  std::vector<ReceivedFrame> Receive(double timeout_s);
  // The port an endpoint is bound to (the one chosen by the system for port 0).
  std::uint16_t bound_port(std::size_t endpoint) const;
  ParserCounts counts() const;
  std::size_t peer_count() const;

 private:
  struct Endpoint {
    int socket = -1;
    FrameParser parser;
    std::vector<sockaddr_in> peers;
  };
  std::vector<Endpoint> endpoints_;
};

// "udp:HOST:PORT" of each listening endpoint of `addresses` (the addresses `link` was made from), with the port it is
// bound to (the one the system chose for port 0): what the commands print for a client to connect.
std::vector<std::string> ListeningAddresses(const std::vector<LinkAddress>& addresses, const UdpLink& link);

// Sends queued messages from `self`, each in its own frame with the next sequence number, packed into datagrams of at
// most kDatagramBytes (several frames a datagram, as MAVLink over UDP allows: one datagram per epoch instead of
// twenty).
class FrameSender {
 public:
  static constexpr std::size_t kDatagramBytes = 1400;  // ours: below a 1500-byte Ethernet MTU with the IP/UDP headers
  FrameSender(UdpLink& link, Address self) : link_(link), self_(self) {}
  // Sends and clears `out`.
  void Flush(std::vector<Outgoing>& out);

 private:
  UdpLink& link_;
  Address self_;
  std::uint8_t sequence_ = 0;
};

}  // namespace uascma::mavlink
