#include "demo/demo_monitor.hpp"

#include <signal.h>
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

#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"
#include "rockwatch/process/child_process.hpp"

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
    if (!is_executable(*option)) throw UsageError("--monitor " + options::quoted(*option) + " is not an executable file");
    return {*option, "--monitor"};
  }
  const char* variable = std::getenv(kMonitorVariable);
  if (variable != nullptr && *variable != '\0') {
    if (!is_executable(variable)) {
      throw UsageError(std::string("$") + kMonitorVariable + " is " + options::quoted(variable) +
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
  process::Command command;
  command.program = path;
  command.arguments = arguments;
  command.stdout_path = out_path;
  command.stderr_path = err_path;
  command.default_signals = true;  // the monitor's own handlers then work as when started from a shell
  pid_ = process::start(command);
}

MonitorProcess::~MonitorProcess() {
  if (pid_ > 0 && !ended_) {
    process::send_signal(pid_, SIGKILL);
    reap(true);
  }
}

bool MonitorProcess::reap(bool block) {
  if (ended_) return true;
  std::optional<int> status = process::poll_status(pid_);
  while (block && !status) {
    sleep_ms(2);
    status = process::poll_status(pid_);
  }
  if (status) {
    ended_ = true;
    wait_status_ = *status;
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
  process::send_signal(pid_, SIGINT);
  const long steps = static_cast<long>(timeout_s * 100.0);
  for (long k = 0; k <= steps; ++k) {
    if (!running()) return true;
    sleep_ms(10);
  }
  process::send_signal(pid_, SIGKILL);
  reap(true);
  return false;
}

std::optional<int> MonitorProcess::exit_status() const {
  if (!ended_) return std::nullopt;
  const process::Exit e = process::decode_status(wait_status_);
  if (e.signal != 0 || e.exit_status < 0) return std::nullopt;
  return e.exit_status;
}

std::string MonitorProcess::exit_text() const {
  if (!ended_) return "running";
  const process::Exit e = process::decode_status(wait_status_);
  if (e.signal != 0) return "killed by signal " + std::to_string(e.signal);
  if (e.exit_status >= 0) return "exit status " + std::to_string(e.exit_status);
  return "ended";
}

}  // namespace rockwatch::cli
