// The Linux adapter of the monitor loop: firmware::Transport over liblcm, the clocks, the receive buffer a udpm://
// URL asks for, and the offline transport that writes an LCM log instead of sending. The monitor never receives
// through liblcm: liblcm's subscription (the benchmark's --receive-path liblcm) is tests/bench/lcm_input_source.hpp.
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

// Where a live monitor can lose input on this machine, and what the adapter does about it (docs/benchmarks-history.md,
// "The monitor over LCM (issue 7)", has the measurements):
//  1. liblcm's receive thread reads every datagram of the multicast group into a queue and silently discards a
//     message when every subscription it matches already holds its queue capacity of messages the program has not
//     handled yet. LCM's default capacity is 30: 3 ms of single samples at 10 kHz, so a monitor descheduled for a few
//     milliseconds lost samples. A subscription to the input channels (the benchmark's,
//     tests/bench/lcm_input_source.hpp) sets its capacity to input_queue_capacity(rate).
//  2. The kernel drops datagrams when the socket's receive buffer is full (the LCM receive thread did not run). The
//     udpm URL option recv_buf_size=BYTES asks for a larger one (SO_RCVBUF); the kernel caps the request at
//     net.core.rmem_max and doubles it. with_receive_buffer() adds recv_buf_size to a udpm:// URL that has none.

// Seconds of single-sample input at the configured rate the input subscriptions may hold before liblcm drops one,
// and the least number of messages they hold.
inline constexpr double kInputQueueSeconds = 2.0;
inline constexpr int kMinInputQueueMessages = 1000;
// max(kMinInputQueueMessages, ceil(kInputQueueSeconds · rate)): 20 000 messages at 10 kHz.
int input_queue_capacity(double sample_rate_hz);

// The receive buffer the monitor asks for by default (recv_buf_size, bytes): with the kernel's doubling, about 200 ms
// of this host's traffic at 10 kHz single samples (input and wall states, ~1 KiB of buffer each) when
// net.core.rmem_max allows it; on a stock kernel (rmem_max 212 992) the request is capped, yet still doubles the
// default buffer.
inline constexpr int kDefaultReceiveBufferBytes = 2 * 1024 * 1024;

// `url` with recv_buf_size=`bytes` added when it is a udpm:// URL without a recv_buf_size option; any other URL
// unchanged (an explicit recv_buf_size, memq://, file://...).
std::string with_receive_buffer(const std::string& url, int bytes = kDefaultReceiveBufferBytes);

// The recv_buf_size a udpm:// URL asks for (bytes), 0 when it asks for none or is not udpm://.
long long requested_receive_buffer(const std::string& url);

// net.core.rmem_max (/proc/sys/net/core/rmem_max, bytes), or -1 when it cannot be read.
long long kernel_rmem_max();

// A warning when `url` asks for a receive buffer larger than net.core.rmem_max lets the kernel give (the request is
// silently capped), naming the sysctl that raises it; empty otherwise.
std::string receive_buffer_warning(const std::string& url);

// Publishes the loop's encoded messages with lcm::LCM (raw bytes; the loop already encoded them).
class LcmTransport final : public firmware::Transport {
 public:
  explicit LcmTransport(lcm::LCM& lcm) : lcm_(lcm) {}
  bool publish(const char* channel, const std::uint8_t* data, std::size_t size) override;

 private:
  lcm::LCM& lcm_;
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
