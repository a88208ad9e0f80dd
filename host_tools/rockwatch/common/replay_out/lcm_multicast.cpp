#include "common/replay_out/lcm_multicast.hpp"

#include <time.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

#include <lcm/lcm-cpp.hpp>

namespace rockwatch::cli {

namespace {

std::int64_t clock_ns(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1000000000 + static_cast<std::int64_t>(ts.tv_nsec);
}

struct ProbeState {
  std::string payload;
  bool received = false;
};

void on_probe(const lcm::ReceiveBuffer* rbuf, const std::string& /*channel*/, ProbeState* state) {
  const auto size = static_cast<std::size_t>(rbuf->data_size);
  if (size == state->payload.size() && std::memcmp(rbuf->data, state->payload.data(), size) == 0) {
    state->received = true;
  }
}

// Standard error redirected into a temporary file for the lifetime of the object; text() reads what was written.
class CapturedStderr {
 public:
  CapturedStderr() {
    std::fflush(stderr);
    file_ = std::tmpfile();
    saved_ = file_ != nullptr ? dup(STDERR_FILENO) : -1;
    if (saved_ >= 0) dup2(fileno(file_), STDERR_FILENO);
  }
  ~CapturedStderr() {
    restore();
    if (file_ != nullptr) std::fclose(file_);
  }
  CapturedStderr(const CapturedStderr&) = delete;
  CapturedStderr& operator=(const CapturedStderr&) = delete;

  std::string first_line() {
    restore();
    if (file_ == nullptr) return {};
    std::rewind(file_);
    char line[256] = {};
    while (std::fgets(line, sizeof line, file_) != nullptr) {
      std::string text(line);
      while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
      if (!text.empty()) return text;
    }
    return {};
  }

 private:
  void restore() {
    if (saved_ < 0) return;
    std::fflush(stderr);
    dup2(saved_, STDERR_FILENO);
    close(saved_);
    saved_ = -1;
  }
  std::FILE* file_ = nullptr;
  int saved_ = -1;
};

}  // namespace

std::unique_ptr<lcm::LCM> open_lcm(const std::string& url, std::string& problem) {
  CapturedStderr captured;
  auto lcm = std::make_unique<lcm::LCM>(url);
  if (lcm->good()) return lcm;
  const std::string said = captured.first_line();
  problem = "LCM could not start with " + url +
            (said.empty() ? std::string(" (no multicast route, or a malformed URL)") : " (" + said + ")");
  return nullptr;
}

std::int64_t realtime_utime() { return clock_ns(CLOCK_REALTIME) / 1000; }

std::int64_t monotonic_ns() { return clock_ns(CLOCK_MONOTONIC); }

MulticastProbe probe_multicast(const std::string& url, int timeout_ms) {
  static std::atomic<int> probes{0};
  MulticastProbe result;
  const std::unique_ptr<lcm::LCM> opened = open_lcm(url, result.problem);
  if (!opened) return result;
  lcm::LCM& lcm = *opened;
  const std::string channel =
      "ROCKWATCH_PROBE_" + std::to_string(static_cast<long>(getpid())) + "_" + std::to_string(probes.fetch_add(1));
  ProbeState state;
  state.payload = channel + "@" + std::to_string(monotonic_ns());
  lcm::Subscription* subscription = lcm.subscribeFunction(channel, &on_probe, &state);
  if (subscription == nullptr) {
    result.problem = "LCM could not subscribe on " + url + " (could not join the multicast group)";
    return result;
  }
  const std::int64_t start_ns = monotonic_ns();
  errno = 0;
  if (lcm.publish(channel, state.payload.data(), static_cast<unsigned int>(state.payload.size())) != 0) {
    const int code = errno;
    result.problem =
        "LCM could not send on " + url + (code != 0 ? std::string(": ") + std::strerror(code) : std::string());
    lcm.unsubscribe(subscription);
    return result;
  }
  const std::int64_t deadline_ns = start_ns + static_cast<std::int64_t>(timeout_ms) * 1000000;
  while (!state.received) {
    const std::int64_t left_ns = deadline_ns - monotonic_ns();
    if (left_ns <= 0) break;
    const int rc = lcm.handleTimeout(static_cast<int>((left_ns + 999999) / 1000000));
    if (rc < 0 && errno != EINTR) break;
  }
  lcm.unsubscribe(subscription);
  if (state.received) {
    result.ok = true;
    result.round_trip_ms = static_cast<double>(monotonic_ns() - start_ns) * 1e-6;
  } else {
    result.problem = "a message sent on " + url + " did not come back within " + std::to_string(timeout_ms) +
                     " ms (multicast is not delivered on this machine)";
  }
  return result;
}

std::string multicast_help(const std::string& url, const MulticastProbe& probe) {
  return "LCM multicast does not work on this machine: " + probe.problem +
         ".\n"
         "The monitor and the replay talk over UDP multicast that never leaves this machine (" +
         url +
         ", ttl=0).\n"
         "It needs a route for multicast and the loopback interface accepting it. As root (or with sudo):\n"
         "  sudo ip link set lo multicast on\n"
         "  sudo ip route add 224.0.0.0/4 dev lo\n"
         "then run the command again (scripts/demo.sh does both when run as root and the route is missing).\n"
         "In a container, the two commands need NET_ADMIN (docker run --cap-add NET_ADMIN) or --network host.\n"
         "A machine with a network connection usually has a default route that carries it already; check with\n"
         "  ip route get 239.255.76.67\n";
}

}  // namespace rockwatch::cli
