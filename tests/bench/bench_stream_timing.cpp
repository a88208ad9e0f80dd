// Loss and timing of a stream of ground_accel_t samples as a subscriber on this machine sees it: used to compare
// `rockwatch replay` with the stock `lcm-logplayer` playing the same samples (docs/BENCHMARKS.md). A timing
// program, not a test.
//
//   bench_stream_timing --expect N --rate HZ [--channel C] [--lcm-url URL] [--idle-s S] [--queue N] [--rx-buffer B]
//
// Receives until N samples have arrived or nothing arrived for S seconds (default 3) after the first one. Loss =
// samples whose seq never arrived. Timing deviation of sample i = (receive time − receive time of the first sample)
// − (seq_i − seq_first)/rate, with the median removed (a constant offset is not an error); prints p50, p99 and max
// of |deviation|.
// The subscription holds up to --queue N unhandled messages (default 100000; LCM's own default, 30, made a subscriber
// that fell 30 ms behind at 1 kHz drop samples inside liblcm: --queue 30 shows it); a udpm:// URL without
// recv_buf_size gets recv_buf_size=B (--rx-buffer, default 2097152; 0 = the URL as given).
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "rockwatch/ground_accel_t.hpp"

namespace {

std::int64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::int64_t{ts.tv_sec} * 1000000000 + ts.tv_nsec;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const auto i = static_cast<std::size_t>(std::ceil(p * double(v.size()))) - 1;
  return v[std::min(i, v.size() - 1)];
}

struct Stream {
  std::vector<std::int64_t> received_ns;  // by seq; 0 = not received
  std::int64_t first_ns = 0, last_ns = 0, count = 0, duplicates = 0, out_of_range = 0;
  void on_sample(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    rockwatch::ground_accel_t m;
    if (m.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) < 0) return;
    const std::int64_t now = monotonic_ns();
    if (count == 0) first_ns = now;
    last_ns = now;
    ++count;
    if (m.seq < 0 || m.seq >= static_cast<std::int64_t>(received_ns.size())) {
      ++out_of_range;
      return;
    }
    auto& slot = received_ns[static_cast<std::size_t>(m.seq)];
    if (slot != 0) ++duplicates;
    else slot = now;
  }
};

}  // namespace

int main(int argc, char** argv) {
  std::size_t expect = 0;
  double rate_hz = 0.0, idle_s = 3.0;
  std::string channel = "ROCKWATCH_ACCEL", url = "udpm://239.255.76.67:7667?ttl=0";
  int queue = 100000;
  long long rx_buffer = 2097152;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--expect") expect = static_cast<std::size_t>(std::atoll(value.c_str()));
    else if (key == "--rate") rate_hz = std::atof(value.c_str());
    else if (key == "--channel") channel = value;
    else if (key == "--lcm-url") url = value;
    else if (key == "--idle-s") idle_s = std::atof(value.c_str());
    else if (key == "--queue") queue = std::atoi(value.c_str());
    else if (key == "--rx-buffer") rx_buffer = std::atoll(value.c_str());
    else {
      std::fprintf(stderr, "unknown option %s\n", key.c_str());
      return 2;
    }
  }
  if (expect == 0 || !(rate_hz > 0.0) || queue < 0 || rx_buffer < 0) {
    std::fprintf(stderr,
                 "usage: %s --expect N --rate HZ [--channel C] [--lcm-url URL] [--idle-s S] [--queue N] "
                 "[--rx-buffer BYTES]\n",
                 argv[0]);
    return 2;
  }
  if (rx_buffer > 0 && url.rfind("udpm://", 0) == 0 && url.find("recv_buf_size=") == std::string::npos) {
    url += (url.find('?') == std::string::npos ? "?" : "&") + std::string("recv_buf_size=") + std::to_string(rx_buffer);
  }
  lcm::LCM lcm(url);
  if (!lcm.good()) {
    std::fprintf(stderr, "cannot open LCM at %s\n", url.c_str());
    return 1;
  }
  Stream s;
  s.received_ns.assign(expect, 0);
  lcm::Subscription* subscription = lcm.subscribe(channel, &Stream::on_sample, &s);
  if (subscription != nullptr) subscription->setQueueCapacity(queue);
  std::fprintf(stderr, "listening on %s for %zu samples\n", channel.c_str(), expect);
  const auto idle_ns = static_cast<std::int64_t>(idle_s * 1e9);
  const std::int64_t give_up = monotonic_ns() + 120000000000LL;
  while (monotonic_ns() < give_up) {
    lcm.handleTimeout(50);
    if (s.count >= static_cast<std::int64_t>(expect)) break;
    if (s.count > 0 && monotonic_ns() - s.last_ns > idle_ns) break;
  }
  std::vector<double> offsets_us;
  std::size_t lost = 0;
  std::int64_t first_seq = -1;
  for (std::size_t i = 0; i < expect; ++i) {
    if (s.received_ns[i] == 0) {
      ++lost;
      continue;
    }
    if (first_seq < 0) first_seq = static_cast<std::int64_t>(i);
    const double ideal_ns = double(static_cast<std::int64_t>(i) - first_seq) * 1e9 / rate_hz;
    offsets_us.push_back((double(s.received_ns[i] - s.received_ns[static_cast<std::size_t>(first_seq)]) - ideal_ns) /
                         1000.0);
  }
  const double median = percentile(offsets_us, 0.5);
  std::vector<double> deviation_us;
  for (double o : offsets_us) deviation_us.push_back(std::fabs(o - median));
  std::printf("%s: expected %zu at %.0f Hz, received %lld, lost %zu (%.4f %%), duplicates %lld; timing deviation "
              "p50 %.1f us, p99 %.1f us, max %.1f us\n",
              channel.c_str(), expect, rate_hz, static_cast<long long>(s.count), lost,
              100.0 * double(lost) / double(expect), static_cast<long long>(s.duplicates),
              percentile(deviation_us, 0.5), percentile(deviation_us, 0.99), percentile(deviation_us, 1.0));
  return 0;
}
