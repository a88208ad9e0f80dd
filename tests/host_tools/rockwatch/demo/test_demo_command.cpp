// `rockwatch demo`: its option rejections, the message when the monitor cannot be found, and the whole demo
// (rockwatch-monitor started, two suite records replayed to it over UDP multicast on this machine, its alarm
// timelines compared with the offline fixed-point runs) when the monitor is built and multicast works here.
#include <unistd.h>

#include <string>
#include <vector>

#include "ci_skip.hpp"
#include "cli_process.hpp"
#include "cli_test_files.hpp"
#include "common/replay_out/lcm_multicast.hpp"

#include "cli_expect.hpp"  // brings in CppUTest, after every standard header

#include <CppUTest/TestHarness.h>

using rockwatch::test::describe;
using rockwatch::test::EnvOverride;
using rockwatch::test::expect_command_rejected;
using rockwatch::test::ProcessResult;
using rockwatch::test::run_rockwatch;

namespace {

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// A port of this test run: other processes on this machine may run a monitor on the default URL at the same time.
std::string private_url() { return "udpm://239.255.76.67:" + std::to_string(7800 + getpid() % 150) + "?ttl=0"; }

}  // namespace

TEST_GROUP(DemoCommand){};

TEST(DemoCommand, BadOptionsAreRefused) {
  expect_command_rejected("demo", {"--speed", "0"}, {"--speed", "> 0"});
  expect_command_rejected("demo", {"--speed", "50"}, {"--speed", "20"});
  expect_command_rejected("demo", {"--set", "0"}, {"--set"});
  expect_command_rejected("demo", {"--pga", "-1"}, {"--pga"});
  expect_command_rejected("demo", {"--lcm-url", "memq://"}, {"--lcm-url", "udpm://"});
  expect_command_rejected("demo", {"--rate", "0"}, {"--rate"});
  expect_command_rejected("demo", {"--monitor", "/nonexistent/rockwatch-monitor"}, {"--monitor", "not an executable"});
  expect_command_rejected("demo", {"--dashboard-hold", "5"}, {"--dashboard-hold", "needs --dashboard"});
  expect_command_rejected("demo", {"--dashboard-http", "127.0.0.1:0"}, {"--dashboard-http", "needs --dashboard"});
  expect_command_rejected("demo", {"--dashboard", "--dashboard-hold", "-1"}, {"--dashboard-hold"});
}

TEST(DemoCommand, MissingMonitorSaysWhereItLookedAndWhatToDo) {
  const EnvOverride monitor("ROCKWATCH_MONITOR", "/nonexistent/rockwatch-monitor");
  expect_command_rejected("demo", {}, {"$ROCKWATCH_MONITOR", "/nonexistent/rockwatch-monitor"});
}

TEST(DemoCommand, MonitorTimelinesMatchTheOfflineSimulation) {
#ifndef ROCKWATCH_MONITOR_PATH
  std::printf("\nnote: rockwatch-monitor is not part of this build: DemoCommand.MonitorTimelinesMatch skipped\n");
#else
  const std::string url = private_url();
  const rockwatch::cli::MulticastProbe probe = rockwatch::cli::probe_multicast(url, 1000);
  if (!probe.ok) {
    if (rockwatch::test::skip_or_fail_in_ci("LCM multicast does not work on this machine (" + probe.problem + ")"))
      return;
  }
  const EnvOverride monitor("ROCKWATCH_MONITOR", ROCKWATCH_MONITOR_PATH);
  // The dashboard's own refusal comes through, before any record is replayed.
  const ProcessResult refused =
      run_rockwatch({"demo", "--dashboard", "--dashboard-http", "0.0.0.0:0", "--lcm-url", url});
  CHECK_EQUAL_TEXT(2, refused.exit_status, describe(refused).c_str());
  CHECK_TEXT(refused.err.find("--dashboard: the dashboard did not start") != std::string::npos &&
                 refused.err.find("--allow-remote") != std::string::npos,
             describe(refused).c_str());
  // The whole demo, with the dashboard serving on a free port during it (the browser test checks the page itself).
  const ProcessResult r =
      run_rockwatch({"demo", "--speed", "4", "--lcm-url", url, "--dashboard", "--dashboard-http", "127.0.0.1:0"});
  const std::string what = describe(r);
  CHECK_EQUAL_TEXT(0, r.exit_status, what.c_str());
  CHECK_TEXT(r.out.find("  dashboard: http://127.0.0.1:") != std::string::npos, what.c_str());
  CHECK_EQUAL_TEXT(2u, count_of(r.out, "match: yes"), what.c_str());
  CHECK_TEXT(r.out.find("collapses at t = 3.05") != std::string::npos, what.c_str());  // set 3 Y at 0.25 g, 1 ms steps
  CHECK_TEXT(r.out.find("survives") != std::string::npos, what.c_str());               // set 3 X
  CHECK_TEXT(r.out.find("COLLAPSED") != std::string::npos, what.c_str());
  CHECK_EQUAL_TEXT(4u, count_of(r.out, "4001 samples received"), what.c_str());
  // The instrumented wall: the true wall (r_ana) collapses, the nominal one open loop does not, the live monitor fused
  // with the wall's sensors follows the true wall and equals the offline fused run of the same samples.
  CHECK_TEXT(r.out.find("truth (r_ana), double engine: collapses at t = 5.639") != std::string::npos, what.c_str());
  CHECK_TEXT(r.out.find("open loop (the monitor without sensors, offline): survives") != std::string::npos,
             what.c_str());
  CHECK_TEXT(r.out.find("the fused monitor said IMMINENT") != std::string::npos, what.c_str());
  CHECK_EQUAL_TEXT(2u, count_of(r.out, "live = offline fused: yes"), what.c_str());
  CHECK_EQUAL_TEXT(1u, count_of(r.out, "1128 wall_sensor_t"), what.c_str());
  // A wall 10 % thinner than its drawings (set 3 Y at 0.18 g): it collapses, the nominal wall open loop only warns;
  // the monitor learns the capacity from the transducer and says IMMINENT before the collapse.
  CHECK_TEXT(r.out.find("truth (0.9 b), double engine: collapses at t = 4.776") != std::string::npos, what.c_str());
  CHECK_EQUAL_TEXT(2u, count_of(r.out, "the fused monitor said IMMINENT"), what.c_str());
  CHECK_TEXT(r.out.find("x_inst estimate 0.090") != std::string::npos, what.c_str());
#endif
}

// --monitor-config with a walls array: one monitor follows the paper wall (named "wall": the unsuffixed channels, the
// timeline compared) and a thicker one on the same ground motion; the demo reports both walls' highest levels.
TEST(DemoCommand, OneMonitorManyWallsFromItsConfig) {
#ifndef ROCKWATCH_MONITOR_PATH
  std::printf("\nnote: rockwatch-monitor is not part of this build: DemoCommand.OneMonitorManyWalls skipped\n");
#else
  const std::string url = private_url();
  const rockwatch::cli::MulticastProbe probe = rockwatch::cli::probe_multicast(url, 1000);
  if (!probe.ok) {
    if (rockwatch::test::skip_or_fail_in_ci("LCM multicast does not work here (" + probe.problem + ")")) return;
  }
  const rockwatch::test::TempDir tmp;
  const std::string config = tmp.file("walls.json");
  rockwatch::test::write_text(config, R"({"walls": [{"name": "wall"}, {"name": "thick", "wall": {"b": 0.2}}]})");
  const EnvOverride monitor("ROCKWATCH_MONITOR", ROCKWATCH_MONITOR_PATH);
  const ProcessResult r = run_rockwatch({"demo", "--speed", "4", "--lcm-url", url, "--monitor-config", config});
  const std::string what = describe(r);
  CHECK_EQUAL_TEXT(0, r.exit_status, what.c_str());
  CHECK_EQUAL_TEXT(2u, count_of(r.out, "match: yes"), what.c_str());  // the paper wall, as without the config
  CHECK_TEXT(r.out.find("walls (highest level): wall COLLAPSED, thick ") != std::string::npos, what.c_str());
  CHECK_EQUAL_TEXT(2u, count_of(r.out, "live = offline fused: yes"), what.c_str());  // the instrumented and the thinner wall
#endif
}
