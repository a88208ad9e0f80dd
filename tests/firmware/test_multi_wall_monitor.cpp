// firmware::MultiWallMonitor: three walls (the paper's, a thicker one, a taller one with other restitution) on one
// shared ground channel each publish, on their own channels, exactly the bytes a MonitorLoop alone with the same
// settings publishes for the same stream (states, alarm events, statuses); a wall's own ground channel reaches that
// wall only; a message no wall reads is counted once; the channel checks across walls and the wall count refuse what
// they must.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/firmware/monitor_loop.hpp"
#include "rockwatch/firmware/multi_wall_monitor.hpp"
#include "rockwatch/firmware/wall_engine.hpp"

#include <CppUTest/TestHarness.h>

#include "memory_transport.hpp"

// The file's own scope in a unity build (tests/CMakeLists.txt): its helpers' names recur in other files of the suite.
namespace unity_test_multi_wall_monitor {

using namespace rockwatch;
namespace fw = rockwatch::firmware;

namespace {

constexpr double kG = 9.81;
constexpr double kPi = 3.14159265358979323846;
constexpr std::int64_t kPeriodUs = 5000;
constexpr std::int64_t kT0 = 1700000000000000;

using Capture = test::MemoryTransport;
using Sent = test::Published;
using test::encode;

std::vector<std::uint8_t> ground(std::int64_t seq, double pga_g) {
  ground_accel_t m{};
  m.utime = kT0 + seq * kPeriodUs;
  m.seq = seq;
  m.schema_version = 1;
  m.ug_mps2 = pga_g * kG * std::sin(2.0 * kPi * 2.0 * double(seq) * 0.005);
  return encode(m);
}

void set(char (&field)[fw::kChannelNameMax], const std::string& name) {
  std::memset(field, 0, sizeof field);
  std::memcpy(field, name.data(), name.size());
}

// The outputs of wall NAME: the default channels suffixed _NAME.
fw::MonitorSettings wall_settings(const std::string& name, double b_m, double h_m, core::Restitution r) {
  fw::MonitorSettings s;
  s.engine.wall = core::paper_wall();
  s.engine.wall.b_m = b_m;
  s.engine.wall.h1_m = s.engine.wall.h2_m = h_m / 2.0;
  s.engine.r_energy = core::restitution_energy_ratio(s.engine.wall, r);
  s.sample_rate_hz = 200.0;
  set(s.channels.wall_state, "ROCKWATCH_WALL_STATE_" + name);
  set(s.channels.alarm, "ROCKWATCH_ALARM_" + name);
  set(s.channels.status, "ROCKWATCH_STATUS_" + name);
  set(s.channels.wall_estimate, "ROCKWATCH_WALL_ESTIMATE_" + name);
  return s;
}

const char* const kNames[3] = {"paper", "thick", "tall"};

std::vector<fw::MonitorSettings> three_walls() {
  return {wall_settings("paper", 0.10, 3.5, core::Restitution{}), wall_settings("thick", 0.14, 3.5, core::Restitution{}),
          wall_settings("tall", 0.10, 4.0, core::Restitution{core::RestitutionKind::ana, 0.0})};
}

}  // namespace

TEST_GROUP(MultiWallMonitor){};

TEST(MultiWallMonitor, EachWallPublishesWhatItsOwnLoopAlonePublishes) {
  const std::vector<fw::MonitorSettings> settings = three_walls();
  fw::WallEngine engines[3];
  fw::SampleEngine* engine_ptrs[3] = {&engines[0], &engines[1], &engines[2]};
  fw::MonitorListener* listeners[3] = {nullptr, nullptr, nullptr};
  Capture capture;
  fw::MultiWallMonitor multi;
  CHECK(multi.init(settings.data(), engine_ptrs, listeners, 3, capture) == fw::MultiWallError::ok);
  LONGS_EQUAL(3, multi.size());
  CHECK_TRUE(multi.reads("ROCKWATCH_ACCEL"));
  CHECK_FALSE(multi.reads("ROCKWATCH_WALL_STATE_paper"));

  // 6 s at 0.25 g, 2 Hz: rocking and alarms in some walls, not in all alike; a status every second.
  constexpr std::int64_t kSamples = 1200;
  multi.publish_status(kT0);
  for (std::int64_t k = 0; k < kSamples; ++k) {
    const std::vector<std::uint8_t> b = ground(k, 0.25);
    multi.on_message("ROCKWATCH_ACCEL", b.data(), b.size(), kT0 + k * kPeriodUs + 1000);
    if (k % 200 == 199) multi.publish_status(kT0 + k * kPeriodUs + 2000);
  }
  std::size_t alarms = 0;
  for (std::size_t w = 0; w < 3; ++w) {
    fw::WallEngine engine;
    Capture alone;
    fw::MonitorLoop loop;
    CHECK(loop.init(settings[w], engine, alone) == fw::MonitorError::ok);
    loop.publish_status(kT0);
    for (std::int64_t k = 0; k < kSamples; ++k) {
      const std::vector<std::uint8_t> b = ground(k, 0.25);
      loop.on_message("ROCKWATCH_ACCEL", b.data(), b.size(), kT0 + k * kPeriodUs + 1000);
      if (k % 200 == 199) loop.publish_status(kT0 + k * kPeriodUs + 2000);
    }
    for (const char* kind : {"ROCKWATCH_WALL_STATE_", "ROCKWATCH_ALARM_", "ROCKWATCH_STATUS_"}) {
      const std::string channel = kind + std::string(kNames[w]);
      const std::vector<Sent> mine = capture.on(channel), theirs = alone.on(channel);
      LONGS_EQUAL_TEXT(theirs.size(), mine.size(), channel.c_str());
      for (std::size_t i = 0; i < mine.size(); ++i) CHECK_TEXT(mine[i].bytes == theirs[i].bytes, channel.c_str());
    }
    LONGS_EQUAL(kSamples, capture.on(std::string("ROCKWATCH_WALL_STATE_") + kNames[w]).size());
    alarms += capture.on(std::string("ROCKWATCH_ALARM_") + kNames[w]).size();
    LONGS_EQUAL(0, multi.wall(w).counters().messages_ignored);
  }
  CHECK_TEXT(alarms > 0, "some wall should raise an alarm at 0.25 g");
  // The walls differ: their states are not the same stream (each wall got its own parameters).
  const std::vector<Sent> paper = capture.on("ROCKWATCH_WALL_STATE_paper"), thick = capture.on("ROCKWATCH_WALL_STATE_thick"),
                          tall = capture.on("ROCKWATCH_WALL_STATE_tall");
  std::size_t differ_thick = 0, differ_tall = 0;
  for (std::size_t i = 0; i < paper.size(); ++i) {
    differ_thick += paper[i].bytes != thick[i].bytes ? 1 : 0;
    differ_tall += paper[i].bytes != tall[i].bytes ? 1 : 0;
  }
  CHECK_TEXT(differ_thick > 100 && differ_tall > 100,
             (std::to_string(differ_thick) + " " + std::to_string(differ_tall)).c_str());
  // A channel nobody reads: counted once, by the first wall.
  const std::vector<std::uint8_t> b = ground(kSamples, 0.0);
  multi.on_message("SOMEONE_ELSE", b.data(), b.size(), kT0);
  LONGS_EQUAL(1, multi.wall(0).counters().messages_ignored);
  LONGS_EQUAL(0, multi.wall(1).counters().messages_ignored);
  LONGS_EQUAL(0, multi.wall(2).counters().messages_ignored);
}

TEST(MultiWallMonitor, AWallsOwnGroundChannelReachesItAlone) {
  std::vector<fw::MonitorSettings> settings = three_walls();
  set(settings[2].channels.accel, "ROCKWATCH_ACCEL_tall");
  set(settings[2].channels.accel_batch, "ROCKWATCH_ACCEL_BATCH_tall");
  fw::WallEngine engines[3];
  fw::SampleEngine* engine_ptrs[3] = {&engines[0], &engines[1], &engines[2]};
  fw::MonitorListener* listeners[3] = {nullptr, nullptr, nullptr};
  Capture capture;
  fw::MultiWallMonitor multi;
  CHECK(multi.init(settings.data(), engine_ptrs, listeners, 3, capture) == fw::MultiWallError::ok);
  for (std::int64_t k = 0; k < 10; ++k) {
    const std::vector<std::uint8_t> b = ground(k, 0.05);
    multi.on_message("ROCKWATCH_ACCEL", b.data(), b.size(), kT0 + k * kPeriodUs);
  }
  for (std::int64_t k = 0; k < 4; ++k) {
    const std::vector<std::uint8_t> b = ground(k, 0.05);
    multi.on_message("ROCKWATCH_ACCEL_tall", b.data(), b.size(), kT0 + k * kPeriodUs);
  }
  LONGS_EQUAL(10, multi.wall(0).counters().samples_received);
  LONGS_EQUAL(10, multi.wall(1).counters().samples_received);
  LONGS_EQUAL(4, multi.wall(2).counters().samples_received);
  LONGS_EQUAL(4, capture.on("ROCKWATCH_WALL_STATE_tall").size());
}

TEST(MultiWallMonitor, ChannelClashesAndWallCountsAreRefused) {
  fw::WallEngine engines[fw::kMaxMonitorWalls + 1];
  fw::SampleEngine* engine_ptrs[fw::kMaxMonitorWalls + 1];
  fw::MonitorListener* listeners[fw::kMaxMonitorWalls + 1] = {};
  std::vector<fw::MonitorSettings> settings;
  for (std::size_t i = 0; i <= fw::kMaxMonitorWalls; ++i) {
    engine_ptrs[i] = &engines[i];
    settings.push_back(wall_settings("w" + std::to_string(i), 0.10, 3.5, core::Restitution{}));
  }
  Capture capture;
  fw::MultiWallMonitor multi;
  CHECK(multi.init(settings.data(), engine_ptrs, listeners, 0, capture) == fw::MultiWallError::wall_count_out_of_range);
  CHECK(multi.init(settings.data(), engine_ptrs, listeners, fw::kMaxMonitorWalls + 1, capture) ==
        fw::MultiWallError::wall_count_out_of_range);
  CHECK(multi.init(settings.data(), engine_ptrs, listeners, fw::kMaxMonitorWalls, capture) == fw::MultiWallError::ok);
  LONGS_EQUAL(fw::kMaxMonitorWalls, multi.size());

  std::vector<fw::MonitorSettings> clash = three_walls();
  set(clash[2].channels.alarm, "ROCKWATCH_ALARM_paper");
  CHECK(multi.init(clash.data(), engine_ptrs, listeners, 3, capture) == fw::MultiWallError::output_channel_shared);
  LONGS_EQUAL(2, multi.failed_wall());
  LONGS_EQUAL(0, multi.size());  // nothing ready after a refusal

  clash = three_walls();
  set(clash[1].channels.accel, "ROCKWATCH_STATUS_tall");
  CHECK(multi.init(clash.data(), engine_ptrs, listeners, 3, capture) == fw::MultiWallError::input_is_output);
  LONGS_EQUAL(1, multi.failed_wall());

  clash = three_walls();
  clash[1].sample_rate_hz = 0.0;
  CHECK(multi.init(clash.data(), engine_ptrs, listeners, 3, capture) == fw::MultiWallError::wall);
  LONGS_EQUAL(1, multi.failed_wall());
  CHECK(multi.wall_error() == fw::MonitorError::sample_rate_out_of_range);
  STRCMP_CONTAINS("publish on the same channel",
                  fw::multi_wall_error_message(fw::MultiWallError::output_channel_shared));
}

}  // namespace unity_test_multi_wall_monitor
