#include "output_file.hpp"

#include <cerrno>
#include <cstdio>

#include "command_runner.hpp"
#include "usage_error.hpp"

namespace rockwatch::cli {

PendingOutputFile::PendingOutputFile(const std::optional<std::string>& path) {
  if (!path) return;
  path_ = *path;
  errno = 0;
  file_.open(path_, std::ios::out | std::ios::trunc | std::ios::binary);
  if (!file_) throw UsageError("--out " + path_ + ": cannot open the file for writing" + system_reason());
  opened_ = true;
}

PendingOutputFile::~PendingOutputFile() {
  if (opened_ && !complete_) {
    file_.close();
    std::remove(path_.c_str());
  }
}

void PendingOutputFile::write(const char* what, const std::function<void(std::ostream&)>& write_content) {
  if (!opened_) return;
  errno = 0;
  write_content(file_);
  file_.close();
  if (file_.fail()) throw UsageError("--out " + path_ + ": writing " + what + " failed" + system_reason());
  complete_ = true;
}

}  // namespace rockwatch::cli
