// Starting another program and waiting for it: `rockwatch demo` starts rockwatch-monitor, and the tests run
// `rockwatch`, the monitor and the log generator as a user or a script does. One implementation (posix_spawn, the
// streams to files, waitpid with a deadline) so every caller gets the same guarantees: no shell, no pipe that can
// deadlock on a chatty child, no wait without an end.
#pragma once

#include <sys/types.h>  // pid_t

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace rockwatch::process {

struct Command {
  std::string program;                 // a path: no PATH search
  std::vector<std::string> arguments;  // argv[1] onwards (argv[0] is the program)
  // Changes to this process's environment for the child: NAME set to the value, or removed with nullopt.
  std::vector<std::pair<std::string, std::optional<std::string>>> environment;
  std::string stdin_path = "/dev/null";
  std::string stdout_path = "/dev/null";  // created or truncated; "/dev/null" discards
  std::string stderr_path = "/dev/null";
  unsigned create_mode = 0644;  // the permissions of an output file the child's start creates
  // The child starts with an empty signal mask and every signal at its default action, whatever this process set
  // (a program that installs its own handlers, such as the monitor, then behaves as when started from a shell).
  bool default_signals = false;
};

// Starts the command without waiting for it. Throws std::runtime_error ("cannot start PROGRAM: reason").
pid_t start(const Command& command);

// As start, for callers that report a failure themselves: 0 and `pid` set, or the error number (posix_spawn's).
int try_start(const Command& command, pid_t& pid);

// The waitpid status of `pid` once it has ended, nullopt while it runs. A pid that is not (or no longer) our child
// counts as ended, with status 0.
std::optional<int> poll_status(pid_t pid);

// Waits for `pid` to end and returns its waitpid status. Throws std::runtime_error when waitpid fails or when the
// process is still running after deadline_s: it is then killed with SIGKILL and reaped ("a hang is a defect").
int wait_status(pid_t pid, double deadline_s);

// Waits for `pid` to end, however long it takes, and returns its waitpid status. Throws std::runtime_error
// ("waitpid: reason") when waitpid fails.
int wait_status(pid_t pid);

// Sends `signal_number` to `pid`; false when the process no longer exists.
bool send_signal(pid_t pid, int signal_number);

// How a process ended, from its waitpid status.
struct Exit {
  int exit_status = -1;  // valid when signal == 0
  int signal = 0;        // the signal that killed the process, 0 when it exited
};
Exit decode_status(int status);

// What a finished process printed, and how it ended.
struct Result {
  int exit_status = -1;  // valid when signal == 0
  int signal = 0;        // the signal that killed the process, 0 when it exited
  std::string out;       // stdout
  std::string err;       // stderr
};

// Runs the command to its end (wait_status with deadline_s) and captures stdout and stderr, through files in a
// temporary directory of its own (command.stdout_path and stderr_path are ignored). Throws as start and wait_status.
Result run(Command command, double deadline_s);

}  // namespace rockwatch::process
