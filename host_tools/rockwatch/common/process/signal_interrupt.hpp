// Ctrl-C (SIGINT) and SIGTERM during a long command (study, replay, demo): instead of killing the process and losing
// the work done, the signal sets a cancel flag the command polls; a study finishes the analyses in flight, writes the
// finished ones and can be resumed, a replay or demo stops between messages and reports what was sent. A second
// signal acts as usual (the default action: the process ends).
#pragma once

#include <atomic>
#include <csignal>

namespace rockwatch::cli {

// Exit status of a command stopped by a signal: 128 + SIGINT, as shells report an interrupted command.
inline constexpr int kExitInterrupted = 130;

// Installs the handlers for its lifetime and restores the previous ones on destruction. One at a time.
class SignalInterrupt {
 public:
  SignalInterrupt();
  ~SignalInterrupt();
  SignalInterrupt(const SignalInterrupt&) = delete;
  SignalInterrupt& operator=(const SignalInterrupt&) = delete;

  // The flag the command polls (run_study, publish_stream); true once a signal arrived.
  const std::atomic<bool>* flag() const;
  bool interrupted() const;
  // The signal that arrived (SIGINT or SIGTERM), 0 before.
  int signal_number() const;

 private:
  struct sigaction old_int_ {};
  struct sigaction old_term_ {};
};

}  // namespace rockwatch::cli
