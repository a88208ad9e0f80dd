// The monitor's own record of its traffic (`rockwatch-monitor --log FILE`): every message received on the input
// channels and every message the monitor published, as a standard LCM log (lcm-logplayer, lcm-logplayer-gui and the
// monitor's offline mode read it).
//
// Why not lcm::LogFile: neither a full disk nor a slow one may cost the monitor anything but the log. Events go into
// one of two blocks allocated when the file is opened; a block is handed to a writer thread once per second (flush(),
// called by the monitor's status timer) and when it is full. The writer writes it at the end of the file and then
// fdatasyncs, so the sample path never waits for the disk. Two blocks: while the writer works on one, the monitor
// fills the other; if the writer still holds its block when the other is full (a disk slower than the traffic), new
// events are lost (counted), never waited for.
//
// What is durable when (docs/RELIABILITY.md "Power loss"): an event is on the disk at most ~2 s after it happened
// (the block it is in is handed over within a second and written and synced then); events_written() counts only
// events whose write and fdatasync both succeeded — what the monitor reports as written survives a power cut.
// A write that fails (disk full, I/O error) loses the events of that block, which are counted; the file is cut back to
// its last complete event so it stays a valid log; the failure is reported by the next flush(), so the caller reports
// it and goes on monitoring; the next block tries again, so logging resumes by itself when space comes back. A failed
// fdatasync loses nothing known, but its events are not known to be durable: counted in events_not_durable().
//
// A restart on the same file keeps it (systemd's Restart=always on a crashed monitor): open() reads the file's events,
// cuts a torn last event (a write cut by SIGKILL or a power cut), and appends after the last complete one with the next
// event number. An existing file that is not an LCM log is refused (never overwritten); one whose damage is not at its
// end (complete events after a bad one) is kept untouched under FILE.N (the first free N ≥ 1) and a new log started.
// Event numbers keep counting across lost events: a gap in them shows where events were lost.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace rockwatch::monitor {

// What open() found in an existing file.
struct TrafficLogResume {
  std::int64_t events_kept = 0;   // complete events found and kept
  std::int64_t bytes_kept = 0;    // their bytes: the new events start here
  std::int64_t next_event_number = 0;
  std::int64_t torn_bytes_cut = 0;  // bytes after the last complete event, cut (a torn write)
  std::string rotated_to;           // the damaged file's new name ("" when not rotated)
};

// Scans an LCM log file's events from its start (pure: reads only). end_of_complete: the byte after the last complete
// event; last_event_number: its number (−1 when none); damaged: a readable event follows a bad region (the damage is
// not a torn tail); not_a_log: bytes that are neither events nor zeros (a torn tail is zeros or a prefix of an event).
struct LcmLogScan {
  std::int64_t events = 0, end_of_complete = 0, file_bytes = 0, last_event_number = -1;
  bool damaged = false, not_a_log = false;
  std::string error;  // a read failed
};
LcmLogScan scan_lcm_log(int fd);

// Reads an LCM log's events in order by the same rule (the monitor's offline mode, tests): it stops at the end of the
// file or at the first event that is not complete, so a log whose write was cut (SIGKILL, power cut) reads to its last
// complete event. (lcm::LogFile 1.3.1 also drops the last complete event when bytes other than an event follow it.)
class LcmLogReader {
 public:
  struct Event {
    std::int64_t number = 0, utime = 0;
    std::string channel;
    std::vector<std::uint8_t> data;
  };
  LcmLogReader() = default;
  ~LcmLogReader();
  LcmLogReader(const LcmLogReader&) = delete;
  LcmLogReader& operator=(const LcmLogReader&) = delete;
  bool open(const std::string& path);  // false with error() set
  // The next event (valid until the next call), or null at the end or at an event that is not complete.
  const Event* next();
  std::int64_t read_end() const { return at_; }         // the byte after the last event read
  std::int64_t file_bytes() const { return file_bytes_; }  // the file's size when opened
  const std::string& error() const { return error_; }

 private:
  int fd_ = -1;
  std::int64_t at_ = 0, file_bytes_ = 0;
  Event event_;
  std::vector<std::uint8_t> buffer_;
  std::int64_t buffer_at_ = 0, buffer_bytes_ = 0;
  bool read(std::int64_t at, std::uint8_t* p, std::size_t n);  // through the buffer; false at the file's end
  std::string error_;
};

class TrafficLog {
 public:
  TrafficLog() = default;
  ~TrafficLog();
  TrafficLog(const TrafficLog&) = delete;
  TrafficLog& operator=(const TrafficLog&) = delete;

  // Opens (or creates) the file, resumes after its last complete event (above), allocates the blocks and starts the
  // writer. False with error() set when the file cannot be opened or is not an LCM log.
  bool open(const std::string& path, std::size_t buffer_bytes = std::size_t{4} << 20);
  bool is_open() const { return fd_ >= 0; }
  const TrafficLogResume& resume() const { return resume_; }

  // Appends one event stamped `utime` [µs since 1970]; hands the block to the writer first when the event does not fit.
  // An event larger than a block, or one that finds both blocks taken, is lost (counted).
  void add(const char* channel, const std::uint8_t* data, std::size_t size, std::int64_t utime);

  // Hands the events so far to the writer (never waits for the disk). False when a write or sync has failed since the
  // last flush() (its events lost or not durable; error() says why).
  bool flush();

  // Hands the events so far to the writer and waits until they are written and synced (tests, shutdown: it waits for
  // the disk, so never on the sample path). False when a write or sync has failed since the last flush(), which
  // still reports it.
  bool drain();

  // Writes and syncs everything, stops the writer and closes. False when a write or sync failed since the last flush().
  bool close();

  // Counts (any thread may call; the writer updates them).
  std::int64_t events_written() const;      // written and synced in this run
  std::int64_t events_lost() const;         // never written: failed writes, events too large, both blocks taken
  std::int64_t events_not_durable() const;  // written but their fdatasync failed
  std::int64_t write_failures() const;      // failed writes and syncs
  std::int64_t bytes_written() const;       // bytes of complete events in the file (kept ones included)
  std::string error() const;                // the last failure ("" when none)

 private:
  struct Block {
    std::vector<std::uint8_t> bytes;
    std::size_t used = 0;
    std::int64_t events = 0;
  };
  bool hand_over();  // the active block to the writer; false when the writer still holds the other
  void writer_main();

  int fd_ = -1;
  bool syncable_ = true;  // fdatasync means something here (false for /dev/null and the like)
  TrafficLogResume resume_;
  Block blocks_[2];
  int active_ = 0;  // the block add() fills (the monitor's thread); the other is the writer's while pending_
  std::int64_t next_event_number_ = 0;
  std::int64_t lost_here_ = 0;  // lost by add() (monitor's thread)
  std::int64_t failures_reported_ = 0;

  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::thread writer_;
  bool pending_ = false, stop_ = false;
  // Guarded by mutex_ (the writer's results):
  std::int64_t offset_ = 0;  // bytes of complete events in the file
  std::int64_t events_written_ = 0, events_lost_ = 0, events_not_durable_ = 0, write_failures_ = 0;
  std::string error_;
};

}  // namespace rockwatch::monitor
