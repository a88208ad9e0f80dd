#include "common/replay_out/replay_publisher.hpp"

#include <time.h>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/replay_out/lcm_multicast.hpp"

#include "rockwatch/ground_accel_batch_t.hpp"
#include "rockwatch/ground_accel_t.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"
#include "rockwatch/process/realtime.hpp"
#include "rockwatch/wall_sensor_t.hpp"

namespace rockwatch::cli {

namespace {

constexpr std::int64_t kProgressPeriodNs = 250'000'000;

// Waits until `deadline_ns` on CLOCK_MONOTONIC. A signal interrupts the wait; it goes on unless `cancel` was set.
void sleep_until(std::int64_t deadline_ns, const std::atomic<bool>* cancel) {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(deadline_ns / 1'000'000'000);
  ts.tv_nsec = static_cast<long>(deadline_ns % 1'000'000'000);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    if (cancel != nullptr && cancel->load()) return;
  }
}

// What the paced loop asks of the system while it runs (rockwatch/process/realtime.hpp), each only when this process
// may have it, undone when the loop ends (the demo goes on in the same process):
//  - timer slack 1 ns: the kernel may defer a timer wake-up by the thread's slack (50 us by default) to group
//    wake-ups (no privilege needed; this thread only; left at 1 ns);
//  - SCHED_FIFO at kReplayPriority for this thread, if it runs under SCHED_OTHER and the process may (root,
//    CAP_SYS_NICE or an RLIMIT_RTPRIO allowance): on a busy machine an ordinary thread waits for the CPU behind the
//    other work, which made the worst deadline of a 1 kHz replay miss by several ms (docs/benchmarks-history.md,
//    "Replay pacing"). The loop sleeps until each deadline, so it takes little CPU; the kernel's real-time throttling
//    bounds it in any case.
//    The priority is low, below a monitor started with `--realtime 50` or `chrt -f 50`;
//  - mlockall(MCL_CURRENT): the pages mapped now (the prepared samples, the code) stay in memory, no page fault
//    mid-stream. Not MCL_FUTURE: with a memory-lock limit, later allocations would fail.
constexpr int kReplayPriority = 10;

process::RealtimeRequest pacing_request() {
  process::RealtimeRequest r;
  r.fifo_priority = kReplayPriority;
  r.only_if_ordinary = true;
  r.memory_lock = process::MemoryLock::current;
  r.minimal_timer_slack = true;
  return r;
}

class Encoder {
 public:
  template <typename Message>
  void encode(const Message& m) {
    const int size = m.getEncodedSize();
    bytes_.resize(static_cast<std::size_t>(size));
    if (m.encode(bytes_.data(), 0, size) != size) throw std::runtime_error("LCM encoding failed");
  }
  const std::uint8_t* data() const { return bytes_.data(); }
  unsigned int size() const { return static_cast<unsigned int>(bytes_.size()); }

 private:
  std::vector<std::uint8_t> bytes_;
};

}  // namespace

ReplayOutcome publish_stream(const ReplayStream& s, const PublishPlan& plan, lcm::LCM* lcm, lcm::LogFile* log,
                             const std::atomic<bool>* cancel, const ReplayProgress& progress) {
  ReplayOutcome out;
  const std::size_t n = s.size();
  const double rate = s.rate_hz;
  out.paced = lcm != nullptr && plan.speed > 0.0;
  const std::int32_t period_us = plan.batch > 0 ? whole_period_us(rate).value_or(0) : 0;
  std::vector<std::int64_t> lateness_ns;
  lateness_ns.reserve(plan.batch > 0 ? n / static_cast<std::size_t>(plan.batch) + 1 : n);
  Encoder encoder;
  rockwatch::ground_accel_t single{};
  single.schema_version = rockwatch::ground_accel_t::SCHEMA_VERSION;
  single.sensor_status = 0;
  rockwatch::ground_accel_batch_t batch{};
  batch.schema_version = rockwatch::ground_accel_batch_t::SCHEMA_VERSION;
  batch.sample_period_us = period_us;
  batch.sensor_status = 0;

  std::optional<process::RealtimeConditions> conditions;
  if (out.paced) {
    conditions.emplace(pacing_request());
    out.realtime = conditions->outcome().realtime;
    out.memory_locked = conditions->outcome().memory_locked;
  }
  const std::int64_t start_ns = monotonic_ns();
  out.start_utime = realtime_utime();
  const auto utime_of = [&](std::size_t i) {
    return out.start_utime + std::llround(static_cast<double>(i) * 1e6 / rate);
  };
  const auto deadline_of = [&](std::size_t i) {
    return start_ns + std::llround(static_cast<double>(i) / rate / plan.speed * 1e9);
  };
  std::int64_t last_ns = start_ns;
  std::int64_t next_progress_ns = start_ns + kProgressPeriodNs;

  // Publishes and/or logs one encoded message; false when the very first message could not be published.
  std::size_t emitted = 0;  // messages of either kind
  // Lateness is measured on the ground messages only (the wall-sensor ones go out just before them).
  const auto emit = [&](const std::string& channel, const Encoder& message, std::int64_t utime,
                        std::int64_t deadline_ns, bool ground) {
    ++emitted;
    if (ground) ++out.messages;
    if (lcm != nullptr) {
      errno = 0;
      const int rc = lcm->publish(channel, message.data(), message.size());
      const int code = errno;
      last_ns = monotonic_ns();
      if (out.paced && ground) lateness_ns.push_back(last_ns - deadline_ns);
      if (rc != 0) {
        ++out.publish_failures;
        if (out.first_failure.empty()) out.first_failure = code != 0 ? std::strerror(code) : "LCM publish failed";
        if (emitted == 1) {
          out.aborted = true;
          return false;
        }
      }
    }
    if (log != nullptr) {
      lcm::LogEvent event{};
      event.timestamp = utime;
      event.channel = channel;
      event.datalen = static_cast<std::int32_t>(message.size());
      event.data = const_cast<std::uint8_t*>(message.data());  // LogFile::writeEvent only reads it
      if (log->writeEvent(&event) != 0) {
        throw UsageError(plan.log_name + ": writing the log failed" +
                         (errno != 0 ? std::string(": ") + std::strerror(errno) : std::string()));
      }
    }
    return true;
  };

  // The wall-sensor samples due by the ground sample `last` (time ≤ its time), each as one wall_sensor_t.
  Encoder sensor_encoder;
  rockwatch::wall_sensor_t sensor{};
  sensor.schema_version = rockwatch::wall_sensor_t::SCHEMA_VERSION;
  std::size_t next_sensor = 0;
  const auto emit_due_sensors = [&](std::size_t last, std::int64_t deadline_ns) {
    if (plan.wall_sensors == nullptr) return true;
    const std::vector<core::WallSensorSample>& w = *plan.wall_sensors;
    const std::int64_t due_utime = utime_of(last);
    for (; next_sensor < w.size() && out.start_utime + w[next_sensor].utime_us <= due_utime; ++next_sensor) {
      const core::WallSensorSample& x = w[next_sensor];
      sensor.utime = out.start_utime + x.utime_us;
      sensor.seq = static_cast<std::int64_t>(next_sensor);
      sensor.x_mid_m = x.x_valid ? x.x_mid_m : 0.0;
      sensor.a_mid_mps2 = x.a_valid ? x.a_mid_mps2 : 0.0;
      sensor.valid = (x.x_valid ? rockwatch::wall_sensor_t::VALID_X : 0) | (x.a_valid ? rockwatch::wall_sensor_t::VALID_A : 0);
      sensor.sensor_status = x.sensor_status;
      sensor_encoder.encode(sensor);
      if (!emit(plan.wall_sensor_channel, sensor_encoder, sensor.utime, deadline_ns, false)) return false;
      ++out.wall_sensor_samples_sent;
    }
    return true;
  };

  // Sends the encoded message whose last sample is seq `last`, after the wall-sensor samples due by then.
  const auto send = [&](std::size_t last) {
    std::int64_t deadline_ns = 0;
    if (out.paced) {
      deadline_ns = deadline_of(last);
      sleep_until(deadline_ns, cancel);
      if (cancel != nullptr && cancel->load()) return false;
    }
    if (!emit_due_sensors(last, deadline_ns)) return false;
    return emit(plan.channel, encoder, utime_of(last), deadline_ns, true);
  };

  std::size_t done = 0;  // seqs handled: sent (their message went out) or dropped
  for (std::size_t i = 0; i < n; ++i) {
    if (cancel != nullptr && cancel->load()) {
      out.interrupted = true;
      break;
    }
    if (!s.sent[i]) {
      ++out.samples_dropped;
      done = i + 1;
      continue;
    }
    bool complete = true;  // a message is ready after this sample
    if (plan.batch == 0) {
      single.utime = utime_of(i);
      single.seq = static_cast<std::int64_t>(i);
      single.ug_mps2 = s.ug_mps2[i];
      single.vg_mps2 = s.vg_mps2[i];
      encoder.encode(single);
    } else {
      if (batch.count == 0) {
        batch.utime = utime_of(i);
        batch.seq = static_cast<std::int64_t>(i);
      }
      batch.ug_mps2[batch.count] = s.ug_mps2[i];
      batch.vg_mps2[batch.count] = s.vg_mps2[i];
      ++batch.count;
      // A batch holds consecutive samples only: it ends before a dropped one, at the end, or when full.
      complete = batch.count == plan.batch || i + 1 == n || !s.sent[i + 1];
      if (complete) {
        for (int k = batch.count; k < kMaxBatchSamples; ++k) batch.ug_mps2[k] = batch.vg_mps2[k] = 0.0;
        encoder.encode(batch);
      }
    }
    if (complete) {
      const auto in_message = static_cast<std::size_t>(plan.batch == 0 ? 1 : batch.count);
      batch.count = 0;
      if (!send(i)) {
        if (!out.aborted) out.interrupted = true;
        break;
      }
      out.samples_sent += in_message;
      done = i + 1;
    }
    if (progress) {
      const std::int64_t now_ns = out.paced ? last_ns : monotonic_ns();
      if (now_ns >= next_progress_ns) {
        progress(done, static_cast<double>(now_ns - start_ns) * 1e-9);
        next_progress_ns = now_ns + kProgressPeriodNs;
      }
    }
  }
  // Samples of a batch that never went out (interrupted while it filled) are not done: samples_done stops before.
  out.samples_done = done;
  if (!out.paced) last_ns = monotonic_ns();
  out.elapsed_s = static_cast<double>(last_ns - start_ns) * 1e-9;
  out.lateness = summarise_lateness(std::move(lateness_ns));
  return out;
}

}  // namespace rockwatch::cli
