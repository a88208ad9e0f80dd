// The monitor image's own IPv4/UDP path (no IP stack): what a host's kernel does for one UDP socket bound to the LCM
// port and joined to the LCM multicast group, and no more. In: Ethernet II frames; IPv4 without options and not
// fragmented (anything else is counted and dropped, as LCM never sends those for the monitor's messages), the header
// checksum checked, UDP to the group (or the image's own address) and the port, its length checked and its checksum
// checked when not 0 (RFC 768: 0 = none). Out: one frame per datagram to the group's multicast MAC
// (01:00:5e + the low 23 bits of the group), IPv4 header checksum generated, UDP checksum 0 (legal for IPv4).
// ARP and IGMP are not needed: the image sends only to the multicast group, on a network the script owns.
// Every function is bounded: one pass over the frame's bytes.
#pragma once

#include <cstddef>
#include <cstdint>

namespace rockwatch::m4 {

struct UdpEndpoint {
  std::uint8_t mac[6] = {};
  std::uint32_t ipv4 = 0;  // host byte order
  std::uint16_t port = 0;
};

// What the receive path did with the frames it was given (each counted once).
struct NetCounters {
  std::int64_t frames = 0;              // frames given to accept_frame()
  std::int64_t not_ipv4 = 0;            // another EtherType (ARP, IPv6, ...) or shorter than an Ethernet header
  std::int64_t ip_malformed = 0;        // IPv4 header: version, options, lengths, checksum
  std::int64_t ip_fragments = 0;        // fragmented datagrams (MF or an offset): not reassembled
  std::int64_t not_udp = 0;             // another protocol
  std::int64_t not_for_us = 0;          // another destination address or port
  std::int64_t udp_malformed = 0;       // UDP length or checksum
  std::int64_t datagrams = 0;           // UDP datagrams delivered to the LCM layer
  std::int64_t sent = 0, send_failures = 0;
};

struct UdpDatagram {
  const std::uint8_t* payload = nullptr;
  std::size_t size = 0;
  std::uint32_t source_ipv4 = 0;  // host byte order
  std::uint16_t source_port = 0;
};

class UdpPath {
 public:
  // local: the image's MAC, address and (source) port; group: the multicast group and the LCM port.
  void init(const UdpEndpoint& local, std::uint32_t group_ipv4, std::uint16_t group_port);
  // A received frame: true and *out when it carries a UDP datagram for the group (or the image) and the port.
  bool accept_frame(const std::uint8_t* frame, std::size_t size, UdpDatagram* out);
  // Builds the frame carrying `payload` to the group's port into `frame` (capacity ≥ 42 + size); its length, or 0
  // when it does not fit one frame (1472 bytes of payload).
  std::size_t build_frame(const std::uint8_t* payload, std::size_t size, std::uint8_t* frame, std::size_t capacity);

  NetCounters& counters() { return counters_; }
  const NetCounters& counters() const { return counters_; }

  static constexpr std::size_t kHeaderBytes = 14 + 20 + 8;
  static constexpr std::size_t kMaxPayload = 1500 - 20 - 8;

 private:
  UdpEndpoint local_{};
  std::uint32_t group_ = 0;
  std::uint16_t port_ = 0;
  std::uint8_t group_mac_[6] = {};
  std::uint16_t ip_id_ = 0;
  NetCounters counters_{};
};

// The Internet checksum (RFC 1071) of `size` bytes, added to `sum` (not yet folded or complemented).
std::uint32_t internet_sum(const std::uint8_t* data, std::size_t size, std::uint32_t sum);
std::uint16_t internet_fold(std::uint32_t sum);

}  // namespace rockwatch::m4
