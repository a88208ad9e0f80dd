#include "log_flusher.hpp"

#include <utility>

#include "lcm_transport.hpp"
#include "monitor_run.hpp"
#include "rockwatch/options/option_values.hpp"

namespace rockwatch::monitor {

bool LoggedTransport::publish(const char* channel, const std::uint8_t* data, std::size_t size) {
  log_.add(channel, data, size, realtime_utime());
  return inner_.publish(channel, data, size);
}

void LogFlusher::flush(firmware::MultiWallMonitor& loop) {
  if (!log_.is_open()) return;
  if (log_.flush()) {
    if (failing_) {
      err_ << kMessagePrefix << "note: --log " << options::quoted(path_) << ": writing again (" << log_.events_lost()
           << " events lost in all)" << std::endl;
      failing_ = false;
    }
    return;
  }
  // One count per failed write or sync, so the status's log_write_failures is the log's write_failures.
  const std::int64_t failures = log_.write_failures();
  for (; failures_noted_ < failures; ++failures_noted_) loop.note_log_write_failure();
  if (!failing_) {
    err_ << kMessagePrefix << "warning: --log " << options::quoted(path_) << ": write failed (" << log_.error() << "); "
         << (log_.events_lost() - lost_reported_) << " events lost; monitoring goes on, the log is retried every "
         << "second" << std::endl;
    failing_ = true;
    lost_reported_ = log_.events_lost();
  }
}

void LogFlusher::drain(firmware::MultiWallMonitor& loop) {
  if (!log_.is_open()) return;
  (void)log_.drain();  // failures are reported by the flush below
  flush(loop);
}

}  // namespace rockwatch::monitor
