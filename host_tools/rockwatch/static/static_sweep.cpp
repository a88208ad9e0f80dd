#include "static/static_sweep.hpp"

#include <charconv>
#include <string>
#include <system_error>
#include <vector>

#include "common/process/text_report.hpp"
#include "rockwatch/core/design_spectrum.hpp"
#include "rockwatch/options/option_values.hpp"
#include "common/process/options_namespace.hpp"
#include "static/static_report.hpp"

namespace rockwatch::cli {

namespace {

void append_number(std::string& text, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  if (result.ec == std::errc{}) text.append(buffer, result.ptr);
}

}  // namespace

std::vector<SweepRow> compute_sweep(const core::StaticInputs& base) {
  std::vector<SweepRow> rows;
  for (const double slenderness : kSweepSlenderness) {
    // λ from an integer count of hundredths, so 0.37 is the double nearest 0.37 rather than 0.1 + 27 × 0.01.
    for (int percent = kSweepLambdaFirstPercent; percent <= kSweepLambdaLastPercent; ++percent) {
      core::StaticInputs in = base;
      in.b_m = kSweepB_m;
      core::set_total_height(in, slenderness * kSweepB_m);
      in.lambda = percent / 100.0;
      SweepRow r;
      r.h_over_b = slenderness;
      r.lambda = in.lambda;
      core::run_static_check(in, r.result);
      rows.push_back(r);
    }
  }
  return rows;
}

void write_sweep_csv(std::ostream& out, const std::vector<SweepRow>& rows) {
  out << kSweepCsvHeader << '\n';
  std::string line;
  for (const SweepRow& r : rows) {
    line.clear();
    const double values[] = {r.h_over_b,          r.result.h_m,      r.lambda,
                             r.result.period_s,   r.result.x_eq_max_m, r.result.allowable_pga_g};
    for (const double v : values) {
      if (!line.empty()) line += ',';
      append_number(line, v);
    }
    line += '\n';
    out << line;
  }
}

std::string sweep_plot_title(const core::StaticInputs& base, bool general_case) {
  std::string title = "Allowable PGA versus lambda, b = " + number_text(kSweepB_m) + " m (static check, SPEC 5)";
  if (general_case) {
    title += "\nK, X, T derived by virtual work: Fp " + number_text(base.fp_npm) + " N/m, a " + number_text(base.a) +
             ", psi " + number_text(base.psi_rad) + " rad";
  }
  title += "\nspectrum " + spectrum_text(base.spectrum);
  if (base.spectrum.kind == core::SpectrumKind::npr9998_2015) {
    title += "\n(back-calculated from the paper's static results; NPR 9998:2015 parameters not public)";
  }
  return title;
}

}  // namespace rockwatch::cli
