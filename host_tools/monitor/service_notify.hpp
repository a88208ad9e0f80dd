// systemd's service notification protocol, without libsystemd: datagrams "READY=1", "WATCHDOG=1", "STOPPING=1" to
// the unix socket named by $NOTIFY_SOCKET (a path, or an abstract name starting with '@'). With WatchdogSec= in the
// unit, systemd sets $WATCHDOG_USEC and restarts the monitor when it stops sending WATCHDOG=1 for that long; the
// monitor sends it from its receive loop (every half period), so a monitor stuck anywhere is restarted.
// Without $NOTIFY_SOCKET every call does nothing.
#pragma once

#include <cstdint>

namespace rockwatch::monitor {

class ServiceNotifier {
 public:
  ServiceNotifier();  // reads $NOTIFY_SOCKET and $WATCHDOG_USEC (and $WATCHDOG_PID: only for this process)
  ~ServiceNotifier();
  ServiceNotifier(const ServiceNotifier&) = delete;
  ServiceNotifier& operator=(const ServiceNotifier&) = delete;

  bool active() const { return fd_ >= 0; }
  void ready();
  void stopping();
  // Sends WATCHDOG=1 when half the watchdog period has passed since the last one (now_ns: CLOCK_MONOTONIC).
  void feed(std::int64_t now_ns);
  std::int64_t watchdog_period_ns() const { return watchdog_ns_; }

 private:
  void send(const char* text);
  int fd_ = -1;
  std::int64_t watchdog_ns_ = 0;  // 0: no watchdog
  std::int64_t last_feed_ns_ = 0;
};

}  // namespace rockwatch::monitor
