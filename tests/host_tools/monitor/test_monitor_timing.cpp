// rockwatch-monitor's timing settings: the clock tolerance (--clock-tolerance / clock_tolerance_s: range, in the
// settings and the digest only when not the default) and what the live receive thread asks of Linux (--realtime /
// realtime_priority, --cpu / cpu, --busy-poll-us / busy_poll_us): bad values name the option or key, and a live
// monitor under --realtime runs under SCHED_FIFO with its memory locked and says so — or, where the system refuses,
// warns and goes on processing samples. Skipped, saying why, when multicast does not work here.
#include <sched.h>
#include <signal.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "monitor_live_support.hpp"
#include "monitor_test_support.hpp"
#include "monitor_expect.hpp"
#include "rockwatch/ground_accel_t.hpp"

#include <CppUTest/TestHarness.h>

using nlohmann::json;
using rockwatch::test::ProcessResult;
using rockwatch::test::TempDir;

namespace {


// A configuration file (`text`) refused with a message naming the file and each of `mentions`.
void expect_timing_config_rejected(const std::string& text, const std::vector<std::string>& mentions) {
  const TempDir dir;
  const std::string path = dir.file("timing.json");
  rockwatch::test::write_file(path, text);
  std::vector<std::string> all{"--config " + path};
  all.insert(all.end(), mentions.begin(), mentions.end());
  rockwatch::test::expect_monitor_rejected({"--config", path, "--print-config"}, all);
}

json printed(const std::string& text, const std::vector<std::string>& extra) {
  return rockwatch::test::monitor_printed_config(text, extra);
}

// The first CPU this process may run on (the monitor must be pinned to one it may use).
int first_allowed_cpu() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return 0;
  for (int c = 0; c < CPU_SETSIZE; ++c) {
    if (CPU_ISSET(c, &set)) return c;
  }
  return 0;
}

std::int64_t realtime_us() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return std::int64_t{ts.tv_sec} * 1000000 + ts.tv_nsec / 1000;
}

// VmLck of a process [kB] (/proc/PID/status); -1 when unknown.
long locked_kib(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmLck:", 0) == 0) return std::stol(line.substr(6));
  }
  return -1;
}

// A live monitor (started as `program` with `arguments`, the monitor's own after `monitor_arguments`): what the
// system saw while it ran and what it said.
struct TimedRun {
  int policy = -1;        // sched_getscheduler of its main thread while running
  int priority = -1;
  long locked_kib = -1;   // VmLck while running
  cpu_set_t affinity{};   // of its main thread while running
  json summary;
  std::string err;
};

TimedRun run_timed(const std::string& program, const std::vector<std::string>& arguments, int samples) {
  const std::string url = rockwatch::test::live_test_url(0);
  const TempDir dir;
  const rockwatch::test::LiveChannels c("RWTIME");
  std::vector<std::string> args = arguments;
  args.insert(args.end(), {"--config", rockwatch::test::write_channels_config(dir, c, "live.json"), "--lcm-url", url});
  const std::string out_path = dir.file("stdout"), err_path = dir.file("stderr");
  const pid_t pid = rockwatch::test::spawn_program(program, args, out_path, err_path);
  const double deadline = rockwatch::test::now_s() + 20.0;
  while (rockwatch::test::read_file(err_path).find("listening on") == std::string::npos) {
    if (rockwatch::test::now_s() > deadline) {
      kill(pid, SIGKILL);
      rockwatch::test::wait_status(pid);
      FAIL(("the monitor did not say it listens within 20 s:\n" + rockwatch::test::read_file(err_path)).c_str());
    }
    rockwatch::test::sleep_s(0.01);
  }
  TimedRun run;
  run.policy = sched_getscheduler(pid);
  sched_param p{};
  if (sched_getparam(pid, &p) == 0) run.priority = p.sched_priority;
  run.locked_kib = locked_kib(pid);
  CPU_ZERO(&run.affinity);
  sched_getaffinity(pid, sizeof run.affinity, &run.affinity);
  // It still does its work: `samples` ground samples at 200 Hz, all received.
  lcm::LCM lcm(url);
  CHECK(lcm.good());
  for (int k = 0; k < samples; ++k) {
    rockwatch::ground_accel_t m{};
    m.utime = realtime_us();
    m.seq = k;
    m.schema_version = rockwatch::ground_accel_t::SCHEMA_VERSION;
    m.ug_mps2 = 0.1;
    lcm.publish(c.accel, &m);
    rockwatch::test::sleep_s(0.005);
  }
  rockwatch::test::sleep_s(0.3);
  kill(pid, SIGTERM);
  const int status = rockwatch::test::wait_status(pid);
  run.err = rockwatch::test::read_file(err_path);
  CHECK_TEXT(WIFEXITED(status) && WEXITSTATUS(status) == 0, run.err.c_str());
  const std::vector<json> lines = rockwatch::test::json_lines(rockwatch::test::read_file(out_path));
  CHECK_TEXT(!lines.empty() && lines.back().contains("summary"), run.err.c_str());
  run.summary = lines.back().at("summary");
  LONGS_EQUAL_TEXT(samples, run.summary.at("counters").at("samples_received").get<long>(), run.err.c_str());
  return run;
}

}  // namespace

TEST_GROUP(MonitorClockTolerance){};

TEST(MonitorClockTolerance, BadValuesNameTheOptionOrKeyAndTheRange) {
  rockwatch::test::expect_monitor_rejected({"--clock-tolerance", "0"}, {"--clock-tolerance", "> 0 s", "got 0"});
  rockwatch::test::expect_monitor_rejected({"--clock-tolerance", "-2"}, {"--clock-tolerance", "> 0 s"});
  rockwatch::test::expect_monitor_rejected({"--clock-tolerance", "86401"}, {"--clock-tolerance", "86400", "got 86401"});
  rockwatch::test::expect_monitor_rejected({"--clock-tolerance", "1e-7"}, {"--clock-tolerance", "0.000001"});
  rockwatch::test::expect_monitor_rejected({"--clock-tolerance", "soon"}, {"--clock-tolerance", "'soon'"});
  expect_timing_config_rejected(R"({"clock_tolerance_s": 0})", {"clock_tolerance_s", "got 0"});
  expect_timing_config_rejected(R"({"clock_tolerance_s": -1})", {"clock_tolerance_s", "got -1"});
  expect_timing_config_rejected(R"({"clock_tolerance_s": 1e6})", {"clock_tolerance_s", "86400"});
  expect_timing_config_rejected(R"({"clock_tolerance_s": "10"})", {"clock_tolerance_s", "expected a number"});
}

TEST(MonitorClockTolerance, InTheSettingsAndTheDigestOnlyWhenNotTheDefault) {
  const json none = printed("", {});
  CHECK_FALSE(none.at("settings").contains("clock_tolerance_s"));
  const json ten = printed(R"({"clock_tolerance_s": 10})", {});
  CHECK(ten.at("config_digest") == none.at("config_digest"));
  const json file = printed(R"({"clock_tolerance_s": 0.5})", {});
  DOUBLES_EQUAL(0.5, file.at("settings").at("clock_tolerance_s").get<double>(), 0.0);
  CHECK(file.at("config_digest") != none.at("config_digest"));
  // The command line over the file.
  const json over = printed(R"({"clock_tolerance_s": 0.5})", {"--clock-tolerance", "2"});
  DOUBLES_EQUAL(2.0, over.at("settings").at("clock_tolerance_s").get<double>(), 0.0);
  CHECK(over.at("config_digest") == printed("", {"--clock-tolerance", "2"}).at("config_digest"));
}

TEST_GROUP(MonitorWorkBudget){};

TEST(MonitorWorkBudget, BadValuesNameTheOptionOrKeyAndTheRange) {
  rockwatch::test::expect_monitor_rejected({"--work-budget", "5"}, {"--work-budget", "0 (off)", "got 5"});
  rockwatch::test::expect_monitor_rejected({"--work-budget", "23000.5"}, {"--work-budget", "whole number"});
  rockwatch::test::expect_monitor_rejected({"--work-budget", "lots"}, {"--work-budget", "'lots'"});
  rockwatch::test::expect_monitor_rejected({"--arith", "double", "--work-budget", "23000"},
                                           {"--work-budget", "fixed-point"});
  expect_timing_config_rejected(R"({"work_budget_units": -1})", {"work_budget_units", "got -1"});
  expect_timing_config_rejected(R"({"work_budget_units": "23000"})", {"work_budget_units", "expected a number"});
}

TEST(MonitorWorkBudget, InTheSettingsAndTheDigestOnlyWhenOn) {
  const json none = printed("", {});
  CHECK_FALSE(none.at("settings").contains("work_budget_units"));
  CHECK(printed(R"({"work_budget_units": 0})", {}).at("config_digest") == none.at("config_digest"));
  const json on = printed(R"({"work_budget_units": 23000})", {});
  LONGS_EQUAL(23000, on.at("settings").at("work_budget_units").get<long>());
  CHECK(on.at("config_digest") != none.at("config_digest"));
  CHECK(on.at("config_digest") == printed("", {"--work-budget", "23000"}).at("config_digest"));
}

TEST(MonitorWorkBudget, TheOverflowPolicyNamesItsOptionOrKeyAndNeedsABudget) {
  rockwatch::test::expect_monitor_rejected({"--work-budget", "23000", "--work-overflow", "later"},
                                           {"--work-overflow must be shed or finish", "'later'"});
  rockwatch::test::expect_monitor_rejected({"--work-overflow", "finish"}, {"--work-overflow", "work budget"});
  expect_timing_config_rejected(R"({"work_budget_units": 23000, "work_overflow": 1})",
                                {"work_overflow", "expected \"shed\" or \"finish\""});
  expect_timing_config_rejected(R"({"work_budget_units": 23000, "work_overflow": "drop"})", {"work_overflow", "'drop'"});
  expect_timing_config_rejected(R"({"work_overflow": "finish"})", {"work_overflow", "work budget"});
  // In the settings and the digest only when not the default.
  const json shed = printed(R"({"work_budget_units": 23000, "work_overflow": "shed"})", {});
  CHECK_FALSE(shed.at("settings").contains("work_overflow"));
  CHECK(shed.at("config_digest") == printed("", {"--work-budget", "23000"}).at("config_digest"));
  const json finish = printed(R"({"work_budget_units": 23000, "work_overflow": "finish"})", {});
  STRCMP_EQUAL("finish", finish.at("settings").at("work_overflow").get<std::string>().c_str());
  CHECK(finish.at("config_digest") != shed.at("config_digest"));
  CHECK(finish.at("config_digest") ==
        printed("", {"--work-budget", "23000", "--work-overflow", "finish"}).at("config_digest"));
}

TEST_GROUP(MonitorTimingOptions){};

TEST(MonitorTimingOptions, BadValuesNameTheOptionOrKey) {
  rockwatch::test::expect_monitor_rejected({"--realtime", "0"}, {"--realtime", "1..99", "got 0"});
  rockwatch::test::expect_monitor_rejected({"--realtime", "100"}, {"--realtime", "got 100"});
  rockwatch::test::expect_monitor_rejected({"--realtime", "high"}, {"--realtime", "'high'"});
  rockwatch::test::expect_monitor_rejected({"--cpu", "-1"}, {"--cpu", "'-1'"});
  rockwatch::test::expect_monitor_rejected({"--cpu", "1.5"}, {"--cpu", "'1.5'"});
  rockwatch::test::expect_monitor_rejected({"--cpu", "1023"}, {"--cpu", "got 1023"});
  rockwatch::test::expect_monitor_rejected({"--busy-poll-us", "0"}, {"--busy-poll-us", "got 0"});
  rockwatch::test::expect_monitor_rejected({"--busy-poll-us", "100001"}, {"--busy-poll-us", "100000"});
  rockwatch::test::expect_monitor_rejected({"--busy-poll-us", "50", "--receive-path", "liblcm"}, {"--busy-poll-us", "--receive-path own"});
  rockwatch::test::expect_monitor_rejected({"--offline-in", "a.lcmlog", "--offline-out", "b.lcmlog", "--realtime", "50"},
                         {"--realtime", "live mode"});
  expect_timing_config_rejected(R"({"realtime_priority": 0})", {"realtime_priority", "got 0"});
  expect_timing_config_rejected(R"({"realtime_priority": 50.5})", {"realtime_priority", "whole number"});
  expect_timing_config_rejected(R"({"realtime_priority": "50"})", {"realtime_priority", "a string"});
  expect_timing_config_rejected(R"({"cpu": -1})", {"cpu", "got -1"});
  expect_timing_config_rejected(R"({"cpu": 4096})", {"cpu", "got 4096"});
  expect_timing_config_rejected(R"({"busy_poll_us": 1e9})", {"busy_poll_us", "got 1000000000"});
}

TEST(MonitorTimingOptions, ReadBackAndNotInTheDigest) {
  const json none = printed("", {});
  CHECK_FALSE(none.contains("timing"));
  const std::string cpu = std::to_string(first_allowed_cpu());
  const json file = printed(R"({"realtime_priority": 40, "busy_poll_us": 20, "cpu": )" + cpu + "}", {});
  LONGS_EQUAL(40, file.at("timing").at("realtime_priority").get<long>());
  LONGS_EQUAL(20, file.at("timing").at("busy_poll_us").get<long>());
  STRCMP_EQUAL(cpu.c_str(), file.at("timing").at("cpu").dump().c_str());
  // When, not what, the monitor computes: the digest stays.
  CHECK(file.at("config_digest") == none.at("config_digest"));
  const json over = printed(R"({"realtime_priority": 40})", {"--realtime", "60"});
  LONGS_EQUAL(60, over.at("timing").at("realtime_priority").get<long>());
  CHECK(over.at("timing").at("cpu").is_null());
}

TEST_GROUP(MonitorRealtime){};

// Permitted (root here, or CAP_SYS_NICE / CAP_IPC_LOCK): the receive thread runs under SCHED_FIFO at the priority,
// pinned, its memory locked, and the summary says so. Where this test process is not permitted, the monitor is not
// either: it must then say so and go on (the refused path, tested on its own below as root).
TEST(MonitorRealtime, UnderRealtimeTheReceiveThreadIsFifoPinnedAndLockedOrWarns) {
  if (rockwatch::test::skip_without_multicast(rockwatch::test::live_test_url(0))) return;
  const int cpu = first_allowed_cpu();
  const TimedRun run = run_timed(ROCKWATCH_MONITOR_PATH, {"--realtime", "20", "--cpu", std::to_string(cpu)}, 40);
  const json& t = run.summary.at("timing");
  LONGS_EQUAL(20, t.at("realtime_priority").get<long>());
  CHECK_TEXT(t.at("pinned").get<bool>(), run.err.c_str());
  CHECK_TEXT(CPU_ISSET(cpu, &run.affinity) && CPU_COUNT(&run.affinity) == 1, run.err.c_str());
  if (t.at("realtime").get<bool>()) {
    LONGS_EQUAL_TEXT(SCHED_FIFO, run.policy, run.err.c_str());
    LONGS_EQUAL(20, run.priority);
    CHECK_TEXT(t.at("memory_locked").get<bool>(), run.err.c_str());
#if !defined(__SANITIZE_ADDRESS__)
    // AddressSanitizer intercepts mlockall and ignores it (it would lock the shadow memory): VmLck stays 0 in the
    // debug build's monitor, which is built with the same sanitizers as this test.
    CHECK_TEXT(run.locked_kib > 0, run.err.c_str());
#endif
    CHECK_TEXT(t.at("warnings").empty(), run.err.c_str());
    CHECK_TEXT(run.err.find("timing: SCHED_FIFO 20, memory locked, pinned to CPU " + std::to_string(cpu)) !=
                   std::string::npos,
               run.err.c_str());
  } else {
    LONGS_EQUAL(SCHED_OTHER, run.policy);
    CHECK_TEXT(run.err.find("warning: --realtime: SCHED_FIFO priority 20") != std::string::npos, run.err.c_str());
    CHECK_FALSE(t.at("warnings").empty());
  }
}

// Refused (here: root without CAP_SYS_NICE and CAP_IPC_LOCK, through setpriv; or an unprivileged test run): a warning
// on stderr naming the option and what would allow it, the summary says realtime false, and the monitor works.
TEST(MonitorRealtime, RefusedRealtimeWarnsAndTheMonitorGoesOn) {
  if (rockwatch::test::skip_without_multicast(rockwatch::test::live_test_url(0))) return;
  const std::string setpriv = "/usr/bin/setpriv";
  const bool root = geteuid() == 0;
  if (root && access(setpriv.c_str(), X_OK) != 0) {
    std::printf("SKIPPED: running as root and %s (util-linux) is missing to drop CAP_SYS_NICE\n", setpriv.c_str());
    return;
  }
  const std::vector<std::string> monitor_args{"--realtime", "30"};
  std::vector<std::string> args;
  if (root) {
    args = {"--bounding-set", "-sys_nice,-ipc_lock", "--inh-caps", "-sys_nice,-ipc_lock", ROCKWATCH_MONITOR_PATH};
  }
  args.insert(args.end(), monitor_args.begin(), monitor_args.end());
  const TimedRun run = run_timed(root ? setpriv : std::string(ROCKWATCH_MONITOR_PATH), args, 40);
  const json& t = run.summary.at("timing");
  if (!root && t.at("realtime").get<bool>()) {
    std::printf("SKIPPED: this unprivileged test run may use SCHED_FIFO (RLIMIT_RTPRIO)\n");
    return;
  }
  CHECK_FALSE(t.at("realtime").get<bool>());
  LONGS_EQUAL(SCHED_OTHER, run.policy);
  CHECK_TEXT(run.err.find("rockwatch-monitor: warning: --realtime: SCHED_FIFO priority 30: Operation not permitted") !=
                 std::string::npos,
             run.err.c_str());
  CHECK_TEXT(run.err.find("the monitor goes on with ordinary scheduling") != std::string::npos, run.err.c_str());
  CHECK_TEXT(run.err.find("CAP_SYS_NICE") != std::string::npos, run.err.c_str());
  CHECK_TEXT(t.at("warnings").size() >= 1, run.err.c_str());
}
