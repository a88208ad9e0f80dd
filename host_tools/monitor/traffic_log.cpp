#include "traffic_log.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace rockwatch::monitor {

namespace {

// LCM log event header (big-endian): sync word, event number, timestamp [µs], channel length, data length.
constexpr std::uint32_t kSyncWord = 0xEDA1DA01u;
constexpr std::size_t kHeaderBytes = 4 + 8 + 8 + 4 + 4;

std::uint8_t* put_be(std::uint8_t* p, std::uint64_t v, int bytes) {
  for (int i = bytes - 1; i >= 0; --i) *p++ = static_cast<std::uint8_t>(v >> (8 * i));
  return p;
}

}  // namespace

TrafficLog::~TrafficLog() { close(); }

bool TrafficLog::open(const std::string& path, std::size_t buffer_bytes) {
  close();
  error_.clear();
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    error_ = std::strerror(errno);
    return false;
  }
  buffer_.assign(buffer_bytes, 0);
  used_ = 0;
  buffered_events_ = 0;
  next_event_number_ = 0;
  offset_ = 0;
  events_written_ = events_lost_ = write_failures_ = 0;
  return true;
}

void TrafficLog::add(const char* channel, const std::uint8_t* data, std::size_t size, std::int64_t utime) {
  if (fd_ < 0) return;
  const std::size_t channel_bytes = std::strlen(channel);
  const std::size_t bytes = kHeaderBytes + channel_bytes + size;
  const std::int64_t number = next_event_number_++;
  if (bytes > buffer_.size() / 2 || size > 0x7fffffffu) {
    ++events_lost_;
    return;
  }
  if (used_ + bytes > buffer_.size() / 2) flush();  // a failed flush empties the buffer too
  std::uint8_t* p = buffer_.data() + used_;
  p = put_be(p, kSyncWord, 4);
  p = put_be(p, static_cast<std::uint64_t>(number), 8);
  p = put_be(p, static_cast<std::uint64_t>(utime), 8);
  p = put_be(p, channel_bytes, 4);
  p = put_be(p, size, 4);
  std::memcpy(p, channel, channel_bytes);
  if (size > 0) std::memcpy(p + channel_bytes, data, size);
  used_ += bytes;
  ++buffered_events_;
}

bool TrafficLog::flush() {
  if (fd_ < 0 || used_ == 0) return true;
  std::size_t done = 0;
  while (done < used_) {
    const ssize_t n = ::pwrite(fd_, buffer_.data() + done, used_ - done, offset_ + static_cast<off_t>(done));
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    // Disk full (or another error): drop this buffer's events and cut the file back to the last complete event
    // (ftruncate fails on devices such as /dev/full; nothing was written there anyway).
    error_ = n < 0 ? std::strerror(errno) : "the file accepted no more bytes";
    if (done > 0) (void)::ftruncate(fd_, offset_);
    ++write_failures_;
    events_lost_ += buffered_events_;
    used_ = 0;
    buffered_events_ = 0;
    return false;
  }
  offset_ += static_cast<std::int64_t>(done);
  events_written_ += buffered_events_;
  used_ = 0;
  buffered_events_ = 0;
  return true;
}

bool TrafficLog::close() {
  if (fd_ < 0) return true;
  bool ok = flush();
  if (::fdatasync(fd_) != 0 && errno != EINVAL && errno != EROFS) {
    if (ok) error_ = std::strerror(errno);
    ok = false;
  }
  if (::close(fd_) != 0 && ok) {
    error_ = std::strerror(errno);
    ok = false;
  }
  fd_ = -1;
  return ok;
}

}  // namespace rockwatch::monitor
