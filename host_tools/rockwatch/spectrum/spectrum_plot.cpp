#include "spectrum/spectrum_plot.hpp"

#include <filesystem>
#include <ostream>
#include <string>
#include <system_error>
#include <vector>

#include "common/process/text_report.hpp"
#include "rockwatch/core/design_spectrum.hpp"
#include "rockwatch/options/option_values.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

namespace {

std::string plot_title(const SpectrumRequest& q, const SpectrumResult& r) {
  std::string title = file_name(r.record.path) + (r.record.source.empty() ? "" : " (" + r.record.source + ")") +
                      ": elastic response spectrum, damping " + number_text(100.0 * q.damping) + " %";
  if (!r.record.description.empty()) {
    std::string description = r.record.description;
    for (char& c : description) {
      if (static_cast<unsigned char>(c) < 0x20) c = ' ';
    }
    if (description.size() > 90) description = description.substr(0, 87) + "...";
    title += "\n" + description;
  }
  return title;
}

std::string target_label(const SpectrumTarget& t) {
  std::string label = "target " + std::string(core::spectrum_name(t.shape.kind)) + ", a_g = " + number_text(t.pga_g) + " g";
  if (t.shape.kind == core::SpectrumKind::npr9998_2015) {
    label += "\n(back-calculated from the paper's static results;\nNPR 9998:2015 parameters are not public)";
  }
  return label;
}

}  // namespace

PlotOutcome plot_spectrum(const SpectrumRequest& q, const SpectrumResult& r) {
  const std::string& png_path = *q.plot_path;
  std::error_code ec;
  std::filesystem::remove(png_path, ec);

  std::vector<std::string> args{png_path, plot_title(q, r), number_text(q.g_mps2())};
  if (q.target) args.push_back(target_label(*q.target));
  return run_plot_script_with_data(
      "response_spectrum", "spectrum.csv", [&r](std::ostream& out) { write_spectrum_csv(out, r); }, args);
}

}  // namespace rockwatch::cli
