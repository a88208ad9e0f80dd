// Runs the built `rockwatch` as a separate process, the way a user or a script does, and captures what it printed.
#pragma once

#include <string>
#include <vector>

namespace rockwatch::test {

struct ProcessResult {
  int exit_status = -1;  // valid when signal == 0
  int signal = 0;        // the signal that killed the process, 0 when it exited
  std::string out;       // stdout
  std::string err;       // stderr
};

// Runs ROCKWATCH_CLI_PATH with `arguments` (argv[1] onwards), stdin from /dev/null. Throws std::runtime_error when
// the process cannot be started.
ProcessResult run_rockwatch(const std::vector<std::string>& arguments);

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
