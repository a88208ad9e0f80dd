// The error every record reader throws: it names the file, the line (0 when not line-specific) and what was
// expected, so a user can fix the file. The `rockwatch` tool maps it to exit status 2.
#pragma once

#include <stdexcept>
#include <string>

namespace rockwatch::records {

class RecordError : public std::runtime_error {
 public:
  RecordError(std::string path, int line, const std::string& what);
  const std::string& path() const { return path_; }
  int line() const { return line_; }

 private:
  std::string path_;
  int line_;
};

}  // namespace rockwatch::records
