// rockwatch-monitor --observer live on LCM (udpm multicast on loopback, ttl=0, a port and channel names of this test
// process's own): this process publishes ground samples and wall-sensor samples of the same times in real time; the
// monitor fuses them and publishes one wall_estimate_t per ground sample, and its summary's "observer" object counts
// the sensor samples, the updates and the one bad reading sent (skipped, saying why, when multicast does not work
// here). Offline, a log with both streams gives one wall_estimate_t per ground sample, the same on every run.
#include <signal.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "lcm_transport.hpp"
#include "monitor_live_support.hpp"
#include "monitor_test_support.hpp"
#include "rockwatch/alarm_event_t.hpp"
#include "rockwatch/ground_accel_t.hpp"
#include "rockwatch/sim/forecast_calibration.hpp"
#include "rockwatch/wall_estimate_t.hpp"
#include "rockwatch/wall_forecast_t.hpp"
#include "rockwatch/wall_sensor_t.hpp"
#include "rockwatch/wall_state_t.hpp"

#include <CppUTest/TestHarness.h>

// The file's own scope in a unity build (tests/CMakeLists.txt): its helpers' names recur in other files of the suite.
namespace unity_test_monitor_live_observer {

using nlohmann::json;
using rockwatch::test::now_s;
using rockwatch::test::skip_without_multicast;
using rockwatch::test::sleep_s;
using rockwatch::test::TempDir;

namespace {

struct Channels : rockwatch::test::LiveChannels {
  Channels()
      : LiveChannels("RWO"),
        sensor(rockwatch::test::unique_channel("RWO_WALL_SENSOR")),
        estimate(rockwatch::test::unique_channel("RWO_WALL_ESTIMATE")) {}
  std::string sensor, estimate;
};

struct Inbox {
  std::vector<rockwatch::wall_estimate_t> estimates;
  std::vector<rockwatch::wall_state_t> states;
  std::string estimate_channel, state_channel;
  static void on_raw(const lcm::ReceiveBuffer* rbuf, const std::string& channel, Inbox* self) {
    if (channel == self->estimate_channel) {
      rockwatch::wall_estimate_t m;
      if (m.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) > 0) self->estimates.push_back(m);
    } else if (channel == self->state_channel) {
      rockwatch::wall_state_t m;
      if (m.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) > 0) self->states.push_back(m);
    }
  }
};

template <typename T>
void publish(lcm::LCM& lcm, const std::string& channel, const T& m) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  CHECK(lcm.publish(channel, bytes.data(), static_cast<unsigned int>(bytes.size())) == 0);
}

}  // namespace

TEST_GROUP(MonitorLiveObserver){};

TEST(MonitorLiveObserver, FusesTheWallSensorsAndPublishesTheEstimate) {
  const std::string url = rockwatch::test::live_test_url(0);
  if (skip_without_multicast(url)) return;
  const TempDir dir;
  const Channels c;
  const json config{{"channels",
                     {{"accel", c.accel},
                      {"accel_batch", c.batch},
                      {"wall_state", c.state},
                      {"alarm", c.alarm},
                      {"status", c.status},
                      {"wall_sensor", c.sensor},
                      {"wall_estimate", c.estimate}}},
                    {"observer", {{"x_noise_m", 0.5e-3}, {"dropout_s", 0.25}}}};
  rockwatch::test::write_file(dir.file("observer.json"), config.dump());
  lcm::LCM lcm(url);
  CHECK(lcm.good());
  Inbox inbox;
  inbox.estimate_channel = c.estimate;
  inbox.state_channel = c.state;
  // One estimate and one state per sample: LCM's default queue of 30 unhandled messages per subscription is too short.
  lcm.subscribeFunction(c.estimate, &Inbox::on_raw, &inbox)->setQueueCapacity(20000);
  lcm.subscribeFunction(c.state, &Inbox::on_raw, &inbox)->setQueueCapacity(20000);
  const pid_t pid = rockwatch::test::start_monitor_listening(
      {"--config", dir.file("observer.json"), "--lcm-url", url, "--observer"}, dir.file("stdout"), dir.file("stderr"));

  // 1.5 s at 200 Hz: the wall at rest under a small ground motion, the transducer reading 0 with a 1 mm offset; one
  // reading is NaN.
  constexpr int kSamples = 300;
  constexpr int kNanAt = 150;
  const std::int64_t t0 = rockwatch::monitor::realtime_utime();
  const double start = now_s();
  for (int i = 0; i < kSamples; ++i) {
    rockwatch::wall_sensor_t s{};
    s.utime = t0 + i * 5000;
    s.seq = i;
    s.schema_version = rockwatch::wall_sensor_t::SCHEMA_VERSION;
    s.x_mid_m = i == kNanAt ? std::numeric_limits<double>::quiet_NaN() : 1e-3;
    s.valid = rockwatch::wall_sensor_t::VALID_X;
    publish(lcm, c.sensor, s);
    rockwatch::ground_accel_t g{};
    g.utime = t0 + i * 5000;
    g.seq = i;
    g.schema_version = 1;
    g.ug_mps2 = 0.1 * std::sin(0.05 * i);
    publish(lcm, c.accel, g);
    if (i % 10 == 9) {
      lcm.handleTimeout(0);
      const double wait = start + (i + 1) * 0.005 - now_s();
      if (wait > 0.0) sleep_s(wait);
    }
  }
  const double deadline = now_s() + 5.0;
  while (inbox.estimates.size() < kSamples && now_s() < deadline) lcm.handleTimeout(50);
  kill(pid, SIGTERM);
  const int status = rockwatch::test::wait_status(pid);
  const std::string err = rockwatch::test::read_file(dir.file("stderr"));
  CHECK_TEXT(WIFEXITED(status) && WEXITSTATUS(status) == 0, err.c_str());
  CHECK_TEXT(err.find("wall observer on") != std::string::npos, err.c_str());
  const std::vector<json> lines = rockwatch::test::json_lines(rockwatch::test::read_file(dir.file("stdout")));
  CHECK_TEXT(!lines.empty() && lines.back().contains("summary"), err.c_str());
  const json& summary = lines.back().at("summary");
  const std::string text = summary.dump();
  CHECK_TEXT(summary.contains("observer"), text.c_str());
  const json& o = summary.at("observer");
  const json& counters = summary.at("counters");
  const long processed = counters.at("samples_processed").get<long>();
  // Loopback normally delivers everything; the counts below allow for a lost datagram without hiding a miscount.
  CHECK_TEXT(processed >= kSamples - 5, text.c_str());
  LONGS_EQUAL_TEXT(processed, o.at("estimates_published").get<long>(), text.c_str());
  const long sensors = o.at("sensor_samples_received").get<long>();
  CHECK_TEXT(sensors >= kSamples - 5 && sensors <= kSamples, text.c_str());
  LONGS_EQUAL_TEXT(sensors, o.at("counters").at("samples").get<long>(), text.c_str());
  LONGS_EQUAL_TEXT(1, o.at("counters").at("not_finite").get<long>(), text.c_str());
  CHECK_TEXT(o.at("counters").at("x_updates").get<long>() >= kSamples - 20, text.c_str());
  LONGS_EQUAL_TEXT(0, o.at("counters").at("dropouts").get<long>(), text.c_str());
  // At rest a reading measures the transducer's offset only.
  DOUBLES_EQUAL(1e-3, o.at("bias_estimate_m").get<double>(), 2e-4);
  LONGS_EQUAL_TEXT(0, counters.at("decode_errors").get<long>(), text.c_str());

  // On LCM: one estimate per state, the alarm reasons MEASURED once the sensor is in.
  CHECK_TEXT(inbox.estimates.size() >= static_cast<std::size_t>(kSamples - 5), text.c_str());
  const rockwatch::wall_estimate_t& last = inbox.estimates.back();
  LONGS_EQUAL(rockwatch::wall_estimate_t::SCHEMA_VERSION, last.schema_version);
  CHECK((last.sensor_health & rockwatch::wall_estimate_t::SENSOR_X_ACTIVE) != 0);
  LONGS_EQUAL(1, last.not_finite);
  CHECK(!inbox.states.empty());
  CHECK((inbox.states.back().alarm_reasons & rockwatch::alarm_event_t::REASON_MEASURED) != 0);
}

namespace {

// An LCM log being written, its events numbered in order.
struct InputLogWriter {
  explicit InputLogWriter(const std::string& path) : log(path, "w") { CHECK(log.good()); }
  void write_raw(const std::string& channel, void* data, std::int32_t size, std::int64_t timestamp) {
    lcm::LogEvent e;
    e.eventnum = eventnum++;
    e.timestamp = timestamp;
    e.channel = channel;
    e.datalen = size;
    e.data = data;
    CHECK(log.writeEvent(&e) == 0);
  }
  template <typename Message>
  void write(const std::string& channel, const Message& m, std::int64_t timestamp) {
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
    m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    write_raw(channel, bytes.data(), static_cast<std::int32_t>(bytes.size()), timestamp);
  }
  lcm::LogFile log;
  std::int64_t eventnum = 0;
};

// A displacement reading of the transducer at utime.
rockwatch::wall_sensor_t x_reading(std::int64_t utime, std::int64_t seq, double x_m) {
  rockwatch::wall_sensor_t s{};
  s.utime = utime;
  s.seq = seq;
  s.schema_version = rockwatch::wall_sensor_t::SCHEMA_VERSION;
  s.x_mid_m = x_m;
  s.valid = rockwatch::wall_sensor_t::VALID_X;
  return s;
}

// An LCM log of n ground samples at 200 Hz with a wall-sensor sample of the same time before each (the transducer
// reading 2 mm), on the default channels.
void write_input_log(const std::string& path, int n) {
  InputLogWriter log(path);
  const std::int64_t t0 = 1700000000000000;
  for (int i = 0; i < n; ++i) {
    const rockwatch::wall_sensor_t s = x_reading(t0 + i * 5000, i, 2e-3);
    log.write("ROCKWATCH_WALL_SENSOR", s, s.utime + 500);
    rockwatch::ground_accel_t g{};
    g.utime = t0 + i * 5000;
    g.seq = i;
    g.schema_version = 1;
    g.ug_mps2 = 0.2 * std::sin(0.05 * i);
    log.write("ROCKWATCH_ACCEL", g, g.utime + 1000);
  }
}

// The messages of one channel of an output log, in order.
template <typename Message>
std::vector<Message> read_messages(const std::string& path, const std::string& channel) {
  lcm::LogFile log(path, "r");
  CHECK(log.good());
  std::vector<Message> out;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    if (e->channel != channel) continue;
    Message m;
    CHECK(m.decode(e->data, 0, e->datalen) == e->datalen);
    out.push_back(m);
  }
  return out;
}

std::vector<rockwatch::wall_estimate_t> read_estimates(const std::string& path) {
  return read_messages<rockwatch::wall_estimate_t>(path, "ROCKWATCH_WALL_ESTIMATE");
}

}  // namespace

TEST(MonitorLiveObserver, OfflineTheLogsWallSensorsAreFusedDeterministically) {
  const TempDir dir;
  constexpr int kSamples = 400;
  write_input_log(dir.file("in.lcmlog"), kSamples);
  std::string first_out;
  for (int run = 0; run < 2; ++run) {
    const std::string out = dir.file("out" + std::to_string(run) + ".lcmlog");
    const rockwatch::test::ProcessResult r = rockwatch::test::run_monitor(
        {"--observer", "--offline-in", dir.file("in.lcmlog"), "--offline-out", out});
    CHECK_EQUAL_TEXT(0, r.exit_status, r.err.c_str());
    const std::vector<json> lines = rockwatch::test::json_lines(r.out);
    CHECK_TEXT(!lines.empty() && lines.back().contains("summary"), r.out.c_str());
    const json& o = lines.back().at("summary").at("observer");
    LONGS_EQUAL_TEXT(kSamples, o.at("sensor_samples_received").get<long>(), o.dump().c_str());
    LONGS_EQUAL_TEXT(kSamples, o.at("estimates_published").get<long>(), o.dump().c_str());
    // The wall stays at rest (0.2 m/s2 is below the start threshold): the readings measure the offset.
    DOUBLES_EQUAL(2e-3, o.at("bias_estimate_m").get<double>(), 1e-4);
    const std::vector<rockwatch::wall_estimate_t> estimates = read_estimates(out);
    LONGS_EQUAL(kSamples, static_cast<long>(estimates.size()));
    CHECK(estimates.back().x_updates >= kSamples - 1);
    CHECK((estimates.back().sensor_health & rockwatch::wall_estimate_t::SENSOR_X_ACTIVE) != 0);
    const std::string bytes = rockwatch::test::read_file(out);
    if (run == 0) {
      first_out = bytes;
    } else {
      CHECK_TEXT(bytes == first_out, "two offline runs on the same log differ");
    }
  }
}

namespace {

// The shipped log (a collapse: ground samples only) with a displacement reading before each ground sample: the
// monitor's own open-loop x of that sample (its wall_state_t without the observer, states_log) plus a ±0.2 mm
// deterministic dither, the reading a transducer on a wall that is the model would give.
void write_log_with_sensor(const std::string& shipped, const std::string& states_log, const std::string& out) {
  std::map<std::int64_t, double> x_of_utime;
  for (const rockwatch::test::OutputLog::State& s : rockwatch::test::read_output_log(states_log).states) {
    x_of_utime[s.message.utime] = s.message.x_m;
  }
  lcm::LogFile in(shipped, "r");
  CHECK(in.good());
  InputLogWriter log(out);
  std::int64_t seq = 0;
  std::uint32_t dither = 12345u;
  while (const lcm::LogEvent* e = in.readNextEvent()) {
    if (e->channel == "ROCKWATCH_ACCEL") {
      rockwatch::ground_accel_t g;
      CHECK(g.decode(e->data, 0, e->datalen) == e->datalen);
      const auto x = x_of_utime.find(g.utime);
      if (x != x_of_utime.end()) {
        dither = dither * 1664525u + 1013904223u;
        const double dither_m = 0.2e-3 * (double(dither >> 8) / double(1u << 24) * 2.0 - 1.0);
        log.write("ROCKWATCH_WALL_SENSOR", x_reading(g.utime, seq++, x->second + dither_m), e->timestamp - 500);
      }
    }
    log.write_raw(e->channel, e->data, e->datalen, e->timestamp);
  }
}

}  // namespace

// With the observer and a displacement transducer the forecasts start from the fused state and its σ
// (wall_forecast_t.fused) and publish the P of the coefficients fitted on fused forecasts (SPEC §10 "From the fused
// state"), as `simulate --wall-sensors` does. Without a transducer reading within the dropout time (the shipped log
// has no wall sensor) the observer's σ grows with its process noise alone: those forecasts start at the state without
// it (fused 0) and take the open loop's coefficients. Before, they were drawn from that σ (σ_ẋ ~0.7 m/s) and said
// P ≈ 1 where the wall had seconds left (on the real records, Brier skill −3.0 against the open loop's 0.40).
TEST(MonitorLiveObserver, OfflineForecastsTakeTheFusedCalibrationOnlyWithADisplacementReading) {
  const TempDir dir;
  const std::string shipped = rockwatch::test::monitor_data_path(rockwatch::test::kShippedLog);
  const rockwatch::sim::ForecastCalibration fused = *rockwatch::sim::default_forecast_calibration(5.0, true);
  const rockwatch::sim::ForecastCalibration open = *rockwatch::sim::default_forecast_calibration(5.0, false);
  // The open loop's states, for the transducer's readings.
  const rockwatch::test::ProcessResult open_loop =
      rockwatch::test::run_monitor({"--offline-in", shipped, "--offline-out", dir.file("open.lcmlog")});
  CHECK_EQUAL_TEXT(0, open_loop.exit_status, open_loop.err.c_str());
  write_log_with_sensor(shipped, dir.file("open.lcmlog"), dir.file("with_sensor.lcmlog"));
  for (const bool with_sensor : {true, false}) {
    const std::string out = dir.file(with_sensor ? "fused.lcmlog" : "no_sensor.lcmlog");
    const rockwatch::test::ProcessResult r = rockwatch::test::run_monitor(
        {"--observer", "--forecast", "20,5", "--offline-in", with_sensor ? dir.file("with_sensor.lcmlog") : shipped,
         "--offline-out", out});
    CHECK_EQUAL_TEXT(0, r.exit_status, r.err.c_str());
    const std::vector<rockwatch::wall_estimate_t> estimates = read_estimates(out);
    CHECK(!estimates.empty());
    if (with_sensor) {
      const rockwatch::wall_estimate_t& last = estimates.back();
      const std::string counts = "sensor samples " + std::to_string(last.sensor_samples) + ", x updates " +
                                 std::to_string(last.x_updates) + ", rejected " + std::to_string(last.rejected) +
                                 ", estimates " + std::to_string(estimates.size());
      CHECK_TEXT(last.x_updates > 400 && last.rejected == 0, counts.c_str());
    }
    int checked = 0, told_apart = 0;
    for (const rockwatch::wall_forecast_t& m : read_messages<rockwatch::wall_forecast_t>(out, "ROCKWATCH_WALL_FORECAST")) {
      if (m.status != rockwatch::wall_forecast_t::STATUS_OK || !std::isfinite(m.energy_ratio_max_2s)) continue;
      LONGS_EQUAL(with_sensor ? 1 : 0, m.fused);
      const rockwatch::sim::ForecastCalibration& want = with_sensor ? fused : open;
      const rockwatch::sim::ForecastCalibration& other = with_sensor ? open : fused;
      DOUBLES_EQUAL(rockwatch::sim::calibrated_probability(want, m.p_collapse, m.members, m.energy_ratio_max_2s,
                                                           m.x_over_x_inst),
                    m.p_collapse_calibrated, 1e-12);
      const double p_other = rockwatch::sim::calibrated_probability(other, m.p_collapse, m.members,
                                                                    m.energy_ratio_max_2s, m.x_over_x_inst);
      if (std::fabs(p_other - m.p_collapse_calibrated) > 1e-3) ++told_apart;
      ++checked;
    }
    CHECK_TEXT(checked >= 5 && told_apart == checked, r.out.c_str());
  }
}

}  // namespace unity_test_monitor_live_observer
