// Where the monitor loop's input comes from (monitor_event_loop.hpp), behind one interface so that the loop —
// status timing, forecasts, shutdown, summary — is the same code whatever the input: the live monitor's own UDP
// receive path (udp_input_source.hpp), an LCM log replayed offline (log_replay_source.hpp), and the benchmark's
// liblcm subscription (tests/bench/lcm_input_source.hpp, built only there). Drake keeps its transport behind one
// interface and replays a log through the same one; this is that shape.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "datagram_input.hpp"
#include "rockwatch/firmware/multi_wall_monitor.hpp"

namespace rockwatch::monitor {

enum class InputPoll {
  ok,      // the wait ended: with messages handed to the sink, or none before the timeout
  ended,   // the input has nothing more (the end of a replayed log); a live input never ends
  failed,  // the wait or the receive failed; errno says why (EINTR: a signal interrupted it)
};

class InputSource {
 public:
  virtual ~InputSource() = default;
  // Waits up to timeout_ms for input and hands every message on the monitor's input channels to `sink`, each with
  // its receive time [µs since 1970-01-01 UTC]. A replay does not wait: it hands over one event and moves its clock
  // (monitor_clock.hpp) to the event after, so the loop schedules what is due before that one.
  virtual InputPoll poll(int timeout_ms, InputMessageSink& sink) = 0;
  // The summary's fields of this input: its receive path and counts, or a replay's logs and events.
  virtual void add_summary(nlohmann::json& summary) const = 0;
  // Why the input stopped by itself, for the summary's "stopped_by" ("end of log"); live inputs never do.
  virtual std::string end_reason() const { return "end of input"; }
};

// A live input as run_live starts it: opened before anything else (a socket that cannot be had is a usage error,
// nothing written yet), started once the walls run and the thread's timing is applied (liblcm's receive thread,
// started by its subscription, inherits the real-time policy and CPU).
class LiveInput : public InputSource {
 public:
  // Receives the input channels of `walls` from now on. False with *problem.
  virtual bool start(firmware::MultiWallMonitor& walls, std::string* problem) = 0;
  // SO_BUSY_POLL on the input's socket (--busy-poll-us). False with *problem when the input has no socket of its own.
  virtual bool set_busy_poll(int us, std::string* problem) = 0;
};

}  // namespace rockwatch::monitor
