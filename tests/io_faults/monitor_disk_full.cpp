// A full disk and write errors under `rockwatch-monitor --log`, with real parts (issue 41, item 4).
//
// One `rockwatch replay` (suite npr9998-2015 set 1 X at 0.40 g, 1 kHz: IMMINENT at 3.18 s, COLLAPSED at 4.30 s of
// the record) feeds three monitors at once on the same group, port and input channel (each its own output channels),
// so all three see the same datagrams:
//   healthy  --log on a roomy tmpfs;
//   full     --log on a small tmpfs (mounted here) that a filler file leaves about one second of log room: it fills
//            about 2 s into the record, before the alarms; the filler is deleted at 5.5 s, after the collapse;
//   eio      --log on the roomy tmpfs with the LD_PRELOAD shim io_fault_shim.so: EIO on every write from 1.5 s,
//            ENOSPC from 2.7 s, a write torn in half then EIO from 3.9 s, healthy again from 5.1 s, and fdatasync
//            failing with EIO at exit.
// The replay is stopped at 8.5 s, the monitors by SIGTERM at 9.5 s. Checks:
//   - every monitor exits 0 and publishes status every second (no stall);
//   - the alarm transitions (level, input_seq) of `full` and `eio` are the healthy monitor's, which reaches
//     COLLAPSED (exactly when no monitor counted a gap; within 100 samples otherwise, the levels in the same order);
//   - the failed writes are counted: log.write_failures ≥ counters.log_write_failures ≥ 1 (the loop's counter misses
//     only a failure found while closing, after the final status; eio: log.write_failures = the write and sync calls
//     the shim failed, from its record), the last status's log_write_failures = the counter, and a status carried
//     QUALITY_LOG_WRITE_FAILED; the healthy monitor: none of this, log complete;
//   - logging resumed: a status after the failures without the flag, events in the file after the gap;
//   - the log is a valid LCM log to its end (every event whole, the file ends at an event boundary, size = the
//     summary's bytes; `rockwatch-monitor --offline-in` reads all of it), its events = events_written +
//     events_not_durable (written, their fdatasync failed), its event numbers increase and their gaps add up to
//     events_lost (the lost events are where the numbers jump).
//
// Needs root to mount tmpfs (in a private mount namespace of this process: the mounts vanish with it even when it is
// killed; unmounted explicitly too) and multicast on loopback. Exit 0 pass, 1 fail, 2 usage, 77 skipped.
#include <fcntl.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <spawn.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "rockwatch/monitor_status_t.hpp"

extern char** environ;

namespace {

using nlohmann::json;
constexpr int kExitPass = 0, kExitFail = 1, kExitUsage = 2, kExitSkip = 77;
using Status = rockwatch::monitor_status_t;

std::int64_t mono_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::int64_t{ts.tv_sec} * 1000000000 + ts.tv_nsec;
}

int failures = 0;
void check(bool ok, const std::string& what) {
  std::cout << (ok ? "  ok    " : "  FAIL  ") << what << "\n";
  if (!ok) ++failures;
}

std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f << text;
}

pid_t spawn(const std::vector<std::string>& args, const std::string& out_path, const std::string& err_path,
            const std::vector<std::string>& extra_env) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  std::vector<std::string> env_strings;
  for (char** e = environ; *e != nullptr; ++e) env_strings.emplace_back(*e);
  for (const std::string& e : extra_env) env_strings.push_back(e);
  std::vector<char*> envp;
  for (std::string& e : env_strings) envp.push_back(e.data());
  envp.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, args[0].c_str(), &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) {
    std::cerr << "monitor_disk_full: cannot start " << args[0] << ": " << std::strerror(rc) << "\n";
    return -1;
  }
  return pid;
}

int wait_with_deadline(pid_t pid, double seconds) {
  const std::int64_t until = mono_ns() + static_cast<std::int64_t>(seconds * 1e9);
  int status = 0;
  for (;;) {
    if (waitpid(pid, &status, WNOHANG) == pid) return status;
    if (mono_ns() > until) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      return -1;
    }
    usleep(10000);
  }
}

bool multicast_works(const std::string& url, std::string& why) {
  lcm::LCM lcm(url);
  if (!lcm.good()) {
    why = "LCM could not start with " + url;
    return false;
  }
  const std::string channel = "RWDISK_PROBE_" + std::to_string(getpid());
  int got = 0;
  struct Probe {
    static void on(const lcm::ReceiveBuffer*, const std::string&, int* n) { ++*n; }
  };
  lcm.subscribeFunction(channel, &Probe::on, &got);
  const std::uint8_t byte = 1;
  for (int attempt = 0; attempt < 5 && got == 0; ++attempt) {
    lcm.publish(channel, &byte, 1);
    const std::int64_t until = mono_ns() + 200000000;
    while (got == 0 && mono_ns() < until) lcm.handleTimeout(20);
  }
  if (got == 0) {
    why = "a message published on " + url + " never came back (no multicast route on loopback? scripts/multicast-route.sh)";
    return false;
  }
  return true;
}

// The mounts of this run: a private mount namespace first, so they go away with this process whatever happens.
// The destructor unmounts and removes the run's directory (kept with --keep) on every way out of main.
struct Mounts {
  std::vector<std::string> points;
  std::string dir;
  bool keep = false;
  ~Mounts() {
    for (auto it = points.rbegin(); it != points.rend(); ++it) umount2(it->c_str(), MNT_DETACH);
    std::error_code ec;
    if (!keep && !dir.empty()) std::filesystem::remove_all(dir, ec);
  }
};

// With --keep the files of both tmpfs are copied to DIR/kept before Mounts' destructor unmounts them.
void finish(Mounts& mounts, const std::string& dir, bool keep) {
  if (keep) {
    std::error_code ec;
    std::filesystem::create_directories(dir + "/kept", ec);
    for (const std::string& p : mounts.points) {
      std::filesystem::copy(p, dir + "/kept", std::filesystem::copy_options::overwrite_existing, ec);
    }
    std::cout << "monitor_disk_full: files kept in " << dir << "/kept\n";
  }
  (void)dir;
}

// An LCM log read strictly: every event whole (sync word, header, channel, data), the file ending at an event.
struct LogRead {
  bool valid = true;
  std::string problem;
  std::int64_t events = 0, bytes = 0;
  std::vector<std::int64_t> numbers;
  std::map<std::string, std::int64_t> per_channel;
  std::int64_t input_events_after_first_gap = 0;
};

std::uint64_t get_be(const unsigned char* p, int n) {
  std::uint64_t v = 0;
  for (int i = 0; i < n; ++i) v = (v << 8) | p[i];
  return v;
}

LogRead read_lcm_log(const std::string& path, const std::string& input_channel) {
  LogRead r;
  const std::string data = read_text(path);
  const auto* p = reinterpret_cast<const unsigned char*>(data.data());
  const std::size_t n = data.size();
  r.bytes = static_cast<std::int64_t>(n);
  std::size_t at = 0;
  bool gap_seen = false;
  while (at < n) {
    if (n - at < 28 || get_be(p + at, 4) != 0xEDA1DA01u) {
      r.valid = false;
      r.problem = "no whole event header at byte " + std::to_string(at);
      return r;
    }
    const auto number = static_cast<std::int64_t>(get_be(p + at + 4, 8));
    const std::uint64_t channel_bytes = get_be(p + at + 20, 4), data_bytes = get_be(p + at + 24, 4);
    if (n - at - 28 < channel_bytes + data_bytes) {
      r.valid = false;
      r.problem = "event " + std::to_string(number) + " cut off at the end of the file (byte " + std::to_string(at) + ")";
      return r;
    }
    const std::string channel(data.data() + at + 28, channel_bytes);
    if (!r.numbers.empty() && number != r.numbers.back() + 1) gap_seen = true;
    if (gap_seen && channel == input_channel) ++r.input_events_after_first_gap;
    r.numbers.push_back(number);
    ++r.per_channel[channel];
    ++r.events;
    at += 28 + channel_bytes + data_bytes;
  }
  return r;
}

struct Monitor {
  std::string tag, log_path, out_path, err_path, config_path;
  std::vector<std::string> env;
  pid_t pid = -1;
  int exit_status = -1;
  std::vector<Status> statuses;
  json summary;
  std::vector<json> alarms;
};

struct Inbox {
  std::map<std::string, Monitor*> by_status_channel;
  static void on_status(const lcm::ReceiveBuffer* rbuf, const std::string& channel, Inbox* self) {
    Status s;
    if (s.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) != static_cast<int>(rbuf->data_size)) return;
    auto it = self->by_status_channel.find(channel);
    if (it != self->by_status_channel.end()) it->second->statuses.push_back(s);
  }
};

void parse_output(Monitor& m) {
  std::istringstream in(read_text(m.out_path));
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    json j = json::parse(line, nullptr, false);
    if (j.is_discarded()) continue;
    if (j.contains("summary")) {
      m.summary = j["summary"];
    } else if (j.contains("level")) {
      m.alarms.push_back(j);
    }
  }
}

std::string transitions_text(const std::vector<json>& alarms) {
  std::string s;
  for (const json& a : alarms) {
    s += a.value("level", std::string("?")) + "@" + std::to_string(a.value("input_seq", -1LL)) + " ";
  }
  return s;
}

struct Options {
  std::string monitor = ROCKWATCH_MONITOR_PATH, rockwatch = ROCKWATCH_CLI_PATH, shim = ROCKWATCH_IOFAULT_SHIM_PATH,
              source_dir = ROCKWATCH_SOURCE_DIR, keep;
  double pga = 0.4;
};

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << "monitor_disk_full: " << a << " needs a value\n";
        std::exit(kExitUsage);
      }
      return argv[++i];
    };
    if (a == "--keep") {
      o.keep = value();
    } else if (a == "--monitor") {
      o.monitor = value();
    } else if (a == "--rockwatch") {
      o.rockwatch = value();
    } else if (a == "--help" || a == "-h") {
      std::cout << "monitor_disk_full [--keep DIR] [--monitor PATH] [--rockwatch PATH]: see the head of "
                   "tests/io_faults/monitor_disk_full.cpp. Exit 0 pass, 1 fail, 2 usage, 77 skipped.\n";
      return kExitPass;
    } else {
      std::cerr << "monitor_disk_full: unknown option " << a << "\n";
      return kExitUsage;
    }
  }
  const std::int64_t t_start = mono_ns();

  if (geteuid() != 0) {
    std::cout << "monitor_disk_full: SKIPPED: not root (mounting the small tmpfs needs it)\n";
    return kExitSkip;
  }
  if (unshare(CLONE_NEWNS) != 0 || mount("none", "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0) {
    std::cout << "monitor_disk_full: SKIPPED: no private mount namespace (" << std::strerror(errno) << ")\n";
    return kExitSkip;
  }
  std::random_device rd;
  std::mt19937 rng(rd() ^ static_cast<unsigned>(getpid()));
  const std::string url = "udpm://239.255.76." + std::to_string(151 + rng() % 40) + ":" +
                          std::to_string(7751 + rng() % 200) + "?ttl=0";
  std::string why;
  if (!multicast_works(url, why)) {
    std::cout << "monitor_disk_full: SKIPPED (multicast unavailable): " << why << "\n";
    return kExitSkip;
  }

  char dir_template[] = "/tmp/rockwatch-disk-full-XXXXXX";
  const std::string dir = o.keep.empty() ? std::string(mkdtemp(dir_template)) : o.keep;
  mkdir(dir.c_str(), 0755);
  const std::string roomy = dir + "/roomy", small = dir + "/small";
  mkdir(roomy.c_str(), 0755);
  mkdir(small.c_str(), 0755);
  Mounts mounts;
  mounts.dir = dir;
  mounts.keep = !o.keep.empty();
  if (mount("tmpfs", roomy.c_str(), "tmpfs", 0, "size=64m") != 0) {
    std::cout << "monitor_disk_full: SKIPPED: cannot mount tmpfs (" << std::strerror(errno) << ")\n";
    return kExitSkip;
  }
  mounts.points.push_back(roomy);
  if (mount("tmpfs", small.c_str(), "tmpfs", 0, "size=4m") != 0) {
    std::cout << "monitor_disk_full: SKIPPED: cannot mount tmpfs (" << std::strerror(errno) << ")\n";
    return kExitSkip;
  }
  mounts.points.push_back(small);
  // The filler leaves about 1 s of log (≈ 330 kB at 1 kHz, one wall): the first flush fits, the second does not.
  const std::string filler = small + "/filler";
  {
    struct statvfs vfs {};
    statvfs(small.c_str(), &vfs);
    const std::uint64_t free_bytes = std::uint64_t{vfs.f_bavail} * vfs.f_frsize;
    const std::uint64_t room = 400u << 10;
    std::ofstream f(filler, std::ios::binary);
    const std::string block(1 << 16, '\x5a');
    for (std::uint64_t w = 0; w + room < free_bytes; w += block.size()) f.write(block.data(), block.size());
  }
  std::cout << "monitor_disk_full: " << url << ", files in " << dir << "\n";

  Monitor healthy, full, eio;
  healthy.tag = "healthy";
  healthy.log_path = roomy + "/healthy.lcmlog";
  full.tag = "full";
  full.log_path = small + "/full.lcmlog";
  eio.tag = "eio";
  eio.log_path = roomy + "/eio.lcmlog";
  const std::string control = roomy + "/iofault.control", shim_record = roomy + "/iofault.record";
  eio.env = {"LD_PRELOAD=" + o.shim, "ROCKWATCH_IOFAULT_MATCH=/eio.lcmlog", "ROCKWATCH_IOFAULT_CONTROL=" + control,
             "ROCKWATCH_IOFAULT_RECORD=" + shim_record};
  std::vector<Monitor*> monitors = {&healthy, &full, &eio};

  lcm::LCM lcm(url);
  Inbox inbox;
  for (Monitor* m : monitors) {
    const std::string up = m->tag == "healthy" ? "HEALTHY" : m->tag == "full" ? "FULL" : "EIO";
    m->out_path = roomy + "/" + m->tag + ".out";
    m->err_path = roomy + "/" + m->tag + ".err";
    m->config_path = roomy + "/" + m->tag + ".json";
    write_text(m->config_path, json{{"channels", {{"wall_state", "RWDISK_STATE_" + up}, {"alarm", "RWDISK_ALARM_" + up},
                                                  {"status", "RWDISK_STATUS_" + up}}}}
                                   .dump());
    inbox.by_status_channel["RWDISK_STATUS_" + up] = m;
    lcm.subscribeFunction("RWDISK_STATUS_" + up, &Inbox::on_status, &inbox);
  }
  for (Monitor* m : monitors) {
    m->pid = spawn({o.monitor, "--config", m->config_path, "--lcm-url", url, "--rate", "1000", "--log", m->log_path},
                   m->out_path, m->err_path, m->env);
    if (m->pid < 0) return kExitFail;
  }
  // Ready when each has published its first status.
  {
    const std::int64_t until = mono_ns() + 15000000000LL;
    auto ready = [&] {
      for (Monitor* m : monitors) {
        if (m->statuses.empty()) return false;
      }
      return true;
    };
    while (!ready() && mono_ns() < until) lcm.handleTimeout(20);
    if (!ready()) {
      std::cout << "monitor_disk_full: FAIL: a monitor published no status within 15 s\n";
      for (Monitor* m : monitors) kill(m->pid, SIGKILL);
      return kExitFail;
    }
  }
  std::vector<std::size_t> statuses_before(monitors.size());
  for (std::size_t i = 0; i < monitors.size(); ++i) statuses_before[i] = monitors[i]->statuses.size();

  const std::string replay_out = roomy + "/replay.out", replay_err = roomy + "/replay.err";
  const std::int64_t t0 = mono_ns();
  const pid_t replay = spawn({o.rockwatch, "replay", "--suite", o.source_dir + "/sim/suites/npr9998-2015", "--set", "1",
                              "--component", "X", "--scale-pga", std::to_string(o.pga), "--rate", "1000",
                              "--lcm-url", url},
                             replay_out, replay_err, {});
  if (replay < 0) return kExitFail;
  struct Step {
    double at_s;
    std::string what;
  };
  const std::vector<Step> schedule = {{1.5, "EIO"},         {2.7, "ENOSPC"}, {3.9, "short-EIO"}, {5.1, ""},
                                      {5.5, "free space"},  {8.5, "stop replay"}, {9.4, "fsync-EIO"},
                                      {9.5, "stop monitors"}};
  std::size_t next = 0;
  std::map<std::string, std::int64_t> status_gap_worst_ms;
  while (next < schedule.size()) {
    const double t = static_cast<double>(mono_ns() - t0) * 1e-9;
    if (t >= schedule[next].at_s) {
      const std::string& w = schedule[next].what;
      if (w == "free space") {
        unlink(filler.c_str());
      } else if (w == "stop replay") {
        kill(replay, SIGINT);
      } else if (w == "stop monitors") {
        for (Monitor* m : monitors) kill(m->pid, SIGTERM);
      } else {
        write_text(control, w);
      }
      std::cout << "monitor_disk_full: t = " << t << " s: " << (w.empty() ? "writes healthy again" : w) << "\n";
      ++next;
      continue;
    }
    lcm.handleTimeout(10);
  }
  const int replay_status = wait_with_deadline(replay, 10);
  for (Monitor* m : monitors) m->exit_status = wait_with_deadline(m->pid, 15);
  {  // the final statuses still in flight
    const std::int64_t until = mono_ns() + 300000000;
    while (mono_ns() < until) lcm.handleTimeout(20);
  }

  // ----- checks
  check(WIFEXITED(replay_status) || WIFSIGNALED(replay_status), "the replay ran and stopped");
  for (Monitor* m : monitors) {
    parse_output(*m);
    check(m->exit_status >= 0 && WIFEXITED(m->exit_status) && WEXITSTATUS(m->exit_status) == 0,
          m->tag + ": exits 0 after SIGTERM");
    check(m->summary.is_object() && m->summary.contains("log"), m->tag + ": summary line with its log object");
    // No stall: statuses every second (the status period; ≤ 1.6 s apart in this subscriber's receive time is
    // approximated by their own utime).
    std::int64_t worst = 0;
    for (std::size_t k = 1; k < m->statuses.size(); ++k) {
      worst = std::max(worst, m->statuses[k].utime - m->statuses[k - 1].utime);
    }
    check(m->statuses.size() >= 9 && worst <= 1600000,
          m->tag + ": status kept coming (" + std::to_string(m->statuses.size()) + " statuses, longest interval " +
              std::to_string(worst / 1000) + " ms)");
  }
  if (failures > 0 || !healthy.summary.is_object() || !full.summary.is_object() || !eio.summary.is_object()) {
    std::cout << "monitor_disk_full: FAIL (every file kept with --keep DIR)\n";
    for (Monitor* m : monitors) std::cout << "--- " << m->tag << " stderr:\n" << read_text(m->err_path);
    finish(mounts, dir, !o.keep.empty());
    return kExitFail;
  }

  // Alarms: the healthy monitor's transitions, on the same samples.
  auto gaps_of = [](const Monitor& m) {
    return m.summary["counters"].value("gaps", 0LL) + m.summary["counters"].value("state_resets", 0LL);
  };
  const bool no_gaps = gaps_of(healthy) == 0 && gaps_of(full) == 0 && gaps_of(eio) == 0;
  bool collapsed = false;
  for (const json& a : healthy.alarms) collapsed = collapsed || a.value("level", std::string()) == "COLLAPSED";
  check(collapsed, "healthy: the wall collapses (" + transitions_text(healthy.alarms) + ")");
  for (Monitor* m : {&full, &eio}) {
    bool same = m->alarms.size() == healthy.alarms.size();
    for (std::size_t k = 0; same && k < m->alarms.size(); ++k) {
      const long long d = m->alarms[k].value("input_seq", -1LL) - healthy.alarms[k].value("input_seq", -1LL);
      same = m->alarms[k].value("level", std::string()) == healthy.alarms[k].value("level", std::string()) &&
             (no_gaps ? d == 0 : std::llabs(d) <= 100);
    }
    check(same, m->tag + ": the healthy monitor's alarm transitions" +
                    std::string(no_gaps ? " at the same input samples" : " (gaps counted: within 100 samples)") +
                    " (" + transitions_text(m->alarms) + ")");
  }

  // The healthy log: complete, nothing lost.
  const json& hl = healthy.summary["log"];
  check(hl.value("write_failures", -1LL) == 0 && hl.value("events_lost", -1LL) == 0 && hl.value("complete", false),
        "healthy: log complete, no failed write (" + hl.dump() + ")");
  for (const Status& s : healthy.statuses) {
    if ((s.data_quality & Status::QUALITY_LOG_WRITE_FAILED) != 0 || s.log_write_failures != 0) {
      check(false, "healthy: a status flagged a log failure");
      break;
    }
  }

  // The shim's record of the eio monitor: the failed write calls (one per failed flush) and the torn ones.
  std::int64_t shim_write_failures = 0, shim_short = 0, shim_sync_failures = 0;
  {
    std::istringstream in(read_text(shim_record));
    std::string call, what;
    while (in >> call >> what) {
      std::string rest;
      std::getline(in, rest);
      if (call == "fsync" || call == "fdatasync") {
        ++shim_sync_failures;
      } else if (what == "short") {
        ++shim_short;
      } else {
        ++shim_write_failures;
      }
    }
  }
  std::cout << "monitor_disk_full: the shim failed " << shim_write_failures << " write calls, tore " << shim_short
            << ", failed " << shim_sync_failures << " syncs\n";
  check(shim_write_failures >= 3 && shim_short >= 1 && shim_sync_failures >= 1,
        "eio: the shim injected EIO/ENOSPC writes, a torn write and a failed fdatasync");

  for (Monitor* m : {&full, &eio}) {
    const json& lg = m->summary["log"];
    const std::int64_t wf = lg.value("write_failures", -1LL), lost = lg.value("events_lost", -1LL),
                       written = lg.value("events_written", -1LL), bytes = lg.value("bytes", -1LL),
                       not_durable = lg.value("events_not_durable", 0LL);
    // The loop counts the failures the log reported before the final status; one found while closing (after it) is
    // in the summary's log object only.
    const std::int64_t counted = m->summary["counters"].value("log_write_failures", -2LL);
    check(wf >= 1 && counted >= 1 && counted <= wf,
          m->tag + ": failed writes counted: log.write_failures " + std::to_string(wf) +
              " >= counters.log_write_failures " + std::to_string(counted) + " >= 1");
    if (m == &eio) {
      check(wf == shim_write_failures + shim_sync_failures,
            "eio: write_failures = the write and sync calls the shim failed (" + std::to_string(wf) + " vs " +
                std::to_string(shim_write_failures) + " + " + std::to_string(shim_sync_failures) + ")");
      check(!lg.value("complete", true) && lg.value("last_error", std::string()).find("Input/output error") != std::string::npos,
            "eio: the failed fdatasync at exit reported (complete false, last_error " + lg.value("last_error", std::string("none")) + ")");
    }
    check(lost > 0, m->tag + ": lost events counted (" + std::to_string(lost) + ")");
    const Status& last = m->statuses.back();
    check(last.log_write_failures == counted, m->tag + ": the last status's log_write_failures " +
                                                  std::to_string(last.log_write_failures) + " = the summary's counter");
    std::size_t first_flagged = m->statuses.size(), cleared_after = 0;
    for (std::size_t k = 0; k < m->statuses.size(); ++k) {
      const bool flagged = (m->statuses[k].data_quality & Status::QUALITY_LOG_WRITE_FAILED) != 0;
      if (flagged && first_flagged == m->statuses.size()) first_flagged = k;
      if (!flagged && first_flagged < k) cleared_after = k;
    }
    check(first_flagged < m->statuses.size(), m->tag + ": a status carried QUALITY_LOG_WRITE_FAILED");
    check(cleared_after > first_flagged, m->tag + ": a later status without the flag (logging resumed)");
    const std::string err = read_text(m->err_path);
    check(err.find("write failed") != std::string::npos && err.find("writing again") != std::string::npos,
          m->tag + ": stderr says the write failed and that writing works again");

    const LogRead r = read_lcm_log(m->log_path, "ROCKWATCH_ACCEL");
    check(r.valid, m->tag + ": the log is a valid LCM log to its end" + (r.valid ? "" : ": " + r.problem));
    check(r.events == written + not_durable && r.bytes == bytes,
          m->tag + ": events in the file " + std::to_string(r.events) + " = events_written " + std::to_string(written) +
              " + events_not_durable " + std::to_string(not_durable) + ", bytes " + std::to_string(r.bytes) +
              " = the summary's " + std::to_string(bytes));
    std::int64_t missing = 0;
    bool increasing = true;
    for (std::size_t k = 1; k < r.numbers.size(); ++k) {
      if (r.numbers[k] <= r.numbers[k - 1]) increasing = false;
      missing += r.numbers[k] - r.numbers[k - 1] - 1;
    }
    if (!r.numbers.empty()) missing += r.numbers.front();
    check(increasing && missing == lost, m->tag + ": event numbers increase; their gaps add up to events_lost (" +
                                             std::to_string(missing) + " vs " + std::to_string(lost) + ")");
    {  // the project's own reader: the monitor's offline mode reads the whole log
      const std::string off_out = roomy + "/" + m->tag + ".offline.out", off_err = roomy + "/" + m->tag + ".offline.err";
      const pid_t off = spawn({o.monitor, "--rate", "1000", "--offline-in", m->log_path, "--offline-out",
                               roomy + "/" + m->tag + ".offline.lcmlog"},
                              off_out, off_err, {});
      const int st = off < 0 ? -1 : wait_with_deadline(off, 30);
      json summary;
      std::istringstream in(read_text(off_out));
      std::string line;
      while (std::getline(in, line)) {
        json j = json::parse(line, nullptr, false);
        if (!j.is_discarded() && j.contains("summary")) summary = j["summary"];
      }
      check(st >= 0 && WIFEXITED(st) && WEXITSTATUS(st) == 0 && summary.is_object() &&
                summary.value("input_log_complete", false) && summary.value("log_events", -1LL) == r.events,
            m->tag + ": rockwatch-monitor --offline-in reads the whole log (" +
                std::to_string(summary.is_object() ? summary.value("log_events", -1LL) : -1LL) + " events, complete)");
    }
    check(r.input_events_after_first_gap > 1000,
          m->tag + ": input events logged after the gap (" + std::to_string(r.input_events_after_first_gap) + ")");
  }
  const double seconds = static_cast<double>(mono_ns() - t_start) * 1e-9;
  std::cout << "monitor_disk_full: " << (failures == 0 ? "PASS" : "FAIL") << " (" << failures << " failed checks, "
            << seconds << " s); alarms " << transitions_text(healthy.alarms) << "; gaps counted: "
            << (no_gaps ? "none" : "some") << "\n";
  if (failures > 0) {
    for (Monitor* m : monitors) std::cout << "--- " << m->tag << " stderr:\n" << read_text(m->err_path);
  }
  finish(mounts, dir, !o.keep.empty());
  return failures == 0 ? kExitPass : kExitFail;
}
