// PNG plots through matplotlib: rockwatch's plot scripts (host_tools/plots/*.py) are embedded in the binary at
// build time and run with a Python that imports matplotlib (Debian's python3-matplotlib). The python3 first on
// PATH may not be Debian's, so the interpreter is searched for.
#pragma once

#include <optional>
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

}  // namespace rockwatch::cli
