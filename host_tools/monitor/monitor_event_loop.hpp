// The monitor's one loop, for every input (monitor_input_source.hpp) on an injected clock (monitor_clock.hpp):
//   the first status when the clock first has a time; then each pass: systemd's watchdog, the statuses due (one a
//   second), the forecasts due, then the input's next messages (a live input waits until the next status, at most
//   100 ms, so a stop is seen at once); shutdown on SIGINT/SIGTERM, the end of the input or a receive that keeps
//   failing: the forecasts stopped, the engine's pending samples published, the log drained, the last status.
// Live and replayed runs differ only in what is injected, so a replay exercises the loop the live monitor runs.
#pragma once

#include <cstdint>
#include <functional>
#include <ostream>
#include <string>

#include "datagram_input.hpp"
#include "forecast_schedule.hpp"
#include "log_flusher.hpp"
#include "monitor_clock.hpp"
#include "monitor_forecast.hpp"
#include "monitor_input_source.hpp"
#include "rockwatch/firmware/multi_wall_monitor.hpp"
#include "service_notify.hpp"
#include "traffic_log.hpp"

namespace rockwatch::monitor {

// Where every input's messages go: into the traffic log (live --log; before the outputs they cause, so the log
// reads in order), the forecast's feed (--forecast: a wait-free copy of the ground, monitor_forecast.hpp), then the
// walls. Null: not in this run.
class LoopInputSink final : public InputMessageSink {
 public:
  LoopInputSink(firmware::MultiWallMonitor& walls, TrafficLog* log, ForecastFeed* feed)
      : walls_(walls), log_(log), feed_(feed) {}
  void on_input_message(const char* channel, const std::uint8_t* data, std::size_t size,
                        std::int64_t receive_utime) override {
    if (log_ != nullptr) log_->add(channel, data, size, receive_utime);
    if (feed_ != nullptr) feed_->on_input(channel, data, size);
    walls_.on_message(channel, data, size, receive_utime);
  }

 private:
  firmware::MultiWallMonitor& walls_;
  TrafficLog* log_;
  ForecastFeed* feed_;
};

// What the loop runs beside the input; null: not in this mode.
struct LoopServices {
  LogFlusher* log = nullptr;               // live --log: flushed before each status, drained before the last
  ServiceNotifier* service = nullptr;      // live: watchdog fed every pass, STOPPING=1 at shutdown
  ForecastSchedule* forecasts = nullptr;   // --forecast
  // Once the first status is out (live: the listening line, the forecast thread, READY=1). False: the loop returns
  // at once with `aborted`, nothing more published.
  std::function<bool()> on_started;
};

struct LoopOutcome {
  std::int64_t statuses = 0;     // status messages published
  std::int64_t run_time_us = 0;  // clock time from the start to the last status
  bool aborted = false;          // on_started refused
  bool receive_failed = false;   // the input failed more than 100 times in a row
  bool stopped = false;          // by a signal
  std::string stopped_by;        // the summary's "stopped_by"
};

// `sink` gets the input's messages (the traffic log, the forecast's feed, then `walls`). Errors go to `err`.
LoopOutcome run_monitor_loop(InputSource& input, MonitorClock& clock, firmware::MultiWallMonitor& walls,
                             InputMessageSink& sink, const LoopServices& services, std::ostream& err);

}  // namespace rockwatch::monitor
