// The paced loop of `rockwatch replay` and `rockwatch demo`: encodes the prepared samples as ground_accel_t (or
// ground_accel_batch_t) messages, waits for each message's absolute deadline on CLOCK_MONOTONIC
// (clock_nanosleep TIMER_ABSTIME), publishes it with LCM and/or writes it to an LCM log, and measures lateness.
// While paced, the thread runs under SCHED_FIFO (low priority) and the process's memory is locked, when the process
// may have them (replay_publisher.cpp, through rockwatch/process/realtime.hpp); both are undone at the end.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "common/replay_out/replay_lateness.hpp"
#include "common/replay_out/replay_stream.hpp"
#include "rockwatch/core/wall_observer.hpp"

namespace rockwatch::cli {

struct PublishPlan {
  std::string channel;
  int batch = 0;         // 0: one ground_accel_t per sample; N: ground_accel_batch_t of up to N samples
  double speed = 1.0;    // deadlines at (i/rate)/speed after the start; 0 = none (as fast as possible)
  std::string log_name;  // for messages about the log: "--log FILE"
  // Wall-sensor samples (times relative to the record's start) sent as wall_sensor_t on wall_sensor_channel
  // alongside the ground stream: each one just before the ground message that reaches its time, so a monitor applies
  // it in the same step as `rockwatch simulate --wall-sensors` does. Null: none.
  const std::vector<core::WallSensorSample>* wall_sensors = nullptr;
  std::string wall_sensor_channel = "ROCKWATCH_WALL_SENSOR";
};

struct ReplayOutcome {
  std::int64_t start_utime = 0;  // utime of seq 0 [µs, CLOCK_REALTIME]
  std::size_t samples_done = 0;  // seqs handled, sent or dropped (all of them unless interrupted or aborted)
  std::size_t samples_sent = 0;
  std::size_t samples_dropped = 0;
  std::size_t messages = 0;          // ground messages encoded (published and/or logged)
  std::size_t wall_sensor_samples_sent = 0;  // wall_sensor_t messages sent (or logged)
  std::size_t publish_failures = 0;  // lcm publish returned an error
  std::string first_failure;         // its reason (errno text)
  bool aborted = false;              // the very first message could not be published: nothing else was tried
  bool interrupted = false;          // the cancel flag was set
  bool paced = false;                // deadlines were waited for (publishing with speed > 0)
  bool realtime = false;             // paced under SCHED_FIFO (the process may: root, CAP_SYS_NICE, RLIMIT_RTPRIO)
  bool memory_locked = false;        // paced with the process's memory locked (mlockall, when permitted)
  double elapsed_s = 0.0;            // start to the last message
  LatenessSummary lateness;          // paced messages only
};

// Called about four times a second with the seqs done so far and the time since the start.
using ReplayProgress = std::function<void(std::size_t done, double elapsed_s)>;

// Sends `stream` through `lcm` (may be null: no publishing) and `log` (may be null). Paced when `lcm` is given and
// plan.speed > 0. `cancel` (may be null) stops the loop between messages, also while waiting. Throws UsageError
// when the log cannot be written. The utime of seq i is start + round(i·1e6/rate) µs.
ReplayOutcome publish_stream(const ReplayStream& stream, const PublishPlan& plan, lcm::LCM* lcm, lcm::LogFile* log,
                             const std::atomic<bool>* cancel, const ReplayProgress& progress);

}  // namespace rockwatch::cli
