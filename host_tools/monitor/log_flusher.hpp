// The live monitor's --log (traffic_log.hpp) as the monitor loop uses it: every published message also goes to the
// log (LoggedTransport), and the loop hands the log's buffer to the disk before each status (LogFlusher), so the
// status carries a log failure. Monitoring never stops for the log.
#pragma once

#include <cstddef>
#include <cstdint>
#include <ostream>
#include <string>

#include "rockwatch/firmware/monitor_loop.hpp"
#include "rockwatch/firmware/multi_wall_monitor.hpp"
#include "traffic_log.hpp"

namespace rockwatch::monitor {

// Every published message into the traffic log (stamped CLOCK_REALTIME now), then on to `inner`.
class LoggedTransport final : public firmware::Transport {
 public:
  LoggedTransport(firmware::Transport& inner, TrafficLog& log) : inner_(inner), log_(log) {}
  bool publish(const char* channel, const std::uint8_t* data, std::size_t size) override;

 private:
  firmware::Transport& inner_;
  TrafficLog& log_;
};

// Writes the log's buffer; a failure is counted by the loop (status flag, counter) and reported on stderr once per
// run of failures, and again when writing works again.
class LogFlusher {
 public:
  LogFlusher(TrafficLog& log, std::string path, std::ostream& err) : log_(log), path_(std::move(path)), err_(err) {}
  void flush(firmware::MultiWallMonitor& loop);
  // At shutdown: everything handed to the disk and waited for, so the last status counts every failure.
  void drain(firmware::MultiWallMonitor& loop);

 private:
  TrafficLog& log_;
  std::string path_;
  std::ostream& err_;
  bool failing_ = false;
  std::int64_t lost_reported_ = 0;   // events lost when the last warning was written
  std::int64_t failures_noted_ = 0;  // failures counted by the loop
};

}  // namespace rockwatch::monitor
