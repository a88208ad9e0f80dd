// rockwatch-monitor as a child process of `rockwatch demo`: where it is, starting it with its output in files (no
// pipe to drain while the replay runs), knowing when it listens, and stopping it the way a supervisor does (SIGINT,
// after which it prints its summary).
#pragma once

#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

namespace rockwatch::cli {

inline constexpr const char* kMonitorVariable = "ROCKWATCH_MONITOR";
inline constexpr const char* kMonitorName = "rockwatch-monitor";

struct MonitorLocation {
  std::string path;
  std::string found_by;  // "--monitor", "$ROCKWATCH_MONITOR", "next to rockwatch"
};

// --monitor, else $ROCKWATCH_MONITOR, else rockwatch-monitor in the directory of the running executable. Throws
// UsageError saying where it looked and how to build it.
MonitorLocation find_monitor(const std::optional<std::string>& option);

class MonitorProcess {
 public:
  // Starts `path` with `arguments`, stdin /dev/null, stdout and stderr into the files named. Throws
  // std::runtime_error when it cannot be started.
  MonitorProcess(const std::string& path, const std::vector<std::string>& arguments, const std::string& out_path,
                 const std::string& err_path);
  ~MonitorProcess();  // kills a monitor still running (SIGKILL) and reaps it
  MonitorProcess(const MonitorProcess&) = delete;
  MonitorProcess& operator=(const MonitorProcess&) = delete;

  pid_t pid() const { return pid_; }
  // False once it has ended (reaped; exit_text() says how).
  bool running();
  // Waits until `err_path` contains `marker` (the monitor's "listening on" line) or `timeout_s` passed, polling.
  // Returns true when the marker appeared; false when it did not (still running: proceed with care) or when the
  // process ended (running() is then false).
  bool wait_for_marker(const std::string& marker, double timeout_s);
  // SIGINT, then up to `timeout_s` for it to end, then SIGKILL. Returns true when it ended by itself.
  bool stop(double timeout_s);
  // "exit status 0", "killed by signal 9", or "running".
  std::string exit_text() const;
  std::optional<int> exit_status() const;

 private:
  bool reap(bool block);
  pid_t pid_ = -1;
  std::string err_path_;
  bool ended_ = false;
  int wait_status_ = 0;
};

// The whole content of a file, or empty when it cannot be read.
std::string file_text(const std::string& path);

}  // namespace rockwatch::cli
