// Fault injection on a live rockwatch-monitor, real processes over UDP multicast on loopback (ttl=0, a port
// and channel names of this test process's own; skipped, saying why, when multicast does not work here):
//   - SIGKILL mid-record: a monitor receiving a stream is killed, a new one started on the same channels while the
//     stream goes on: the new one publishes wall states within a few samples of its start, its first status says
//     QUALITY_MONITOR_RESTARTED, and its first state is at rest (the state restarted from rest) although the wall
//     was rocking when the first one died;
//   - `rockwatch replay` killed mid-record and started again from the beginning: the monitor counts exactly one
//     publisher restart, flags it in a wall state and a status, restarts the wall from rest at seq 0 and goes on
//     (no duplicate, out-of-order or gap counted for the new session's samples).
// SIGTERM/SIGINT clean stops, the flushed --log after SIGTERM (complete, readable, event counts equal to the summary's)
// and the full disk are test_monitor_live.cpp's (TheLogRecordsEveryInputAndOutput, AFullDiskLosesTheLogNotTheMonitoring).
#include <signal.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "lcm_transport.hpp"
#include "monitor_live_support.hpp"
#include "monitor_test_support.hpp"
#include "rockwatch/ground_accel_t.hpp"

#include <CppUTest/TestHarness.h>

// The file's own scope in a unity build (tests/CMakeLists.txt): its helpers' names recur in other files of the suite.
namespace unity_test_monitor_faults {

using nlohmann::json;
using rockwatch::test::now_s;
using rockwatch::test::skip_without_multicast;
using rockwatch::test::sleep_s;
using rockwatch::test::TempDir;

namespace {
// Channel names of this test file's own.
struct Channels : rockwatch::test::LiveChannels {
  Channels() : LiveChannels("RWF") {}
};
}  // namespace

namespace {

// A port of this process's own, above test_monitor_live.cpp's range (20000 + 2·(pid mod 20000) + 0/1).
std::string fault_url(int offset) {
  const int port = 60000 + static_cast<int>(getpid() % 2700) * 2 + offset;
  return "udpm://239.255.76.67:" + std::to_string(port) + "?ttl=0";
}

// What this process receives from the monitors, in order.
struct Inbox {
  std::string state_channel, status_channel;
  std::vector<rockwatch::wall_state_t> states;
  std::vector<rockwatch::monitor_status_t> statuses;

  static void on_raw(const lcm::ReceiveBuffer* rbuf, const std::string& channel, Inbox* self) {
    const int size = static_cast<int>(rbuf->data_size);
    if (channel == self->state_channel) {
      rockwatch::wall_state_t m{};
      if (m.decode(rbuf->data, 0, size) == size) self->states.push_back(m);
    } else if (channel == self->status_channel) {
      rockwatch::monitor_status_t m{};
      if (m.decode(rbuf->data, 0, size) == size) self->statuses.push_back(m);
    }
  }
};

// Starts a monitor, stdout/stderr to DIR/NAME.out/.err, and waits until it says it listens (fails the test else).
bool listening(const std::string& err_path) {
  return rockwatch::test::read_file(err_path).find("listening on") != std::string::npos;
}

pid_t start_monitor_and_wait(const TempDir& dir, const std::string& name, const std::string& url,
                             const Channels& c) {
  return rockwatch::test::start_monitor_listening(
      {"--config", rockwatch::test::write_channels_config(dir, c, "faults.json"), "--lcm-url", url},
      dir.file(name + ".out"), dir.file(name + ".err"));
}

// SIGTERM, clean exit, the summary (last stdout line).
json stop_monitor(pid_t pid, const TempDir& dir, const std::string& name) {
  kill(pid, SIGTERM);
  const int status = rockwatch::test::wait_status(pid);
  const std::string err = rockwatch::test::read_file(dir.file(name + ".err"));
  CHECK_TEXT(WIFEXITED(status) && WEXITSTATUS(status) == 0, err.c_str());
  const std::vector<json> lines = rockwatch::test::json_lines(rockwatch::test::read_file(dir.file(name + ".out")));
  CHECK_TEXT(!lines.empty() && lines.back().contains("summary"), err.c_str());
  return lines.back().at("summary");
}

void publish_sample(lcm::LCM& lcm, const std::string& channel, std::int64_t seq, std::int64_t utime, double ug) {
  rockwatch::ground_accel_t m{};
  m.utime = utime;
  m.seq = seq;
  m.schema_version = rockwatch::ground_accel_t::SCHEMA_VERSION;
  m.ug_mps2 = ug;
  m.vg_mps2 = 0.0;
  m.sensor_status = 0;
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  CHECK(lcm.publish(channel, bytes.data(), static_cast<unsigned int>(bytes.size())) == 0);
}

}  // namespace

TEST_GROUP(MonitorFaults){};

// The stream (200 Hz, the monitor's default rate): two periods of a 4 Hz sine of 2.5 m/s² (the paper wall rocks
// from 0.02 s and comes to rest after about 2 s; `rockwatch simulate` agrees), then rest. The first monitor is killed
// with SIGKILL at 1.0 s, while the wall rocks; the second is started at once, the stream going on; the test runs
// until 2.5 s after the second one listens.
TEST(MonitorFaults, SigkillMidRecordRestartsFromRestWithinAFewSamples) {
  const std::string url = fault_url(0);
  if (skip_without_multicast(url)) return;
  const TempDir dir;
  const Channels c;
  lcm::LCM lcm(url);
  CHECK(lcm.good());
  Inbox inbox;
  inbox.state_channel = c.state;
  inbox.status_channel = c.status;
  lcm.subscribeFunction(c.state, &Inbox::on_raw, &inbox)->setQueueCapacity(100000);
  lcm.subscribeFunction(c.status, &Inbox::on_raw, &inbox)->setQueueCapacity(1000);

  const pid_t first = start_monitor_and_wait(dir, "first", url, c);
  constexpr double kRate = 200.0;
  constexpr std::int64_t kPeriodUs = 5000;
  constexpr std::int64_t kSeq0 = 5000;  // a sensor that has been running for a while
  const auto ug = [](std::int64_t k) {
    const double t = static_cast<double>(k) / kRate;
    return t < 0.5 ? 2.5 * std::sin(2.0 * 3.14159265358979323846 * 4.0 * t) : 0.0;
  };
  const std::int64_t t0_us = rockwatch::monitor::realtime_utime();
  const double t0 = now_s();
  pid_t second = -1;
  std::size_t states_of_first = 0, statuses_of_first = 0;
  bool first_was_moving = false;
  std::int64_t seq_sent_at_spawn = -1, seq_sent_when_listening = -1, last_seq_sent = -1;
  double second_listening_at = -1.0, spawned_at = -1.0;
  for (std::int64_t k = 0;; ++k) {
    const double due = t0 + static_cast<double>(k) / kRate;
    while (now_s() < due) lcm.handleTimeout(1);
    publish_sample(lcm, c.accel, kSeq0 + k, t0_us + k * kPeriodUs, ug(k));
    last_seq_sent = kSeq0 + k;
    if (k == 200) {  // 1.0 s: SIGKILL, mid-record, mid-motion
      kill(first, SIGKILL);
      const int status = rockwatch::test::wait_status(first);
      CHECK(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
      // Whatever the first monitor published before dying, drained (until 20 ms without a message).
      for (const double until = now_s() + 0.1; now_s() < until && lcm.handleTimeout(20) > 0;) {
      }
      states_of_first = inbox.states.size();
      statuses_of_first = inbox.statuses.size();
      CHECK(states_of_first > 0);
      first_was_moving = inbox.states.back().moving != 0;
      seq_sent_at_spawn = last_seq_sent;
      spawned_at = now_s();
      second = rockwatch::test::spawn_monitor(
          {"--config", rockwatch::test::write_channels_config(dir, c, "faults.json"), "--lcm-url", url},
                                              dir.file("second.out"), dir.file("second.err"));
    }
    if (second > 0 && second_listening_at < 0.0 && k % 2 == 0 && listening(dir.file("second.err"))) {
      second_listening_at = now_s();
      seq_sent_when_listening = last_seq_sent;
    }
    if (second_listening_at > 0.0 && now_s() > second_listening_at + 2.5) break;
    if (now_s() > t0 + 30.0) break;
  }
  CHECK_TEXT(second_listening_at > 0.0, "the second monitor never said it listens");
  for (const double until = now_s() + 0.3; now_s() < until;) lcm.handleTimeout(20);
  const json summary = stop_monitor(second, dir, "second");
  for (const double until = now_s() + 0.3; now_s() < until;) lcm.handleTimeout(20);

  // The first monitor was rocking the wall when it died.
  CHECK_TEXT(first_was_moving, "the wall was at rest when the first monitor was killed: the test proves less");
  // The second monitor's outputs: its wall states number from 0 again (the first's were far past 0 when it died).
  std::size_t second_begin = states_of_first;
  while (second_begin < inbox.states.size() && inbox.states[second_begin].seq != 0) ++second_begin;
  LONGS_EQUAL_TEXT(states_of_first, second_begin, "states of the first monitor arrived after it was reaped");
  const std::vector<rockwatch::wall_state_t> second_states(inbox.states.begin() + static_cast<long>(second_begin),
                                                            inbox.states.end());
  CHECK(!second_states.empty());
  const rockwatch::wall_state_t& s0 = second_states.front();
  LONGS_EQUAL(0, s0.seq);
  // Restarted from rest: at its first sample the wall is at rest at x = 0 (the first monitor had it rocking).
  LONGS_EQUAL(0, s0.moving);
  DOUBLES_EQUAL(0.0, s0.x_m, 0.0);
  DOUBLES_EQUAL(0.0, s0.xd_mps, 0.0);
  // Within a few samples of its start: its first state answers a sample sent at most a few periods after it said
  // it listens (it subscribes before saying so: it may take one sent before).
  const std::int64_t after_listening = s0.input_seq - seq_sent_when_listening;
  const std::int64_t after_spawn = s0.input_seq - seq_sent_at_spawn;
  char note[256];
  std::snprintf(note, sizeof note,
                "second monitor: first state answers seq %lld: %lld samples after its spawn (%.0f ms to listen), "
                "%lld after it said it listens",
                static_cast<long long>(s0.input_seq), static_cast<long long>(after_spawn),
                (second_listening_at - spawned_at) * 1e3, static_cast<long long>(after_listening));
  UT_PRINT(note);
  CHECK_TEXT(after_listening <= 3, note);
  // From then on every sample sent is processed, in order, once.
  for (std::size_t i = 1; i < second_states.size(); ++i) {
    LONGS_EQUAL(second_states[i - 1].input_seq + 1, second_states[i].input_seq);
    LONGS_EQUAL(static_cast<long>(i), second_states[i].seq);
  }
  LONGS_EQUAL(last_seq_sent, second_states.back().input_seq);
  // Its first status says it (re)started with the wall at rest.
  std::size_t status_begin = statuses_of_first;
  while (status_begin < inbox.statuses.size() && inbox.statuses[status_begin].seq != 0) ++status_begin;
  CHECK(status_begin < inbox.statuses.size());
  const rockwatch::monitor_status_t& st0 = inbox.statuses[status_begin];
  LONGS_EQUAL(0, st0.seq);
  CHECK((st0.data_quality & rockwatch::monitor_status_t::QUALITY_MONITOR_RESTARTED) != 0);
  // Its counters: a clean start at the sample it first got, nothing lost, no restart of the publisher.
  const json& k = summary.at("counters");
  LONGS_EQUAL(static_cast<long>(second_states.size()), k.at("samples_received").get<long>());
  LONGS_EQUAL(static_cast<long>(second_states.size()), k.at("samples_processed").get<long>());
  for (const char* zero : {"gaps", "state_resets", "duplicates", "out_of_order", "publisher_restarts",
                           "decode_errors", "samples_bridged"}) {
    LONGS_EQUAL_TEXT(0, k.at(zero).get<long>(), zero);
  }
}

namespace {

struct ReplayRun {
  pid_t pid;
  std::string out, err;
};

ReplayRun start_replay(const TempDir& dir, const std::string& name, const std::string& url, const Channels& c) {
  ReplayRun r{-1, dir.file(name + ".out"), dir.file(name + ".err")};
  r.pid = rockwatch::test::spawn_rockwatch(
      {"replay", "--suite", std::string(ROCKWATCH_SOURCE_DIR) + "/sim/suites/npr9998-2015", "--set", "1",
       "--component", "X", "--scale-pga", "0.2", "--lcm-url", url, "--lcm-channel", c.accel, "--json"},
      r.out, r.err);
  return r;
}

}  // namespace

// `rockwatch replay` (real time, 200 Hz, seq from 0) killed with SIGKILL 1.5 s into a 20 s record, then started
// again from the beginning and stopped with SIGINT 1.5 s later. The monitor: one publisher restart, flagged in the
// state at the new seq 0 and in a status; the wall restarted from rest there; no duplicate, out-of-order, gap or
// state reset; the accounting identity holds and every sample of the second session is processed.
TEST(MonitorFaults, ReplayRestartedMidRecordIsOnePublisherRestart) {
  const std::string url = fault_url(1);
  if (skip_without_multicast(url)) return;
  const TempDir dir;
  const Channels c;
  lcm::LCM lcm(url);
  CHECK(lcm.good());
  Inbox inbox;
  inbox.state_channel = c.state;
  inbox.status_channel = c.status;
  lcm.subscribeFunction(c.state, &Inbox::on_raw, &inbox)->setQueueCapacity(100000);
  lcm.subscribeFunction(c.status, &Inbox::on_raw, &inbox)->setQueueCapacity(1000);
  const pid_t monitor = start_monitor_and_wait(dir, "monitor", url, c);

  const auto pump_for = [&](double seconds) {
    for (const double until = now_s() + seconds; now_s() < until;) lcm.handleTimeout(10);
  };
  const ReplayRun first = start_replay(dir, "replay1", url, c);
  // 1.5 s after the first sample reached the monitor (the replay loads the record first).
  for (const double until = now_s() + 20.0; inbox.states.empty() && now_s() < until;) lcm.handleTimeout(10);
  CHECK_TEXT(!inbox.states.empty(), rockwatch::test::read_file(first.err).c_str());
  pump_for(1.5);
  kill(first.pid, SIGKILL);
  const int s1 = rockwatch::test::wait_status(first.pid);
  CHECK(WIFSIGNALED(s1) && WTERMSIG(s1) == SIGKILL);
  pump_for(0.1);
  const std::size_t states_of_first = inbox.states.size();
  const std::int64_t last_seq_first = inbox.states.back().input_seq;
  CHECK(last_seq_first > 100);

  const ReplayRun second = start_replay(dir, "replay2", url, c);
  for (const double until = now_s() + 20.0; inbox.states.size() == states_of_first && now_s() < until;) {
    lcm.handleTimeout(10);
  }
  pump_for(1.5);
  kill(second.pid, SIGINT);
  const int s2 = rockwatch::test::wait_status(second.pid);
  CHECK_TEXT(WIFEXITED(s2) && WEXITSTATUS(s2) == 130, rockwatch::test::read_file(second.err).c_str());
  const json replay2 = json::parse(rockwatch::test::read_file(second.out), nullptr, false);
  CHECK_TEXT(replay2.is_object(), rockwatch::test::read_file(second.out).c_str());
  const auto sent2 = replay2.at("samples_sent").get<std::int64_t>();
  pump_for(0.3);
  const json summary = stop_monitor(monitor, dir, "monitor");
  pump_for(0.3);

  const json& k = summary.at("counters");
  const std::string what = k.dump();
  LONGS_EQUAL_TEXT(1, k.at("publisher_restarts").get<long>(), what.c_str());
  for (const char* zero : {"duplicates", "out_of_order", "gaps", "state_resets", "samples_bridged", "decode_errors"}) {
    LONGS_EQUAL_TEXT(0, k.at(zero).get<long>(), (std::string(zero) + ": " + what).c_str());
  }
  // Accounted for: both sessions' samples received, each processed once.
  const auto received = k.at("samples_received").get<std::int64_t>();
  LONGS_EQUAL_TEXT(last_seq_first + 1 + sent2, received, what.c_str());
  LONGS_EQUAL_TEXT(received, k.at("samples_processed").get<long>(), what.c_str());
  // The second session's states: from seq 0, every one, the first flagged and at rest.
  const std::vector<rockwatch::wall_state_t> second_states(inbox.states.begin() + static_cast<long>(states_of_first),
                                                            inbox.states.end());
  LONGS_EQUAL(sent2, static_cast<long>(second_states.size()));
  const rockwatch::wall_state_t& r0 = second_states.front();
  LONGS_EQUAL(0, r0.input_seq);
  CHECK((r0.data_quality & rockwatch::monitor_status_t::QUALITY_PUBLISHER_RESTART) != 0);
  LONGS_EQUAL(0, r0.moving);
  DOUBLES_EQUAL(0.0, r0.x_m, 0.0);
  for (std::size_t i = 1; i < second_states.size(); ++i) {
    LONGS_EQUAL(static_cast<long>(i), second_states[i].input_seq);
    CHECK((second_states[i].data_quality & rockwatch::monitor_status_t::QUALITY_PUBLISHER_RESTART) == 0);
  }
  // The state before it (the first session's last) is not flagged; a status after the restart is.
  CHECK((inbox.states[states_of_first - 1].data_quality & rockwatch::monitor_status_t::QUALITY_PUBLISHER_RESTART) ==
        0);
  bool status_flagged = false;
  for (const rockwatch::monitor_status_t& st : inbox.statuses) {
    status_flagged = status_flagged || ((st.data_quality & rockwatch::monitor_status_t::QUALITY_PUBLISHER_RESTART) != 0 &&
                                        st.publisher_restarts == 1);
  }
  CHECK_TEXT(status_flagged, "no status said the publisher restarted");
}

}  // namespace unity_test_monitor_faults
