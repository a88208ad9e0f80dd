#include "udp_ipv4.hpp"

#include <cstring>

namespace rockwatch::m4 {

namespace {

std::uint16_t be16(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] << 8 | p[1]); }
std::uint32_t be32(const std::uint8_t* p) {
  return std::uint32_t{p[0]} << 24 | std::uint32_t{p[1]} << 16 | std::uint32_t{p[2]} << 8 | p[3];
}
void put16(std::uint8_t* p, std::uint32_t v) {
  p[0] = static_cast<std::uint8_t>(v >> 8);
  p[1] = static_cast<std::uint8_t>(v);
}
void put32(std::uint8_t* p, std::uint32_t v) {
  put16(p, v >> 16);
  put16(p + 2, v);
}

constexpr std::size_t kEth = 14, kIp = 20, kUdp = 8;

}  // namespace

std::uint32_t internet_sum(const std::uint8_t* data, std::size_t size, std::uint32_t sum) {
  std::size_t i = 0;
  for (; i + 1 < size; i += 2) sum += be16(data + i);
  if (i < size) sum += std::uint32_t{data[i]} << 8;
  return sum;
}

std::uint16_t internet_fold(std::uint32_t sum) {
  while ((sum >> 16) != 0) sum = (sum & 0xffffu) + (sum >> 16);
  return static_cast<std::uint16_t>(sum);
}

void UdpPath::init(const UdpEndpoint& local, std::uint32_t group_ipv4, std::uint16_t group_port) {
  local_ = local;
  group_ = group_ipv4;
  port_ = group_port;
  const std::uint8_t mac[6] = {0x01, 0x00, 0x5e, static_cast<std::uint8_t>((group_ipv4 >> 16) & 0x7fu),
                               static_cast<std::uint8_t>(group_ipv4 >> 8), static_cast<std::uint8_t>(group_ipv4)};
  std::memcpy(group_mac_, mac, sizeof mac);
}

bool UdpPath::accept_frame(const std::uint8_t* f, std::size_t size, UdpDatagram* out) {
  ++counters_.frames;
  if (size < kEth || be16(f + 12) != 0x0800u) {
    ++counters_.not_ipv4;
    return false;
  }
  const std::uint8_t* ip = f + kEth;
  const std::size_t ip_room = size - kEth;  // the frame may carry padding after the datagram
  if (ip_room < kIp || ip[0] != 0x45u) {  // version 4, 20-byte header (options: not accepted)
    ++counters_.ip_malformed;
    return false;
  }
  const std::size_t total = be16(ip + 2);
  if (total < kIp || total > ip_room || internet_fold(internet_sum(ip, kIp, 0)) != 0xffffu) {
    ++counters_.ip_malformed;
    return false;
  }
  if ((be16(ip + 6) & 0x3fffu) != 0) {  // MF or a fragment offset
    ++counters_.ip_fragments;
    return false;
  }
  if (ip[9] != 17) {
    ++counters_.not_udp;
    return false;
  }
  const std::uint32_t dst = be32(ip + 16);
  const std::uint8_t* udp = ip + kIp;
  const std::size_t udp_room = total - kIp;
  if (udp_room < kUdp) {
    ++counters_.udp_malformed;
    return false;
  }
  if ((dst != group_ && dst != local_.ipv4) || be16(udp + 2) != port_) {
    ++counters_.not_for_us;
    return false;
  }
  const std::size_t udp_length = be16(udp + 4);
  if (udp_length < kUdp || udp_length > udp_room) {
    ++counters_.udp_malformed;
    return false;
  }
  const std::uint16_t checksum = be16(udp + 6);
  if (checksum != 0) {
    // Pseudo-header: source, destination, protocol, UDP length; then the UDP header and data.
    std::uint32_t sum = internet_sum(ip + 12, 8, 0) + 17u + static_cast<std::uint32_t>(udp_length);
    sum = internet_sum(udp, udp_length, sum);
    if (internet_fold(sum) != 0xffffu) {
      ++counters_.udp_malformed;
      return false;
    }
  }
  ++counters_.datagrams;
  out->payload = udp + kUdp;
  out->size = udp_length - kUdp;
  out->source_ipv4 = be32(ip + 12);
  out->source_port = be16(udp);
  return true;
}

std::size_t UdpPath::build_frame(const std::uint8_t* payload, std::size_t size, std::uint8_t* f,
                                 std::size_t capacity) {
  if (size > kMaxPayload || capacity < kHeaderBytes + size) return 0;
  std::memcpy(f, group_mac_, 6);
  std::memcpy(f + 6, local_.mac, 6);
  put16(f + 12, 0x0800u);
  std::uint8_t* ip = f + kEth;
  ip[0] = 0x45;
  ip[1] = 0;
  put16(ip + 2, static_cast<std::uint32_t>(kIp + kUdp + size));
  put16(ip + 4, ++ip_id_);
  put16(ip + 6, 0x4000u);  // don't fragment
  ip[8] = 1;               // TTL: one hop (a host-only network)
  ip[9] = 17;
  put16(ip + 10, 0);
  put32(ip + 12, local_.ipv4);
  put32(ip + 16, group_);
  put16(ip + 10, static_cast<std::uint16_t>(~internet_fold(internet_sum(ip, kIp, 0))));
  std::uint8_t* udp = ip + kIp;
  put16(udp, local_.port);
  put16(udp + 2, port_);
  put16(udp + 4, static_cast<std::uint32_t>(kUdp + size));
  put16(udp + 6, 0);  // no checksum (RFC 768; IPv4)
  std::memcpy(udp + kUdp, payload, size);
  std::size_t length = kHeaderBytes + size;
  if (length < 60) {  // the Ethernet minimum (without FCS): pad
    std::memset(f + length, 0, 60 - length);
    length = 60;
  }
  return length;
}

}  // namespace rockwatch::m4
