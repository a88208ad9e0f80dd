#include "rockwatch/firmware/multi_wall_monitor.hpp"

#include <cstring>

namespace rockwatch::firmware {

namespace {

bool same(const char* a, const char* b) { return std::strncmp(a, b, kChannelNameMax) == 0; }

// The channels a wall publishes on (the estimate only with the observer).
int outputs(const MonitorSettings& s, const char* (&out)[4]) {
  out[0] = s.channels.wall_state;
  out[1] = s.channels.alarm;
  out[2] = s.channels.status;
  out[3] = s.channels.wall_estimate;
  return s.engine.observer_enabled ? 4 : 3;
}

int inputs(const MonitorSettings& s, const char* (&in)[3]) {
  in[0] = s.channels.accel;
  in[1] = s.channels.accel_batch;
  in[2] = s.channels.wall_sensor;
  return s.engine.observer_enabled ? 3 : 2;
}

}  // namespace

const char* multi_wall_error_message(MultiWallError e) {
  switch (e) {
    case MultiWallError::ok: return "ok";
    case MultiWallError::wall: return "a wall's monitor loop refused its settings";
    case MultiWallError::wall_count_out_of_range: return "the number of walls must be from 1 to kMaxMonitorWalls";
    case MultiWallError::output_channel_shared: return "two walls publish on the same channel";
    case MultiWallError::input_is_output: return "a wall reads a channel another wall publishes on";
  }
  return "?";
}

MultiWallError MultiWallMonitor::init(const MonitorSettings* settings, SampleEngine* const* engines,
                                      MonitorListener* const* listeners, std::size_t count, Transport& transport) {
  count_ = 0;
  failed_wall_ = 0;
  wall_error_ = MonitorError::ok;
  if (count < 1 || count > kMaxMonitorWalls) return MultiWallError::wall_count_out_of_range;
  // Channels first, across walls (each loop checks its own): outputs unique, no input another wall's output.
  for (std::size_t i = 0; i < count; ++i) {
    const char* out_i[4];
    const int n_out_i = outputs(settings[i], out_i);
    const char* in_i[3];
    const int n_in_i = inputs(settings[i], in_i);
    for (std::size_t j = 0; j < count; ++j) {
      if (j == i) continue;
      const char* out_j[4];
      const int n_out_j = outputs(settings[j], out_j);
      for (int b = 0; b < n_out_j; ++b) {
        for (int a = 0; a < n_out_i; ++a) {
          if (j < i && same(out_i[a], out_j[b])) {
            failed_wall_ = i;
            return MultiWallError::output_channel_shared;
          }
        }
        for (int a = 0; a < n_in_i; ++a) {
          if (same(in_i[a], out_j[b])) {
            failed_wall_ = i;
            return MultiWallError::input_is_output;
          }
        }
      }
    }
  }
  for (std::size_t i = 0; i < count; ++i) {
    const MonitorError e = loops_[i].init(settings[i], *engines[i], transport, listeners[i]);
    if (e != MonitorError::ok) {
      failed_wall_ = i;
      wall_error_ = e;
      return MultiWallError::wall;
    }
  }
  count_ = count;
  return MultiWallError::ok;
}

bool MultiWallMonitor::wall_reads(std::size_t i, const char* channel) const {
  const MonitorSettings& s = loops_[i].settings();
  const char* in[3];
  const int n = inputs(s, in);
  for (int k = 0; k < n; ++k) {
    if (same(channel, in[k])) return true;
  }
  return false;
}

bool MultiWallMonitor::reads(const char* channel) const {
  if (channel == nullptr) return false;
  for (std::size_t i = 0; i < count_; ++i) {
    if (wall_reads(i, channel)) return true;
  }
  return false;
}

void MultiWallMonitor::on_message(const char* channel, const std::uint8_t* data, std::size_t size,
                                  std::int64_t receive_utime) {
  if (count_ == 0) return;
  bool routed = false;
  if (channel != nullptr) {
    for (std::size_t i = 0; i < count_; ++i) {
      if (!wall_reads(i, channel)) continue;
      loops_[i].on_message(channel, data, size, receive_utime);
      routed = true;
    }
  }
  if (!routed) loops_[0].on_message(channel, data, size, receive_utime);  // counted there as ignored
}

void MultiWallMonitor::finish_pending() {
  for (std::size_t i = 0; i < count_; ++i) loops_[i].finish_pending();
}

void MultiWallMonitor::publish_status(std::int64_t now_utime) {
  for (std::size_t i = 0; i < count_; ++i) loops_[i].publish_status(now_utime);
}

void MultiWallMonitor::note_log_write_failure() {
  for (std::size_t i = 0; i < count_; ++i) loops_[i].note_log_write_failure();
}

void MultiWallMonitor::note_datagram_counts(std::int64_t rejected, std::int64_t from_other_sources) {
  for (std::size_t i = 0; i < count_; ++i) loops_[i].note_datagram_counts(rejected, from_other_sources);
}

void MultiWallMonitor::set_step_clock(MonitorLoop::ClockNs clock) {
  for (std::size_t i = 0; i < count_; ++i) loops_[i].set_step_clock(clock);
}

}  // namespace rockwatch::firmware
