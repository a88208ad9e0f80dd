// Latency from publishing a ground-acceleration sample to receiving the wall state that answers it, through a live
// rockwatch-monitor over LCM (UDP multicast on this machine, ttl=0), and loss (samples never answered).
// A timing program, not a test: figures go to docs/BENCHMARKS.md.
//
//   bench_monitor_latency MONITOR_EXE [--rate HZ] [--seconds S] [--batch N] [--lcm-url URL]
//
// It starts the monitor itself (--lcm-url, --rate), waits for its first status message, publishes from a second
// thread at absolute deadlines (CLOCK_MONOTONIC, TIMER_ABSTIME) — one ground_accel_t per sample, or one
// ground_accel_batch_t per N samples — and receives wall_state_t on the main thread. Latency of a sample = receive
// time of its wall_state_t − publish time of the message that carried it. Prints one line of figures.
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
#include <string>
#include <thread>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "rockwatch/ground_accel_batch_t.hpp"
#include "rockwatch/ground_accel_t.hpp"
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
    std::fprintf(stderr, "usage: %s MONITOR_EXE [--rate HZ] [--seconds S] [--batch N] [--lcm-url URL]\n", argv[0]);
    return 2;
  }
  const std::string monitor = argv[1];
  double rate_hz = 1000.0, seconds = 10.0;
  int batch = 1;
  std::string url = "udpm://239.255.76.67:7667?ttl=0";
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--rate") rate_hz = std::atof(value.c_str());
    else if (key == "--seconds") seconds = std::atof(value.c_str());
    else if (key == "--batch") batch = std::atoi(value.c_str());
    else if (key == "--lcm-url") url = value;
    else {
      std::fprintf(stderr, "unknown option %s\n", key.c_str());
      return 2;
    }
  }
  if (!(rate_hz > 0.0) || !(seconds > 0.0) || batch < 1 || batch > 50) {
    std::fprintf(stderr, "--rate and --seconds must be > 0, --batch in 1..50\n");
    return 2;
  }
  const auto n = static_cast<std::size_t>(std::llround(rate_hz * seconds));

  const std::string rate_text = std::to_string(rate_hz);
  const pid_t child = fork();
  if (child == 0) {
    if (std::freopen("/dev/null", "w", stdout) == nullptr) _exit(127);
    execl(monitor.c_str(), monitor.c_str(), "--lcm-url", url.c_str(), "--rate", rate_text.c_str(),
          static_cast<char*>(nullptr));
    _exit(127);
  }

  lcm::LCM rx(url);
  if (!rx.good()) {
    std::fprintf(stderr, "cannot open LCM at %s (multicast route on lo?)\n", url.c_str());
    kill(child, SIGTERM);
    return 1;
  }
  std::vector<std::atomic<std::int64_t>> published_ns(n);
  Receiver receiver;
  receiver.published_ns = &published_ns;
  receiver.received_ns.assign(n, 0);
  bool monitor_ready = false;
  struct Ready {
    bool* flag;
    void on_status(const lcm::ReceiveBuffer*, const std::string&) { *flag = true; }
  } ready{&monitor_ready};
  rx.subscribe("ROCKWATCH_WALL_STATE", &Receiver::on_state, &receiver);
  rx.subscribe("ROCKWATCH_STATUS", &Ready::on_status, &ready);
  const std::int64_t wait_until = monotonic_ns() + 5000000000LL;
  while (!monitor_ready && monotonic_ns() < wait_until) rx.handleTimeout(100);
  if (!monitor_ready) {
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
      const double ug = 0.5 * std::sin(2.0 * M_PI * 1.5 * double(i) / rate_hz);  // below the rocking threshold
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
          m.ug_mps2[k] = 0.5 * std::sin(2.0 * M_PI * 1.5 * double(i + std::size_t(k)) / rate_hz);
          published_ns[i + std::size_t(k)].store(now);
        }
        tx.publish("ROCKWATCH_ACCEL_BATCH", &m);
      }
    }
    done.store(true);
  });

  // Receive until the publisher is done and nothing has arrived for a second.
  for (;;) {
    rx.handleTimeout(50);
    if (done.load() && monotonic_ns() - receiver.last_receive_ns > 1000000000LL) break;
  }
  publisher.join();
  kill(child, SIGTERM);
  waitpid(child, nullptr, 0);

  std::vector<double> latency_us;
  latency_us.reserve(n);
  std::size_t lost = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (receiver.received_ns[i] == 0) {
      ++lost;
      continue;
    }
    latency_us.push_back(double(receiver.received_ns[i] - published_ns[i].load()) / 1000.0);
  }
  std::printf("rate %.0f Hz, batch %d, %zu samples: answered %zu, lost %zu (%.4f %%), latency p50 %.1f us, p99 %.1f us, "
              "max %.1f us\n",
              rate_hz, batch, n, latency_us.size(), lost, 100.0 * double(lost) / double(n),
              percentile(latency_us, 0.50), percentile(latency_us, 0.99), percentile(latency_us, 1.0));
  return lost == 0 ? 0 : 3;
}
