// The Linux adapter of the monitor loop (issue 7): firmware::Transport over liblcm, the subscription that hands the
// raw bytes of the two input channels to MonitorLoop::on_message, the clocks, and the offline transport that writes
// an LCM log instead of sending.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include <lcm/lcm-cpp.hpp>

#include "rockwatch/firmware/monitor_loop.hpp"

namespace rockwatch::monitor {

// CLOCK_REALTIME in µs since 1970-01-01 UTC (the messages' utime, the receive time).
std::int64_t realtime_utime();
// CLOCK_MONOTONIC in ns: MonitorLoop's step clock (worst_step_ns) and the status timer.
std::int64_t monotonic_ns();

// LCM subscribes by regular expression (implicitly ^...$): the expression that matches exactly `channel`.
std::string exact_channel_regex(const std::string& channel);

// Publishes the loop's encoded messages with lcm::LCM (raw bytes; the loop already encoded them).
class LcmTransport final : public firmware::Transport {
 public:
  explicit LcmTransport(lcm::LCM& lcm) : lcm_(lcm) {}
  bool publish(const char* channel, const std::uint8_t* data, std::size_t size) override;

 private:
  lcm::LCM& lcm_;
};

// Subscribes the loop's two input channels (and only those, exactly) and passes every message's raw bytes to
// MonitorLoop::on_message with the receive time LCM stamped on it (CLOCK_REALTIME µs; now when LCM gave none).
// Unsubscribes on destruction. Messages arrive while the owner calls lcm.handle()/handleTimeout().
class LcmInput {
 public:
  LcmInput(lcm::LCM& lcm, firmware::MonitorLoop& loop);
  ~LcmInput();
  LcmInput(const LcmInput&) = delete;
  LcmInput& operator=(const LcmInput&) = delete;
  bool good() const { return accel_ != nullptr && batch_ != nullptr; }
  std::int64_t messages() const { return messages_; }

 private:
  static void on_raw(const lcm::ReceiveBuffer* rbuf, const std::string& channel, LcmInput* self);

  lcm::LCM& lcm_;
  firmware::MonitorLoop& loop_;
  lcm::Subscription* accel_ = nullptr;
  lcm::Subscription* batch_ = nullptr;
  std::int64_t messages_ = 0;
};

// Offline mode: every published message becomes an event of an LCM log, timestamped with the time set by
// set_event_time() (the timestamp of the input event being handled), so the output depends on the input log only.
class LogTransport final : public firmware::Transport {
 public:
  explicit LogTransport(lcm::LogFile& log) : log_(log) {}
  void set_event_time(std::int64_t utime) { event_utime_ = utime; }
  bool publish(const char* channel, const std::uint8_t* data, std::size_t size) override;
  std::int64_t events_written() const { return written_; }
  std::int64_t write_failures() const { return failures_; }

 private:
  lcm::LogFile& log_;
  std::int64_t event_utime_ = 0;
  std::int64_t written_ = 0;
  std::int64_t failures_ = 0;
};

}  // namespace rockwatch::monitor
