// SIGINT / SIGTERM stop the monitor cleanly: a flag the monitor loop checks every pass (live at least every 100 ms,
// a replay before every event), then the last status and the summary. SIGPIPE is ignored meanwhile.
#pragma once

#include <csignal>
#include <string>

namespace rockwatch::monitor {

// Installs the handlers for its lifetime (one at a time: the flag is the process's) and restores the old ones.
class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  static bool stopped();
  // "SIGINT", "SIGTERM" or "signal N": the summary's "stopped_by".
  static std::string stopped_by();

 private:
  struct sigaction old_int_ {};
  struct sigaction old_term_ {};
  struct sigaction old_pipe_ {};
};

}  // namespace rockwatch::monitor
