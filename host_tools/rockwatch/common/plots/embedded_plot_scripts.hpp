// The plot scripts of host_tools/plots/, compiled into the binary (see host_tools/cmake/embed_plot_scripts.cmake).
#pragma once

#include <cstddef>

namespace rockwatch::cli {

struct EmbeddedPlotScript {
  const char* name;            // file name without ".py", e.g. "static_sweep"; nullptr ends the table
  const unsigned char* bytes;  // the script's UTF-8 text, not NUL-terminated as far as `size` goes
  std::size_t size;
};

// Every embedded script, ended by an entry whose name is nullptr. Defined in the generated source.
const EmbeddedPlotScript* embedded_plot_scripts();

}  // namespace rockwatch::cli
