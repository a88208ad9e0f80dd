#include "traffic_log.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

namespace rockwatch::monitor {

namespace {

// LCM log event header (big-endian): sync word, event number, timestamp [µs], channel length, data length.
constexpr std::uint32_t kSyncWord = 0xEDA1DA01u;
constexpr std::size_t kHeaderBytes = 4 + 8 + 8 + 4 + 4;
constexpr std::uint32_t kMaxChannelBytes = 255;         // LCM allows 63; generous, still rejects garbage
constexpr std::uint32_t kMaxDataBytes = 256u << 20;     // far above any message the monitor logs

std::uint8_t* put_be(std::uint8_t* p, std::uint64_t v, int bytes) {
  for (int i = bytes - 1; i >= 0; --i) *p++ = static_cast<std::uint8_t>(v >> (8 * i));
  return p;
}
std::uint64_t get_be(const std::uint8_t* p, int bytes) {
  std::uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v = (v << 8) | p[i];
  return v;
}

// Reads up to n bytes at off; the count read (short at the end of the file), −1 on error.
ssize_t read_at(int fd, std::uint8_t* p, std::size_t n, std::int64_t off) {
  std::size_t done = 0;
  while (done < n) {
    const ssize_t r = ::pread(fd, p + done, n - done, static_cast<off_t>(off) + static_cast<off_t>(done));
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) return -1;
    if (r == 0) break;
    done += static_cast<std::size_t>(r);
  }
  return static_cast<ssize_t>(done);
}

// An event header that could start a real event of a file of `file_bytes` at `at`: its length (0 when not one).
std::int64_t event_length(const std::uint8_t* h, std::int64_t at, std::int64_t file_bytes) {
  if (get_be(h, 4) != kSyncWord) return 0;
  const std::uint64_t channel = get_be(h + 20, 4), data = get_be(h + 24, 4);
  if (channel == 0 || channel > kMaxChannelBytes || data > kMaxDataBytes) return 0;
  const std::int64_t length = static_cast<std::int64_t>(kHeaderBytes + channel + data);
  return at + length <= file_bytes ? length : 0;
}

}  // namespace

LcmLogScan scan_lcm_log(int fd) {
  LcmLogScan s;
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    s.error = std::strerror(errno);
    return s;
  }
  s.file_bytes = static_cast<std::int64_t>(st.st_size);
  std::vector<std::uint8_t> chunk(std::size_t{1} << 20);
  std::int64_t chunk_at = 0, chunk_bytes = 0;  // chunk holds the file's bytes [chunk_at, chunk_at + chunk_bytes)
  // The header at `at`, read through the chunk (null when the file ends before a whole header).
  const auto header_at = [&](std::int64_t at) -> const std::uint8_t* {
    if (at < chunk_at || at + static_cast<std::int64_t>(kHeaderBytes) > chunk_at + chunk_bytes) {
      const ssize_t r = read_at(fd, chunk.data(), chunk.size(), at);
      if (r < 0) {
        s.error = std::strerror(errno);
        return nullptr;
      }
      chunk_at = at;
      chunk_bytes = r;
      if (chunk_bytes < static_cast<std::int64_t>(kHeaderBytes)) return nullptr;
    }
    return chunk.data() + (at - chunk_at);
  };
  std::int64_t at = 0;
  while (at + static_cast<std::int64_t>(kHeaderBytes) <= s.file_bytes) {
    const std::uint8_t* h = header_at(at);
    if (h == nullptr) break;
    const std::int64_t length = event_length(h, at, s.file_bytes);
    if (length == 0) break;
    s.last_event_number = static_cast<std::int64_t>(get_be(h + 4, 8));
    ++s.events;
    at += length;
  }
  if (!s.error.empty()) return s;
  s.end_of_complete = at;
  // What follows the last complete event: zeros or the start of one event (a torn tail), or something else.
  const std::int64_t tail = s.file_bytes - at;
  if (tail == 0) return s;
  std::vector<std::uint8_t> rest(static_cast<std::size_t>(std::min<std::int64_t>(tail, std::int64_t{64} << 20)));
  const ssize_t r = read_at(fd, rest.data(), rest.size(), at);
  if (r < 0) {
    s.error = std::strerror(errno);
    return s;
  }
  rest.resize(static_cast<std::size_t>(r));
  bool starts_an_event = rest.size() >= 4 && get_be(rest.data(), 4) == kSyncWord;
  if (rest.size() < 4) {  // a prefix of the sync word, or zeros
    std::uint8_t sync[4];
    put_be(sync, kSyncWord, 4);
    starts_an_event = std::equal(rest.begin(), rest.end(), sync);
  }
  const bool zeros = std::all_of(rest.begin(), rest.end(), [](std::uint8_t b) { return b == 0; });
  // A readable event after the bad point: the damage is inside, not at the end.
  for (std::size_t k = 1; k + kHeaderBytes <= rest.size(); ++k) {
    if (rest[k] != 0xED || get_be(&rest[k], 4) != kSyncWord) continue;
    if (event_length(&rest[k], at + static_cast<std::int64_t>(k), s.file_bytes) > 0) {
      s.damaged = true;
      return s;
    }
  }
  // A page of zeros before an event's start is a power cut's signature too; anything else is not a log we wrote.
  if (!starts_an_event && !zeros) {
    std::size_t first = 0;
    while (first < rest.size() && rest[first] == 0) ++first;
    const bool zeros_then_event = first > 0 && first + 4 <= rest.size() && get_be(&rest[first], 4) == kSyncWord;
    if (!zeros_then_event) s.not_a_log = true;
  }
  return s;
}

LcmLogReader::~LcmLogReader() {
  if (fd_ >= 0) ::close(fd_);
}

bool LcmLogReader::open(const std::string& path) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  struct stat st {};
  if (fd_ < 0 || ::fstat(fd_, &st) != 0) {
    error_ = std::strerror(errno);
    return false;
  }
  file_bytes_ = static_cast<std::int64_t>(st.st_size);
  at_ = buffer_at_ = buffer_bytes_ = 0;
  buffer_.assign(std::size_t{1} << 20, 0);
  return true;
}

bool LcmLogReader::read(std::int64_t at, std::uint8_t* p, std::size_t n) {
  if (at + static_cast<std::int64_t>(n) > file_bytes_) return false;
  if (n > buffer_.size()) return read_at(fd_, p, n, at) == static_cast<ssize_t>(n);
  if (at < buffer_at_ || at + static_cast<std::int64_t>(n) > buffer_at_ + buffer_bytes_) {
    const ssize_t r = read_at(fd_, buffer_.data(), buffer_.size(), at);
    if (r < 0) {
      error_ = std::strerror(errno);
      return false;
    }
    buffer_at_ = at;
    buffer_bytes_ = r;
    if (buffer_bytes_ < static_cast<std::int64_t>(n)) return false;
  }
  std::memcpy(p, buffer_.data() + (at - buffer_at_), n);
  return true;
}

const LcmLogReader::Event* LcmLogReader::next() {
  if (fd_ < 0) return nullptr;
  std::uint8_t h[kHeaderBytes];
  if (!read(at_, h, kHeaderBytes)) return nullptr;
  const std::int64_t length = event_length(h, at_, file_bytes_);
  if (length == 0) return nullptr;
  const std::size_t channel = static_cast<std::size_t>(get_be(h + 20, 4)), data = static_cast<std::size_t>(get_be(h + 24, 4));
  event_.channel.resize(channel);
  event_.data.resize(data);
  if (!read(at_ + static_cast<std::int64_t>(kHeaderBytes), reinterpret_cast<std::uint8_t*>(&event_.channel[0]),
            channel) ||
      (data > 0 && !read(at_ + static_cast<std::int64_t>(kHeaderBytes + channel), event_.data.data(), data))) {
    return nullptr;
  }
  event_.number = static_cast<std::int64_t>(get_be(h + 4, 8));
  event_.utime = static_cast<std::int64_t>(get_be(h + 12, 8));
  at_ += length;
  return &event_;
}

TrafficLog::~TrafficLog() { close(); }

bool TrafficLog::open(const std::string& path, std::size_t buffer_bytes) {
  close();
  std::lock_guard<std::mutex> lock(mutex_);
  error_.clear();
  resume_ = TrafficLogResume{};
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0 && (errno == EACCES || errno == EISDIR)) fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    error_ = std::strerror(errno);
    return false;
  }
  struct stat st {};
  const bool regular = ::fstat(fd_, &st) == 0 && S_ISREG(st.st_mode);
  syncable_ = regular;
  offset_ = 0;
  next_event_number_ = 0;
  if (regular && st.st_size > 0) {
    const LcmLogScan s = scan_lcm_log(fd_);
    const auto refuse = [&](const std::string& why) {
      error_ = why;
      ::close(fd_);
      fd_ = -1;
      return false;
    };
    if (!s.error.empty()) return refuse("cannot read the existing file (" + s.error + ")");
    if (s.events == 0 && s.not_a_log) {
      return refuse("the file exists and is not an LCM log (it does not start with an event); it is not "
                    "overwritten: move it away or name another file");
    }
    if (s.damaged || s.not_a_log) {
      // Complete events after a bad region (or bytes that are no torn write): keep the file as it is, start anew.
      std::string rotated;
      for (int n = 1; n < 1000 && rotated.empty(); ++n) {
        const std::string candidate = path + "." + std::to_string(n);
        struct stat other {};
        if (::stat(candidate.c_str(), &other) != 0 && errno == ENOENT) rotated = candidate;
      }
      if (rotated.empty() || ::rename(path.c_str(), rotated.c_str()) != 0) {
        return refuse("the existing log is damaged before its end and could not be kept aside as " +
                      (rotated.empty() ? path + ".N" : rotated) + " (" + std::strerror(errno) + ")");
      }
      ::close(fd_);
      fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
      if (fd_ < 0) {
        error_ = std::strerror(errno);
        return false;
      }
      resume_.rotated_to = rotated;
    } else {
      // A torn last event (SIGKILL or a power cut inside a write): cut; resume after the last complete event.
      if (s.end_of_complete < s.file_bytes && ::ftruncate(fd_, static_cast<off_t>(s.end_of_complete)) != 0) {
        return refuse(std::string("cannot cut the torn end of the existing log (") + std::strerror(errno) + ")");
      }
      resume_.events_kept = s.events;
      resume_.bytes_kept = s.end_of_complete;
      resume_.torn_bytes_cut = s.file_bytes - s.end_of_complete;
      offset_ = s.end_of_complete;
      next_event_number_ = s.last_event_number + 1;
      if (resume_.torn_bytes_cut > 0) (void)::fdatasync(fd_);
    }
  }
  resume_.next_event_number = next_event_number_;
  for (Block& b : blocks_) {
    b.bytes.assign(std::max<std::size_t>(buffer_bytes / 2, 4096), 0);
    b.used = 0;
    b.events = 0;
  }
  active_ = 0;
  lost_here_ = 0;
  failures_reported_ = 0;
  events_written_ = events_lost_ = events_not_durable_ = write_failures_ = 0;
  pending_ = stop_ = false;
  writer_ = std::thread([this] { writer_main(); });
  return true;
}

void TrafficLog::add(const char* channel, const std::uint8_t* data, std::size_t size, std::int64_t utime) {
  if (fd_ < 0) return;
  const std::size_t channel_bytes = std::strlen(channel);
  const std::size_t bytes = kHeaderBytes + channel_bytes + size;
  const std::int64_t number = next_event_number_++;
  Block* b = &blocks_[active_];
  if (bytes > b->bytes.size() || size > 0x7fffffffu || channel_bytes == 0 || channel_bytes > kMaxChannelBytes) {
    ++lost_here_;
    return;
  }
  if (b->used + bytes > b->bytes.size()) {
    if (!hand_over()) {  // the writer still holds the other block: the disk is slower than the traffic
      ++lost_here_;
      return;
    }
    b = &blocks_[active_];
  }
  std::uint8_t* p = b->bytes.data() + b->used;
  p = put_be(p, kSyncWord, 4);
  p = put_be(p, static_cast<std::uint64_t>(number), 8);
  p = put_be(p, static_cast<std::uint64_t>(utime), 8);
  p = put_be(p, channel_bytes, 4);
  p = put_be(p, size, 4);
  std::memcpy(p, channel, channel_bytes);
  if (size > 0) std::memcpy(p + channel_bytes, data, size);
  b->used += bytes;
  ++b->events;
}

bool TrafficLog::hand_over() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (pending_) return false;
  pending_ = true;
  active_ = 1 - active_;
  blocks_[active_].used = 0;
  blocks_[active_].events = 0;
  cv_.notify_all();
  return true;
}

void TrafficLog::writer_main() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    cv_.wait(lock, [this] { return pending_ || stop_; });
    if (!pending_) return;  // stop_ and nothing left
    Block& b = blocks_[1 - active_];
    const std::int64_t at = offset_;
    lock.unlock();
    std::size_t done = 0;
    int write_errno = 0;
    bool refused = false;  // a write that wrote nothing without an error
    while (done < b.used) {
      const off_t where = static_cast<off_t>(at + static_cast<std::int64_t>(done));
      const ssize_t n = ::pwrite(fd_, b.bytes.data() + done, b.used - done, where);
      if (n > 0) {
        done += static_cast<std::size_t>(n);
        continue;
      }
      if (n < 0 && errno == EINTR) continue;
      write_errno = n < 0 ? errno : ENOSPC;
      refused = n == 0;
      break;
    }
    int sync_errno = 0;
    if (write_errno != 0) {
      // Disk full (or another error): this block's events are lost; the file is cut back to its last complete event
      // (ftruncate fails on devices such as /dev/full; nothing was written there anyway).
      if (done > 0) (void)::ftruncate(fd_, static_cast<off_t>(at));
    } else if (syncable_ && b.used > 0 && ::fdatasync(fd_) != 0 && errno != EINVAL && errno != EROFS) {
      sync_errno = errno;
    }
    lock.lock();
    if (write_errno != 0) {
      error_ = refused ? "the file accepted no more bytes" : std::strerror(write_errno);
      ++write_failures_;
      events_lost_ += b.events;
    } else {
      offset_ = at + static_cast<std::int64_t>(b.used);
      if (sync_errno != 0) {
        error_ = std::string("fdatasync: ") + std::strerror(sync_errno);
        ++write_failures_;
        events_not_durable_ += b.events;
      } else {
        events_written_ += b.events;
      }
    }
    b.used = 0;
    b.events = 0;
    pending_ = false;
    cv_.notify_all();
  }
}

bool TrafficLog::flush() {
  if (fd_ < 0) return true;
  if (blocks_[active_].used > 0) (void)hand_over();  // the writer busy: these events go with the next hand-over
  std::lock_guard<std::mutex> lock(mutex_);
  const bool ok = write_failures_ == failures_reported_;
  failures_reported_ = write_failures_;
  return ok;
}

bool TrafficLog::drain() {
  if (fd_ < 0) return true;
  for (int round = 0; round < 2; ++round) {  // the writer may hold the other block: wait, then hand this one over
    {
      std::unique_lock<std::mutex> lock(mutex_);
      cv_.wait(lock, [this] { return !pending_; });
    }
    if (blocks_[active_].used > 0) (void)hand_over();
  }
  std::unique_lock<std::mutex> lock(mutex_);
  cv_.wait(lock, [this] { return !pending_; });
  return write_failures_ == failures_reported_;  // not consumed: the next flush() reports them
}

bool TrafficLog::close() {
  if (fd_ < 0) return true;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait(lock, [this] { return !pending_; });
  }
  if (blocks_[active_].used > 0) (void)hand_over();
  {
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait(lock, [this] { return !pending_; });
    stop_ = true;
    cv_.notify_all();
  }
  if (writer_.joinable()) writer_.join();
  std::lock_guard<std::mutex> lock(mutex_);
  events_lost_ += lost_here_;
  lost_here_ = 0;
  bool ok = write_failures_ == failures_reported_;
  failures_reported_ = write_failures_;
  if (::close(fd_) != 0 && ok) {
    error_ = std::strerror(errno);
    ok = false;
  }
  fd_ = -1;
  return ok;
}

std::int64_t TrafficLog::events_written() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return events_written_;
}
std::int64_t TrafficLog::events_lost() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return events_lost_ + lost_here_;
}
std::int64_t TrafficLog::events_not_durable() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return events_not_durable_;
}
std::int64_t TrafficLog::write_failures() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return write_failures_;
}
std::int64_t TrafficLog::bytes_written() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return offset_;
}
std::string TrafficLog::error() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return error_;
}

}  // namespace rockwatch::monitor
