#include "common/process/output_file.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <fstream>
#include <functional>
#include <ostream>
#include <string>
#include <utility>

#include "common/process/command_runner.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

void check_output_file(const std::string& option, const std::string& path) {
  if (path.empty()) throw UsageError(option + " needs a file name");
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return;  // a new file (a missing directory is reported when it is opened)
  if (S_ISDIR(st.st_mode)) throw UsageError(option + " " + path + ": is a directory, give a file name");
  if (!S_ISREG(st.st_mode)) {
    throw UsageError(option + " " + path + ": is " + file_kind_text(st.st_mode) +
                     ", not a regular file: give the name of a file to write");
  }
}

void remove_output_file(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode)) std::remove(path.c_str());
}

void write_output_file(const std::string& path, const std::function<void(std::ostream&)>& write_content,
                       const std::string& shown_as) {
  errno = 0;
  std::ofstream file(path, std::ios::out | std::ios::trunc | std::ios::binary);
  if (!file) throw UsageError("--out: cannot open " + path + " for writing" + system_reason());
  write_content(file);
  file.close();
  if (file.fail()) {
    const std::string reason = system_reason();
    remove_output_file(path);
    throw UsageError("--out: writing " + (shown_as.empty() ? path : shown_as) + " failed" + reason);
  }
}

PendingOutputFile::PendingOutputFile(const std::optional<std::string>& path, std::string option)
    : option_(std::move(option)) {
  if (!path) return;
  path_ = *path;
  errno = 0;
  file_.open(path_, std::ios::out | std::ios::trunc | std::ios::binary);
  if (!file_) throw UsageError(option_ + " " + path_ + ": cannot open the file for writing" + system_reason());
  opened_ = true;
}

PendingOutputFile::~PendingOutputFile() {
  if (opened_ && !complete_) {
    file_.close();
    remove_output_file(path_);
  }
}

void PendingOutputFile::write(const char* what, const std::function<void(std::ostream&)>& write_content) {
  if (!opened_) return;
  errno = 0;
  write_content(file_);
  file_.close();
  if (file_.fail()) throw UsageError(option_ + " " + path_ + ": writing " + what + " failed" + system_reason());
  complete_ = true;
}

}  // namespace rockwatch::cli
