// Writes the seed corpus of fuzz_monitor_loop (tests/fuzz/corpus/monitor_loop) in its input layout
// (monitor_fuzz_input.hpp): valid ground_accel_t / ground_accel_batch_t messages taken from the golden replay log
// tests/data/monitor/set01_X_0.40g_200Hz.lcmlog (a real stream in which the paper wall collapses), and short
// synthetic streams with one input fault of each kind the loop handles, and one with the wall observer on: ground and
// wall_sensor_t messages with each wall-sensor fault. Deterministic.
//
//   make_monitor_seeds tests/data/monitor/set01_X_0.40g_200Hz.lcmlog tests/fuzz/corpus/monitor_loop
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "monitor_fuzz_input.hpp"
#include "rockwatch/ground_accel_batch_t.hpp"
#include "rockwatch/ground_accel_t.hpp"
#include "rockwatch/wall_sensor_t.hpp"

using rockwatch::ground_accel_batch_t;
using rockwatch::ground_accel_t;
namespace in = rockwatch::fuzz::monitor_input;

namespace {

constexpr std::int64_t kT0 = 1700000000000000;
constexpr std::int64_t kPeriodUs = 5000;
using Bytes = std::vector<std::uint8_t>;

template <typename T>
Bytes encode(const T& m) {
  Bytes b(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

ground_accel_t sample(std::int64_t seq, double ug, double vg = 0.0) {
  ground_accel_t m{};
  m.utime = kT0 + (seq - 1) * kPeriodUs;
  m.seq = seq;
  m.schema_version = ground_accel_t::SCHEMA_VERSION;
  m.ug_mps2 = ug;
  m.vg_mps2 = vg;
  m.sensor_status = 0;
  return m;
}

ground_accel_batch_t batch_of(const std::vector<ground_accel_t>& samples, std::size_t first, std::size_t count) {
  ground_accel_batch_t b{};
  b.utime = samples[first].utime;
  b.seq = samples[first].seq;
  b.schema_version = ground_accel_batch_t::SCHEMA_VERSION;
  b.sample_period_us = static_cast<std::int32_t>(kPeriodUs);
  b.count = static_cast<std::int32_t>(count);
  for (std::size_t i = 0; i < count; ++i) {
    b.ug_mps2[i] = samples[first + i].ug_mps2;
    b.vg_mps2[i] = samples[first + i].vg_mps2;
  }
  b.sensor_status = 0;
  return b;
}

// 2 Hz at 0.2 g: the paper wall rocks with impacts.
double rocking_ug(std::int64_t seq) {
  return 0.20 * 9.81 * std::sin(2.0 * 3.14159265358979323846 * 2.0 * 0.005 * static_cast<double>(seq));
}

// 5 ms of receive clock per message on average (advance 2 or 3 steps of 2 ms).
std::uint8_t paced(std::size_t index, std::uint8_t flags = 0) {
  return static_cast<std::uint8_t>(flags | in::advance(index % 2 == 0 ? 2 : 3));
}

void write(const std::string& dir, const std::string& name, const Bytes& input) {
  std::ofstream out(dir + "/" + name, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(input.data()), static_cast<std::streamsize>(input.size()));
  if (!out) {
    std::cerr << "make_monitor_seeds: cannot write " << dir << "/" << name << '\n';
    std::exit(1);
  }
  std::cerr << name << ": " << input.size() << " bytes\n";
}

std::vector<ground_accel_t> read_log(const std::string& path) {
  lcm::LogFile log(path, "r");
  if (!log.good()) {
    std::cerr << "make_monitor_seeds: cannot read " << path << '\n';
    std::exit(1);
  }
  std::vector<ground_accel_t> samples;
  while (const lcm::LogEvent* event = log.readNextEvent()) {
    ground_accel_t m;
    if (m.decode(event->data, 0, event->datalen) == event->datalen) samples.push_back(m);
  }
  return samples;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: make_monitor_seeds GOLDEN.lcmlog OUT_DIR\n";
    return 2;
  }
  const std::vector<ground_accel_t> log = read_log(argv[1]);
  const std::string dir = argv[2];
  if (log.size() < 1000) {
    std::cerr << "make_monitor_seeds: expected the 1601-sample golden log, got " << log.size() << " samples\n";
    return 1;
  }

  // The first second of the golden log, one ground_accel_t per message.
  {
    Bytes input{0x00};
    for (std::size_t i = 0; i < 200; ++i) in::append_message(input, paced(i), encode(log[i]));
    write(dir, "golden_single_first_1s", input);
  }
  // The whole golden log (the wall collapses at 4.3 s) in batches of 50: every alarm level is reached; with the
  // fixed-point engine and with the double one (settings bit 7).
  for (const std::uint8_t settings : {std::uint8_t{0x00}, std::uint8_t{0x80}}) {
    Bytes input{settings};
    for (std::size_t first = 0, k = 0; first < log.size(); first += 50, ++k) {
      const std::size_t count = std::min<std::size_t>(50, log.size() - first);
      in::append_message(input, static_cast<std::uint8_t>(in::kBatch | in::advance(15)),
                         encode(batch_of(log, first, count)));
    }
    write(dir, settings == 0 ? "golden_batches_collapse" : "golden_batches_collapse_double", input);
  }

  // Synthetic rocking with one fault of each kind, single messages.
  {
    Bytes input{0x00};
    std::size_t i = 0;
    auto send = [&](const ground_accel_t& m, std::uint8_t flags = 0) {
      in::append_message(input, paced(i++, flags), encode(m));
    };
    std::int64_t seq = 10001;
    for (; seq <= 10040; ++seq) send(sample(seq, rocking_ug(seq)));
    send(sample(seq - 1, rocking_ug(seq - 1)));           // duplicate
    send(sample(seq - 70, rocking_ug(seq - 70)));         // out of order (older than the remembered 64)
    seq += 3;                                             // gap of 3: bridged
    send(sample(seq, rocking_ug(seq)));
    seq += 41;                                            // gap of 40: state reset
    send(sample(seq, rocking_ug(seq)));
    auto nan = sample(++seq, std::numeric_limits<double>::quiet_NaN());
    send(nan);                                            // not finite
    auto inf = sample(++seq, 0.0, std::numeric_limits<double>::infinity());
    send(inf);
    send(sample(++seq, 100.0));                           // out of range
    send(sample(++seq, 0.5, -20.0));                      // lift-off: g + vg <= 0
    auto flagged = sample(++seq, 0.5);
    flagged.sensor_status = ground_accel_t::SENSOR_CLIPPED | ground_accel_t::SENSOR_CLOCK_UNSYNC;
    send(flagged);                                        // sensor flags
    auto late = sample(++seq, 0.5);
    late.utime -= 1000000;                                // late by a second
    send(late);
    auto schema = sample(++seq, 0.5);
    schema.schema_version = 2;                            // decode error: schema
    send(schema);
    Bytes cut = encode(sample(seq, 0.5));
    cut.pop_back();                                       // decode error: length
    in::append_message(input, paced(i++), cut);
    send(sample(seq, 0.5), in::kStatusBefore);            // status before
    send(sample(++seq, 0.5), in::kPublishFails);          // transport refuses
    send(sample(++seq, 0.5), in::kOtherChannel);          // another channel: ignored
    for (std::int64_t k = 0; k < 20; ++k) {
      ++seq;
      send(sample(seq, rocking_ug(seq)));
    }
    for (std::int64_t k = 1; k <= 20; ++k) send(sample(k, rocking_ug(k)));  // the publisher restarted from 1
    write(dir, "faults_single", input);
  }

  // Batches: valid ones, then each batch-level fault.
  {
    std::vector<ground_accel_t> samples;
    for (std::int64_t seq = 1; seq <= 400; ++seq) samples.push_back(sample(seq, rocking_ug(seq)));
    Bytes input{0x00};
    std::size_t i = 0;
    auto send = [&](const ground_accel_batch_t& b, std::uint8_t flags = 0) {
      in::append_message(input, static_cast<std::uint8_t>(in::kBatch | flags | in::advance(15)), encode(b));
      ++i;
    };
    send(batch_of(samples, 0, 50));
    send(batch_of(samples, 40, 50));                      // overlaps: 10 duplicates
    send(batch_of(samples, 95, 50), in::kStatusBefore);   // gap of 5: bridged
    auto zero = batch_of(samples, 145, 50);
    zero.count = 0;                                       // decode error: count 0
    send(zero);
    auto many = batch_of(samples, 145, 50);
    many.count = 51;                                      // decode error: count > MAX_SAMPLES
    send(many);
    auto period = batch_of(samples, 145, 50);
    period.sample_period_us = 0;                          // decode error: period
    send(period);
    auto nan = batch_of(samples, 145, 50);
    nan.ug_mps2[3] = std::numeric_limits<double>::quiet_NaN();
    nan.vg_mps2[7] = 1e300;
    send(nan);
    send(batch_of(samples, 195, 7), in::kPublishFails);
    auto extreme = batch_of(samples, 202, 50);
    extreme.seq = std::numeric_limits<std::int64_t>::max() - 10;  // seq saturates inside the batch
    extreme.utime = std::numeric_limits<std::int64_t>::max() - 100;
    send(extreme);
    send(batch_of(samples, 300, 50));                     // far below: publisher restart
    write(dir, "faults_batch", input);
  }

  // The wall observer (settings bit 6): rocking ground samples, each preceded by a wall-sensor sample of its time,
  // then each wall-sensor fault once.
  {
    Bytes input{0x40};
    std::size_t i = 0;
    auto sensor = [&](std::int64_t seq, double x, std::int32_t valid = 3, double a = 0.0) {
      rockwatch::wall_sensor_t s{};
      s.utime = kT0 + (seq - 1) * kPeriodUs;
      s.seq = seq;
      s.schema_version = rockwatch::wall_sensor_t::SCHEMA_VERSION;
      s.x_mid_m = x;
      s.a_mid_mps2 = a;
      s.valid = valid;
      s.sensor_status = 0;
      return s;
    };
    auto send_sensor = [&](const rockwatch::wall_sensor_t& s) {
      in::append_message(input, static_cast<std::uint8_t>(in::kWallSensor), encode(s));
    };
    auto send = [&](const ground_accel_t& m) { in::append_message(input, paced(i++), encode(m)); };
    std::int64_t seq = 1;
    for (; seq <= 60; ++seq) {
      send_sensor(sensor(seq, 0.002 * std::sin(0.2 * static_cast<double>(seq)), 3, rocking_ug(seq)));
      send(sample(seq, rocking_ug(seq)));
    }
    send_sensor(sensor(seq, std::numeric_limits<double>::quiet_NaN()));  // not finite
    send_sensor(sensor(seq, 0.0, 2, std::numeric_limits<double>::infinity()));
    send_sensor(sensor(seq, 5.0));                                        // out of range
    auto stale = sensor(seq, 0.0);
    stale.utime -= 200000;                                                // stale
    send_sensor(stale);
    auto flagged = sensor(seq, 0.0);
    flagged.sensor_status = rockwatch::wall_sensor_t::SENSOR_CLIPPED;     // sensor status
    send_sensor(flagged);
    send_sensor(flagged);                                                 // repeated datagram
    auto future = sensor(seq + 400, 0.0);                                 // ahead of the ground stream
    send_sensor(future);
    auto far = sensor(seq, 0.0);
    far.utime += 3600000000LL;                                            // untrusted time
    send_sensor(far);
    auto schema = sensor(seq, 0.0);
    schema.schema_version = 2;                                            // decode error
    send_sensor(schema);
    send(sample(seq, rocking_ug(seq)));
    for (std::int64_t k = 0; k < 20; ++k) send_sensor(sensor(seq + k, 0.05));  // sensors without ground: overflow
    for (++seq; seq <= 140; ++seq) {
      if (seq % 3 == 0) send_sensor(sensor(seq, 0.01));                   // stuck, slower than the ground
      send(sample(seq, rocking_ug(seq)));
    }
    write(dir, "wall_sensors", input);
  }

  // The same short stream under other settings (bridge, restart window, rate, sensor range, restitution).
  for (const std::uint8_t settings : {std::uint8_t{0x55}, std::uint8_t{0xAA}, std::uint8_t{0xFF}, std::uint8_t{0x37}}) {
    Bytes input{settings};
    for (std::int64_t seq = 1; seq <= 60; ++seq) {
      const std::int64_t sent = seq % 17 == 0 ? seq + 2 : seq;  // a few gaps of 2
      in::append_message(input, paced(static_cast<std::size_t>(seq)), encode(sample(sent, 3.0 * rocking_ug(sent))));
    }
    char name[32];
    std::snprintf(name, sizeof name, "settings_%02x", settings);
    write(dir, name, input);
  }
  return 0;
}
