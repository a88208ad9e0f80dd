// `rockwatch spectrum --plot`: Sa(T) on a log period axis, with the target spectrum when there is one, drawn by the
// embedded host_tools/plots/response_spectrum.py.
#pragma once

#include <string>

#include "common/plots/python_plot.hpp"
#include "spectrum/spectrum_report.hpp"
#include "spectrum/spectrum_request.hpp"

namespace rockwatch::cli {

// Writes the spectrum to a private temporary CSV, runs the script and removes the CSV. An existing file at the PNG
// path is removed first, so a failed plot never leaves an old figure that looks like this one.
PlotOutcome plot_spectrum(const SpectrumRequest& request, const SpectrumResult& result);

}  // namespace rockwatch::cli
