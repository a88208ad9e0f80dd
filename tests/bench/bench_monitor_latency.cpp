// Latency from publishing a ground-acceleration sample to receiving the wall state that answers it, through a live
// rockwatch-monitor over LCM (UDP multicast on this machine, ttl=0), and loss (samples never answered).
// A timing program, not a test: figures go to docs/BENCHMARKS.md.
//
//   bench_monitor_latency MONITOR_EXE [--rate HZ] [--seconds S] [--batch N] [--lcm-url URL] [--queue N]
//                         [--rx-buffer BYTES] [--receive-path own|liblcm] [--monitor-args "ARG ..."] [--cpu N]
//                         [--amplitude MPS2] [--frequency HZ]
//
// The ground: a sine of --amplitude (default 0.5 m/s2: below the paper wall's rocking threshold, the wall at rest)
// and --frequency (default 1.5 Hz). 1.4 m/s2 at 4 Hz keeps the paper wall rocking without collapse (max |x| 0.15
// x_inst, about 8 impacts a second): the case in which `--monitor-args "--forecast 200,5"` computes every forecast
// (docs/BENCHMARKS.md, "Forecast").
//
// --receive-path is handed to the monitor: its own checked datagram path (default) or liblcm's receive thread, so
// the two can be measured side by side in one session (docs/BENCHMARKS.md). liblcm's needs MONITOR_EXE =
// rockwatch-monitor-liblcm (built here, tests/bench: the same monitor loop with lcm_input_source.hpp as its input);
// rockwatch-monitor reads with its own path only. --monitor-args: more arguments for the
// monitor, split at spaces (e.g. "--realtime 50 --cpu 1"); the monitor's summary "timing" object (what the system
// granted) is printed on a third line. --cpu N pins this program's threads (publisher and subscriber) to CPU N, after
// the monitor is started (which keeps its own affinity).
//
// It starts the monitor itself (--lcm-url, --rate), waits for its first status message, publishes from a second
// thread at absolute deadlines (CLOCK_MONOTONIC, TIMER_ABSTIME) — one ground_accel_t per sample, or one
// ground_accel_batch_t per N samples — and receives wall_state_t on the main thread. Latency of a sample = receive
// time of its wall_state_t − publish time of the message that carried it. Prints one line of figures, then where
// the lost samples went missing:
//   - input: samples the monitor never received (its last monitor_status_t: samples_received, gaps);
//   - output: wall states the monitor published (samples_processed) that this subscriber did not receive;
//   - kernel: datagrams the kernel dropped on the monitor's and on this process's UDP sockets (the drops column of
//     /proc/net/udp, receive buffer full) and the machine's Udp RcvbufErrors over the run (/proc/net/snmp).
//   What is lost and not dropped by a kernel was dropped inside liblcm: its receive thread discards a message when
//   every subscription it matches already holds its queue capacity of unhandled messages (30 by default).
// --queue N sets this subscriber's queue capacity (lcm::Subscription::setQueueCapacity; 0 = unbounded; default
// 100000, more than any run's messages; --queue 30 is LCM's default). The monitor and the publisher get --lcm-url as
// given; this subscriber adds recv_buf_size=2097152 to a udpm:// URL without one (--rx-buffer BYTES, 0 = as given).
#include <dirent.h>
#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "rockwatch/ground_accel_batch_t.hpp"
#include "rockwatch/ground_accel_t.hpp"
#include "rockwatch/monitor_status_t.hpp"
#include "rockwatch/wall_state_t.hpp"

namespace {

std::int64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::int64_t{ts.tv_sec} * 1000000000 + ts.tv_nsec;
}

std::int64_t realtime_us() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return std::int64_t{ts.tv_sec} * 1000000 + ts.tv_nsec / 1000;
}

void sleep_until_ns(std::int64_t t_ns) {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(t_ns / 1000000000);
  ts.tv_nsec = static_cast<long>(t_ns % 1000000000);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const auto i = static_cast<std::size_t>(std::ceil(p * double(v.size()))) - 1;  // nearest rank
  return v[std::min(i, v.size() - 1)];
}

// The socket inodes process `pid` holds (/proc/PID/fd -> "socket:[INODE]").
std::set<unsigned long> socket_inodes(pid_t pid) {
  std::set<unsigned long> inodes;
  const std::string dir = "/proc/" + std::to_string(pid) + "/fd";
  DIR* d = opendir(dir.c_str());
  if (d == nullptr) return inodes;
  while (const dirent* e = readdir(d)) {
    char target[64] = {};
    const std::string link = dir + "/" + e->d_name;
    const ssize_t len = readlink(link.c_str(), target, sizeof target - 1);
    unsigned long inode = 0;
    if (len > 0 && std::sscanf(target, "socket:[%lu]", &inode) == 1) inodes.insert(inode);
  }
  closedir(d);
  return inodes;
}

// Datagrams the kernel dropped on the UDP sockets of `pid` (sum of /proc/net/udp's drops column); -1 if unknown.
long long udp_drops(pid_t pid) {
  const std::set<unsigned long> inodes = socket_inodes(pid);
  std::ifstream in("/proc/net/udp");
  if (!in || inodes.empty()) return -1;
  std::string line;
  std::getline(in, line);  // header
  long long drops = 0;
  while (std::getline(in, line)) {
    // sl local rem st tx:rx tr:when retrnsmt uid timeout inode ref pointer drops
    std::istringstream f(line);
    std::string sl, local, rem, st, queues, timer, retr, uid, timeout, ptr;
    unsigned long inode = 0;
    int ref = 0;
    long long d = 0;
    if (f >> sl >> local >> rem >> st >> queues >> timer >> retr >> uid >> timeout >> inode >> ref >> ptr >> d &&
        inodes.count(inode) != 0) {
      drops += d;
    }
  }
  return drops;
}

// The machine's Udp RcvbufErrors (/proc/net/snmp); -1 if unknown.
long long udp_rcvbuf_errors() {
  std::ifstream in("/proc/net/snmp");
  std::string names, values;
  while (std::getline(in, names)) {
    if (names.rfind("Udp:", 0) != 0 || !std::getline(in, values)) continue;
    std::istringstream n(names), v(values);
    std::string name, value;
    while (n >> name && v >> value) {
      if (name == "RcvbufErrors") return std::atoll(value.c_str());
    }
    return -1;
  }
  return -1;
}

struct Receiver {
  std::vector<std::atomic<std::int64_t>>* published_ns = nullptr;
  std::vector<std::int64_t> received_ns;
  std::int64_t states = 0, duplicates = 0, last_receive_ns = 0;

  void on_state(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    rockwatch::wall_state_t s;
    if (s.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) < 0) return;
    const std::int64_t now = monotonic_ns();
    last_receive_ns = now;
    ++states;
    if (s.input_seq < 0 || s.input_seq >= static_cast<std::int64_t>(received_ns.size())) return;
    auto& slot = received_ns[static_cast<std::size_t>(s.input_seq)];
    if (slot != 0) {
      ++duplicates;
      return;
    }
    slot = now;
  }
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: %s MONITOR_EXE [--rate HZ] [--seconds S] [--batch N] [--lcm-url URL] [--queue N] "
                 "[--rx-buffer BYTES] [--receive-path own|liblcm] [--monitor-args \"ARG ...\"] [--cpu N]\n",
                 argv[0]);
    return 2;
  }
  const std::string monitor = argv[1];
  double rate_hz = 1000.0, seconds = 10.0;
  double amplitude_mps2 = 0.5, frequency_hz = 1.5;  // the ground sine
  int batch = 1;
  int queue = 100000;
  long long rx_buffer = 2097152;
  std::string url = "udpm://239.255.76.67:7667?ttl=0";
  std::string receive_path = "own";
  std::vector<std::string> monitor_args;
  int cpu = -1;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--queue") queue = std::atoi(value.c_str());
    else if (key == "--rx-buffer") rx_buffer = std::atoll(value.c_str());
    else if (key == "--rate") rate_hz = std::atof(value.c_str());
    else if (key == "--amplitude") amplitude_mps2 = std::atof(value.c_str());
    else if (key == "--frequency") frequency_hz = std::atof(value.c_str());
    else if (key == "--seconds") seconds = std::atof(value.c_str());
    else if (key == "--batch") batch = std::atoi(value.c_str());
    else if (key == "--lcm-url") url = value;
    else if (key == "--receive-path") receive_path = value;
    else if (key == "--monitor-args") {
      std::istringstream words(value);
      for (std::string w; words >> w;) monitor_args.push_back(w);
    } else if (key == "--cpu") cpu = std::atoi(value.c_str());
    else {
      std::fprintf(stderr, "unknown option %s\n", key.c_str());
      return 2;
    }
  }
  if (!(rate_hz > 0.0) || !(seconds > 0.0) || batch < 1 || batch > 50 || queue < 0 || rx_buffer < 0) {
    std::fprintf(stderr, "--rate and --seconds must be > 0, --batch in 1..50, --queue and --rx-buffer >= 0\n");
    return 2;
  }
  const auto n = static_cast<std::size_t>(std::llround(rate_hz * seconds));

  const std::string rate_text = std::to_string(rate_hz);
  // The monitor's stdout (alarm lines, the summary) goes to a temporary file: its summary says what timing it got.
  char summary_path[] = "/tmp/bench_monitor_latency.XXXXXX";
  const int summary_fd = mkstemp(summary_path);
  if (summary_fd < 0) {
    std::perror("mkstemp");
    return 1;
  }
  std::vector<std::string> args{monitor, "--lcm-url", url, "--rate", rate_text, "--receive-path", receive_path};
  args.insert(args.end(), monitor_args.begin(), monitor_args.end());
  std::vector<char*> argv_monitor;
  for (std::string& a : args) argv_monitor.push_back(a.data());
  argv_monitor.push_back(nullptr);
  const pid_t child = fork();
  if (child == 0) {
    if (dup2(summary_fd, STDOUT_FILENO) < 0) _exit(127);
    execv(monitor.c_str(), argv_monitor.data());
    _exit(127);
  }
  close(summary_fd);
  if (cpu >= 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(cpu, &set);
    if (sched_setaffinity(0, sizeof set, &set) != 0) {  // this thread; the publisher thread inherits it
      std::perror("--cpu: sched_setaffinity");
      kill(child, SIGTERM);
      return 2;
    }
  }

  std::string rx_url = url;
  if (rx_buffer > 0 && url.rfind("udpm://", 0) == 0 && url.find("recv_buf_size=") == std::string::npos) {
    rx_url += (url.find('?') == std::string::npos ? "?" : "&") + std::string("recv_buf_size=") + std::to_string(rx_buffer);
  }
  lcm::LCM rx(rx_url);
  if (!rx.good()) {
    std::fprintf(stderr, "cannot open LCM at %s (multicast route on lo?)\n", rx_url.c_str());
    kill(child, SIGTERM);
    return 1;
  }
  std::vector<std::atomic<std::int64_t>> published_ns(n);
  Receiver receiver;
  receiver.published_ns = &published_ns;
  receiver.received_ns.assign(n, 0);
  struct Status {
    rockwatch::monitor_status_t last{};
    std::int64_t count = 0, receive_ns = 0;
    void on_status(const lcm::ReceiveBuffer* rbuf, const std::string&) {
      if (last.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) < 0) return;
      ++count;
      receive_ns = monotonic_ns();
    }
  } status;
  lcm::Subscription* states = rx.subscribe("ROCKWATCH_WALL_STATE", &Receiver::on_state, &receiver);
  rx.subscribe("ROCKWATCH_STATUS", &Status::on_status, &status);
  if (states != nullptr) states->setQueueCapacity(queue);
  const std::int64_t wait_until = monotonic_ns() + 5000000000LL;
  while (status.count == 0 && monotonic_ns() < wait_until) rx.handleTimeout(100);
  if (status.count == 0) {
    std::fprintf(stderr, "the monitor did not publish a status within 5 s\n");
    kill(child, SIGTERM);
    waitpid(child, nullptr, 0);
    return 1;
  }

  std::atomic<bool> done{false};
  std::thread publisher([&]() {
    lcm::LCM tx(url);
    const std::int64_t period_ns = static_cast<std::int64_t>(std::llround(1e9 / rate_hz));
    const std::int64_t t0 = monotonic_ns() + 100000000;  // 0.1 s to settle
    for (std::size_t i = 0; i < n; i += std::size_t(batch)) {
      sleep_until_ns(t0 + std::int64_t(i + std::size_t(batch) - 1) * period_ns);  // when the last sample exists
      const std::int64_t now = monotonic_ns();
      const double ug = amplitude_mps2 * std::sin(2.0 * M_PI * frequency_hz * double(i) / rate_hz);
      if (batch == 1) {
        rockwatch::ground_accel_t m{};
        m.utime = realtime_us();
        m.seq = static_cast<std::int64_t>(i);
        m.schema_version = rockwatch::ground_accel_t::SCHEMA_VERSION;
        m.ug_mps2 = ug;
        published_ns[i].store(now);
        tx.publish("ROCKWATCH_ACCEL", &m);
      } else {
        rockwatch::ground_accel_batch_t m{};
        m.utime = realtime_us();
        m.seq = static_cast<std::int64_t>(i);
        m.schema_version = rockwatch::ground_accel_batch_t::SCHEMA_VERSION;
        m.sample_period_us = static_cast<std::int32_t>(std::llround(1e6 / rate_hz));
        m.count = static_cast<std::int32_t>(std::min<std::size_t>(std::size_t(batch), n - i));
        for (std::int32_t k = 0; k < m.count; ++k) {
          m.ug_mps2[k] = amplitude_mps2 * std::sin(2.0 * M_PI * frequency_hz * double(i + std::size_t(k)) / rate_hz);
          published_ns[i + std::size_t(k)].store(now);
        }
        tx.publish("ROCKWATCH_ACCEL_BATCH", &m);
      }
    }
    done.store(true);
  });

  const long long rcvbuf_errors_before = udp_rcvbuf_errors();
  // Receive until the publisher is done, nothing has arrived for a second and a status published after the last
  // wall state has arrived (its counters then cover the whole run; at most 3 s more).
  std::int64_t done_ns = 0;
  for (;;) {
    rx.handleTimeout(50);
    if (!done.load()) continue;
    const std::int64_t now = monotonic_ns();
    if (done_ns == 0) done_ns = now;
    if (now - receiver.last_receive_ns > 1000000000LL &&
        (status.receive_ns > receiver.last_receive_ns || now - done_ns > 4000000000LL)) {
      break;
    }
  }
  publisher.join();
  const long long monitor_kernel_drops = udp_drops(child), own_kernel_drops = udp_drops(getpid());
  const long long rcvbuf_errors = udp_rcvbuf_errors() - rcvbuf_errors_before;
  kill(child, SIGTERM);
  waitpid(child, nullptr, 0);

  std::vector<double> latency_us;
  latency_us.reserve(n);
  std::size_t unanswered = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (receiver.received_ns[i] == 0) {
      ++unanswered;
      continue;
    }
    latency_us.push_back(double(receiver.received_ns[i] - published_ns[i].load()) / 1000.0);
  }
  // A sample the monitor never received but bridged (held the previous input across a short gap) has a wall state
  // all the same: it is lost too. The few bridged states stay in the latency figures.
  const rockwatch::monitor_status_t& m = status.last;
  const std::size_t bridged = m.samples_bridged > 0 ? static_cast<std::size_t>(m.samples_bridged) : 0;
  const std::size_t lost = unanswered + bridged;
  std::printf("rate %.0f Hz, batch %d, %zu samples: answered %zu, lost %zu (%.4f %%: %zu unanswered, %zu bridged), "
              "latency p50 %.1f us, p99 %.1f us, max %.1f us\n",
              rate_hz, batch, n, latency_us.size(), lost, 100.0 * double(lost) / double(n), unanswered, bridged,
              percentile(latency_us, 0.50), percentile(latency_us, 0.99), percentile(latency_us, 1.0));
  std::printf("  monitor: received %lld of %zu samples (%lld gaps, %lld bridged, %lld duplicates, %lld out of order, "
              "%lld late), processed %lld; subscriber (queue %d): %lld wall states, %lld duplicates; kernel drops: "
              "monitor socket %lld, subscriber socket %lld, Udp RcvbufErrors +%lld\n",
              static_cast<long long>(m.samples_received), n, static_cast<long long>(m.gaps),
              static_cast<long long>(m.samples_bridged), static_cast<long long>(m.duplicates),
              static_cast<long long>(m.out_of_order), static_cast<long long>(m.late),
              static_cast<long long>(m.samples_processed), queue, static_cast<long long>(receiver.states),
              static_cast<long long>(receiver.duplicates), monitor_kernel_drops, own_kernel_drops, rcvbuf_errors);
  // The monitor's summary: the last line of its stdout; its "timing" object, if any.
  std::ifstream summary_in(summary_path);
  std::string line, last;
  while (std::getline(summary_in, line)) {
    if (!line.empty()) last = line;
  }
  std::remove(summary_path);
  const std::size_t at = last.find("\"timing\":{");
  if (at != std::string::npos) {
    const std::size_t end = last.find('}', at);
    std::printf("  monitor timing: %s\n", last.substr(at + 9, end == std::string::npos ? std::string::npos : end - at - 8).c_str());
  } else if (!monitor_args.empty()) {
    std::printf("  monitor timing: none in its summary\n");
  }
  // With --forecast: what the forecasts cost and whether their rate held (its summary's "forecast" object).
  const std::size_t fat = last.find("\"forecast\":{");
  if (fat != std::string::npos) {
    const std::size_t end = last.find('}', fat);
    std::printf("  monitor forecast: %s\n",
                last.substr(fat + 11, end == std::string::npos ? std::string::npos : end - fat - 10).c_str());
  }
  return lost == 0 ? 0 : 3;
}
