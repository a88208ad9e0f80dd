// The monitor loop: decode → input checks → the engine (SampleEngine) → encode and publish. The input rules are in
// monitor_loop.hpp. Firmware rules: no allocation, no exceptions, no stdio; every loop is bounded (batch ≤
// MAX_SAMPLES samples, ≤ max_bridge_samples bridged steps per message).
#include "rockwatch/firmware/monitor_loop.hpp"

#include <climits>
#include <cmath>
#include <cstring>

#ifndef ROCKWATCH_VERSION_MAJOR
#error "ROCKWATCH_VERSION_MAJOR/MINOR/PATCH come from CMake's PROJECT_VERSION (firmware/CMakeLists.txt)"
#endif

namespace rockwatch::firmware {

namespace {

using Status = rockwatch::monitor_status_t;

// The published bits are core's bits, one for one (the messages carry them unchanged).
using Estimate = rockwatch::wall_estimate_t;
namespace flag = core::observer_flag;
static_assert(Estimate::SENSOR_X_ACTIVE == flag::x_active && Estimate::SENSOR_A_ACTIVE == flag::a_active &&
              Estimate::SENSOR_LOST == flag::sensor_lost && Estimate::SENSOR_REJECTED == flag::rejected &&
              Estimate::SENSOR_NOT_FINITE == flag::not_finite && Estimate::SENSOR_OUT_OF_RANGE == flag::out_of_range &&
              Estimate::SENSOR_STUCK == flag::stuck && Estimate::SENSOR_MOTION_WHILE_QUIET == flag::motion_while_quiet &&
              Estimate::SENSOR_MISALIGNED == flag::misaligned && Estimate::SENSOR_STALE == flag::stale &&
              Estimate::SENSOR_QUEUE_OVERFLOW == flag::queue_overflow &&
              Estimate::SENSOR_REINITIALISED == flag::reinitialised && Estimate::SENSOR_FLAG == flag::sensor_flag &&
              Estimate::SENSOR_JUMP == flag::jump && Estimate::SENSOR_ESTIMATE_CLAMPED == flag::estimate_clamped &&
              Estimate::SENSOR_MODEL_DOUBT == flag::model_doubt,
              "wall_estimate_t SENSOR_* must equal core::observer_flag");
static_assert(rockwatch::alarm_event_t::REASON_MEASURED == core::alarm_reason::measured &&
              rockwatch::alarm_event_t::REASON_PREDICTED == core::alarm_reason::predicted &&
              rockwatch::alarm_event_t::REASON_SENSOR_FAULT == core::alarm_reason::sensor_fault &&
              rockwatch::alarm_event_t::REASON_ARITHMETIC_SATURATED == core::alarm_reason::arithmetic_saturated,
              "alarm_event_t REASON_* must equal core::alarm_reason");

constexpr int kSeenBits = 64;  // duplicates are told from out-of-order samples over the last 64 seqs

// Saturating int64 arithmetic: seq and utime come from the network and may be anything.
std::int64_t sat_add(std::int64_t a, std::int64_t b) {
  std::int64_t r = 0;
  if (__builtin_add_overflow(a, b, &r)) return b > 0 ? INT64_MAX : INT64_MIN;
  return r;
}
std::int64_t sat_sub(std::int64_t a, std::int64_t b) {
  std::int64_t r = 0;
  if (__builtin_sub_overflow(a, b, &r)) return b < 0 ? INT64_MAX : INT64_MIN;
  return r;
}

bool name_valid(const char (&name)[kChannelNameMax]) {
  return name[0] != '\0' && std::memchr(name, '\0', kChannelNameMax) != nullptr;
}

bool same_name(const char* channel, const char (&name)[kChannelNameMax]) {
  return std::strncmp(channel, name, kChannelNameMax) == 0;
}

std::int8_t level_code(core::AlarmLevel l) { return static_cast<std::int8_t>(l); }

}  // namespace

const char* monitor_error_message(MonitorError e) {
  switch (e) {
    case MonitorError::ok: return "ok";
    case MonitorError::engine: return "the wall engine refused its configuration (see the engine error)";
    case MonitorError::sample_rate_out_of_range:
      return "sample_rate_hz must be in (0, 10000] Hz with 1/rate within the engine's step range (0, 0.03] s";
    case MonitorError::bridge_out_of_range: return "max_bridge_samples must be in [0, 1000]";
    case MonitorError::sensor_range_out_of_range: return "sensor_range_mps2 must be in (0, 80] m/s2";
    case MonitorError::late_limit_out_of_range: return "late_limit_s must be in (0, 60] s";
    case MonitorError::channel_name_invalid:
      return "channel names must be non-empty and NUL-terminated within 64 bytes, and each input channel must "
             "differ from every other channel";
    case MonitorError::restart_window_out_of_range: return "restart_window must be in [1, 1000000000] samples";
    case MonitorError::arithmetic_invalid: return "arithmetic must be fixed_point or double_precision";
    case MonitorError::clock_tolerance_out_of_range:
      return "clock_tolerance_us must be in [1, 86400000000] us (up to one day)";
  }
  return "?";
}

MonitorError MonitorLoop::init(const MonitorSettings& s, SampleEngine& engine, Transport& transport,
                               MonitorListener* listener) {
  ready_ = false;
  if (!(s.sample_rate_hz > 0.0 && s.sample_rate_hz <= 10000.0 && 1.0 / s.sample_rate_hz <= 0.03)) {
    return MonitorError::sample_rate_out_of_range;
  }
  if (s.max_bridge_samples < 0 || s.max_bridge_samples > 1000) return MonitorError::bridge_out_of_range;
  if (!(s.sensor_range_mps2 > 0.0 && s.sensor_range_mps2 <= 80.0)) return MonitorError::sensor_range_out_of_range;
  if (!(s.late_limit_s > 0.0 && s.late_limit_s <= 60.0)) return MonitorError::late_limit_out_of_range;
  if (s.restart_window < 1 || s.restart_window > 1000000000) return MonitorError::restart_window_out_of_range;
  if (s.clock_tolerance_us < 1 || s.clock_tolerance_us > kMaxClockTolerance_us) {
    return MonitorError::clock_tolerance_out_of_range;
  }
  const MonitorChannels& c = s.channels;
  // The wall-sensor channels exist only with the observer: without it their names are not checked, so that a
  // configuration valid before them stays valid.
  const char(*names[7])[kChannelNameMax] = {&c.accel,  &c.accel_batch, &c.wall_state,   &c.alarm,
                                            &c.status, &c.wall_sensor, &c.wall_estimate};
  const bool observer = s.engine.observer_enabled;
  const int n_names = observer ? 7 : 5;
  for (int i = 0; i < n_names; ++i) {
    if (!name_valid(*names[i])) return MonitorError::channel_name_invalid;
  }
  const int inputs[3] = {0, 1, 5};
  for (int k = 0; k < (observer ? 3 : 2); ++k) {
    const int input = inputs[k];
    for (int other = 0; other < n_names; ++other) {
      if (other != input && same_name(*names[input], *names[other])) return MonitorError::channel_name_invalid;
    }
  }

  settings_ = s;
  settings_.engine.dt_s = 1.0 / s.sample_rate_hz;
  if ((s.arithmetic != MonitorArithmetic::fixed_point && s.arithmetic != MonitorArithmetic::double_precision) ||
      engine.arithmetic() != s.arithmetic) {
    return MonitorError::arithmetic_invalid;
  }
  engine_ = &engine;
  engine_error_ = engine.init(settings_.engine);
  if (engine_error_ != WallEngineError::ok) return MonitorError::engine;

  transport_ = &transport;
  listener_ = listener;
  counters_ = MonitorCounters{};
  have_last_ = false;
  last_seq_ = 0;
  last_utime_ = 0;
  have_trusted_time_ = false;
  last_trusted_utime_ = 0;
  seen_mask_ = 0;
  last_ug_ = 0.0;
  last_vg_ = 0.0;
  period_us_ = std::llround(1e6 / s.sample_rate_hz);
  late_limit_us_ = std::llround(s.late_limit_s * 1e6);
  last_time_trusted_ = false;
  step_end_us_ = 0;
  state_seq_ = 0;
  alarm_seq_ = 0;
  status_seq_ = 0;
  estimate_seq_ = 0;
  quality_since_status_ = Status::QUALITY_MONITOR_RESTARTED;
  last_observer_ = core::ObserverSample{};
  have_sensor_ = false;
  last_sensor_seq_ = 0;
  last_sensor_utime_ = 0;
  engine.start(0.0, 0.0);
  level_ = core::AlarmLevel::quiet;
  ready_ = true;
  return MonitorError::ok;
}

core::AlarmLevel MonitorLoop::alarm_level() const { return level_; }

const core::ObserverCounters* MonitorLoop::observer_counters() const {
  return ready_ && settings_.engine.observer_enabled ? &engine_->observer_counters() : nullptr;
}

void MonitorLoop::on_message(const char* channel, const std::uint8_t* data, std::size_t size,
                             std::int64_t receive_utime) {
  if (!ready_) return;
  if (channel == nullptr) {
    ++counters_.messages_ignored;
    return;
  }
  if (same_name(channel, settings_.channels.accel)) {
    on_accel(data, size, receive_utime);
  } else if (same_name(channel, settings_.channels.accel_batch)) {
    on_accel_batch(data, size, receive_utime);
  } else if (settings_.engine.observer_enabled && same_name(channel, settings_.channels.wall_sensor)) {
    on_wall_sensor(data, size, receive_utime);
  } else {
    ++counters_.messages_ignored;
  }
}

void MonitorLoop::decode_error() {
  ++counters_.decode_errors;
  quality_since_status_ |= Status::QUALITY_DECODE_ERROR;
}

void MonitorLoop::on_accel(const std::uint8_t* data, std::size_t size, std::int64_t receive_utime) {
  rockwatch::ground_accel_t m;
  if (data == nullptr || size > static_cast<std::size_t>(INT_MAX)) return decode_error();
  const int n = static_cast<int>(size);
  if (m.decode(data, 0, n) != n || m.schema_version != rockwatch::ground_accel_t::SCHEMA_VERSION) {
    return decode_error();
  }
  ++counters_.samples_received;
  process_sample(m.utime, m.seq, m.ug_mps2, m.vg_mps2, m.sensor_status, sat_sub(receive_utime, m.utime));
}

void MonitorLoop::on_accel_batch(const std::uint8_t* data, std::size_t size, std::int64_t receive_utime) {
  rockwatch::ground_accel_batch_t m;
  if (data == nullptr || size > static_cast<std::size_t>(INT_MAX)) return decode_error();
  const int n = static_cast<int>(size);
  if (m.decode(data, 0, n) != n || m.schema_version != rockwatch::ground_accel_batch_t::SCHEMA_VERSION || m.count < 1 ||
      m.count > rockwatch::ground_accel_batch_t::MAX_SAMPLES || m.sample_period_us <= 0) {
    return decode_error();
  }
  counters_.samples_received += m.count;
  // A batch cannot leave before its newest sample: lateness is judged on that one, for every sample of the batch.
  const std::int64_t newest_utime = sat_add(m.utime, std::int64_t{m.count - 1} * m.sample_period_us);
  for (int i = 0; i < m.count; ++i) {
    const std::int64_t utime = sat_add(m.utime, std::int64_t{i} * m.sample_period_us);
    process_sample(utime, sat_add(m.seq, i), m.ug_mps2[i], m.vg_mps2[i], m.sensor_status,
                   sat_sub(receive_utime, newest_utime));
  }
}

void MonitorLoop::on_wall_sensor(const std::uint8_t* data, std::size_t size, std::int64_t receive_utime) {
  rockwatch::wall_sensor_t m;
  if (data == nullptr || size > static_cast<std::size_t>(INT_MAX)) return decode_error();
  const int n = static_cast<int>(size);
  if (m.decode(data, 0, n) != n || m.schema_version != rockwatch::wall_sensor_t::SCHEMA_VERSION) {
    return decode_error();
  }
  ++counters_.sensor_samples_received;
  // The sample's time is all that places it against the ground stream, so it is judged against that stream's clock
  // (the last ground sample's time; the receive time before the first one): a sample far from it would apply the
  // reading to the wrong step or, stamped ahead, hold the queue for ever — dropped, not used. Against the ground
  // stream rather than the monitor's clock: a replay faster than real time runs both streams ahead of the monitor's
  // clock together, and they stay aligned.
  const std::int64_t reference_utime = have_last_ ? last_utime_ : receive_utime;
  const std::int64_t delay_us = sat_sub(reference_utime, m.utime);
  if (!(delay_us >= -settings_.clock_tolerance_us && delay_us <= settings_.clock_tolerance_us)) {
    ++counters_.time_untrusted;
    ++counters_.sensor_time_untrusted;
    quality_since_status_ |= Status::QUALITY_TIME_UNTRUSTED;
    return;
  }
  if (have_sensor_ && m.seq == last_sensor_seq_ && m.utime == last_sensor_utime_) {
    ++counters_.sensor_duplicates;
    quality_since_status_ |= Status::QUALITY_DUPLICATE;
    return;
  }
  have_sensor_ = true;
  last_sensor_seq_ = m.seq;
  last_sensor_utime_ = m.utime;
  core::WallSensorSample sample;
  sample.utime_us = m.utime;
  sample.x_mid_m = m.x_mid_m;
  sample.a_mid_mps2 = m.a_mid_mps2;
  sample.x_valid = (m.valid & rockwatch::wall_sensor_t::VALID_X) != 0;
  sample.a_valid = (m.valid & rockwatch::wall_sensor_t::VALID_A) != 0;
  sample.sensor_status = m.sensor_status;
  // Faults found on arrival also reach the next step's flags; flagged here for the status in case no step follows
  // (sensor samples without ground samples).
  if ((engine_->push_sensor(sample) & core::observer_flag::faults) != 0) {
    quality_since_status_ |= Status::QUALITY_SENSOR_FAULT;
  }
}

void MonitorLoop::process_sample(std::int64_t utime, std::int64_t seq, double ug, double vg,
                                 std::int32_t sensor_status, std::int64_t delay_us) {
  std::int32_t quality = 0;
  // A sample time far from the monitor's clock (a publisher's clock that jumped, a forged or corrupted utime) is not
  // evidence of anything: counted and flagged, and kept out of the time-based restart test below, so one bad stamp
  // cannot make a restarted publisher's samples look like duplicates. Its value is processed as usual.
  const bool time_trusted = delay_us >= -settings_.clock_tolerance_us && delay_us <= settings_.clock_tolerance_us;
  if (!time_trusted) {
    ++counters_.time_untrusted;
    quality |= Status::QUALITY_TIME_UNTRUSTED;
  }
  bool reset = !have_last_;
  std::int64_t missing = 0;  // samples to bridge before this one
  if (have_last_) {
    const std::int64_t d = sat_sub(seq, last_seq_);
    if (d <= 0) {
      // A sequence number that goes back while the sample time goes forward is a new publisher session (a replay
      // or sensor restarted), however few samples it had sent; so is a jump back beyond the restart window.
      const bool time_went_forward = time_trusted && have_trusted_time_ && utime > last_trusted_utime_;
      if (d < -settings_.restart_window || time_went_forward) {
        ++counters_.publisher_restarts;
        quality |= Status::QUALITY_PUBLISHER_RESTART;
        reset = true;
      } else {
        const bool seen = d > -kSeenBits && ((seen_mask_ >> static_cast<unsigned>(-d)) & 1u) != 0;
        if (seen) {
          ++counters_.duplicates;
          quality_since_status_ |= Status::QUALITY_DUPLICATE;
        } else {
          ++counters_.out_of_order;
          quality_since_status_ |= Status::QUALITY_OUT_OF_ORDER;
        }
        quality_since_status_ |= quality & Status::QUALITY_TIME_UNTRUSTED;
        return;
      }
    } else if (d > 1) {
      ++counters_.gaps;
      if (d - 1 <= settings_.max_bridge_samples) {
        missing = d - 1;
        quality |= Status::QUALITY_GAP_BRIDGED;
      } else {
        ++counters_.state_resets;
        quality |= Status::QUALITY_STATE_UNKNOWN;
        reset = true;
      }
    }
  }

  // The values: NaN/Inf and out-of-range components replaced by the last good value of that component. Cleaned
  // before a gap is bridged: the bridge ends at this sample's (cleaned) value.
  const double before_ug = last_ug_, before_vg = last_vg_;  // the last good input before the gap [m/s²]
  if (sensor_status != 0) {
    ++counters_.sensor_flags;
    quality |= Status::QUALITY_SENSOR_FLAG;
  }
  const bool ug_finite = std::isfinite(ug), vg_finite = std::isfinite(vg);
  if (!ug_finite || !vg_finite) {
    ++counters_.rejected_not_finite;
    quality |= Status::QUALITY_NOT_FINITE;
  }
  const double range = settings_.sensor_range_mps2;
  const bool ug_in_range = !ug_finite || std::fabs(ug) <= range, vg_in_range = !vg_finite || std::fabs(vg) <= range;
  if (!ug_in_range || !vg_in_range) {
    ++counters_.rejected_out_of_range;
    quality |= Status::QUALITY_OUT_OF_RANGE;
  }
  if (ug_finite && ug_in_range) {
    last_ug_ = ug;
  } else {
    ug = last_ug_;
  }
  if (vg_finite && vg_in_range) {
    last_vg_ = vg;
  } else {
    vg = last_vg_;
  }
  // Bridge a short gap (≤ max_bridge_samples steps; SPEC §12): the missing inputs interpolated linearly between the
  // last good input before the gap and this sample's, which has arrived when the gap is found. Holding the last value
  // instead shifts the ground's impulse by up to half the gap and, near instability, delays or loses the alarm.
  if (missing > 0) {
    const double span = static_cast<double>(missing + 1);
    for (std::int64_t k = 1; k <= missing; ++k) {
      ++counters_.samples_bridged;
      const double w = static_cast<double>(k) / span;  // (0, 1): the missing sample's place in the gap
      step_and_publish(sat_add(last_utime_, k * period_us_), last_seq_ + k, before_ug + w * (ug - before_ug),
                       before_vg + w * (vg - before_vg), Status::QUALITY_GAP_BRIDGED, false, true,
                       last_time_trusted_);
    }
  }

  if (!(settings_.engine.wall.g_mps2 + vg > 0.0)) quality |= Status::QUALITY_LIFT_OFF;
  if (delay_us > late_limit_us_) {
    ++counters_.late;
    quality |= Status::QUALITY_LATE;
  }

  const std::int64_t shift = reset ? kSeenBits : (missing + 1);
  seen_mask_ = (shift >= kSeenBits ? 0 : seen_mask_ << static_cast<unsigned>(shift)) | 1u;
  have_last_ = true;
  last_seq_ = seq;
  last_utime_ = utime;
  if (time_trusted) {
    have_trusted_time_ = true;
    last_trusted_utime_ = utime;
  }
  last_time_trusted_ = time_trusted;
  step_and_publish(utime, seq, ug, vg, quality, reset, false, time_trusted);
}

EngineSample MonitorLoop::run_engine(double ug, double vg, bool reset, std::int64_t t_us) {
  const bool first = reset && counters_.samples_processed == 0;
  if (first) return engine_->start(ug, vg);      // the monitor's first sample: wall at rest, alarm QUIET
  if (reset) return engine_->restart(ug, vg);    // state unknown: motion from rest, the alarm keeps its level
  return engine_->step_at(ug, vg, t_us, period_us_);
}

void MonitorLoop::step_and_publish(std::int64_t utime, std::int64_t seq, double ug, double vg, std::int32_t quality,
                                   bool reset, bool bridged, bool time_trusted) {
  // The sensor clock of this step: the sample's own time when trusted, else one period after the previous step (a
  // stamp an hour ahead would apply every queued sensor sample at once, one an hour behind none).
  const bool first_step = counters_.samples_processed == 0;
  step_end_us_ = time_trusted || first_step ? utime : sat_add(step_end_us_, period_us_);
  if (meta_count_ == kMaxPendingMeta) meta_count_ = 0;  // not reached: the engine queues at most one fewer
  pending_meta_[(meta_head_ + meta_count_) % kMaxPendingMeta] = PendingMeta{utime, seq, quality, reset, bridged};
  ++meta_count_;
  const std::int64_t t0 = step_clock_ != nullptr ? step_clock_() : 0;
  run_engine(ug, vg, reset, step_end_us_);
  ++counters_.samples_processed;
  if (step_clock_ != nullptr) {
    const std::int64_t ns = sat_sub(step_clock_(), t0);
    if (ns > counters_.worst_step_ns) counters_.worst_step_ns = ns;
  }
  publish_finished();
}

void MonitorLoop::publish_finished() {
  const int n = engine_->finished_count();
  for (int i = 0; i < n && meta_count_ > 0; ++i) {
    const PendingMeta m = pending_meta_[meta_head_];
    meta_head_ = (meta_head_ + 1) % kMaxPendingMeta;
    --meta_count_;
    publish_state(m, engine_->finished_sample(i));
  }
}

void MonitorLoop::finish_pending() {
  if (!ready_) return;
  while (engine_->pending_samples() > 0) {
    engine_->finish_pending();
    publish_finished();
  }
}

void MonitorLoop::publish_state(const PendingMeta& m, const EngineSample& e) {
  const core::AlarmLevel before = level_;
  const std::int64_t utime = m.utime, seq = m.seq;
  std::int32_t quality = m.quality;
  const bool reset = m.reset;
  if (e.late_calls > 0) {
    ++counters_.samples_late;
    if (e.late_calls > counters_.max_late_calls) counters_.max_late_calls = e.late_calls;
  }
  if (e.work_shed) {
    ++counters_.samples_work_shed;
    quality |= Status::QUALITY_WORK_SHED;
  }
  if (e.work_overrun) {
    ++counters_.samples_over_budget;
    quality |= Status::QUALITY_OVER_BUDGET;
  }
  if (!reset && e.input_invalid) quality |= Status::QUALITY_LIFT_OFF;
  if (!reset && e.saturated) {
    ++counters_.saturated;
    quality |= Status::QUALITY_SATURATED;
  }
  // lift_off counts received samples; a bridged step holds an input already counted.
  if (!m.bridged && (quality & Status::QUALITY_LIFT_OFF) != 0) ++counters_.lift_off;
  quality_since_status_ |= quality;

  std::uint32_t reasons = e.alarm.reasons;
  if ((quality & Status::QUALITY_LIFT_OFF) != 0) reasons |= core::alarm_reason::input_invalid;
  last_observer_ = e.observer;
  if (e.observer.enabled) {
    // Which state the alarm saw, and whether a sensor fault coincides with it: never an alarm from a faulty sensor
    // without saying so.
    const bool measured = (e.observer.flags & (core::observer_flag::x_active | core::observer_flag::a_active)) != 0;
    reasons |= measured ? core::alarm_reason::measured : core::alarm_reason::predicted;
    if ((e.observer.flags & core::observer_flag::faults) != 0) {
      reasons |= core::alarm_reason::sensor_fault;
      quality |= Status::QUALITY_SENSOR_FAULT;
      quality_since_status_ |= Status::QUALITY_SENSOR_FAULT;
    }
  }
  const core::AlarmLevel level = e.alarm.level;
  level_ = level;
  const double x = e.x_m, xd = e.xd_mps;
  const double energy_ratio = e.energy_ratio;
  const double t_inst = e.t_to_instability_s;

  rockwatch::wall_state_t st;
  st.utime = utime;
  st.seq = state_seq_++;
  st.input_seq = seq;
  st.schema_version = rockwatch::wall_state_t::SCHEMA_VERSION;
  st.x_m = x;
  st.xd_mps = xd;
  st.theta1_rad = x / settings_.engine.wall.h1_m;
  st.side = static_cast<std::int8_t>(e.side_positive ? 1 : -1);
  st.moving = static_cast<std::int8_t>(e.moving ? 1 : 0);
  st.energy_ratio = energy_ratio;
  st.alarm_level = level_code(level);
  st.alarm_reasons = static_cast<std::int32_t>(reasons);
  st.t_to_instability_s = t_inst;
  st.data_quality = quality;
  const int st_size = st.getEncodedSize();
  if (st_size <= static_cast<int>(sizeof out_buffer_) &&
      st.encode(out_buffer_, 0, static_cast<int>(sizeof out_buffer_)) == st_size &&
      publish(settings_.channels.wall_state, st_size)) {
    ++counters_.states_published;
  }
  if (e.observer.enabled) publish_estimate(utime, seq, e);

  if (level == before) return;
  ++counters_.alarm_events;
  rockwatch::alarm_event_t ev;
  ev.utime = utime;
  ev.seq = alarm_seq_++;
  ev.input_seq = seq;
  ev.schema_version = rockwatch::alarm_event_t::SCHEMA_VERSION;
  ev.level = level_code(level);
  ev.previous_level = level_code(before);
  ev.reasons = static_cast<std::int32_t>(reasons);
  ev.x_m = x;
  ev.xd_mps = xd;
  ev.energy_ratio = energy_ratio;
  ev.t_to_instability_s = t_inst;
  const int ev_size = ev.getEncodedSize();
  if (ev_size <= static_cast<int>(sizeof out_buffer_) &&
      ev.encode(out_buffer_, 0, static_cast<int>(sizeof out_buffer_)) == ev_size) {
    publish(settings_.channels.alarm, ev_size);
  } else {
    ++counters_.publish_failures;
  }
  if (listener_ != nullptr) listener_->on_alarm(ev);
}

void MonitorLoop::publish_estimate(std::int64_t utime, std::int64_t seq, const EngineSample& e) {
  const core::ObserverCounters& c = engine_->observer_counters();
  rockwatch::wall_estimate_t m;
  m.utime = utime;
  m.seq = estimate_seq_++;
  m.input_seq = seq;
  m.schema_version = rockwatch::wall_estimate_t::SCHEMA_VERSION;
  m.x_m = e.x_m;
  m.xd_mps = e.xd_mps;
  m.sigma_x_m = e.observer.sigma_x_m;
  m.sigma_xd_mps = e.observer.sigma_xd_mps;
  m.r_estimate = e.observer.r_estimate;
  m.sigma_r = e.observer.sigma_r;
  m.bias_m = e.observer.bias_m;
  m.innovation_x_m = e.observer.innovation_x_m;
  m.innovation_a_mps2 = e.observer.innovation_a_mps2;
  m.sensor_health = static_cast<std::int32_t>(e.observer.flags);
  m.sensor_samples = c.samples;
  m.x_updates = c.x_updates;
  m.a_updates = c.a_updates;
  m.rejected = c.rejected;
  m.not_finite = c.not_finite;
  m.out_of_range = c.out_of_range;
  m.stuck = c.stuck;
  m.motion_while_quiet = c.motion_while_quiet;
  m.jumps = c.jumps;
  m.misaligned = c.misaligned;
  m.stale = c.stale;
  m.queue_overflow = c.queue_overflow;
  m.reinitialised = c.reinitialised;
  m.dropouts = c.dropouts;
  m.sensor_flags = c.sensor_flags;
  m.time_untrusted = counters_.sensor_time_untrusted;
  m.duplicates = counters_.sensor_duplicates;
  m.x_inst_estimate_m = e.observer.x_inst_estimate_m;
  m.sigma_x_inst_m = e.observer.sigma_x_inst_m;
  m.x_inst_alarm_m = e.observer.x_inst_alarm_m;
  m.omega_estimate_rps = e.observer.omega_estimate_rps;
  m.sigma_omega_rps = e.observer.sigma_omega_rps;
  m.c_estimate_mps2 = e.observer.c_estimate_mps2;
  m.sigma_c_mps2 = e.observer.sigma_c_mps2;
  m.k_estimate_ps2 = e.observer.k_estimate_ps2;
  m.sigma_k_ps2 = e.observer.sigma_k_ps2;
  m.clamped = c.clamped;
  const core::ObserverSensorStatus& xs = e.observer.x_status;
  const core::ObserverSensorStatus& as = e.observer.a_status;
  m.x_innovation_var_m2 = xs.innovation_variance;
  m.x_test_ratio = xs.test_ratio;
  m.x_rejected = xs.rejected;
  m.x_last_fused_utime = xs.last_fused_us;
  m.a_innovation_var_m2ps4 = as.innovation_variance;
  m.a_test_ratio = as.test_ratio;
  m.a_rejected = as.rejected;
  m.a_last_fused_utime = as.last_fused_us;
  const int size = m.getEncodedSize();
  if (size <= static_cast<int>(sizeof out_buffer_) &&
      m.encode(out_buffer_, 0, static_cast<int>(sizeof out_buffer_)) == size) {
    if (publish(settings_.channels.wall_estimate, size)) ++counters_.estimates_published;
  } else {
    ++counters_.publish_failures;
  }
}

bool MonitorLoop::publish(const char* channel, int size) {
  if (transport_->publish(channel, out_buffer_, static_cast<std::size_t>(size))) return true;
  ++counters_.publish_failures;
  return false;
}

void MonitorLoop::note_log_write_failure() {
  if (!ready_) return;
  ++counters_.log_write_failures;
  quality_since_status_ |= Status::QUALITY_LOG_WRITE_FAILED;
}

void MonitorLoop::note_datagram_counts(std::int64_t rejected, std::int64_t from_other_sources) {
  if (!ready_) return;
  if (rejected != counters_.datagrams_rejected || from_other_sources != counters_.datagrams_from_other_sources) {
    quality_since_status_ |= Status::QUALITY_BAD_DATAGRAM;
  }
  counters_.datagrams_rejected = rejected;
  counters_.datagrams_from_other_sources = from_other_sources;
}

void MonitorLoop::publish_status(std::int64_t now_utime) {
  if (!ready_) return;
  if (counters_.samples_processed == processed_at_last_status_) finish_pending();  // the stream paused
  processed_at_last_status_ = counters_.samples_processed;
  Status m;
  m.utime = now_utime;
  m.seq = status_seq_++;
  m.schema_version = Status::SCHEMA_VERSION;
  m.version_major = ROCKWATCH_VERSION_MAJOR;
  m.version_minor = ROCKWATCH_VERSION_MINOR;
  m.version_patch = ROCKWATCH_VERSION_PATCH;
  m.config_digest = settings_.config_digest;
  const MonitorCounters& c = counters_;
  m.samples_received = c.samples_received;
  m.samples_processed = c.samples_processed;
  m.samples_bridged = c.samples_bridged;
  m.gaps = c.gaps;
  m.state_resets = c.state_resets;
  m.duplicates = c.duplicates;
  m.out_of_order = c.out_of_order;
  m.late = c.late;
  m.rejected_not_finite = c.rejected_not_finite;
  m.rejected_out_of_range = c.rejected_out_of_range;
  m.lift_off = c.lift_off;
  m.publisher_restarts = c.publisher_restarts;
  m.decode_errors = c.decode_errors;
  m.saturated = c.saturated;
  m.worst_step_ns = c.worst_step_ns;
  m.data_quality = quality_since_status_;
  m.alarm_level = level_code(alarm_level());
  m.arithmetic = engine_->arithmetic() == MonitorArithmetic::double_precision ? Status::ARITH_DOUBLE : Status::ARITH_FIXED;
  m.sensor_flags = c.sensor_flags;
  m.messages_ignored = c.messages_ignored;
  m.publish_failures = c.publish_failures;
  m.log_write_failures = c.log_write_failures;
  m.time_untrusted = c.time_untrusted;
  m.datagrams_rejected = c.datagrams_rejected;
  m.datagrams_from_other_sources = c.datagrams_from_other_sources;
  const int size = m.getEncodedSize();
  bool sent = false;
  if (size <= static_cast<int>(sizeof out_buffer_) &&
      m.encode(out_buffer_, 0, static_cast<int>(sizeof out_buffer_)) == size) {
    sent = publish(settings_.channels.status, size);
  } else {
    ++counters_.publish_failures;
  }
  // The quality bits are "since the last status that was sent": a lost status must not lose them.
  if (sent) quality_since_status_ = 0;
}

}  // namespace rockwatch::firmware
