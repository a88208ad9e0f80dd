#include "cli_process.hpp"

#include <stdlib.h>  // setenv, unsetenv (POSIX)

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

namespace rockwatch::test {

TempDir::TempDir() {
  std::string pattern = (std::filesystem::temp_directory_path() / "rockwatch_test_cli.XXXXXX").string();
  std::vector<char> buffer(pattern.begin(), pattern.end());
  buffer.push_back('\0');
  if (mkdtemp(buffer.data()) == nullptr) throw std::runtime_error(std::string("mkdtemp: ") + std::strerror(errno));
  path_ = buffer.data();
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

pid_t spawn_program(const std::string& path, const std::vector<std::string>& arguments, const std::string& out_path,
                    const std::string& err_path) {
  process::Command command;
  command.program = path;
  command.arguments = arguments;
  command.stdout_path = out_path;
  command.stderr_path = err_path;
  return process::start(command);
}

ProcessResult run_program(const std::string& path, const std::vector<std::string>& arguments) {
  process::Command command;
  command.program = path;
  command.arguments = arguments;
  return process::run(command, kProcessDeadline_s);
}

pid_t spawn_rockwatch(const std::vector<std::string>& arguments, const std::string& out_path,
                      const std::string& err_path) {
  return spawn_program(ROCKWATCH_CLI_PATH, arguments, out_path, err_path);
}

int wait_status(pid_t pid, double deadline_s) { return process::wait_status(pid, deadline_s); }

ProcessResult run_rockwatch(const std::vector<std::string>& arguments) {
  return run_program(ROCKWATCH_CLI_PATH, arguments);
}

EnvOverride::EnvOverride(const char* name, const char* value) : name_(name) {
  if (const char* old = std::getenv(name)) old_ = old;
  if (value != nullptr) {
    setenv(name, value, 1);
  } else {
    unsetenv(name);
  }
}

EnvOverride::~EnvOverride() {
  if (old_) {
    setenv(name_.c_str(), old_->c_str(), 1);
  } else {
    unsetenv(name_.c_str());
  }
}

}  // namespace rockwatch::test
