// PNG plots through matplotlib: rockwatch's plot scripts (host_tools/plots/*.py) are embedded in the binary at
// build time and run with a Python that imports matplotlib (Debian's python3-matplotlib). The python3 first on
// PATH may not be Debian's, so the interpreter is searched for.
#pragma once

#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace rockwatch::cli {

// $ROCKWATCH_PYTHON if set (and able to import matplotlib), else /usr/bin/python3, else python3 on PATH.
std::optional<std::string> find_matplotlib_python();

struct PlotOutcome {
  bool ok = false;
  std::string message;  // on failure: what went wrong, including the script's stderr
};

// Runs the embedded script `script_name` (e.g. "static_sweep") with `args`; no shell is involved.
PlotOutcome run_plot_script(const std::string& script_name, const std::vector<std::string>& args);

// Writes the plot's data with `write_data` to a private temporary file `data_file_name`, runs `script_name` with
// that file's path followed by `args`, and removes the file whatever happens.
PlotOutcome run_plot_script_with_data(const std::string& script_name, const std::string& data_file_name,
                                      const std::function<void(std::ostream&)>& write_data,
                                      const std::vector<std::string>& args);

}  // namespace rockwatch::cli
