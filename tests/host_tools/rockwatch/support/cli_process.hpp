// Runs the built `rockwatch` (and other programs: the monitor, the log generator) as a separate process, the way a
// user or a script does, and captures what it printed. The process handling itself is rockwatch_process.
#pragma once

#include <sys/types.h>  // pid_t

#include <optional>
#include <string>
#include <vector>

#include "rockwatch/process/child_process.hpp"

namespace rockwatch::test {

using ProcessResult = process::Result;  // exit_status (when signal == 0), signal, out, err

// Runs `path` with `arguments` (argv[1] onwards), stdin from /dev/null, to its end (kProcessDeadline_s). Throws
// std::runtime_error when the process cannot be started or hangs.
ProcessResult run_program(const std::string& path, const std::vector<std::string>& arguments);

// Starts `path` without waiting for it, stdin from /dev/null, stdout and stderr to the files named. Throws
// std::runtime_error when the process cannot be started.
pid_t spawn_program(const std::string& path, const std::vector<std::string>& arguments, const std::string& out_path,
                    const std::string& err_path);

// Runs ROCKWATCH_CLI_PATH with `arguments` (argv[1] onwards), stdin from /dev/null. Throws std::runtime_error when
// the process cannot be started.
ProcessResult run_rockwatch(const std::vector<std::string>& arguments);

// Starts ROCKWATCH_CLI_PATH without waiting for it, stdin from /dev/null, stdout and stderr to the files named, so a
// test can watch or signal it mid-run ("/dev/null" discards a stream). Throws std::runtime_error when the process
// cannot be started.
pid_t spawn_rockwatch(const std::vector<std::string>& arguments, const std::string& out_path,
                      const std::string& err_path);

// No tool may hang: every process a test waits for has a deadline (far above any tool's run time in the tests, also
// under the sanitizers); past it the process is killed and the test fails naming the hang.
inline constexpr double kProcessDeadline_s = 150.0;

// Waits for `pid` to end and returns its waitpid status. Throws std::runtime_error when waitpid fails or when the
// process is still running after deadline_s (it is then killed with SIGKILL).
int wait_status(pid_t pid, double deadline_s = kProcessDeadline_s);

// Sets (or clears, with nullptr) an environment variable for one test and restores it afterwards. The processes a
// test starts inherit the test's environment, so this also sets their variables.
class EnvOverride {
 public:
  EnvOverride(const char* name, const char* value);
  ~EnvOverride();
  EnvOverride(const EnvOverride&) = delete;
  EnvOverride& operator=(const EnvOverride&) = delete;

 private:
  std::string name_;
  std::optional<std::string> old_;
};

// A fresh directory under the system temporary directory, removed with its contents on destruction.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

}  // namespace rockwatch::test
