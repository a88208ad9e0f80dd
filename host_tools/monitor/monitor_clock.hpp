// The clock the monitor loop runs on (monitor_event_loop.hpp), injected: live, the machine's clocks; replaying a
// log, the log's own timestamps, so that a replay's statuses, forecasts and output log depend on the input log only
// (the same log in, the same bytes out, on any machine and at any speed).
#pragma once

#include <cstdint>

#include "lcm_transport.hpp"

namespace rockwatch::monitor {

class MonitorClock {
 public:
  virtual ~MonitorClock() = default;
  // Whether the clock has a time: a replay has none before its log's first event (an empty log: never).
  virtual bool has_time() const = 0;
  // The time the loop schedules statuses and forecasts by [µs]: live CLOCK_MONOTONIC (a step of the wall clock must
  // not bunch or skip statuses); replaying, the time of the next event the input will hand over.
  virtual std::int64_t now_us() const = 0;
  // The loop handles the moment `at_us` (a due status or forecast, or the end): returns the utime the messages
  // published for it carry. Live, CLOCK_REALTIME now (at_us is a monotonic schedule, not a date); replaying, at_us
  // itself, which also stamps the output log's events published until the next call.
  virtual std::int64_t enter(std::int64_t at_us) = 0;
  // Whether the loop publishes the status of every whole second it missed. A replay does (the log covers those
  // seconds; one status for a gap of a minute or more); a live monitor that was stopped for a while does not: the
  // statuses would all carry the same wall time, so it publishes one and counts the seconds from now.
  virtual bool catches_up() const = 0;
};

// Live: CLOCK_MONOTONIC schedules, CLOCK_REALTIME stamps (lcm_transport.hpp's clocks).
class LiveClock final : public MonitorClock {
 public:
  bool has_time() const override { return true; }
  std::int64_t now_us() const override { return monotonic_ns() / 1000; }
  std::int64_t enter(std::int64_t /*at_us*/) override { return realtime_utime(); }
  bool catches_up() const override { return false; }
};

// Replaying a log: the input (log_replay_source.hpp) moves the clock to each event's time; every output is written
// to the output log at the time the loop entered last.
class ReplayClock final : public MonitorClock {
 public:
  explicit ReplayClock(LogTransport& output) : output_(output) {}
  // The next event's log time [µs]: the loop's now until the input hands that event over.
  void advance_to(std::int64_t utime) {
    now_us_ = utime;
    has_time_ = true;
  }
  bool has_time() const override { return has_time_; }
  std::int64_t now_us() const override { return now_us_; }
  std::int64_t enter(std::int64_t at_us) override {
    output_.set_event_time(at_us);
    return at_us;
  }
  bool catches_up() const override { return true; }

 private:
  LogTransport& output_;
  std::int64_t now_us_ = 0;
  bool has_time_ = false;
};

}  // namespace rockwatch::monitor
