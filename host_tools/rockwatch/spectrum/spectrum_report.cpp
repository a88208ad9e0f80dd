#include "spectrum/spectrum_report.hpp"

#include <charconv>
#include <cstddef>
#include <cstdio>
#include <optional>
#include <ostream>
#include <string>
#include <system_error>
#include <vector>

#include "common/records_in/record_selection.hpp"
#include "common/process/text_report.hpp"
#include "rockwatch/core/design_spectrum.hpp"
#include "rockwatch/options/option_values.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

namespace {

std::string duration_text(const std::optional<double>& d_s, const std::optional<double>& from_s,
                          const std::optional<double>& to_s, const char* from_label, const char* to_label) {
  if (!d_s || !from_s || !to_s) return "undefined (no motion)";
  return format("%.2f s (%s = %.2f s, %s = %.2f s)", *d_s, from_label, *from_s, to_label, *to_s);
}

void append_number(std::string& row, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  if (result.ec == std::errc{}) row.append(buffer, result.ptr);
}

}  // namespace

double target_sa_mps2(const SpectrumTarget& target, double g_mps2, double period_s) {
  return target.pga_g * g_mps2 * core::spectrum_shape(target.shape, period_s);
}

std::string target_text(const SpectrumTarget& t) {
  return std::string(core::spectrum_name(t.shape.kind)) + " (p " + number_text(t.shape.p) + ", TB " +
         number_text(t.shape.tb_s) + " s, TC " + number_text(t.shape.tc_s) + " s, TD " + number_text(t.shape.td_s) +
         " s)";
}

nlohmann::ordered_json spectrum_json(const SpectrumRequest& q, const SpectrumResult& r) {
  nlohmann::ordered_json j;
  j["periods_s"] = r.spectrum.periods_s;
  j["sa_mps2"] = r.spectrum.psa_mps2;
  j["pga_mps2"] = r.measures.pga_mps2;
  j["pgv_mps"] = r.measures.pgv_mps;
  j["pgd_m"] = r.measures.pgd_m;
  j["arias_mps"] = r.measures.arias_mps;
  j["d5_75_s"] = number_or_null(r.measures.d5_75_s);
  j["d5_95_s"] = number_or_null(r.measures.d5_95_s);
  if (q.target) {
    j["target_sa_mps2"] = r.target_sa_mps2;
    j["target"] = core::spectrum_name(q.target->shape.kind);
  }
  add_selection_json(j, q.record);
  return j;
}

std::string spectrum_summary_text(const SpectrumRequest& q, const SpectrumResult& r) {
  const double g = q.g_mps2();
  const sim::IntensityMeasures& m = r.measures;
  std::string out;
  out += "rockwatch spectrum: elastic response spectrum and intensity measures of a record\n\n";

  out += "Record\n";
  line(out, "file", file_name(r.record.path) + " (" + format_name(r.record.format) + ", values in " + r.record.units +
                        ")");
  if (!r.record.source.empty()) line(out, "", printable(r.record.source) + ", " + printable(r.record.path));
  // A suite record's header says what the source line says: once is enough.
  if (!r.record.description.empty() && r.record.description != r.record.source) {
    line(out, "", printable(r.record.description));
  }
  const double duration_s = r.record.dt_s * (static_cast<double>(r.record.samples) - 1.0);
  line(out, "", format("%zu samples at dt %s s, duration %s s", r.record.samples, number_text(r.record.dt_s).c_str(),
                       number_text(duration_s).c_str()));
  if (r.vertical_column_ignored) line(out, "", "third (vertical) column not used: the spectrum is of the second");

  out += "\nIntensity measures\n";
  line(out, "PGA", format("%.4f g = %.4f m/s2", m.pga_mps2 / g, m.pga_mps2));
  line(out, "PGV", format("%.4f m/s (baseline-corrected)", m.pgv_mps));
  line(out, "PGD", format("%.4f m (baseline-corrected)", m.pgd_m));
  line(out, "Arias intensity", format("%.4f m/s", m.arias_mps));
  line(out, "D5-75", duration_text(m.d5_75_s, m.t5_s, m.t75_s, "t5", "t75"));
  line(out, "D5-95", duration_text(m.d5_95_s, m.t5_s, m.t95_s, "t5", "t95"));

  out += format("\nSpectrum (damping %s %%, Sa = pseudo-acceleration omega^2 Sd)\n", number_text(100.0 * q.damping).c_str());
  if (q.target) {
    out += format("  %8s %12s %9s %12s %9s %8s\n", "T [s]", "Sa [m/s2]", "Sa [g]", "Se [m/s2]", "Se [g]", "Sa/Se");
  } else {
    out += format("  %8s %12s %9s %12s\n", "T [s]", "Sa [m/s2]", "Sa [g]", "Sd [m]");
  }
  for (std::size_t i = 0; i < r.standard.periods_s.size(); ++i) {
    const double t = r.standard.periods_s[i], sa = r.standard.psa_mps2[i];
    if (q.target) {
      const double se = r.standard_target_sa_mps2[i];
      out += format("  %8s %12.4f %9.4f %12.4f %9.4f %8.3f\n", number_text(t).c_str(), sa, sa / g, se, se / g, sa / se);
    } else {
      out += format("  %8s %12.4f %9.4f %12.6f\n", number_text(t).c_str(), sa, sa / g, r.standard.sd_m[i]);
    }
  }
  std::size_t peak = 0;
  for (std::size_t i = 1; i < r.spectrum.psa_mps2.size(); ++i) {
    if (r.spectrum.psa_mps2[i] > r.spectrum.psa_mps2[peak]) peak = i;
  }
  const PeriodGrid& grid = q.periods;
  line(out, "periods", format("%zu, log-spaced from %s to %s s", grid.count, number_text(grid.from_s).c_str(),
                              number_text(grid.to_s).c_str()) +
                           (q.json || q.out_csv_path ? "" : " (all of them: --out or --json)"));
  if (!r.spectrum.psa_mps2.empty()) {
    const double sa = r.spectrum.psa_mps2[peak];
    line(out, "peak Sa on the grid", format("%.4f m/s2 = %.4f g at T = %.4g s (%.2f x PGA)", sa, sa / g,
                                            r.spectrum.periods_s[peak], m.pga_mps2 > 0.0 ? sa / m.pga_mps2 : 0.0));
  }

  if (q.target) {
    out += "\nTarget\n";
    line(out, "design spectrum", target_text(*q.target));
    line(out, "", core::spectrum_provenance(q.target->shape.kind));
    line(out, "design PGA", format("a_g = %s g = %.4f m/s2; Se(T) = a_g * shape(T)", number_text(q.target->pga_g).c_str(),
                                   q.target->pga_g * g));
    std::size_t above = 0;
    for (std::size_t i = 0; i < r.target_sa_mps2.size(); ++i) {
      if (r.spectrum.psa_mps2[i] > r.target_sa_mps2[i]) ++above;
    }
    line(out, "Sa > Se", format("at %zu of %zu grid periods", above, r.target_sa_mps2.size()));
  }

  out += "\nNotes\n";
  out += "  PSA at short period tends to the PGA; peaks are taken at the samples, the oscillators start at rest.\n";
  if (q.target && q.target->shape.kind == core::SpectrumKind::npr9998_2015) {
    out += "  The npr9998-2015 target is back-calculated from the design paper's two static results, not the\n"
           "  published NPR 9998:2015 bedrock spectrum (its parameters are not public).\n";
  }
  return out;
}

void write_spectrum_csv(std::ostream& out, const SpectrumResult& r) {
  const bool with_target = !r.target_sa_mps2.empty();
  out << (with_target ? kSpectrumCsvHeaderWithTarget : kSpectrumCsvHeader) << '\n';
  std::string row;
  for (std::size_t i = 0; i < r.spectrum.periods_s.size(); ++i) {
    row.clear();
    append_number(row, r.spectrum.periods_s[i]);
    row += ',';
    append_number(row, r.spectrum.psa_mps2[i]);
    if (with_target) {
      row += ',';
      append_number(row, r.target_sa_mps2[i]);
    }
    row += '\n';
    out << row;
  }
}

}  // namespace rockwatch::cli
