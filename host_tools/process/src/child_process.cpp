#include "rockwatch/process/child_process.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

extern char** environ;

namespace rockwatch::process {

namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// This process's environment with the command's changes applied, as "NAME=value" strings.
std::vector<std::string> child_environment(const Command& command) {
  std::vector<std::string> entries;
  for (char** e = environ; e != nullptr && *e != nullptr; ++e) entries.emplace_back(*e);
  for (const auto& [name, value] : command.environment) {
    const std::string prefix = name + "=";
    std::vector<std::string> kept;
    for (std::string& entry : entries) {
      if (entry.compare(0, prefix.size(), prefix) != 0) kept.push_back(std::move(entry));
    }
    entries = std::move(kept);
    if (value) entries.push_back(prefix + *value);
  }
  return entries;
}

std::vector<char*> pointers(std::vector<std::string>& strings) {
  std::vector<char*> p;
  for (std::string& s : strings) p.push_back(s.data());
  p.push_back(nullptr);
  return p;
}

// A fresh directory under the system temporary directory, removed with its contents on destruction.
class CaptureDir {
 public:
  CaptureDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "rockwatch_process.XXXXXX").string();
    std::vector<char> buffer(pattern.begin(), pattern.end());
    buffer.push_back('\0');
    if (mkdtemp(buffer.data()) == nullptr) throw std::runtime_error(std::string("mkdtemp: ") + std::strerror(errno));
    path_ = buffer.data();
  }
  ~CaptureDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  CaptureDir(const CaptureDir&) = delete;
  CaptureDir& operator=(const CaptureDir&) = delete;
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

}  // namespace

int try_start(const Command& command, pid_t& pid) {
  std::vector<std::string> args{command.program};
  args.insert(args.end(), command.arguments.begin(), command.arguments.end());
  std::vector<char*> argv = pointers(args);
  std::vector<std::string> env_strings;
  char** envp = environ;
  std::vector<char*> env_pointers;
  if (!command.environment.empty()) {
    env_strings = child_environment(command);
    env_pointers = pointers(env_strings);
    envp = env_pointers.data();
  }

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, command.stdin_path.c_str(), O_RDONLY, 0);
  const auto mode = static_cast<mode_t>(command.create_mode);
  posix_spawn_file_actions_addopen(&actions, 1, command.stdout_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, mode);
  posix_spawn_file_actions_addopen(&actions, 2, command.stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, mode);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  if (command.default_signals) {
    sigset_t none, all;
    sigemptyset(&none);
    sigfillset(&all);
    posix_spawnattr_setsigmask(&attributes, &none);
    posix_spawnattr_setsigdefault(&attributes, &all);
    posix_spawnattr_setflags(&attributes, static_cast<short>(POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF));
  }
  const int error = posix_spawn(&pid, command.program.c_str(), &actions, &attributes, argv.data(), envp);
  posix_spawnattr_destroy(&attributes);
  posix_spawn_file_actions_destroy(&actions);
  return error;
}

pid_t start(const Command& command) {
  pid_t pid = 0;
  const int error = try_start(command, pid);
  if (error != 0) throw std::runtime_error("cannot start " + command.program + ": " + std::strerror(error));
  return pid;
}

std::optional<int> poll_status(pid_t pid) {
  int status = 0;
  pid_t r = 0;
  do {
    r = waitpid(pid, &status, WNOHANG);
  } while (r < 0 && errno == EINTR);
  if (r == pid) return status;
  if (r < 0) return 0;  // not our child (ECHILD): nothing to wait for
  return std::nullopt;
}

int wait_status(pid_t pid) {
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw std::runtime_error(std::string("waitpid: ") + std::strerror(errno));
  }
  return status;
}

int wait_status(pid_t pid, double deadline_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(deadline_s);
  int status = 0;
  for (;;) {
    const pid_t r = waitpid(pid, &status, WNOHANG);
    if (r == pid) return status;
    if (r < 0 && errno != EINTR) throw std::runtime_error(std::string("waitpid: ") + std::strerror(errno));
    if (std::chrono::steady_clock::now() >= deadline) {
      kill(pid, SIGKILL);
      while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      std::ostringstream message;
      message << "process " << pid << " did not end within " << deadline_s << " s: killed (a hang is a defect)";
      throw std::runtime_error(message.str());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

bool send_signal(pid_t pid, int signal_number) { return kill(pid, signal_number) == 0; }

Exit decode_status(int status) {
  Exit e;
  if (WIFEXITED(status)) e.exit_status = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) e.signal = WTERMSIG(status);
  return e;
}

// stdout and stderr go to files rather than pipes: no reader thread, and no deadlock when the child writes a lot.
Result run(Command command, double deadline_s) {
  const CaptureDir capture;
  command.stdout_path = capture.file("stdout");
  command.stderr_path = capture.file("stderr");
  const Exit e = decode_status(wait_status(start(command), deadline_s));
  Result result;
  result.exit_status = e.exit_status;
  result.signal = e.signal;
  result.out = slurp(command.stdout_path);
  result.err = slurp(command.stderr_path);
  return result;
}

}  // namespace rockwatch::process
