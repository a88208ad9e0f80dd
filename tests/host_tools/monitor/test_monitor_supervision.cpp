// Supervision of rockwatch-monitor: scripts/monitor-supervisor.sh restarts a killed monitor, which is back and
// processing within a second (a status on LCM from the new process, then samples processed); the systemd
// notification protocol (READY=1, WATCHDOG=1 at half of $WATCHDOG_USEC, STOPPING=1) received on a real unix datagram
// socket standing in for systemd's.
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "lcm_transport.hpp"
#include "monitor_live_support.hpp"
#include "monitor_test_support.hpp"
#include "rockwatch/ground_accel_t.hpp"
#include "rockwatch/monitor_status_t.hpp"

#include <CppUTest/TestHarness.h>

// The file's own scope in a unity build (tests/CMakeLists.txt): its helpers' names recur in other files of the suite.
namespace unity_test_monitor_supervision {

using rockwatch::test::now_s;
using rockwatch::test::TempDir;

namespace {

struct Channels : rockwatch::test::LiveChannels {
  Channels() : LiveChannels("RWS") {}
};

std::string test_url() { return rockwatch::test::live_test_url(1); }

struct Statuses {
  std::vector<rockwatch::monitor_status_t> all;
  std::vector<double> arrival_s;
  static void on_raw(const lcm::ReceiveBuffer* rbuf, const std::string&, Statuses* self) {
    rockwatch::monitor_status_t m;
    if (m.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) > 0) {
      self->all.push_back(m);
      self->arrival_s.push_back(now_s());
    }
  }
};

pid_t read_pid(const std::string& path) {
  const std::string text = rockwatch::test::read_file(path);
  return text.empty() ? 0 : static_cast<pid_t>(std::atol(text.c_str()));
}

// Waits until the pid file names a process other than `previous`.
pid_t wait_for_new_pid(const std::string& path, pid_t previous, double timeout_s) {
  const double deadline = now_s() + timeout_s;
  while (now_s() < deadline) {
    const pid_t p = read_pid(path);
    if (p != 0 && p != previous) return p;
    rockwatch::test::sleep_s(0.01);
  }
  return 0;
}

}  // namespace

TEST_GROUP(MonitorSupervision){};

TEST(MonitorSupervision, AKilledMonitorIsBackAndProcessingWithinASecond) {
  const std::string url = test_url();
  if (rockwatch::test::skip_without_multicast(url)) return;
  const TempDir dir;
  const Channels c;
  lcm::LCM lcm(url);
  CHECK(lcm.good());
  Statuses statuses;
  lcm.subscribeFunction(c.status, &Statuses::on_raw, &statuses);
  const std::string pid_file = dir.file("monitor.pid");
  const pid_t supervisor = rockwatch::test::spawn_program(
      "/bin/bash",
      {std::string(ROCKWATCH_SOURCE_DIR) + "/scripts/monitor-supervisor.sh", "--monitor", ROCKWATCH_MONITOR_PATH,
       "--pid-file", pid_file, "--", "--config", rockwatch::test::write_channels_config(dir, c, "sup.json"),
       "--lcm-url", url},
      dir.file("stdout"), dir.file("stderr"));
  const pid_t first = wait_for_new_pid(pid_file, 0, 10.0);
  CHECK_TEXT(first != 0, rockwatch::test::read_file(dir.file("stderr")).c_str());
  // The first monitor is up: its first status (seq 0) arrives.
  double deadline = now_s() + 10.0;
  while (statuses.all.empty() && now_s() < deadline) lcm.handleTimeout(20);
  CHECK_TEXT(!statuses.all.empty(), rockwatch::test::read_file(dir.file("stderr")).c_str());

  kill(first, SIGKILL);
  const double killed_at = now_s();
  const std::size_t before = statuses.all.size();
  const pid_t second = wait_for_new_pid(pid_file, first, 5.0);
  CHECK_TEXT(second != 0, rockwatch::test::read_file(dir.file("stderr")).c_str());
  // The new monitor announces itself with a status of seq 0 (QUALITY_MONITOR_RESTARTED).
  deadline = now_s() + 5.0;
  std::size_t restarted = 0;
  while (restarted == 0 && now_s() < deadline) {
    lcm.handleTimeout(5);
    for (std::size_t k = before; k < statuses.all.size() && restarted == 0; ++k) {
      if (statuses.all[k].seq == 0) restarted = k;
    }
  }
  CHECK_TEXT(restarted != 0, "no status from the restarted monitor within 5 s");
  const double back_after_s = statuses.arrival_s[restarted] - killed_at;
  CHECK_TEXT((statuses.all[restarted].data_quality & rockwatch::monitor_status_t::QUALITY_MONITOR_RESTARTED) != 0,
             "the first status of the new monitor says it restarted");
  // Processing: samples published now are counted by the new monitor's next status.
  const std::int64_t t0 = rockwatch::monitor::realtime_utime();
  for (int i = 0; i < 10; ++i) {
    rockwatch::ground_accel_t m{};
    m.utime = t0 + i * 5000;
    m.seq = i;
    m.schema_version = 1;
    std::vector<std::uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
    m.encode(b.data(), 0, static_cast<int>(b.size()));
    lcm.publish(c.accel, b.data(), static_cast<unsigned int>(b.size()));
  }
  deadline = now_s() + 3.0;
  bool processed = false;
  while (!processed && now_s() < deadline) {
    lcm.handleTimeout(20);
    processed = statuses.all.back().samples_processed == 10;
  }
  CHECK_TEXT(processed, "the restarted monitor did not report the 10 samples within 3 s");
  std::printf("\n  monitor back %.0f ms after SIGKILL (status seq 0 received)\n", back_after_s * 1e3);
  CHECK_TEXT(back_after_s < 1.0, ("back after " + std::to_string(back_after_s) + " s").c_str());

  kill(supervisor, SIGTERM);
  const int status = rockwatch::test::wait_status(supervisor);
  const std::string err = rockwatch::test::read_file(dir.file("stderr"));
  CHECK_TEXT(WIFEXITED(status) && WEXITSTATUS(status) == 0, err.c_str());
  CHECK_TEXT(err.find("ended (signal 9)") != std::string::npos, err.c_str());
  CHECK_TEXT(err.find("stopped after 1 restart(s)") != std::string::npos, err.c_str());
  CHECK_TEXT(kill(second, 0) != 0, "the monitor outlived its supervisor");
}

TEST(MonitorSupervision, SystemdNotificationsReadyWatchdogStopping) {
  const std::string url = test_url();
  if (rockwatch::test::skip_without_multicast(url)) return;
  const TempDir dir;
  const Channels c;
  const std::string socket_path = dir.file("notify.sock");
  const int fd = socket(AF_UNIX, SOCK_DGRAM, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  CHECK(socket_path.size() < sizeof address.sun_path);
  std::snprintf(address.sun_path, sizeof address.sun_path, "%s", socket_path.c_str());
  CHECK(bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0);
  timeval timeout{0, 100000};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);

  setenv("NOTIFY_SOCKET", socket_path.c_str(), 1);
  setenv("WATCHDOG_USEC", "400000", 1);  // 0.4 s: WATCHDOG=1 every ≥ 0.2 s
  const pid_t pid = rockwatch::test::spawn_monitor(
      {"--config", rockwatch::test::write_channels_config(dir, c, "notify.json"), "--lcm-url", url},
      dir.file("stdout"), dir.file("stderr"));
  unsetenv("NOTIFY_SOCKET");
  unsetenv("WATCHDOG_USEC");

  std::vector<std::string> got;
  const double deadline = now_s() + 10.0;
  int watchdogs = 0;
  while (watchdogs < 3 && now_s() < deadline) {
    char buffer[256];
    const ssize_t n = recv(fd, buffer, sizeof buffer, 0);
    if (n <= 0) continue;
    got.emplace_back(buffer, static_cast<std::size_t>(n));
    if (got.back() == "WATCHDOG=1") ++watchdogs;
  }
  kill(pid, SIGTERM);
  const int status = rockwatch::test::wait_status(pid);
  CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  for (int k = 0; k < 20; ++k) {
    char buffer[256];
    const ssize_t n = recv(fd, buffer, sizeof buffer, 0);
    if (n > 0) got.emplace_back(buffer, static_cast<std::size_t>(n));
  }
  close(fd);
  std::string all;
  for (const std::string& s : got) all += s + " ";
  CHECK_TEXT(!got.empty() && got.front() == "READY=1", all.c_str());
  LONGS_EQUAL_TEXT(3, watchdogs, all.c_str());
  CHECK_TEXT(got.back() == "STOPPING=1", all.c_str());
}

}  // namespace unity_test_monitor_supervision
