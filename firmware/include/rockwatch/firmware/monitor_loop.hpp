// The monitor loop: LCM-encoded input samples in, wall state, alarm transitions and status out, through a transport
// seam (Transport) that the Linux LCM adapter, the offline log mode and the tests implement.
//
// Firmware rules: after init() no allocation, bounded work per sample (WallEngine), messages decoded from and
// encoded into caller-owned fixed buffers (the lcm-gen types in firmware/lcmtypes are fixed size, so their
// encode/decode never allocate). Input faults never stop the loop: each is counted (MonitorCounters), flagged in the
// published state and status (monitor_status_t QUALITY_* bits), and the loop goes on.
//
// Input handling, per sample (ground_accel_t, or each sample of a ground_accel_batch_t):
// - seq == last + 1: processed.
// - seq ≤ last, same sample again: duplicate, dropped. seq < last − restart_window: the publisher restarted —
//   counted, flagged, the wall state restarts from rest and the sequence follows the new numbering. Other seq < last:
//   out of order, dropped.
// - seq > last + 1: a gap of (seq − last − 1) samples. Up to max_bridge_samples: bridged by holding the last good
//   input for the missing samples (counted, flagged QUALITY_GAP_BRIDGED), then the sample is processed. Longer:
//   the state is unknown — the engine restarts from rest (QUALITY_STATE_UNKNOWN, counted in state_resets).
// - NaN/Inf or |value| > sensor_range_mps2: counted, flagged, the last good input is used instead.
// - G = g + v̈ ≤ 0: counted (lift_off), flagged; the engine holds its state (SPEC §1).
// - receive time − sample time > late_limit_s: counted as late (still processed).
// - a message on an input channel that does not decode as its type: decode_errors, flagged; ignored.
#pragma once

#include <cstddef>
#include <cstdint>

#include "rockwatch/firmware/wall_engine.hpp"
#include "rockwatch/alarm_event_t.hpp"
#include "rockwatch/ground_accel_batch_t.hpp"
#include "rockwatch/ground_accel_t.hpp"
#include "rockwatch/monitor_status_t.hpp"
#include "rockwatch/wall_state_t.hpp"

namespace rockwatch::firmware {

inline constexpr std::size_t kChannelNameMax = 64;  // bytes including the terminating NUL

struct MonitorChannels {
  char accel[kChannelNameMax] = "ROCKWATCH_ACCEL";
  char accel_batch[kChannelNameMax] = "ROCKWATCH_ACCEL_BATCH";
  char wall_state[kChannelNameMax] = "ROCKWATCH_WALL_STATE";
  char alarm[kChannelNameMax] = "ROCKWATCH_ALARM";
  char status[kChannelNameMax] = "ROCKWATCH_STATUS";
};

struct MonitorSettings {
  WallEngineConfig engine{};           // wall, r, κ, alarm; engine.dt_s is set from sample_rate_hz by init()
  double sample_rate_hz = 200.0;       // expected input rate [Hz]; the engine steps once per sample
  std::int32_t max_bridge_samples = 10;  // longest gap bridged by holding the input [samples]
  double sensor_range_mps2 = 80.0;     // |ü|, |v̈| above this are out of range [m/s²] (≤ 80: the engine's input limit)
  double late_limit_s = 0.05;          // received later than this after the sample time: late [s]
  std::int64_t restart_window = 1000;  // seq this far below the last one: the publisher restarted [samples]
  MonitorChannels channels{};
  std::int64_t config_digest = 0;      // published in monitor_status_t (the host computes it from the config file)
};

// Why init() refused the settings. Values are stable: append, never renumber.
enum class MonitorError : std::uint8_t {
  ok = 0,
  engine = 1,                // see engine_error()
  sample_rate_out_of_range = 2,  // (0, 10000] Hz and 1/rate within the engine's step range
  bridge_out_of_range = 3,   // max_bridge_samples in [0, 1000]
  sensor_range_out_of_range = 4,  // (0, 80] m/s²
  late_limit_out_of_range = 5,    // (0, 60] s
  channel_name_invalid = 6,  // empty or not NUL-terminated
};

const char* monitor_error_message(MonitorError e);

// The seam. publish() sends encoded bytes; returns false when the transport could not send (counted, not fatal).
class Transport {
 public:
  virtual ~Transport() = default;
  virtual bool publish(const char* channel, const std::uint8_t* data, std::size_t size) = 0;
};

// Optional host-side hook (the executable prints alarm transitions as JSON lines). Called after publishing.
class MonitorListener {
 public:
  virtual ~MonitorListener() = default;
  virtual void on_alarm(const rockwatch::alarm_event_t& event) = 0;
};

struct MonitorCounters {
  std::int64_t samples_received = 0, samples_processed = 0, samples_bridged = 0, gaps = 0, state_resets = 0;
  std::int64_t duplicates = 0, out_of_order = 0, late = 0, rejected_not_finite = 0, rejected_out_of_range = 0;
  std::int64_t lift_off = 0, publisher_restarts = 0, decode_errors = 0, saturated = 0, sensor_flags = 0;
  std::int64_t publish_failures = 0, messages_ignored = 0;  // ignored: on channels the monitor does not read
  std::int64_t worst_step_ns = 0;
  std::int64_t alarm_events = 0, states_published = 0;
};

class MonitorLoop {
 public:
  // Validates and prepares everything (all floating point of the engine's init happens here). `listener` may be
  // null. The wall starts at rest; the first status says QUALITY_MONITOR_RESTARTED.
  MonitorError init(const MonitorSettings& settings, Transport& transport, MonitorListener* listener = nullptr);
  WallEngineError engine_error() const { return engine_error_; }

  // One received message. receive_utime: the monitor's clock at reception [µs since 1970-01-01 UTC].
  // step_clock_ns (optional): a monotonic clock for worst_step_ns; null = not measured.
  void on_message(const char* channel, const std::uint8_t* data, std::size_t size, std::int64_t receive_utime);

  // Encodes and publishes monitor_status_t (the adapter calls it once per second and on exit).
  void publish_status(std::int64_t now_utime);

  const MonitorCounters& counters() const { return counters_; }
  const WallEngine& engine() const { return engine_; }
  const MonitorSettings& settings() const { return settings_; }
  core::AlarmLevel alarm_level() const;

  // Monotonic clock used for worst_step_ns; the Linux adapter installs clock_gettime, tests a fake or nothing.
  using ClockNs = std::int64_t (*)();
  void set_step_clock(ClockNs clock) { step_clock_ = clock; }

 private:
  void process_sample(std::int64_t utime, std::int64_t seq, double ug, double vg, std::int32_t sensor_status,
                      std::int64_t receive_utime);

  MonitorSettings settings_{};
  Transport* transport_ = nullptr;
  MonitorListener* listener_ = nullptr;
  WallEngine engine_{};
  WallEngineError engine_error_ = WallEngineError::ok;
  MonitorCounters counters_{};
  ClockNs step_clock_ = nullptr;
  // Sequence and input state, output numbering, flags since the last status: see monitor_loop.cpp.
  bool have_last_ = false;
  std::int64_t last_seq_ = 0;
  std::int64_t last_utime_ = 0;
  double last_ug_ = 0.0, last_vg_ = 0.0;
  std::int64_t state_seq_ = 0, alarm_seq_ = 0, status_seq_ = 0;
  std::int32_t quality_since_status_ = 0;
  // Encode buffers, sized for the largest message (ground_accel_batch_t is the largest type).
  std::uint8_t out_buffer_[1024]{};
};

}  // namespace rockwatch::firmware
