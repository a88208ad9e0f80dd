// No allocation per message in firmware::MonitorLoop: the counting malloc/free/new/delete replacements of
// test_engine_allocations.cpp, around 100 000 on_message() calls (plus a status every 200 calls) over a stream with
// every input fault the loop handles — gaps bridged and too long, duplicates, out-of-order and late samples, NaN,
// Inf, out-of-range values, lift-off, publisher restarts, batches (good and bad), wrong message types, truncated
// bytes, foreign channels — and a wall that rocks, raises every alarm level and collapses. The messages are encoded
// before the measured window; the transport and the listener only count. Then the same stream with the wall observer
// on and a wall_sensor_t before every ground sample (with NaN, stale, repeated and undecodable sensor messages and a
// 0.5 s stretch without sensors per cycle). Exits 1 unless both counts are 0 and the streams really exercised all of
// that. A self-check first makes sure deliberate allocations are counted.
//
// A plain program, not a CppUTest suite (CppUTest replaces operator new), and not built with sanitizers
// (tests/firmware/proofs/CMakeLists.txt registers it as `monitor_allocations` only in builds without -fsanitize).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <new>
#include <vector>

#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/firmware/monitor_loop.hpp"
#include "rockwatch/firmware/wall_engine.hpp"

#include "counting_allocator.hpp"

namespace {
namespace fw = rockwatch::firmware;
using rockwatch::alarm_event_t;
using rockwatch::ground_accel_batch_t;
using rockwatch::ground_accel_t;

constexpr double kG = 9.81;
constexpr double kPi = 3.14159265358979323846;
constexpr double kDt = 0.005;
constexpr std::int64_t kPeriodUs = 5000;
constexpr std::int64_t kT0 = 1700000000000000;
constexpr std::size_t kMeasuredCalls = 100000;
const char* const kAccel = "ROCKWATCH_ACCEL";
const char* const kBatch = "ROCKWATCH_ACCEL_BATCH";
const char* const kSensor = "ROCKWATCH_WALL_SENSOR";

struct Message {
  const char* channel;
  std::vector<std::uint8_t> bytes;
  std::int64_t receive_utime;
};

template <typename T>
Message encoded(const char* channel, const T& m, std::int64_t receive_utime) {
  Message msg{channel, std::vector<std::uint8_t>(static_cast<std::size_t>(m.getEncodedSize())), receive_utime};
  m.encode(msg.bytes.data(), 0, static_cast<int>(msg.bytes.size()));
  return msg;
}

// The wall-frame input of engine_test_input.hpp's cycle (12 s): rocking at 0.2 g with a 0.05 g vertical for 7 s,
// one 1 Hz cycle at 0.5 g that tips the wall, then quiet.
void input(std::int64_t k, double& ug, double& vg) {
  const double t = double(k) * kDt;
  ug = 0.0;
  vg = 0.0;
  if (t < 7.0) {
    ug = 0.20 * kG * std::sin(2.0 * kPi * 2.0 * t);
    vg = 0.05 * kG * std::sin(2.0 * kPi * 3.0 * t);
  } else if (t < 8.0) {
    ug = 0.50 * kG * std::sin(2.0 * kPi * 1.0 * (t - 7.0));
  }
}

ground_accel_t sample(std::int64_t k) {
  ground_accel_t m{};
  m.utime = kT0 + k * kPeriodUs;
  m.seq = k;
  m.schema_version = 1;
  input(k, m.ug_mps2, m.vg_mps2);
  return m;
}

// The wall-sensor message of sample k: a transducer reading of a wall rocking at 2 Hz (it need not agree with the
// model: rejections and re-initialisations are part of what is exercised), an accelerometer reading of the ground.
Message sensor_message(std::int64_t k, std::int64_t receive) {
  rockwatch::wall_sensor_t s{};
  s.utime = kT0 + k * kPeriodUs;
  s.seq = k;
  s.schema_version = 1;
  s.x_mid_m = 0.01 * std::sin(2.0 * kPi * 2.0 * double(k) * kDt);
  double vg = 0.0;
  input(k, s.a_mid_mps2, vg);
  s.valid = 3;  // VALID_X | VALID_A
  if (k % 89 == 0) s.x_mid_m = std::numeric_limits<double>::quiet_NaN();
  if (k % 79 == 0) s.utime -= 20 * kPeriodUs;  // 100 ms behind the ground stream: stale
  return encoded(kSensor, s, receive);
}

// One 12 s cycle of messages with faults; seq restarts at 0 every cycle, so each repetition is a publisher restart.
// with_sensors: a wall-sensor message before each ground message (none at 3–3.5 s).
std::vector<Message> make_cycle(bool with_sensors = false) {
  std::vector<Message> out;
  const std::int64_t n = 2400;
  auto on_time = [](const ground_accel_t& m) { return m.utime + 1000; };
  for (std::int64_t k = 0; k < n; ++k) {
    if (k >= 1800 && k < 2000) {  // batches of 50
      if (k % 50 == 0) {
        ground_accel_batch_t b{};
        b.utime = kT0 + k * kPeriodUs;
        b.seq = k;
        b.schema_version = 1;
        b.sample_period_us = static_cast<std::int32_t>(kPeriodUs);
        b.count = 50;
        for (int i = 0; i < 50; ++i) input(k + i, b.ug_mps2[i], b.vg_mps2[i]);
        out.push_back(encoded(kBatch, b, b.utime + 49 * kPeriodUs + 1000));
        b.count = 0;  // a bad batch after it
        out.push_back(encoded(kBatch, b, b.utime));
      }
      continue;
    }
    if (k >= 1500 && k < 1520) continue;  // 20 missing: beyond the bridge limit, state reset at 1520
    if (k > 0 && k % 211 == 0) continue;  // 1 missing, sent after the next one (out of order)
    ground_accel_t m = sample(k);
    std::int64_t receive = on_time(m);
    if (with_sensors && !(k >= 600 && k < 700)) {
      out.push_back(sensor_message(k, receive));
      if (k % 83 == 0) out.push_back(sensor_message(k, receive));  // repeated datagram
      if (k % 250 == 0) {
        Message cut = sensor_message(k + 1, receive);  // truncated
        cut.bytes.pop_back();
        out.push_back(cut);
      }
    }
    if (k % 301 == 0) m.ug_mps2 = std::numeric_limits<double>::quiet_NaN();
    if (k % 307 == 0) m.vg_mps2 = std::numeric_limits<double>::infinity();
    if (k % 401 == 0) m.ug_mps2 = 100.0;
    if (k % 503 == 0) m.vg_mps2 = -12.0;
    if (k % 113 == 0) receive += 100000;
    if (k % 127 == 0) m.sensor_status = ground_accel_t::SENSOR_CLIPPED;
    out.push_back(encoded(kAccel, m, receive));
    if (k % 97 == 0) out.push_back(encoded(kAccel, m, receive));  // duplicate
    if (k > 1 && (k - 1) % 211 == 0) out.push_back(encoded(kAccel, sample(k - 1), on_time(m)));  // the late one
    if (k % 250 == 0) {
      Message cut = encoded(kAccel, m, receive);  // truncated
      cut.bytes.pop_back();
      out.push_back(cut);
      rockwatch::wall_state_t w{};
      out.push_back(encoded(kAccel, w, receive));        // wrong type
      out.push_back(encoded("OTHER_CHANNEL", m, receive));  // not an input channel
      ground_accel_t v2 = m;
      v2.schema_version = 2;
      out.push_back(encoded(kAccel, v2, receive));
    }
  }
  return out;
}

class CountingTransport : public fw::Transport {
 public:
  bool publish(const char*, const std::uint8_t*, std::size_t size) override {
    ++messages;
    bytes += size;
    return true;
  }
  std::uint64_t messages = 0, bytes = 0;
};

class CountingListener : public fw::MonitorListener {
 public:
  void on_alarm(const alarm_event_t& e) override {
    ++events;
    if (e.level == alarm_event_t::LEVEL_IMMINENT) ++imminent;
    if (e.level == alarm_event_t::LEVEL_COLLAPSED) ++collapsed;
  }
  std::uint64_t events = 0, imminent = 0, collapsed = 0;
};

}  // namespace

int main() {
  if (!counting_allocator::self_check()) {
    std::fprintf(stderr, "FAIL: the allocation counters do not see deliberate allocations\n");
    return 1;
  }
  const std::vector<Message> cycle = make_cycle();
  fw::MonitorSettings s;
  s.engine.wall = rockwatch::core::paper_wall();
  s.engine.r_energy = rockwatch::core::r_exp(s.engine.wall);
  s.sample_rate_hz = 1.0 / kDt;
  CountingTransport transport;
  CountingListener listener;
  fw::WallEngine engine;
  fw::MonitorLoop loop;
  const std::uint64_t before_init = g_calls;
  const fw::MonitorError e = loop.init(s, engine, transport, &listener);
  const std::uint64_t init_calls = g_calls - before_init;
  if (e != fw::MonitorError::ok) {
    std::fprintf(stderr, "FAIL: MonitorLoop::init: %s\n", fw::monitor_error_message(e));
    return 1;
  }

  const std::uint64_t before = g_calls;
  std::size_t j = 0;
  for (std::size_t i = 0; i < kMeasuredCalls; ++i) {
    const Message& m = cycle[j];
    loop.on_message(m.channel, m.bytes.data(), m.bytes.size(), m.receive_utime);
    if (i % 200 == 199) loop.publish_status(m.receive_utime);
    j = j + 1 == cycle.size() ? 0 : j + 1;
  }
  const std::uint64_t calls = g_calls - before;

  const fw::MonitorCounters& c = loop.counters();
  std::printf("init: %llu allocation calls (allowed); cycle of %zu messages\n",
              static_cast<unsigned long long>(init_calls), cycle.size());
  std::printf("on_message: %zu calls; samples received %lld, processed %lld, bridged %lld; gaps %lld, state resets %lld,"
              " duplicates %lld, out of order %lld, late %lld, not finite %lld, out of range %lld, lift-off %lld,"
              " publisher restarts %lld, decode errors %lld, sensor flags %lld, ignored %lld\n",
              kMeasuredCalls, static_cast<long long>(c.samples_received), static_cast<long long>(c.samples_processed),
              static_cast<long long>(c.samples_bridged), static_cast<long long>(c.gaps),
              static_cast<long long>(c.state_resets), static_cast<long long>(c.duplicates),
              static_cast<long long>(c.out_of_order), static_cast<long long>(c.late),
              static_cast<long long>(c.rejected_not_finite), static_cast<long long>(c.rejected_out_of_range),
              static_cast<long long>(c.lift_off), static_cast<long long>(c.publisher_restarts),
              static_cast<long long>(c.decode_errors), static_cast<long long>(c.sensor_flags),
              static_cast<long long>(c.messages_ignored));
  std::printf("published: %llu messages (%llu bytes), %lld states, %llu alarm events (%llu IMMINENT, %llu COLLAPSED)\n",
              static_cast<unsigned long long>(transport.messages), static_cast<unsigned long long>(transport.bytes),
              static_cast<long long>(c.states_published), static_cast<unsigned long long>(listener.events),
              static_cast<unsigned long long>(listener.imminent), static_cast<unsigned long long>(listener.collapsed));
  std::printf("allocation calls during on_message()/publish_status(): %llu\n", static_cast<unsigned long long>(calls));
  const bool eventful = c.samples_bridged > 0 && c.state_resets > 0 && c.duplicates > 0 && c.out_of_order > 0 &&
                        c.late > 0 && c.rejected_not_finite > 0 && c.rejected_out_of_range > 0 && c.lift_off > 0 &&
                        c.publisher_restarts > 0 && c.decode_errors > 0 && c.sensor_flags > 0 &&
                        c.messages_ignored > 0 && listener.imminent > 0 && listener.collapsed > 0 &&
                        c.states_published == c.samples_processed && c.samples_processed > 90000;
  if (!eventful) {
    std::fprintf(stderr, "FAIL: the stream did not exercise every fault, the alarm and a collapse; the count would "
                         "prove nothing\n");
    return 1;
  }
  if (calls != 0) {
    std::fprintf(stderr, "FAIL: MonitorLoop allocated (%llu calls)\n", static_cast<unsigned long long>(calls));
    return 1;
  }
  // The observer: the same stream with the wall sensors, on a fresh loop and engine.
  const std::vector<Message> sensor_cycle = make_cycle(true);
  fw::MonitorSettings so = s;
  so.engine.observer_enabled = true;
  CountingTransport observer_transport;
  CountingListener observer_listener;
  fw::WallEngine observer_engine;
  fw::MonitorLoop observer_loop;
  if (observer_loop.init(so, observer_engine, observer_transport, &observer_listener) != fw::MonitorError::ok) {
    std::fprintf(stderr, "FAIL: MonitorLoop::init with the observer\n");
    return 1;
  }
  const std::uint64_t before_observer = g_calls;
  j = 0;
  for (std::size_t i = 0; i < kMeasuredCalls; ++i) {
    const Message& m = sensor_cycle[j];
    observer_loop.on_message(m.channel, m.bytes.data(), m.bytes.size(), m.receive_utime);
    if (i % 200 == 199) observer_loop.publish_status(m.receive_utime);
    j = j + 1 == sensor_cycle.size() ? 0 : j + 1;
  }
  const std::uint64_t observer_calls = g_calls - before_observer;
  const fw::MonitorCounters& oc = observer_loop.counters();
  const rockwatch::core::ObserverCounters& ob = *observer_loop.observer_counters();
  std::printf("observer: %zu on_message calls; %lld sensor samples, %lld repeated, %lld decode errors; %lld samples "
              "processed, %lld estimates; %lld x and %lld a updates, %lld rejected, %lld not finite, %lld stale, %lld "
              "re-initialisations, %lld dropouts; %llu alarm events\n",
              kMeasuredCalls, static_cast<long long>(oc.sensor_samples_received),
              static_cast<long long>(oc.sensor_duplicates), static_cast<long long>(oc.decode_errors),
              static_cast<long long>(oc.samples_processed), static_cast<long long>(oc.estimates_published),
              static_cast<long long>(ob.x_updates), static_cast<long long>(ob.a_updates),
              static_cast<long long>(ob.rejected), static_cast<long long>(ob.not_finite),
              static_cast<long long>(ob.stale), static_cast<long long>(ob.reinitialised),
              static_cast<long long>(ob.dropouts), static_cast<unsigned long long>(observer_listener.events));
  std::printf("allocation calls during on_message()/publish_status() with the observer: %llu\n",
              static_cast<unsigned long long>(observer_calls));
  if (!(oc.sensor_samples_received > 10000 && oc.sensor_duplicates > 0 && oc.decode_errors > 0 &&
        oc.estimates_published == oc.samples_processed && ob.x_updates > 0 && ob.a_updates > 0 && ob.rejected > 0 &&
        ob.not_finite > 0 && ob.stale > 0 && ob.dropouts > 0 && observer_listener.events > 0)) {
    std::fprintf(stderr, "FAIL: the observer stream did not exercise the sensor faults, updates and a dropout\n");
    return 1;
  }
  if (observer_calls != 0) {
    std::fprintf(stderr, "FAIL: MonitorLoop with the observer allocated (%llu calls)\n",
                 static_cast<unsigned long long>(observer_calls));
    return 1;
  }
  std::printf("ok\n");
  return 0;
}
