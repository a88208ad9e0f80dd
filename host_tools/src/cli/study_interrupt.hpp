// Ctrl-C (SIGINT) and SIGTERM during a `rockwatch study`: instead of killing the process and losing every finished
// analysis, the signal sets the batch engine's cancel flag; the analyses in flight finish, the finished ones are
// written, and the study can be resumed. A second signal acts as usual (the default action: the process ends).
#pragma once

#include <atomic>
#include <csignal>

namespace rockwatch::cli {

// Exit status of a study stopped by a signal: 128 + SIGINT, as shells report an interrupted command.
inline constexpr int kExitInterrupted = 130;

// Installs the handlers for its lifetime and restores the previous ones on destruction. One at a time.
class StudyInterrupt {
 public:
  StudyInterrupt();
  ~StudyInterrupt();
  StudyInterrupt(const StudyInterrupt&) = delete;
  StudyInterrupt& operator=(const StudyInterrupt&) = delete;

  // The flag run_study polls; true once a signal arrived.
  const std::atomic<bool>* flag() const;
  bool interrupted() const;
  // The signal that arrived (SIGINT or SIGTERM), 0 before.
  int signal_number() const;

 private:
  struct sigaction old_int_ {};
  struct sigaction old_term_ {};
};

}  // namespace rockwatch::cli
