// No allocation per message in firmware::MultiWallMonitor: the counting replacements of counting_allocator.hpp
// around 100 000 on_message() calls (a status of every wall each 200) for kMaxMonitorWalls walls of different
// geometry sharing one ground channel, the last wall also with a ground channel of its own, and messages on a channel
// nobody reads. The ground rocks hard enough to raise alarms and collapse walls, so every path runs. Exits 1 unless
// the count is 0 and the walls really moved (a state per sample each, alarms).
// A plain program (CppUTest replaces operator new); not built with sanitizers (tests/firmware/proofs/CMakeLists.txt).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/firmware/multi_wall_monitor.hpp"
#include "rockwatch/firmware/wall_engine.hpp"

#include "counting_allocator.hpp"

namespace {
namespace fw = rockwatch::firmware;

constexpr std::int64_t kPeriodUs = 5000;
constexpr std::int64_t kT0 = 1700000000000000;
constexpr std::size_t kMeasuredCalls = 100000;

class CountingTransport final : public fw::Transport {
 public:
  bool publish(const char*, const std::uint8_t*, std::size_t) override {
    ++published;
    return true;
  }
  std::int64_t published = 0;
};

class CountingListener final : public fw::MonitorListener {
 public:
  void on_alarm(const rockwatch::alarm_event_t&) override { ++events; }
  std::int64_t events = 0;
};

void set(char (&field)[fw::kChannelNameMax], const std::string& name) {
  std::memset(field, 0, sizeof field);
  std::memcpy(field, name.data(), name.size());
}

struct Message {
  const char* channel;
  std::vector<std::uint8_t> bytes;
  std::int64_t receive_utime;
};

}  // namespace

int main() {
  if (!counting_allocator::self_check()) {
    std::fprintf(stderr, "FAIL: the allocation counters do not see deliberate allocations\n");
    return 1;
  }
  constexpr std::size_t kWalls = fw::kMaxMonitorWalls;
  std::vector<fw::MonitorSettings> settings(kWalls);
  for (std::size_t i = 0; i < kWalls; ++i) {
    fw::MonitorSettings& s = settings[i];
    s.engine.wall = rockwatch::core::paper_wall();
    s.engine.wall.b_m = 0.10 + 0.01 * double(i % 4);
    s.engine.wall.h1_m = s.engine.wall.h2_m = 1.4 + 0.05 * double(i);
    s.engine.r_energy = rockwatch::core::r_exp(s.engine.wall);
    s.sample_rate_hz = 200.0;
    const std::string name = "w" + std::to_string(i);
    set(s.channels.wall_state, "ROCKWATCH_WALL_STATE_" + name);
    set(s.channels.alarm, "ROCKWATCH_ALARM_" + name);
    set(s.channels.status, "ROCKWATCH_STATUS_" + name);
    set(s.channels.wall_estimate, "ROCKWATCH_WALL_ESTIMATE_" + name);
  }
  set(settings[kWalls - 1].channels.accel, "ROCKWATCH_ACCEL_own");

  // A 12 s cycle (seq restarting each time: a publisher restart) of a 2 Hz ground motion growing to 0.6 g.
  std::vector<Message> cycle;
  for (std::int64_t k = 0; k < 2400; ++k) {
    rockwatch::ground_accel_t m{};
    m.utime = kT0 + k * kPeriodUs;
    m.seq = k;
    m.schema_version = 1;
    m.ug_mps2 = 0.6 * 9.81 * (double(k) / 2400.0) * std::sin(2.0 * 3.14159265358979 * 2.0 * double(k) * 0.005);
    std::vector<std::uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
    m.encode(b.data(), 0, static_cast<int>(b.size()));
    cycle.push_back(Message{"ROCKWATCH_ACCEL", b, m.utime + 1000});
    if (k % 3 == 0) cycle.push_back(Message{"ROCKWATCH_ACCEL_own", b, m.utime + 1000});
    if (k % 100 == 0) cycle.push_back(Message{"NOBODY_READS_THIS", b, m.utime + 1000});
  }

  std::vector<fw::WallEngine> engines(kWalls);
  fw::SampleEngine* engine_ptrs[kWalls];
  fw::MonitorListener* listener_ptrs[kWalls];
  CountingListener listener;
  for (std::size_t i = 0; i < kWalls; ++i) {
    engine_ptrs[i] = &engines[i];
    listener_ptrs[i] = &listener;
  }
  CountingTransport transport;
  static fw::MultiWallMonitor multi;  // ~kWalls kB: not on the stack
  const fw::MultiWallError e = multi.init(settings.data(), engine_ptrs, listener_ptrs, kWalls, transport);
  if (e != fw::MultiWallError::ok) {
    std::fprintf(stderr, "FAIL: MultiWallMonitor::init: %s (wall %zu)\n", fw::multi_wall_error_message(e),
                 multi.failed_wall());
    return 1;
  }

  const std::uint64_t before = g_calls;
  std::size_t j = 0;
  for (std::size_t i = 0; i < kMeasuredCalls; ++i) {
    const Message& m = cycle[j];
    multi.on_message(m.channel, m.bytes.data(), m.bytes.size(), m.receive_utime);
    if (i % 200 == 199) multi.publish_status(m.receive_utime);
    j = j + 1 == cycle.size() ? 0 : j + 1;
  }
  const std::uint64_t calls = g_calls - before;
  std::int64_t states = 0;
  for (std::size_t i = 0; i < kWalls; ++i) states += multi.wall(i).counters().states_published;
  std::printf("%zu walls, %zu on_message calls: %lld wall states, %lld alarm events, %lld messages published, "
              "%lld ignored; %llu allocation calls\n",
              kWalls, kMeasuredCalls, static_cast<long long>(states), static_cast<long long>(listener.events),
              static_cast<long long>(transport.published),
              static_cast<long long>(multi.wall(0).counters().messages_ignored),
              static_cast<unsigned long long>(calls));
  if (states < 1000000 || listener.events == 0 || multi.wall(0).counters().messages_ignored == 0) {
    std::fprintf(stderr, "FAIL: the stream did not exercise the walls (states, alarms, ignored channel)\n");
    return 1;
  }
  if (calls != 0) {
    std::fprintf(stderr, "FAIL: %llu allocation calls while processing messages\n",
                 static_cast<unsigned long long>(calls));
    return 1;
  }
  std::printf("OK: no allocation per message with %zu walls\n", kWalls);
  return 0;
}
