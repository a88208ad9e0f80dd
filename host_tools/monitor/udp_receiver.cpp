#include "udp_receiver.hpp"

#include "lcm_transport.hpp"  // requested_receive_buffer

#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>

namespace rockwatch::monitor {

bool parse_udpm_url(const std::string& url, UdpmEndpoint* out, std::string* error) {
  const std::string scheme = "udpm://";
  if (url.rfind(scheme, 0) != 0) {
    *error = "expected a udpm://GROUP:PORT URL (the live monitor receives LCM's UDP multicast only)";
    return false;
  }
  const std::size_t query = url.find('?');
  const std::string address = url.substr(scheme.size(), query == std::string::npos ? std::string::npos
                                                                                    : query - scheme.size());
  const std::size_t colon = address.rfind(':');
  if (colon == std::string::npos) {
    *error = "expected udpm://GROUP:PORT, found no port in " + address;
    return false;
  }
  in_addr group{};
  if (inet_pton(AF_INET, address.substr(0, colon).c_str(), &group) != 1 ||
      (ntohl(group.s_addr) >> 28) != 0xEu) {
    *error = "expected an IPv4 multicast group (224.0.0.0/4), found " + address.substr(0, colon);
    return false;
  }
  const std::string port_text = address.substr(colon + 1);
  char* end = nullptr;
  const long port = std::strtol(port_text.c_str(), &end, 10);
  if (port_text.empty() || end == nullptr || *end != '\0' || port < 1 || port > 65535) {
    *error = "expected a port in 1..65535, found " + port_text;
    return false;
  }
  out->group = ntohl(group.s_addr);
  out->port = static_cast<std::uint16_t>(port);
  out->receive_buffer_bytes = requested_receive_buffer(url);
  return true;
}

UdpReceiver::~UdpReceiver() {
  if (fd_ >= 0) ::close(fd_);
}

bool UdpReceiver::open(const UdpmEndpoint& endpoint, std::string* error) {
  fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd_ < 0) {
    *error = std::string("socket: ") + std::strerror(errno);
    return false;
  }
  const int one = 1;
  if (::setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one) != 0) {
    *error = std::string("SO_REUSEADDR: ") + std::strerror(errno);
    return false;
  }
  if (endpoint.receive_buffer_bytes > 0) {
    const int bytes = endpoint.receive_buffer_bytes > 0x7fffffffLL ? 0x7fffffff
                                                                    : static_cast<int>(endpoint.receive_buffer_bytes);
    (void)::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &bytes, sizeof bytes);  // capped by rmem_max: said at start
  }
  sockaddr_in local{};
  local.sin_family = AF_INET;
  local.sin_addr.s_addr = htonl(INADDR_ANY);
  local.sin_port = htons(endpoint.port);
  if (::bind(fd_, reinterpret_cast<const sockaddr*>(&local), sizeof local) != 0) {
    *error = "bind to port " + std::to_string(endpoint.port) + ": " + std::strerror(errno);
    return false;
  }
  ip_mreq membership{};
  membership.imr_multiaddr.s_addr = htonl(endpoint.group);
  membership.imr_interface.s_addr = htonl(INADDR_ANY);
  if (::setsockopt(fd_, IPPROTO_IP, IP_ADD_MEMBERSHIP, &membership, sizeof membership) != 0) {
    *error = std::string("joining the multicast group: ") + std::strerror(errno) +
             " (no multicast route? see `ip route` for 224.0.0.0/4)";
    return false;
  }
  return true;
}

int UdpReceiver::receive(DatagramInput& input, int timeout_ms, std::int64_t (*clock)(), int max_datagrams) {
  pollfd p{fd_, POLLIN, 0};
  const int ready = ::poll(&p, 1, timeout_ms);
  if (ready < 0) return -1;
  if (ready == 0) return 0;
  int received = 0;
  while (received < max_datagrams) {
    sockaddr_in from{};
    socklen_t from_size = sizeof from;
    const ssize_t n = ::recvfrom(fd_, buffer_, sizeof buffer_, MSG_TRUNC, reinterpret_cast<sockaddr*>(&from),
                                 &from_size);
    if (n < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK) break;
      if (errno == EINTR) continue;
      return received > 0 ? received : -1;
    }
    ++datagrams_;
    ++received;
    std::size_t size = static_cast<std::size_t>(n);
    if (size > sizeof buffer_) {  // MSG_TRUNC reports the datagram's real length
      ++truncated_;
      size = sizeof buffer_;
    }
    const firmware::DatagramSource source{ntohl(from.sin_addr.s_addr), ntohs(from.sin_port)};
    input.on_datagram(buffer_, size, source, clock());
  }
  return received;
}

bool UdpReceiver::set_busy_poll(int us, std::string* error) {
  if (fd_ < 0) {
    *error = "SO_BUSY_POLL: the socket is not open";
    return false;
  }
  if (::setsockopt(fd_, SOL_SOCKET, SO_BUSY_POLL, &us, sizeof us) != 0) {
    const int code = errno;
    *error = std::string("SO_BUSY_POLL ") + std::to_string(us) + " us: " + std::strerror(code) +
             (code == EPERM ? " (above net.core.busy_read it needs CAP_NET_ADMIN)" : "");
    return false;
  }
  return true;
}

long long UdpReceiver::receive_buffer_bytes() const {
  int bytes = 0;
  socklen_t size = sizeof bytes;
  if (fd_ < 0 || ::getsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &bytes, &size) != 0) return -1;
  return bytes;
}

}  // namespace rockwatch::monitor
