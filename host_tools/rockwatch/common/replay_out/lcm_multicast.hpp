// LCM on this machine for `rockwatch replay` and `rockwatch demo`: the default URL (UDP multicast that stays on this
// host, ttl=0), the clocks the messages are stamped with, and the probe that tells whether multicast works here
// before anything is started, with the instructions to make it work when it does not.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <lcm/lcm-cpp.hpp>

namespace rockwatch::cli {

// The URL of `rockwatch-monitor` and `rockwatch replay` by default: multicast group and port of LCM, ttl=0 so no
// packet leaves this machine.
inline constexpr const char* kDefaultLcmUrl = "udpm://239.255.76.67:7667?ttl=0";

// CLOCK_REALTIME in µs since 1970-01-01 UTC: the utime of the messages (the host clock).
std::int64_t realtime_utime();
// CLOCK_MONOTONIC in ns: the replay's deadlines and the lateness measurements.
std::int64_t monotonic_ns();

// lcm::LCM on `url`, or null with `problem` set ("LCM could not start with URL (connect: Network is unreachable)").
// liblcm prints its own advice on standard error when it fails (ifconfig/route commands): it is captured and only
// its first line kept in `problem`, so the user reads one explanation, ours (multicast_help).
std::unique_ptr<lcm::LCM> open_lcm(const std::string& url, std::string& problem);

struct MulticastProbe {
  bool ok = false;
  double round_trip_ms = 0.0;  // publish to receive, when ok
  std::string problem;         // what failed, when not ok ("LCM could not start ...", "nothing received within 1 s")
};

// Opens `url`, subscribes a channel of its own (ROCKWATCH_PROBE_<pid>_<n>), publishes one message on it and waits up to
// `timeout_ms` for it to come back through the network stack. A udpm:// URL comes back only when multicast is
// routed on this machine (and the loopback interface accepts it); memq:// always does.
MulticastProbe probe_multicast(const std::string& url, int timeout_ms = 1000);

// What to do when the probe failed: the commands that enable multicast on the loopback interface, for a user who
// may not know what multicast is. Several lines, each ending in '\n'.
std::string multicast_help(const std::string& url, const MulticastProbe& probe);

}  // namespace rockwatch::cli
