#include "common/plots/python_plot.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "common/plots/embedded_plot_scripts.hpp"
#include "rockwatch/process/child_process.hpp"

namespace rockwatch::cli {

namespace {

// The same statements a plot script starts with: a Python whose matplotlib imports but cannot load pyplot
// (a broken install) would otherwise pass the check and fail later with a less helpful message.
constexpr const char* kMatplotlibProbe = "import matplotlib; matplotlib.use('Agg'); import matplotlib.pyplot";

// A script's stderr can be a long traceback; its end says what went wrong.
constexpr std::size_t kMaxStderrShown = 2000;

struct ProcessOutcome {
  bool started = false;
  std::string start_error;  // why it could not be started
  bool exited = false;
  int exit_status = -1;
  int signal = 0;
};

// Runs `program` with `args` (argv[1] onwards) directly, no shell: stdin and stdout on /dev/null, stderr to
// `stderr_path` (or /dev/null when empty).
ProcessOutcome run_process(const std::string& program, const std::vector<std::string>& args,
                           const std::string& stderr_path) {
  process::Command command;
  command.program = program;
  command.arguments = args;
  command.stderr_path = stderr_path.empty() ? std::string("/dev/null") : stderr_path;
  command.create_mode = 0600;
  ProcessOutcome outcome;
  pid_t pid = 0;
  if (const int error = process::try_start(command, pid); error != 0) {
    outcome.start_error = std::strerror(error);
    return outcome;
  }
  outcome.started = true;
  int status = 0;
  try {
    status = process::wait_status(pid);
  } catch (const std::runtime_error& e) {
    outcome.start_error = e.what();
    return outcome;
  }
  const process::Exit e = process::decode_status(status);
  if (e.signal != 0) {
    outcome.signal = e.signal;
  } else if (e.exit_status >= 0) {
    outcome.exited = true;
    outcome.exit_status = e.exit_status;
  }
  return outcome;
}

bool is_executable_file(const std::string& path) {
  struct stat info {};
  return stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode) && access(path.c_str(), X_OK) == 0;
}

// The first executable `name` in $PATH, as the shell would find it.
std::optional<std::string> find_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (path == nullptr) return std::nullopt;
  const std::string dirs = path;
  std::size_t start = 0;
  while (start <= dirs.size()) {
    const std::size_t end = dirs.find(':', start);
    const std::string dir = dirs.substr(start, end == std::string::npos ? std::string::npos : end - start);
    const std::string candidate = (dir.empty() ? std::string(".") : dir) + "/" + name;
    if (is_executable_file(candidate)) return candidate;
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return std::nullopt;
}

// Once per interpreter path and process: the probe imports pyplot (0.3-1 s), and a command that writes several plots
// searched before each (the matplotlib runner's suite probed /usr/bin/python3 five times: 25 % of its timeout under
// the sanitizers beside CI's builds).
// Fixed slots, not a map: nothing allocated that outlives the call (the suites' leak checks).
struct ProbedPython {
  char path[512];
  bool imports;
};
bool imports_matplotlib(const std::string& python) {
  static std::mutex mutex;
  static ProbedPython probed[8];
  static std::size_t n_probed = 0;
  const std::lock_guard<std::mutex> lock(mutex);
  for (std::size_t i = 0; i < n_probed; ++i) {
    if (python == probed[i].path) return probed[i].imports;
  }
  const ProcessOutcome o = run_process(python, {"-c", kMatplotlibProbe}, "");
  const bool imports = o.started && o.exited && o.exit_status == 0;
  if (n_probed < std::size(probed) && python.size() < sizeof probed[0].path) {
    std::memcpy(probed[n_probed].path, python.c_str(), python.size() + 1);
    probed[n_probed].imports = imports;
    ++n_probed;
  }
  return imports;
}

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  return std::filesystem::equivalent(a, b, ec);
}

struct PythonSearch {
  std::optional<std::string> python;
  std::vector<std::string> tried;  // "WHERE: WHY NOT", for the message when none qualifies
};

PythonSearch search_python() {
  PythonSearch search;
  std::vector<std::string> checked;
  const auto consider = [&](const std::string& origin, const std::optional<std::string>& path) {
    if (search.python) return;
    if (!path) {
      search.tried.push_back(origin + ": not found");
      return;
    }
    for (const std::string& c : checked) {
      if (same_file(c, *path)) return;  // python3 on PATH is often /usr/bin/python3 itself
    }
    checked.push_back(*path);
    const std::string where = origin == *path ? origin : origin + " (" + *path + ")";
    if (!is_executable_file(*path)) {
      search.tried.push_back(where + ": not an executable file");
    } else if (!imports_matplotlib(*path)) {
      search.tried.push_back(where + ": cannot import matplotlib");
    } else {
      search.python = *path;
    }
  };

  const char* chosen = std::getenv("ROCKWATCH_PYTHON");
  if (chosen != nullptr && *chosen != '\0') {
    const std::string value = chosen;
    consider("$ROCKWATCH_PYTHON", value.find('/') == std::string::npos ? find_on_path(value) : value);
  }
  consider("/usr/bin/python3", std::string("/usr/bin/python3"));
  consider("python3 on PATH", find_on_path("python3"));
  return search;
}

const EmbeddedPlotScript* find_script(const std::string& name) {
  for (const EmbeddedPlotScript* s = embedded_plot_scripts(); s->name != nullptr; ++s) {
    if (name == s->name) return s;
  }
  return nullptr;
}

std::string embedded_names() {
  std::string names;
  for (const EmbeddedPlotScript* s = embedded_plot_scripts(); s->name != nullptr; ++s) {
    names += (names.empty() ? "" : ", ") + std::string(s->name);
  }
  return names.empty() ? std::string("none") : names;
}

// A private directory (mkdtemp: only this process can use it, whatever else runs in the temporary directory),
// removed with its contents whatever happens.
class ScratchDirectory {
 public:
  explicit ScratchDirectory(const std::string& prefix) {
    std::error_code ec;
    const std::filesystem::path base = std::filesystem::temp_directory_path(ec);
    const std::string pattern = ((ec ? std::filesystem::path("/tmp") : base) / (prefix + ".XXXXXX")).string();
    std::vector<char> buffer(pattern.begin(), pattern.end());
    buffer.push_back('\0');
    if (mkdtemp(buffer.data()) == nullptr) {
      error_ = std::string("cannot create a temporary directory: ") + std::strerror(errno);
      return;
    }
    path_ = buffer.data();
  }
  ~ScratchDirectory() {
    if (path_.empty()) return;
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDirectory(const ScratchDirectory&) = delete;
  ScratchDirectory& operator=(const ScratchDirectory&) = delete;

  bool ok() const { return !path_.empty(); }
  const std::string& error() const { return error_; }
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
  std::string error_;
};

std::string read_tail(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r' || text.back() == ' ')) text.pop_back();
  if (text.size() > kMaxStderrShown) text = "..." + text.substr(text.size() - kMaxStderrShown);
  return text;
}

}  // namespace

std::optional<std::string> find_matplotlib_python() { return search_python().python; }

PlotOutcome run_plot_script(const std::string& script_name, const std::vector<std::string>& args) {
  const EmbeddedPlotScript* script = find_script(script_name);
  if (script == nullptr) {
    return {false, "no embedded plot script named '" + script_name + "' (embedded: " + embedded_names() + ")"};
  }
  const PythonSearch search = search_python();
  if (!search.python) {
    std::string tried;
    for (const std::string& t : search.tried) tried += (tried.empty() ? "" : "; ") + t;
    return {false, "no Python with matplotlib found (" + tried +
                       "); install python3-matplotlib or set ROCKWATCH_PYTHON to a Python that has it"};
  }

  const ScratchDirectory scratch("rockwatch_plot");
  if (!scratch.ok()) return {false, scratch.error()};
  const std::string script_path = scratch.file(script_name + ".py");
  const std::string stderr_path = scratch.file("stderr.txt");
  {
    std::ofstream out(script_path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(script->bytes), static_cast<std::streamsize>(script->size));
    out.close();
    if (!out) return {false, "cannot write the plot script to " + script_path};
  }

  std::vector<std::string> python_args{script_path};
  python_args.insert(python_args.end(), args.begin(), args.end());
  const ProcessOutcome o = run_process(*search.python, python_args, stderr_path);
  if (!o.started) return {false, "cannot run " + *search.python + ": " + o.start_error};
  if (o.exited && o.exit_status == 0) return {true, {}};

  std::string message = "plot script " + script_name + " (" + *search.python + ") ";
  message += o.exited ? "failed with exit status " + std::to_string(o.exit_status)
                      : "was killed by signal " + std::to_string(o.signal);
  const std::string tail = read_tail(stderr_path);
  if (!tail.empty()) message += ":\n" + tail;
  return {false, message};
}

PlotOutcome run_plot_script_with_data(const std::string& script_name, const std::string& data_file_name,
                                      const std::function<void(std::ostream&)>& write_data,
                                      const std::vector<std::string>& args) {
  const ScratchDirectory scratch("rockwatch_" + script_name);
  if (!scratch.ok()) return {false, scratch.error()};
  const std::string data_path = scratch.file(data_file_name);
  {
    std::ofstream data(data_path, std::ios::binary);
    write_data(data);
    data.close();
    if (!data) return {false, "cannot write the plot data to " + data_path};
  }
  std::vector<std::string> script_args{data_path};
  script_args.insert(script_args.end(), args.begin(), args.end());
  return run_plot_script(script_name, script_args);
}

}  // namespace rockwatch::cli
