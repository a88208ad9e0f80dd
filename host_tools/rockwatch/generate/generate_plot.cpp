#include "generate/generate_plot.hpp"

#include <charconv>
#include <cstddef>
#include <filesystem>
#include <ostream>
#include <string>
#include <system_error>
#include <vector>

#include "common/process/text_report.hpp"
#include "rockwatch/core/design_spectrum.hpp"
#include "rockwatch/options/option_values.hpp"
#include "common/process/options_namespace.hpp"
#include "rockwatch/sim/response_spectrum.hpp"

namespace rockwatch::cli {

namespace {

namespace synthesis = sim::synthesis;

void append_number(std::string& row, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  if (result.ec == std::errc{}) row.append(buffer, result.ptr);
}

// One column per record, named "set01_X": the script groups them by the letter after the last '_'.
struct PlotColumns {
  std::vector<std::string> names;
  std::vector<std::vector<double>> psa_mps2;
};

PlotColumns record_spectra(const GenerateRequest& q, const GeneratedSuite& suite, const std::vector<double>& periods) {
  PlotColumns columns;
  for (const synthesis::GeneratedSet& set : suite.sets) {
    for (const synthesis::GeneratedComponent& c : set.components) {
      columns.names.push_back(format("set%02d_%c", set.set_number, synthesis::component_letter(c.component)));
      columns.psa_mps2.push_back(
          sim::response_spectrum(c.acc_mps2, q.settings.dt_s, periods, q.settings.damping).psa_mps2);
    }
  }
  return columns;
}

void write_plot_csv(std::ostream& out, const GenerateRequest& q, const std::vector<double>& periods,
                    const PlotColumns& columns) {
  const synthesis::GeneratorSettings& s = q.settings;
  const double ag_mps2 = s.pga_g * s.g_mps2;
  const double avg_mps2 = ag_mps2 * s.vertical_pga_ratio;
  out << "period_s,target_h_mps2,target_v_mps2";
  for (const std::string& name : columns.names) out << ',' << name;
  out << '\n';
  std::string row;
  for (std::size_t i = 0; i < periods.size(); ++i) {
    row.clear();
    append_number(row, periods[i]);
    row += ',';
    append_number(row, ag_mps2 * core::spectrum_shape(s.horizontal_target, periods[i]));
    row += ',';
    append_number(row, avg_mps2 * core::spectrum_shape(s.vertical_target, periods[i]));
    for (const std::vector<double>& psa : columns.psa_mps2) {
      row += ',';
      append_number(row, psa[i]);
    }
    row += '\n';
    out << row;
  }
}

std::string target_label(const core::SpectrumShape& shape, const std::string& pga_text) {
  std::string label = "target " + std::string(core::spectrum_name(shape.kind)) + ", " + pga_text;
  if (shape.kind == core::SpectrumKind::npr9998_2015) {
    label += "\n(back-calculated from the paper's static results;\nNPR 9998:2015 parameters are not public)";
  }
  return label;
}

}  // namespace

PlotOutcome plot_suite_spectra(const GenerateRequest& q, const GeneratedSuite& suite) {
  for (const char* name : kSuitePlotNames) {
    std::error_code ec;
    std::filesystem::remove(std::filesystem::path(q.out_dir) / name, ec);
  }
  const synthesis::GeneratorSettings& s = q.settings;
  const std::vector<double> periods = sim::log_spaced_periods(kSuitePlotFromS, kSuitePlotToS, kSuitePlotPeriods);
  const PlotColumns columns = record_spectra(q, suite, periods);
  const std::string title = format("Suite %s, %d set%s, seed ", core::spectrum_name(s.horizontal_target.kind), q.sets,
                                   q.sets == 1 ? "" : "s") +
                            std::to_string(s.seed) + ": " + number_text(100.0 * s.damping) + " %-damped spectra";
  const std::vector<std::string> args{
      q.out_dir,
      title,
      number_text(s.g_mps2),
      number_text(s.check_from_s),
      number_text(s.check_to_s),
      number_text(s.accept_min),
      number_text(s.accept_max),
      target_label(s.horizontal_target, "a_g = " + number_text(s.pga_g) + " g"),
      target_label(s.vertical_target, "a_vg = " + number_text(s.pga_g * s.vertical_pga_ratio) + " g"),
  };
  return run_plot_script_with_data(
      "suite_spectra", "suite_spectra.csv",
      [&](std::ostream& out) { write_plot_csv(out, q, periods, columns); }, args);
}

}  // namespace rockwatch::cli
