// The monitor loop: LCM-encoded input samples in, wall state, alarm transitions and status out, through a transport
// seam (Transport) that the Linux LCM adapter, the offline log mode and the tests implement.
//
// Firmware rules: after init() no allocation, bounded work per sample (WallEngine), messages decoded from and
// encoded into caller-owned fixed buffers (the lcm-gen types in firmware/lcmtypes are fixed size, so their
// encode/decode never allocate). Input faults never stop the loop: each is counted (MonitorCounters), flagged in the
// published state and status (monitor_status_t QUALITY_* bits), and the loop goes on.
//
// Input handling, per sample (ground_accel_t, or each sample of a ground_accel_batch_t):
// - the first sample (and the first after a reset below): the engine restarts from rest with this sample as its
//   current input (no step: bit-identical to `rockwatch simulate --arith fixed`, which starts from sample 0).
// - seq == last + 1: processed (one engine step).
// - seq ≤ last with a sample time later than the last sample's, or seq < last − restart_window: the publisher
//   restarted (a new session numbers from 0 again with the current time) — counted, flagged, the wall state restarts
//   from rest at this sample and the sequence follows the new numbering.
// - otherwise seq == last, or seq < last and received before (the last 64 seqs are remembered): duplicate, dropped.
//   Other seq < last (never received: bridged over or older than the remembered 64): out of order, dropped.
// - seq > last + 1: a gap of (seq − last − 1) samples. Up to max_bridge_samples: bridged from both sides (SPEC §12):
//   the missing inputs interpolated linearly between the last good input and this sample's (after its value checks
//   below), each one engine step and one published state with input_seq = the missing seq; counted in
//   samples_bridged, flagged QUALITY_GAP_BRIDGED, as is the sample that ends the gap; then the sample is processed. Longer: the state is unknown — the engine restarts from rest at this sample (QUALITY_STATE_UNKNOWN,
//   counted in state_resets). At most max_bridge_samples bridged steps per message: bounded work.
// - NaN/Inf (rejected_not_finite) or |value| > sensor_range_mps2 (rejected_out_of_range): counted once per sample,
//   flagged; each bad component is replaced by the last good value of that component (0 before any).
// - G = g + v̈ ≤ 0 (or the engine reports its input invalid): counted (lift_off), flagged; the engine holds its
//   state (SPEC §1) and sets REASON_INPUT_INVALID.
// - |receive time − sample time| > settings.clock_tolerance_us (default 10 s): time_untrusted,
//   QUALITY_TIME_UNTRUSTED; processed by its seq, but its time is not used for the restart test above (one sample
//   stamped an hour ahead must not make a restarted publisher's samples look older than the last one).
// - receive time − sample time > late_limit_s: counted as late (still processed); for a batch the time of its newest
//   sample counts for all its samples (a batch cannot be sent before its last sample). Only processed samples are
//   checked for lateness, sensor flags, range and lift-off; dropped ones count only as duplicate / out of order.
// - a message on an input channel that does not decode as its type (fingerprint, length: decode() must consume
//   exactly `size` bytes), or with schema_version != 1, batch count outside 1..MAX_SAMPLES, sample_period_us ≤ 0:
//   decode_errors, QUALITY_DECODE_ERROR in the status; ignored. Messages on other channels: messages_ignored.
// Wall sensors (settings.engine.observer_enabled; core::WallObserver in the engine): a wall_sensor_t is decoded and
// checked like a ground message (decode errors and schema_version != 1 counted as decode_errors), a sample stamped more
// than settings.clock_tolerance_us from the ground stream's time (the last ground sample's utime; before the first
// one, the receive time) is counted (time_untrusted, sensor_time_untrusted) and dropped (its time is what aligns it
// with the ground stream), the others are pushed into the engine, which queues them until a ground step reaches their
// utime. Each ground step ends at the ground sample's utime (a step whose ground sample's
// time is not trusted ends one period after the previous step). Every processed sample then also publishes a
// wall_estimate_t; the alarm reasons say which state the alarm saw — REASON_MEASURED (a sensor corrected it within the
// dropout time) or REASON_PREDICTED (the model alone) — and REASON_SENSOR_FAULT plus QUALITY_SENSOR_FAULT mark a
// sample at which the observer raised a sensor fault (core::observer_flag::faults). Sensor samples without ground
// samples overflow the observer's queue (counted, QUALITY_SENSOR_FAULT in the status); ground samples without sensor
// samples run the model alone (SENSOR_LOST, dropouts, REASON_PREDICTED). A wall_sensor_t with the seq and utime of the
// previous one pushed is a repeated datagram: counted (sensor_duplicates), QUALITY_DUPLICATE, dropped (applied twice
// it would count as two measurements and towards a stuck transducer). Observer off: the wall-sensor channel is not
// an input (its messages count as messages_ignored) and every output is what it was without the observer.
// Outputs: one wall_state_t per processed sample (received or bridged); an alarm_event_t per alarm level change,
// including the change to QUIET when a reset (long gap, publisher restart) restarts the alarm from a higher level;
// the listener is called after each alarm_event_t is published.
#pragma once

#include <cstddef>
#include <cstdint>

#include "rockwatch/firmware/sample_engine.hpp"
#include "rockwatch/alarm_event_t.hpp"
#include "rockwatch/ground_accel_batch_t.hpp"
#include "rockwatch/ground_accel_t.hpp"
#include "rockwatch/monitor_status_t.hpp"
#include "rockwatch/wall_estimate_t.hpp"
#include "rockwatch/wall_sensor_t.hpp"
#include "rockwatch/wall_state_t.hpp"

namespace rockwatch::firmware {

inline constexpr std::size_t kChannelNameMax = 64;  // bytes including the terminating NUL
// The default of MonitorSettings::clock_tolerance_us (10 s), and its largest accepted value (one day).
inline constexpr std::int64_t kDefaultClockTolerance_us = 10000000;
inline constexpr std::int64_t kMaxClockTolerance_us = 86400000000;
// The host's default bridge (rockwatch-monitor without max_bridge_samples): gaps up to this long are interpolated,
// round(kDefaultBridge_s × rate) samples, at least 10, at most 1000 (SPEC §12: a burst of 50 lost datagrams at 1 kHz
// is bridged, not a restart from rest).
inline constexpr double kDefaultBridge_s = 0.1;

struct MonitorChannels {
  char accel[kChannelNameMax] = "ROCKWATCH_ACCEL";
  char accel_batch[kChannelNameMax] = "ROCKWATCH_ACCEL_BATCH";
  char wall_state[kChannelNameMax] = "ROCKWATCH_WALL_STATE";
  char alarm[kChannelNameMax] = "ROCKWATCH_ALARM";
  char status[kChannelNameMax] = "ROCKWATCH_STATUS";
  // Used only with the observer (settings.engine.observer_enabled): an input and an output.
  char wall_sensor[kChannelNameMax] = "ROCKWATCH_WALL_SENSOR";
  char wall_estimate[kChannelNameMax] = "ROCKWATCH_WALL_ESTIMATE";
};

struct MonitorSettings {
  WallEngineConfig engine{};           // wall, r, κ, model, alarm; engine.dt_s is set from sample_rate_hz by init()
  MonitorArithmetic arithmetic = MonitorArithmetic::fixed_point;  // the engine handed to init() must run this
  double sample_rate_hz = 200.0;       // expected input rate [Hz]; the engine steps once per sample
  // Longest gap bridged by interpolation [samples]. The host's default is rate-dependent (kDefaultBridge_s below);
  // this one is the firmware's fixed default.
  std::int32_t max_bridge_samples = 10;
  double sensor_range_mps2 = 80.0;     // |ü|, |v̈| above this are out of range [m/s²] (≤ 80: the engine's input limit)
  double late_limit_s = 0.05;          // received later than this after the sample time: late [s]
  std::int64_t restart_window = 1000;  // seq this far below the last one: the publisher restarted [samples]
  // A sample stamped further than this from the monitor's clock at reception (future or past) has a time the monitor
  // does not trust: counted (time_untrusted), flagged (QUALITY_TIME_UNTRUSTED), not used to detect publisher
  // restarts. [µs], in [1, kMaxClockTolerance_us]. How far the publishers' clocks may be from the monitor's (NTP or
  // PTP keeps a lab's within milliseconds) plus the longest delivery delay.
  std::int64_t clock_tolerance_us = kDefaultClockTolerance_us;
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
  channel_name_invalid = 6,  // empty, not NUL-terminated, or an input channel equal to another channel
  restart_window_out_of_range = 7,  // restart_window in [1, 10⁹] samples
  arithmetic_invalid = 8,    // not a MonitorArithmetic value, or not the arithmetic of the engine given
  clock_tolerance_out_of_range = 9,  // clock_tolerance_us in [1, kMaxClockTolerance_us]
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

// As in monitor_status_t. samples_processed: samples the engine took (steps, and restarts from rest at the first
// sample or after a reset), received or bridged: one wall_state_t each (states_published counts those the transport
// accepted). alarm_events: level changes (published or not).
struct MonitorCounters {
  std::int64_t samples_received = 0, samples_processed = 0, samples_bridged = 0, gaps = 0, state_resets = 0;
  std::int64_t duplicates = 0, out_of_order = 0, late = 0, rejected_not_finite = 0, rejected_out_of_range = 0;
  std::int64_t lift_off = 0, publisher_restarts = 0, decode_errors = 0, saturated = 0, sensor_flags = 0;
  std::int64_t publish_failures = 0, messages_ignored = 0;  // ignored: on channels the monitor does not read
  std::int64_t log_write_failures = 0;  // reported by the host (note_log_write_failure)
  std::int64_t time_untrusted = 0;  // samples stamped more than clock_tolerance_us from the receive time
  // Reported by the host's receive path (note_datagram_counts): malformed datagrams, and datagrams from sources not
  // accepted.
  std::int64_t datagrams_rejected = 0, datagrams_from_other_sources = 0;
  std::int64_t worst_step_ns = 0;
  std::int64_t alarm_events = 0, states_published = 0;
  // With the observer: wall_sensor_t samples decoded, those dropped for an untrusted time (also in time_untrusted) or
  // as a repeat of the previous message, and wall_estimate_t messages the transport accepted.
  std::int64_t sensor_samples_received = 0, sensor_time_untrusted = 0, sensor_duplicates = 0, estimates_published = 0;
  // Carry-over (core/work_meter.hpp): samples the engine finished in a later call than their own (published then,
  // with their own utime), the most calls one waited, those whose events it did not locate because its queue was
  // full, and those it finished beyond a call's budget to make room in a full queue (WorkOverflow::finish). Counted
  // here and in the monitor's summary; the last two also flagged in the state's data_quality and the status
  // (QUALITY_WORK_SHED, QUALITY_OVER_BUDGET).
  std::int64_t samples_late = 0, max_late_calls = 0, samples_work_shed = 0, samples_over_budget = 0;
};

class MonitorLoop {
 public:
  // Validates and prepares everything (all floating point of the engine's init happens here): the loop runs
  // `engine` (the caller owns it; it must outlive the loop's use and run settings.arithmetic), initialised here with
  // settings.engine. `listener` may be null. The wall starts at rest; the first status says
  // QUALITY_MONITOR_RESTARTED.
  MonitorError init(const MonitorSettings& settings, SampleEngine& engine, Transport& transport,
                    MonitorListener* listener = nullptr);
  WallEngineError engine_error() const { return engine_error_; }

  // One received message. receive_utime: the monitor's clock at reception [µs since 1970-01-01 UTC].
  // Ignored (nothing counted) before a successful init().
  void on_message(const char* channel, const std::uint8_t* data, std::size_t size, std::int64_t receive_utime);

  // The host's own log of the traffic could not be written: counted and flagged in the next status (monitoring goes
  // on; the firmware itself writes no files).
  void note_log_write_failure();
  // The host's receive path's totals so far (it counts them by reason): carried in the status; an increase is
  // flagged (QUALITY_BAD_DATAGRAM) in the next one.
  void note_datagram_counts(std::int64_t rejected, std::int64_t from_other_sources);

  // Encodes and publishes monitor_status_t (the adapter calls it once per second and on exit). Samples the engine
  // still works on (carry-over) are finished first when no sample arrived since the last status (the stream paused).
  void publish_status(std::int64_t now_utime);
  // Finishes and publishes every sample the engine still works on (the adapter calls it before its last status).
  void finish_pending();

  const MonitorCounters& counters() const { return counters_; }
  // With the observer (settings.engine.observer_enabled): its counters since init(), and its estimates after the last
  // processed sample; null / zero without it.
  const core::ObserverCounters* observer_counters() const;
  const core::ObserverSample& last_observer() const { return last_observer_; }
  const MonitorSettings& settings() const { return settings_; }
  core::AlarmLevel alarm_level() const;

  // Monotonic clock used for worst_step_ns (the time of one engine call, SampleEngine::step, start or restart,
  // without encoding and publishing); the Linux adapter installs clock_gettime, tests a fake or nothing (null = not
  // measured, worst_step_ns stays 0).
  using ClockNs = std::int64_t (*)();
  void set_step_clock(ClockNs clock) { step_clock_ = clock; }

 private:
  void on_accel(const std::uint8_t* data, std::size_t size, std::int64_t receive_utime);
  void on_accel_batch(const std::uint8_t* data, std::size_t size, std::int64_t receive_utime);
  void on_wall_sensor(const std::uint8_t* data, std::size_t size, std::int64_t receive_utime);
  void decode_error();
  // delay_us: receive time − sample time (for a batch: − the time of its newest sample).
  void process_sample(std::int64_t utime, std::int64_t seq, double ug, double vg, std::int32_t sensor_status,
                      std::int64_t delay_us);
  // Engine step or reset (reset: first = the monitor's first sample, else a restart of the motion); ug, vg in the
  // wall frame [m/s²]; the step ends at t_us on the sensor clock.
  EngineSample run_engine(double ug, double vg, bool reset, std::int64_t t_us);
  // Engine step or reset with timing; then publishes the state (and the alarm event on a level change).
  // bridged: a held input for a missing sample (not counted again as an input fault). time_trusted: utime may align
  // the wall sensors.
  void step_and_publish(std::int64_t utime, std::int64_t seq, double ug, double vg, std::int32_t quality, bool reset,
                        bool bridged, bool time_trusted);
  void publish_estimate(std::int64_t utime, std::int64_t seq, const EngineSample& e);
  bool publish(const char* channel, int size);
  // What the loop knows of a sample the engine has not finished yet (carry-over): published with its state.
  struct PendingMeta {
    std::int64_t utime, seq;
    std::int32_t quality;
    bool reset, bridged;
  };
  // The engine's finished samples of its last call, each with its PendingMeta, in order.
  void publish_finished();
  void publish_state(const PendingMeta& m, const EngineSample& e);

  bool ready_ = false;  // init() succeeded
  MonitorSettings settings_{};
  Transport* transport_ = nullptr;
  MonitorListener* listener_ = nullptr;
  SampleEngine* engine_ = nullptr;
  core::AlarmLevel level_ = core::AlarmLevel::quiet;  // the engine's alarm level after the last sample
  WallEngineError engine_error_ = WallEngineError::ok;
  MonitorCounters counters_{};
  ClockNs step_clock_ = nullptr;
  // Sequence and input state, output numbering, flags since the last status: see monitor_loop.cpp.
  bool have_last_ = false;
  std::int64_t last_seq_ = 0;
  std::int64_t last_utime_ = 0;
  bool have_trusted_time_ = false;
  std::int64_t last_trusted_utime_ = 0;  // time of the last sample whose time was trusted (restart detection)
  std::uint64_t seen_mask_ = 0;  // bit k: seq last_seq_ − k was a received, processed sample
  double last_ug_ = 0.0, last_vg_ = 0.0;  // last good value of each component [m/s²]
  std::int64_t period_us_ = 5000;  // 1/sample_rate_hz [µs] (times of bridged samples)
  std::int64_t late_limit_us_ = 50000;
  bool last_time_trusted_ = false;  // the last processed sample's time was trusted (bridged steps follow it)
  std::int64_t step_end_us_ = 0;     // where the last engine step ended on the sensor clock [µs]
  std::int64_t state_seq_ = 0, alarm_seq_ = 0, status_seq_ = 0, estimate_seq_ = 0;
  std::int32_t quality_since_status_ = 0;
  core::ObserverSample last_observer_{};
  bool have_sensor_ = false;  // the last wall_sensor_t pushed (repeats of it are dropped)
  std::int64_t last_sensor_seq_ = 0, last_sensor_utime_ = 0;
  // Samples given to the engine and not yet published (one more than the engine's queue holds).
  static constexpr int kMaxPendingMeta = core::StepperAlarmChain<core::FixedRockingStepper>::kMaxPendingSamples + 1;
  PendingMeta pending_meta_[kMaxPendingMeta]{};
  int meta_head_ = 0, meta_count_ = 0;
  std::int64_t processed_at_last_status_ = -1;
  // Encode buffers, sized for the largest message (ground_accel_batch_t is the largest type).
  std::uint8_t out_buffer_[1024]{};
};

}  // namespace rockwatch::firmware
