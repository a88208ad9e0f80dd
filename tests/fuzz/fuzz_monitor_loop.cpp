// The monitor's message path: firmware::MonitorLoop::on_message on ROCKWATCH_ACCEL / ROCKWATCH_ACCEL_BATCH bytes
// (lcm decode, schema and batch checks, sequence accounting, gap bridging, restarts, value checks, the fixed-point
// engine and alarm, encoding of wall_state_t / alarm_event_t / monitor_status_t), and with the wall observer on
// ROCKWATCH_WALL_SENSOR bytes (wall_estimate_t out), several messages per input
// (layout: monitor_fuzz_input.hpp). After every message the loop's bookkeeping is checked against what it published;
// a violated invariant is a crash. Seeds: tests/fuzz/corpus/monitor_loop (make_monitor_seeds.cpp).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>

#include "fuzz_support.hpp"
#include "monitor_fuzz_input.hpp"
#include "rockwatch/core/model.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/firmware/monitor_loop.hpp"
#include "rockwatch/firmware/wall_engine.hpp"
#include "rockwatch/sim/double_wall_engine.hpp"

using namespace rockwatch;
namespace fw = rockwatch::firmware;
namespace in = rockwatch::fuzz::monitor_input;

namespace {

constexpr int kLevels = 5;  // QUIET … COLLAPSED

template <typename T>
bool decodes(T& m, const std::uint8_t* data, std::size_t size) {
  return m.decode(data, 0, static_cast<int>(size)) == static_cast<int>(size);
}

// Decodes and checks everything the loop publishes; refuses publishes when told to.
class CheckingTransport : public fw::Transport {
 public:
  bool publish(const char* channel, const std::uint8_t* data, std::size_t size) override {
    if (fail) return false;
    if (std::strcmp(channel, "ROCKWATCH_WALL_STATE") == 0) {
      wall_state_t m;
      ROCKWATCH_FUZZ_CHECK(decodes(m, data, size));
      ROCKWATCH_FUZZ_CHECK(m.schema_version == 1);
      ROCKWATCH_FUZZ_CHECK(m.seq > last_state_seq);  // numbered per processed sample; failed publishes leave holes
      last_state_seq = m.seq;
      ROCKWATCH_FUZZ_CHECK(std::isfinite(m.x_m) && std::isfinite(m.xd_mps) && std::isfinite(m.theta1_rad));
      ROCKWATCH_FUZZ_CHECK(std::isfinite(m.energy_ratio) && std::isfinite(m.t_to_instability_s));
      ROCKWATCH_FUZZ_CHECK(m.alarm_level >= 0 && m.alarm_level < kLevels);
      ROCKWATCH_FUZZ_CHECK(m.side == 1 || m.side == -1);
      ++states;
    } else if (std::strcmp(channel, "ROCKWATCH_ALARM") == 0) {
      alarm_event_t m;
      ROCKWATCH_FUZZ_CHECK(decodes(m, data, size));
      ROCKWATCH_FUZZ_CHECK(m.level != m.previous_level);
      ROCKWATCH_FUZZ_CHECK(m.level >= 0 && m.level < kLevels && m.previous_level >= 0 && m.previous_level < kLevels);
      ++alarms;
    } else if (std::strcmp(channel, "ROCKWATCH_WALL_ESTIMATE") == 0) {
      wall_estimate_t m;
      ROCKWATCH_FUZZ_CHECK(decodes(m, data, size));
      ROCKWATCH_FUZZ_CHECK(m.schema_version == wall_estimate_t::SCHEMA_VERSION);  // 3 since the sensors' status
      ROCKWATCH_FUZZ_CHECK(std::isfinite(m.x_inst_estimate_m) && m.x_inst_estimate_m >= 0.0);
      ROCKWATCH_FUZZ_CHECK(std::isfinite(m.sigma_x_inst_m) && m.sigma_x_inst_m >= 0.0);
      ROCKWATCH_FUZZ_CHECK(m.seq > last_estimate_seq);
      last_estimate_seq = m.seq;
      for (const double v : {m.x_m, m.xd_mps, m.sigma_x_m, m.sigma_xd_mps, m.r_estimate, m.sigma_r, m.bias_m,
                             m.innovation_x_m, m.innovation_a_mps2}) {
        ROCKWATCH_FUZZ_CHECK(std::isfinite(v));
      }
      ROCKWATCH_FUZZ_CHECK(m.sigma_x_m >= 0.0 && m.sigma_xd_mps >= 0.0 && m.sigma_r >= 0.0);
      ROCKWATCH_FUZZ_CHECK(m.r_estimate >= 0.0 && m.r_estimate <= 1.0);
      for (const std::int64_t c : {m.sensor_samples, m.x_updates, m.a_updates, m.rejected, m.not_finite,
                                   m.out_of_range, m.stuck, m.motion_while_quiet, m.jumps, m.misaligned, m.stale,
                                   m.queue_overflow, m.reinitialised, m.dropouts, m.sensor_flags, m.time_untrusted,
                                   m.duplicates}) {
        ROCKWATCH_FUZZ_CHECK(c >= 0);
      }
      ROCKWATCH_FUZZ_CHECK(m.x_updates + m.a_updates + m.stale + m.queue_overflow <= 2 * m.sensor_samples);
      ++estimates;
    } else if (std::strcmp(channel, "ROCKWATCH_STATUS") == 0) {
      monitor_status_t m;
      ROCKWATCH_FUZZ_CHECK(decodes(m, data, size));
      for (const std::int64_t c : {m.samples_received, m.samples_processed, m.samples_bridged, m.gaps, m.state_resets,
                                   m.duplicates, m.out_of_order, m.late, m.rejected_not_finite,
                                   m.rejected_out_of_range, m.lift_off, m.publisher_restarts, m.decode_errors,
                                   m.saturated, m.worst_step_ns, m.time_untrusted, m.datagrams_rejected,
                                   m.datagrams_from_other_sources}) {
        ROCKWATCH_FUZZ_CHECK(c >= 0);
      }
      ++statuses;
    } else {
      const bool own_channel = false;  // a publish on a channel the loop does not own
      ROCKWATCH_FUZZ_CHECK(own_channel);
    }
    return true;
  }

  bool fail = false;
  std::int64_t last_state_seq = -1, last_estimate_seq = -1;
  std::int64_t states = 0, alarms = 0, statuses = 0, estimates = 0;
};

// The alarm events form a chain: each starts from the level the previous one reached.
class ChainListener : public fw::MonitorListener {
 public:
  void on_alarm(const alarm_event_t& event) override {
    ROCKWATCH_FUZZ_CHECK(event.previous_level == level);
    level = event.level;
    ++events;
  }
  std::int8_t level = 0;
  std::int64_t events = 0;
};

fw::MonitorSettings settings_from(std::uint8_t byte) {
  static const std::int32_t kBridge[4] = {10, 0, 1, 1000};
  static const std::int64_t kRestart[4] = {1000, 1, 64, 1000000000};
  static const double kRate[4] = {200.0, 1000.0, 50.0, 10000.0};
  fw::MonitorSettings s;
  s.engine.wall = core::paper_wall();
  core::Restitution r;
  s.sensor_range_mps2 = 80.0;
  if ((byte & 0x40) != 0) {
    r.kind = core::RestitutionKind::value;
    r.value = 1.0;
    s.sensor_range_mps2 = 5.0;
    s.engine.observer_enabled = true;
  }
  s.engine.r_energy = core::restitution_energy_ratio(s.engine.wall, r);
  if ((byte & 0x80) != 0) {
    s.arithmetic = fw::MonitorArithmetic::double_precision;
    s.engine.model = core::ModelKind::full;
  }
  s.max_bridge_samples = kBridge[byte & 3];
  s.restart_window = kRestart[(byte >> 2) & 3];
  s.sample_rate_hz = kRate[(byte >> 4) & 3];
  return s;
}

void check_counters(const fw::MonitorCounters& c, const CheckingTransport& transport, const ChainListener& listener,
                    std::int64_t ignored_sent, bool observer) {
  for (const std::int64_t v :
       {c.samples_received, c.samples_processed, c.samples_bridged, c.gaps, c.state_resets, c.duplicates,
        c.out_of_order, c.late, c.rejected_not_finite, c.rejected_out_of_range, c.lift_off, c.publisher_restarts,
        c.decode_errors, c.saturated, c.sensor_flags, c.publish_failures, c.messages_ignored, c.worst_step_ns,
        c.alarm_events, c.states_published}) {
    ROCKWATCH_FUZZ_CHECK(v >= 0);
  }
  // Every received sample is dropped (duplicate, out of order) or processed once; every bridged sample is processed.
  ROCKWATCH_FUZZ_CHECK(c.samples_received >= c.duplicates + c.out_of_order);
  ROCKWATCH_FUZZ_CHECK(c.samples_processed == c.samples_received - c.duplicates - c.out_of_order + c.samples_bridged);
  // Per processed (received) sample at most one of each fault count.
  const std::int64_t taken = c.samples_received - c.duplicates - c.out_of_order;
  for (const std::int64_t v : {c.late, c.rejected_not_finite, c.rejected_out_of_range, c.lift_off, c.sensor_flags}) {
    ROCKWATCH_FUZZ_CHECK(v <= taken);
  }
  ROCKWATCH_FUZZ_CHECK(c.samples_bridged <= c.gaps * 1000);
  ROCKWATCH_FUZZ_CHECK(c.states_published <= c.samples_processed);
  ROCKWATCH_FUZZ_CHECK(c.states_published == transport.states);
  ROCKWATCH_FUZZ_CHECK(c.alarm_events == listener.events);
  ROCKWATCH_FUZZ_CHECK(c.messages_ignored == ignored_sent);
  // With the observer, one estimate per published state (the same transport verdict); none without it.
  ROCKWATCH_FUZZ_CHECK(c.estimates_published == transport.estimates);
  ROCKWATCH_FUZZ_CHECK(c.estimates_published == (observer ? c.states_published : 0));
  ROCKWATCH_FUZZ_CHECK(c.sensor_time_untrusted <= c.time_untrusted);
  ROCKWATCH_FUZZ_CHECK(observer || c.sensor_samples_received == 0);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  CheckingTransport transport;
  ChainListener listener;
  const auto loop = std::make_unique<fw::MonitorLoop>();
  const fw::MonitorSettings settings = settings_from(data[0]);
  fw::WallEngine fixed_engine;
  rockwatch::sim::DoubleWallEngine double_engine;
  fw::SampleEngine& engine = settings.arithmetic == fw::MonitorArithmetic::double_precision
                                 ? static_cast<fw::SampleEngine&>(double_engine)
                                 : static_cast<fw::SampleEngine&>(fixed_engine);
  ROCKWATCH_FUZZ_CHECK(loop->init(settings, engine, transport, &listener) == fw::MonitorError::ok);

  std::int64_t receive_utime = in::kReceiveClockStartUs;
  std::int64_t ignored_sent = 0;
  std::size_t at = 1;
  while (at < size) {
    const std::uint8_t selector = data[at++];
    std::size_t length = 0;
    for (int k = 0; k < 2 && at < size; ++k) length |= static_cast<std::size_t>(data[at++]) << (8 * k);
    length = std::min(length, size - at);
    const std::uint8_t* payload = data + at;
    at += length;

    receive_utime += (selector >> 4) * in::kClockStepUs;
    transport.fail = (selector & in::kPublishFails) != 0;
    if ((selector & in::kStatusBefore) != 0) loop->publish_status(receive_utime);
    const char* channel = (selector & in::kBatch) != 0 ? "ROCKWATCH_ACCEL_BATCH" : "ROCKWATCH_ACCEL";
    const bool observer = settings.engine.observer_enabled;
    if ((selector & in::kWallSensor) == in::kWallSensor) {
      channel = "ROCKWATCH_WALL_SENSOR";
      if (!observer) ++ignored_sent;
    } else if ((selector & in::kOtherChannel) != 0) {
      channel = "ROCKWATCH_OTHER";
      ++ignored_sent;
    }
    loop->on_message(channel, payload, length, receive_utime);
    check_counters(loop->counters(), transport, listener, ignored_sent, observer);
    ROCKWATCH_FUZZ_CHECK(static_cast<std::int8_t>(loop->alarm_level()) == listener.level);
  }
  transport.fail = false;
  loop->publish_status(receive_utime);
  return 0;
}
