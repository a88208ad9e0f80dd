// The monitor's own UDP multicast socket for LCM's udpm:// provider: joins the group of the URL, asks for its
// receive buffer, and hands every datagram with its source address to a DatagramInput (datagram_input.hpp). liblcm
// never reads a datagram in the live monitor: it only publishes (liblcm 1.3.1's udpm provider opens its receive
// socket on the first subscribe or handle, neither of which the monitor calls).
#pragma once

#include <cstdint>
#include <string>

#include "datagram_input.hpp"

namespace rockwatch::monitor {

struct UdpmEndpoint {
  std::uint32_t group = 0;   // IPv4 multicast group, host byte order
  std::uint16_t port = 0;
  long long receive_buffer_bytes = 0;  // recv_buf_size option; 0 = the kernel's default
};

// Parses "udpm://A.B.C.D:PORT[?opt=v&...]" (LCM's syntax; options other than recv_buf_size are the publisher's).
// False with *error saying what was expected.
bool parse_udpm_url(const std::string& url, UdpmEndpoint* out, std::string* error);

class UdpReceiver {
 public:
  UdpReceiver() = default;
  ~UdpReceiver();
  UdpReceiver(const UdpReceiver&) = delete;
  UdpReceiver& operator=(const UdpReceiver&) = delete;

  // Opens, binds the port (shared with other LCM processes: SO_REUSEADDR) and joins the group. False with *error.
  bool open(const UdpmEndpoint& endpoint, std::string* error);
  // Waits up to timeout_ms for a datagram, then receives every pending one (at most max_datagrams) into `input`,
  // stamped with clock(). Returns the number received, or −1 on a socket error (errno set; EINTR included).
  int receive(DatagramInput& input, int timeout_ms, std::int64_t (*clock)(), int max_datagrams = 4096);
  std::int64_t datagrams() const { return datagrams_; }
  std::int64_t truncated() const { return truncated_; }  // larger than the 64 KiB buffer: cut, then rejected
  long long receive_buffer_bytes() const;                 // what the kernel granted (SO_RCVBUF)
  // SO_BUSY_POLL: a receive busy-waits up to `us` µs in the driver before sleeping (after open()). False with *error
  // (above net.core.busy_read it needs CAP_NET_ADMIN).
  bool set_busy_poll(int us, std::string* error);

 private:
  int fd_ = -1;
  std::int64_t datagrams_ = 0, truncated_ = 0;
  std::uint8_t buffer_[65536]{};
};

}  // namespace rockwatch::monitor
