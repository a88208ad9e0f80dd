#include "service_notify.hpp"

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstddef>
#include <cstdlib>
#include <cstring>

namespace rockwatch::monitor {

ServiceNotifier::ServiceNotifier() {
  const char* path = std::getenv("NOTIFY_SOCKET");
  if (path == nullptr || path[0] == '\0') return;
  sockaddr_un address{};
  const std::size_t length = std::strlen(path);
  if (length >= sizeof address.sun_path || (path[0] != '/' && path[0] != '@')) return;
  address.sun_family = AF_UNIX;
  std::memcpy(address.sun_path, path, length);
  if (path[0] == '@') address.sun_path[0] = '\0';  // abstract namespace
  fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0) return;
  const socklen_t size = static_cast<socklen_t>(offsetof(sockaddr_un, sun_path) + length);
  if (::connect(fd_, reinterpret_cast<const sockaddr*>(&address), size) != 0) {
    ::close(fd_);
    fd_ = -1;
    return;
  }
  const char* usec = std::getenv("WATCHDOG_USEC");
  const char* pid = std::getenv("WATCHDOG_PID");
  const bool for_us = pid == nullptr || std::strtoll(pid, nullptr, 10) == static_cast<long long>(::getpid());
  if (usec != nullptr && for_us) {
    const long long us = std::strtoll(usec, nullptr, 10);
    if (us > 0) watchdog_ns_ = us * 1000;
  }
}

ServiceNotifier::~ServiceNotifier() {
  if (fd_ >= 0) ::close(fd_);
}

void ServiceNotifier::send(const char* text) {
  if (fd_ >= 0) (void)::send(fd_, text, std::strlen(text), MSG_NOSIGNAL);
}

void ServiceNotifier::ready() { send("READY=1"); }
void ServiceNotifier::stopping() { send("STOPPING=1"); }

void ServiceNotifier::feed(std::int64_t now_ns) {
  if (watchdog_ns_ <= 0 || now_ns - last_feed_ns_ < watchdog_ns_ / 2) return;
  last_feed_ns_ = now_ns;
  send("WATCHDOG=1");
}

}  // namespace rockwatch::monitor
