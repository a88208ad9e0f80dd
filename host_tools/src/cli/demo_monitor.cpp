#include "demo_monitor.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "option_values.hpp"
#include "usage_error.hpp"

extern char** environ;

namespace rockwatch::cli {

namespace {

bool is_executable(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec) && access(path.c_str(), X_OK) == 0;
}

std::string executable_dir() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : exe.parent_path().string();
}

void sleep_ms(long ms) {
  timespec ts{};
  ts.tv_sec = ms / 1000;
  ts.tv_nsec = (ms % 1000) * 1000000L;
  nanosleep(&ts, nullptr);
}

}  // namespace

std::string file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

MonitorLocation find_monitor(const std::optional<std::string>& option) {
  if (option) {
    if (!is_executable(*option)) throw UsageError("--monitor " + cli::quoted(*option) + " is not an executable file");
    return {*option, "--monitor"};
  }
  const char* variable = std::getenv(kMonitorVariable);
  if (variable != nullptr && *variable != '\0') {
    if (!is_executable(variable)) {
      throw UsageError(std::string("$") + kMonitorVariable + " is " + cli::quoted(variable) +
                       ", which is not an executable file: point it at rockwatch-monitor, or unset it");
    }
    return {variable, std::string("$") + kMonitorVariable};
  }
  const std::string dir = executable_dir();
  const std::string beside = (std::filesystem::path(dir) / kMonitorName).string();
  if (!dir.empty() && is_executable(beside)) return {beside, "next to rockwatch"};
  throw UsageError(std::string(kMonitorName) + " was not found (looked for $" + kMonitorVariable + ", not set, and " +
                   (dir.empty() ? std::string("the directory of rockwatch, unknown") : beside) +
                   "): build it (`cmake --build build/release`, or ./scripts/demo.sh, builds it next to rockwatch), or "
                   "give --monitor PATH or set $" +
                   kMonitorVariable);
}

MonitorProcess::MonitorProcess(const std::string& path, const std::vector<std::string>& arguments,
                               const std::string& out_path, const std::string& err_path)
    : err_path_(err_path) {
  std::vector<std::string> args{path};
  args.insert(args.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  // The monitor gets the default signal dispositions and an empty mask, whatever this process has.
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t none, all;
  sigemptyset(&none);
  sigfillset(&all);
  posix_spawnattr_setsigmask(&attributes, &none);
  posix_spawnattr_setsigdefault(&attributes, &all);
  posix_spawnattr_setflags(&attributes, static_cast<short>(POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF));
  const int error = posix_spawn(&pid_, path.c_str(), &actions, &attributes, argv.data(), environ);
  posix_spawnattr_destroy(&attributes);
  posix_spawn_file_actions_destroy(&actions);
  if (error != 0) throw std::runtime_error("cannot start " + path + ": " + std::strerror(error));
}

MonitorProcess::~MonitorProcess() {
  if (pid_ > 0 && !ended_) {
    kill(pid_, SIGKILL);
    reap(true);
  }
}

bool MonitorProcess::reap(bool block) {
  if (ended_) return true;
  int status = 0;
  pid_t r = 0;
  do {
    r = waitpid(pid_, &status, block ? 0 : WNOHANG);
  } while (r < 0 && errno == EINTR);
  if (r == pid_) {
    ended_ = true;
    wait_status_ = status;
  } else if (r < 0) {
    ended_ = true;  // not our child any more (ECHILD): nothing to wait for
    wait_status_ = 0;
  }
  return ended_;
}

bool MonitorProcess::running() { return !reap(false); }

bool MonitorProcess::wait_for_marker(const std::string& marker, double timeout_s) {
  const long steps = static_cast<long>(timeout_s * 100.0);
  for (long k = 0; k <= steps; ++k) {
    if (file_text(err_path_).find(marker) != std::string::npos) return true;
    if (!running()) return false;
    sleep_ms(10);
  }
  return false;
}

bool MonitorProcess::stop(double timeout_s) {
  if (!running()) return true;
  kill(pid_, SIGINT);
  const long steps = static_cast<long>(timeout_s * 100.0);
  for (long k = 0; k <= steps; ++k) {
    if (!running()) return true;
    sleep_ms(10);
  }
  kill(pid_, SIGKILL);
  reap(true);
  return false;
}

std::optional<int> MonitorProcess::exit_status() const {
  if (!ended_ || !WIFEXITED(wait_status_)) return std::nullopt;
  return WEXITSTATUS(wait_status_);
}

std::string MonitorProcess::exit_text() const {
  if (!ended_) return "running";
  if (WIFEXITED(wait_status_)) return "exit status " + std::to_string(WEXITSTATUS(wait_status_));
  if (WIFSIGNALED(wait_status_)) return "killed by signal " + std::to_string(WTERMSIG(wait_status_));
  return "ended";
}

}  // namespace rockwatch::cli
