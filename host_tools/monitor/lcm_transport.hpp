// The Linux adapter of the monitor loop: firmware::Transport over liblcm, the subscription that hands the
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

// Where a live monitor can lose input on this machine, and what the adapter does about it (docs/benchmarks-history.md,
// "The monitor over LCM (issue 7)", has the measurements):
//  1. liblcm's receive thread reads every datagram of the multicast group into a queue and silently discards a
//     message when every subscription it matches already holds its queue capacity of messages the program has not
//     handled yet. LCM's default capacity is 30: 3 ms of single samples at 10 kHz, so a monitor descheduled for a few
//     milliseconds lost samples. LcmInput sets the capacity of its subscriptions to input_queue_capacity(rate).
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

// Subscribes the loop's two input channels (and the wall-sensor channel with the observer; only those, exactly) and passes every message's raw bytes to
// MonitorLoop::on_message with the receive time LCM stamped on it (CLOCK_REALTIME µs; now when LCM gave none).
// Both subscriptions hold up to input_queue_capacity(the loop's sample rate) unhandled messages (not LCM's 30).
// Any other subscription of the same LCM instance to an input channel needs the same capacity: liblcm keeps a
// message when one matching subscription has room, then hands it to each subscription that has messages counted.
// Unsubscribes on destruction. Messages arrive while the owner calls lcm.handle()/handleTimeout().
class LcmInput {
 public:
  LcmInput(lcm::LCM& lcm, firmware::MonitorLoop& loop);
  ~LcmInput();
  LcmInput(const LcmInput&) = delete;
  LcmInput& operator=(const LcmInput&) = delete;
  bool good() const {
    return accel_ != nullptr && batch_ != nullptr && (!loop_.settings().engine.observer_enabled || sensor_ != nullptr);
  }
  std::int64_t messages() const { return messages_; }
  int queue_capacity() const { return queue_capacity_; }

 private:
  static void on_raw(const lcm_recv_buf_t* rbuf, const char* channel, void* self);

  lcm::LCM& lcm_;
  firmware::MonitorLoop& loop_;
  // The C API: lcm-cpp's callbacks take the channel as a std::string, a heap allocation per message for names over
  // 15 characters (ROCKWATCH_ACCEL_BATCH) — the soak's allocation count found its twin on the publishing side.
  lcm_subscription_t* accel_ = nullptr;
  lcm_subscription_t* batch_ = nullptr;
  lcm_subscription_t* sensor_ = nullptr;  // the wall-sensor channel, with the observer only
  int queue_capacity_ = 0;
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
