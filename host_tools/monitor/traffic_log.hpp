// The monitor's own record of its traffic (`rockwatch-monitor --log FILE`): every message received on the two input
// channels and every message the monitor published, as a standard LCM log (lcm-logplayer, lcm-logplayer-gui and the
// monitor's offline mode read it).
//
// Why not lcm::LogFile: a full disk must cost the monitor nothing but the log. Events go into a buffer allocated when
// the file is opened and reach the file once per second (flush(), called by the monitor's status timer), when the
// buffer is half full, and on exit — never one write per sample. A write that fails (disk full, I/O error) loses the
// events of that buffer, which are counted; the file is cut back to its last complete event so it stays a valid log;
// the failure is reported to the caller, which reports it and goes on monitoring; the next flush tries again, so
// logging resumes by itself when space comes back. Event numbers keep counting across lost events: a gap in them in
// the file shows where events were lost.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace rockwatch::monitor {

class TrafficLog {
 public:
  TrafficLog() = default;
  ~TrafficLog();
  TrafficLog(const TrafficLog&) = delete;
  TrafficLog& operator=(const TrafficLog&) = delete;

  // Creates (or truncates) the file and allocates the buffer. False with error() set when the file cannot be opened.
  bool open(const std::string& path, std::size_t buffer_bytes = std::size_t{4} << 20);
  bool is_open() const { return fd_ >= 0; }

  // Appends one event stamped `utime` [µs since 1970]; writes the buffer first when the event does not fit in its
  // free half. An event larger than half the buffer is lost (counted).
  void add(const char* channel, const std::uint8_t* data, std::size_t size, std::int64_t utime);

  // Writes the buffered events. False when this write failed (its events lost, error() says why).
  bool flush();

  // flush(), fdatasync and close. False when the last flush or the sync failed.
  bool close();

  std::int64_t events_written() const { return events_written_; }
  std::int64_t events_lost() const { return events_lost_; }
  std::int64_t write_failures() const { return write_failures_; }
  std::int64_t bytes_written() const { return offset_; }
  const std::string& error() const { return error_; }  // the last failure ("" when none)

 private:
  int fd_ = -1;
  std::vector<std::uint8_t> buffer_;
  std::size_t used_ = 0;
  std::int64_t buffered_events_ = 0;
  std::int64_t next_event_number_ = 0;
  std::int64_t offset_ = 0;  // bytes of complete events in the file
  std::int64_t events_written_ = 0, events_lost_ = 0, write_failures_ = 0;
  std::string error_;
};

}  // namespace rockwatch::monitor
