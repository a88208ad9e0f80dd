// One monitor, many walls: a fixed number of MonitorLoops (one per wall, each with its own engine, wall parameters and
// output channels) fed from the same input messages. A building's walls share a ground sensor: each message goes to
// every wall that reads its channel (a ground channel shared by all, or a wall's own ground or wall-sensor channel),
// and each wall publishes its own wall_state_t, alarm_event_t, monitor_status_t (and wall_estimate_t) on its own
// channels. A message on a channel no wall reads is counted once, by the first wall (messages_ignored).
//
// Firmware rules as MonitorLoop: the walls are a fixed array (kMaxMonitorWalls, set at compile time), init() is the
// only setup, no allocation per message; the work per message is that of the walls that read it.
#pragma once

#include <cstddef>
#include <cstdint>

#include "rockwatch/firmware/monitor_loop.hpp"

namespace rockwatch::firmware {

// The most walls one monitor follows: the array of loops is part of the object, so every MultiWallMonitor costs
// kMaxMonitorWalls × sizeof(MonitorLoop) (4.2 kB each on x86-64, plus each wall's engine, allocated by the host).
// 16 by default, what a Cortex-M4's RAM holds beside everything else (67 kB); the host build (firmware/CMakeLists.txt)
// sets ROCKWATCH_MAX_MONITOR_WALLS=64 (266 kB), which one host core follows at 1 kHz (docs/BENCHMARKS.md, "Load: 64
// walls and 50 viewers"). The embedded builds compile this file without it: the M4 image never holds 64.
#ifndef ROCKWATCH_MAX_MONITOR_WALLS
#define ROCKWATCH_MAX_MONITOR_WALLS 16
#endif
inline constexpr std::size_t kMaxMonitorWalls = ROCKWATCH_MAX_MONITOR_WALLS;
static_assert(kMaxMonitorWalls >= 1 && kMaxMonitorWalls <= 1024, "ROCKWATCH_MAX_MONITOR_WALLS: 1 to 1024");

// Why init() refused. Values are stable: append, never renumber.
enum class MultiWallError : std::uint8_t {
  ok = 0,
  wall = 1,                     // a wall's MonitorLoop refused: failed_wall(), wall_error() (and its engine_error())
  wall_count_out_of_range = 2,  // count in [1, kMaxMonitorWalls]
  output_channel_shared = 3,    // two walls publish on one channel (state, alarm, status, estimate)
  input_is_output = 4,          // a wall's input channel is a channel another wall publishes on
};

const char* multi_wall_error_message(MultiWallError e);

class MultiWallMonitor {
 public:
  // settings[i], engines[i] and listeners[i] (null: none) of wall i < count. On refusal failed_wall() names the
  // wall (for the channel checks: the second of the two walls).
  MultiWallError init(const MonitorSettings* settings, SampleEngine* const* engines,
                      MonitorListener* const* listeners, std::size_t count, Transport& transport);
  std::size_t failed_wall() const { return failed_wall_; }
  MonitorError wall_error() const { return wall_error_; }

  // One received message, to every wall that reads its channel (else counted as ignored by wall 0).
  void on_message(const char* channel, const std::uint8_t* data, std::size_t size, std::int64_t receive_utime);
  // Whether some wall reads `channel` (the host's receive path keeps only those).
  bool reads(const char* channel) const;

  void publish_status(std::int64_t now_utime);  // every wall's monitor_status_t
  void finish_pending();  // every wall's samples still in work (MonitorLoop::finish_pending)
  void note_log_write_failure();
  void note_datagram_counts(std::int64_t rejected, std::int64_t from_other_sources);
  void set_step_clock(MonitorLoop::ClockNs clock);

  std::size_t size() const { return count_; }
  MonitorLoop& wall(std::size_t i) { return loops_[i]; }
  const MonitorLoop& wall(std::size_t i) const { return loops_[i]; }

 private:
  bool wall_reads(std::size_t i, const char* channel) const;

  MonitorLoop loops_[kMaxMonitorWalls];
  std::size_t count_ = 0;
  std::size_t failed_wall_ = 0;
  MonitorError wall_error_ = MonitorError::ok;
};

}  // namespace rockwatch::firmware
