#include "monitor_event_loop.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "monitor_run.hpp"
#include "stop_signals.hpp"

namespace rockwatch::monitor {

namespace {

constexpr std::int64_t kSecondUs = 1000000;
constexpr std::int64_t kLongestWaitMs = 100;     // a live wait: SIGINT/SIGTERM are seen within it
constexpr int kMostReceiveFailuresInARow = 100;  // then the socket is taken as broken: exit, for a supervisor

}  // namespace

LoopOutcome run_monitor_loop(InputSource& input, MonitorClock& clock, firmware::MultiWallMonitor& walls,
                             InputMessageSink& sink, const LoopServices& services, std::ostream& err) {
  LoopOutcome outcome;
  const auto status_at = [&](std::int64_t at_us) {
    walls.publish_status(clock.enter(at_us));
    ++outcome.statuses;
  };
  // The first status as soon as the clock has a time (a live monitor stopped during its setup still publishes its
  // first and last); a replay of an empty log publishes nothing at all.
  const bool started = clock.has_time();
  std::int64_t start_us = 0, next_status_us = 0;
  if (started) {
    status_at(clock.now_us());
    if (services.on_started && !services.on_started()) {
      outcome.aborted = true;
      return outcome;
    }
    start_us = clock.now_us();
    next_status_us = start_us + kSecondUs;
  }
  int failures_in_a_row = 0;
  while (!StopSignals::stopped()) {
    std::int64_t wait_ms = kLongestWaitMs;
    if (started) {
      const std::int64_t now_us = clock.now_us();
      if (services.service != nullptr) services.service->feed(now_us * 1000);
      while (now_us >= next_status_us) {
        if (clock.catches_up() && now_us - next_status_us >= 60 * kSecondUs) {
          next_status_us += (now_us - next_status_us) / kSecondUs * kSecondUs;  // a gap of a minute: one status
        }
        if (services.log != nullptr) services.log->flush(walls);  // before the status, which then carries a failure
        status_at(next_status_us);
        next_status_us += kSecondUs;
        if (!clock.catches_up() && next_status_us <= now_us) next_status_us = now_us + kSecondUs;
      }
      if (services.forecasts != nullptr) services.forecasts->run_due(now_us);
      wait_ms = std::clamp<std::int64_t>((next_status_us - now_us + 999) / 1000, 0, kLongestWaitMs);
    }
    errno = 0;
    const InputPoll poll = input.poll(static_cast<int>(wait_ms), sink);
    if (poll == InputPoll::ok) {
      failures_in_a_row = 0;
      continue;
    }
    if (poll == InputPoll::ended) break;
    if (StopSignals::stopped()) break;
    if (errno == EINTR) continue;
    if (++failures_in_a_row > kMostReceiveFailuresInARow) {
      err << kMessagePrefix << "error: the receive socket failed " << failures_in_a_row << " times in a row ("
          << std::strerror(errno) << "); stopping\n";
      outcome.receive_failed = true;
      break;
    }
  }
  if (services.service != nullptr) services.service->stopping();
  if (services.forecasts != nullptr) services.forecasts->stop();
  if (started) {
    // The engine's carry-over samples are published (at the end's time) before the last status.
    const std::int64_t end_us = clock.now_us();
    clock.enter(end_us);
    walls.finish_pending();
    if (services.log != nullptr) services.log->drain(walls);
    status_at(end_us);
    outcome.run_time_us = clock.now_us() - start_us;
  }
  outcome.stopped = StopSignals::stopped();
  if (outcome.receive_failed) outcome.stopped_by = "receive failure";
  else if (outcome.stopped) outcome.stopped_by = StopSignals::stopped_by();
  else outcome.stopped_by = input.end_reason();
  return outcome;
}

}  // namespace rockwatch::monitor
