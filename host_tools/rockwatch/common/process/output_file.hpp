// A --out file opened before the work, so a wrong directory is reported at once, not after a long run. A failed
// run must not leave a truncated or empty file that looks like a result: the file is removed unless it was
// written completely.
#pragma once

#include <fstream>
#include <functional>
#include <optional>
#include <ostream>
#include <string>

namespace rockwatch::cli {

// An output path the tool may create, truncate and, when the run fails, remove: refused when it exists and is not a
// regular file. A directory cannot take the file; a FIFO with no reader would block the tool for ever; a device
// (/dev/null, /dev/full) would be removed with the failed run's output, or (--plot) replaced by a file. Throws
// UsageError "OPTION PATH: is a directory, give a file name" or "OPTION PATH: is a FIFO (named pipe), not a
// regular file: give the name of a file to write".
void check_output_file(const std::string& option, const std::string& path);

// Removes a failed run's output, but only a regular file: never a device or a FIFO that took its place.
void remove_output_file(const std::string& path);

// Writes a whole --out file at once; a failed write removes it. Throws UsageError "--out: cannot open PATH for
// writing: REASON" or "--out: writing NAME failed: REASON", NAME being `shown_as` if given (a temporary file named
// as the file it becomes), else PATH.
void write_output_file(const std::string& path, const std::function<void(std::ostream&)>& write_content,
                       const std::string& shown_as = {});

class PendingOutputFile {
 public:
  // Without a path nothing is opened and write() does nothing. Throws UsageError
  // "OPTION PATH: cannot open the file for writing: REASON" (OPTION: the option that named the file).
  explicit PendingOutputFile(const std::optional<std::string>& path, std::string option = "--out");
  PendingOutputFile(const PendingOutputFile&) = delete;
  PendingOutputFile& operator=(const PendingOutputFile&) = delete;
  ~PendingOutputFile();

  // Writes the content and closes the file. Throws UsageError "OPTION PATH: writing WHAT failed: REASON".
  void write(const char* what, const std::function<void(std::ostream&)>& write_content);

 private:
  std::string option_;
  std::string path_;
  std::ofstream file_;
  bool opened_ = false;
  bool complete_ = false;
};

}  // namespace rockwatch::cli
