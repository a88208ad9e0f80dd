// The in-memory transport of the monitor loop's unit tests (test_firmware): keeps every message the loop publishes and
// decodes them by channel; encode() makes the bytes of an input message. One home for the three suites that drive a
// MonitorLoop or MultiWallMonitor in memory (end-to-end tests use real UDP multicast instead).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "rockwatch/firmware/monitor_loop.hpp"

#include <CppUTest/TestHarness.h>

namespace rockwatch::test {

struct Published {
  std::string channel;
  std::vector<std::uint8_t> bytes;
};

class MemoryTransport : public firmware::Transport {
 public:
  bool publish(const char* channel, const std::uint8_t* data, std::size_t size) override {
    if (fail) return false;
    sent.push_back(Published{channel, std::vector<std::uint8_t>(data, data + size)});
    return true;
  }
  // The messages published on `channel`, in order.
  std::vector<Published> on(const std::string& channel) const {
    std::vector<Published> out;
    for (const Published& p : sent) {
      if (p.channel == channel) out.push_back(p);
    }
    return out;
  }
  // The same, decoded (each must decode whole).
  template <typename T>
  std::vector<T> decoded(const std::string& channel) const {
    std::vector<T> out;
    for (const Published& p : on(channel)) {
      T m;
      LONGS_EQUAL(static_cast<long>(p.bytes.size()), m.decode(p.bytes.data(), 0, static_cast<int>(p.bytes.size())));
      out.push_back(m);
    }
    return out;
  }
  // On the default channels.
  std::vector<wall_state_t> states() const { return decoded<wall_state_t>("ROCKWATCH_WALL_STATE"); }
  std::vector<alarm_event_t> alarms() const { return decoded<alarm_event_t>("ROCKWATCH_ALARM"); }
  std::vector<monitor_status_t> statuses() const { return decoded<monitor_status_t>("ROCKWATCH_STATUS"); }
  std::vector<wall_estimate_t> estimates() const { return decoded<wall_estimate_t>("ROCKWATCH_WALL_ESTIMATE"); }

  bool fail = false;  // publish() refuses while set (a transport that cannot send)
  std::vector<Published> sent;
};

template <typename T>
std::vector<std::uint8_t> encode(const T& m) {
  std::vector<std::uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
  LONGS_EQUAL(static_cast<long>(b.size()), m.encode(b.data(), 0, static_cast<int>(b.size())));
  return b;
}

}  // namespace rockwatch::test
