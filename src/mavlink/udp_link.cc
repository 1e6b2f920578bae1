#include "uascma/mavlink/udp_link.h"

#include <arpa/inet.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>

#include "uascma/common/error.h"

namespace uascma::mavlink {
namespace {

constexpr std::size_t kDatagramBytes = 65536;       // the largest UDP datagram
constexpr int kReceiveBufferBytes = 4 * 1024 * 1024;  // ours: 4 MiB, a second of a 10,000-frame/s flood

sockaddr_in MakeAddress(const std::string& host, std::uint16_t port, const std::string& source) {
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  const std::string numeric = host == "localhost" ? "127.0.0.1" : host;
  if (inet_pton(AF_INET, numeric.c_str(), &address.sin_addr) != 1)
    throw InputError(source, "HOST", "an IPv4 address or localhost, got \"" + host + "\"");
  return address;
}

bool SamePeer(const sockaddr_in& a, const sockaddr_in& b) {
  return a.sin_addr.s_addr == b.sin_addr.s_addr && a.sin_port == b.sin_port;
}

}  // namespace

LinkAddress ParseLinkAddress(const std::string& text, const std::string& source) {
  const std::string expected = "udp:HOST:PORT or udpout:HOST:PORT, got \"" + text + "\"";
  const auto first = text.find(':');
  const auto last = text.rfind(':');
  if (first == std::string::npos || first == last) throw InputError(source, "address", expected);
  LinkAddress address;
  const std::string scheme = text.substr(0, first);
  if (scheme == "udp") {
    address.kind = LinkAddress::Kind::kListen;
  } else if (scheme == "udpout") {
    address.kind = LinkAddress::Kind::kSendTo;
  } else {
    throw InputError(source, "address", expected);
  }
  address.host = text.substr(first + 1, last - first - 1);
  const std::string port = text.substr(last + 1);
  unsigned value = 0;
  const auto [end, error] = std::from_chars(port.data(), port.data() + port.size(), value);
  if (error != std::errc{} || end != port.data() + port.size() || value > 65535)
    throw InputError(source, "PORT", "an integer from 0 to 65535, got \"" + port + "\"");
  address.port = static_cast<std::uint16_t>(value);
  MakeAddress(address.host, address.port, source);  // checks HOST
  return address;
}

UdpLink::UdpLink(const std::vector<LinkAddress>& addresses) {
  for (const LinkAddress& address : addresses) {
    Endpoint endpoint;
    endpoint.socket = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (endpoint.socket < 0) throw InputError("--mavlink", "socket", std::strerror(errno));
    // Room for a burst (a flood, or a peer that reads late): the kernel caps it at net.core.rmem_max.
    const int buffer_bytes = kReceiveBufferBytes;
    setsockopt(endpoint.socket, SOL_SOCKET, SO_RCVBUF, &buffer_bytes, sizeof buffer_bytes);
    const sockaddr_in target = MakeAddress(address.host, address.port, "--mavlink");
    if (address.kind == LinkAddress::Kind::kListen) {
      const int yes = 1;
      setsockopt(endpoint.socket, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
      if (bind(endpoint.socket, reinterpret_cast<const sockaddr*>(&target), sizeof target) != 0) {
        const std::string why = std::strerror(errno);
        close(endpoint.socket);
        throw InputError("--mavlink", "udp:" + address.host + ":" + std::to_string(address.port),
                         "an address this machine can listen on (" + why + ")");
      }
    } else {
      endpoint.peers.push_back(target);
    }
    endpoints_.push_back(std::move(endpoint));
  }
}

UdpLink::~UdpLink() {
  for (const Endpoint& endpoint : endpoints_) close(endpoint.socket);
}

void UdpLink::Send(std::span<const std::uint8_t> bytes) {
  for (const Endpoint& endpoint : endpoints_) {
    for (const sockaddr_in& peer : endpoint.peers) {
      // A full socket buffer or an unreachable peer loses this datagram, as a radio link would: not an error.
      sendto(endpoint.socket, bytes.data(), bytes.size(), MSG_DONTWAIT, reinterpret_cast<const sockaddr*>(&peer),
             sizeof peer);
    }
  }
}

std::vector<ReceivedFrame> UdpLink::Receive(double timeout_s) {
  std::vector<pollfd> polls;
  for (const Endpoint& endpoint : endpoints_) polls.push_back(pollfd{endpoint.socket, POLLIN, 0});
  const int timeout_ms = timeout_s > 0 ? static_cast<int>(timeout_s * 1000.0 + 0.5) : 0;
  std::vector<ReceivedFrame> received;
  if (poll(polls.data(), polls.size(), timeout_ms) <= 0) return received;
  std::vector<std::uint8_t> buffer(kDatagramBytes);
  std::vector<Frame> frames;
  for (Endpoint& endpoint : endpoints_) {
    for (;;) {
      sockaddr_in from{};
      socklen_t from_length = sizeof from;
      const ssize_t n = recvfrom(endpoint.socket, buffer.data(), buffer.size(), 0, reinterpret_cast<sockaddr*>(&from),
                                 &from_length);
      if (n < 0) break;  // EAGAIN: nothing more now
      frames.clear();
      endpoint.parser.ParseDatagram(std::span(buffer.data(), static_cast<std::size_t>(n)), frames);
      if (frames.empty()) continue;
      bool known = false;
      for (const sockaddr_in& peer : endpoint.peers) known = known || SamePeer(peer, from);
      if (!known) endpoint.peers.push_back(from);
      for (const Frame& frame : frames) received.push_back(ReceivedFrame{frame, from});
    }
  }
  return received;
}

std::uint16_t UdpLink::bound_port(std::size_t endpoint) const {
  sockaddr_in address{};
  socklen_t length = sizeof address;
  getsockname(endpoints_.at(endpoint).socket, reinterpret_cast<sockaddr*>(&address), &length);
  return ntohs(address.sin_port);
}

ParserCounts UdpLink::counts() const {
  ParserCounts total;
  for (const Endpoint& endpoint : endpoints_) {
    const ParserCounts& c = endpoint.parser.counts();
    total.frames += c.frames;
    total.bad_checksum += c.bad_checksum;
    total.unknown_message += c.unknown_message;
    total.signed_frames += c.signed_frames;
    total.unsupported_flags += c.unsupported_flags;
    total.truncated += c.truncated;
    total.skipped_bytes += c.skipped_bytes;
    total.sequence_gaps += c.sequence_gaps;
  }
  return total;
}

std::size_t UdpLink::peer_count() const {
  std::size_t count = 0;
  for (const Endpoint& endpoint : endpoints_) count += endpoint.peers.size();
  return count;
}

std::vector<std::string> ListeningAddresses(const std::vector<LinkAddress>& addresses, const UdpLink& link) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < addresses.size(); ++i) {
    if (addresses[i].kind == LinkAddress::Kind::kListen) {
      out.push_back("udp:" + addresses[i].host + ":" + std::to_string(link.bound_port(i)));
    }
  }
  return out;
}

void FrameSender::Flush(std::vector<Outgoing>& out) {
  std::vector<std::uint8_t> datagram;
  for (const Outgoing& message : out) {
    const std::vector<std::uint8_t> frame = EncodeFrame(message.info, message.payload, self_, sequence_++);
    if (datagram.size() + frame.size() > kDatagramBytes) {
      link_.Send(datagram);
      datagram.clear();
    }
    datagram.insert(datagram.end(), frame.begin(), frame.end());
  }
  if (!datagram.empty()) link_.Send(datagram);
  out.clear();
}

}  // namespace uascma::mavlink
