// `rockwatch generate`'s figures, like the design paper's Figures 4 and 5: every record's 5 %-damped spectrum thin
// grey, the suite mean thick, the target and 0.9 x / 1.3 x target dashed, the acceptance band shaded; drawn by the
// embedded host_tools/plots/suite_spectra.py in one Python run (matplotlib's start-up is most of a plot's time).
#pragma once

#include <cstddef>

#include "common/plots/python_plot.hpp"
#include "generate/generate_report.hpp"
#include "generate/generate_request.hpp"

namespace rockwatch::cli {

// Horizontal (X and Y), vertical (Z), then one per component; written into the suite directory.
inline constexpr const char* kSuitePlotNames[] = {"spectra_horizontal.png", "spectra_vertical.png", "spectra_X.png",
                                                  "spectra_Y.png", "spectra_Z.png"};

// The plotted periods: log-spaced over the range of rockwatch spectrum's default.
inline constexpr double kSuitePlotFromS = 0.02;
inline constexpr double kSuitePlotToS = 4.0;
inline constexpr std::size_t kSuitePlotPeriods = 100;

// Computes every record's spectrum (sim::response_spectrum at the settings' damping), writes them with both targets
// to a private temporary CSV and runs the script. The PNGs of kSuitePlotNames are removed first, so a failed plot
// never leaves an old figure that looks like this suite's.
PlotOutcome plot_suite_spectra(const GenerateRequest& request, const GeneratedSuite& suite);

}  // namespace rockwatch::cli
