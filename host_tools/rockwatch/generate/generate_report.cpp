#include "generate/generate_report.hpp"

#include <charconv>
#include <cstddef>
#include <cstdio>
#include <optional>
#include <ostream>
#include <string>
#include <system_error>
#include <vector>

#include "common/process/text_report.hpp"
#include "common/process/tool_version.hpp"
#include "rockwatch/options/option_values.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

namespace {

namespace synthesis = sim::synthesis;

std::string component_name(synthesis::Component c) { return std::string(1, synthesis::component_letter(c)); }

double target_pga_mps2(const synthesis::GeneratorSettings& s, synthesis::Component c) {
  const double ag_mps2 = s.pga_g * s.g_mps2;
  return synthesis::is_vertical(c) ? ag_mps2 * s.vertical_pga_ratio : ag_mps2;
}

nlohmann::ordered_json target_json(const core::SpectrumShape& shape) {
  nlohmann::ordered_json j;
  j["spec"] = target_spec_text(shape);
  j["name"] = core::spectrum_name(shape.kind);
  j["p"] = shape.p;
  j["tb_s"] = shape.tb_s;
  j["tc_s"] = shape.tc_s;
  j["td_s"] = shape.td_s;
  j["provenance"] = core::spectrum_provenance(shape.kind);
  return j;
}

nlohmann::ordered_json window_json(const synthesis::DurationWindow& w) {
  nlohmann::ordered_json j;
  j["min_s"] = w.min_s;
  j["max_s"] = w.max_s;
  return j;
}

nlohmann::ordered_json settings_json(const GenerateRequest& q) {
  const synthesis::GeneratorSettings& s = q.settings;
  nlohmann::ordered_json j;
  j["sets"] = q.sets;
  j["seed"] = s.seed;
  j["dt_s"] = s.dt_s;
  j["duration_s"] = s.duration_s;
  j["g_mps2"] = s.g_mps2;
  j["pga_g"] = s.pga_g;
  j["ag_mps2"] = target_pga_mps2(s, synthesis::Component::x);
  j["vertical_pga_ratio"] = s.vertical_pga_ratio;
  j["avg_mps2"] = target_pga_mps2(s, synthesis::Component::z);
  j["horizontal_target"] = target_json(s.horizontal_target);
  j["vertical_target"] = target_json(s.vertical_target);
  j["damping"] = s.damping;
  j["iterations"] = s.iterations;
  j["match_from_s"] = s.match_from_s;
  j["match_to_s"] = s.match_to_s;
  j["match_periods"] = s.match_periods;
  j["check_from_s"] = s.check_from_s;
  j["check_to_s"] = s.check_to_s;
  j["check_periods"] = s.check_periods;
  j["accept_min"] = s.accept_min;
  j["accept_max"] = s.accept_max;
  j["horizontal_d5_75_s"] = window_json(s.horizontal_d5_75_s);
  j["horizontal_d5_95_s"] = window_json(s.horizontal_d5_95_s);
  j["vertical_d5_75_s"] = window_json(s.vertical_d5_75_s);
  j["vertical_d5_95_s"] = window_json(s.vertical_d5_95_s);
  j["max_attempts"] = s.max_attempts;
  j["suite_mean_tolerance"] = s.suite_mean_tolerance;
  j["match_level"] = s.match_level;
  j["correction_exponent"] = s.correction_exponent;
  j["clip_fraction"] = s.clip_fraction;
  j["fft_padding"] = s.fft_padding;
  j["envelope_spread"] = s.envelope_spread;
  return j;
}

nlohmann::ordered_json component_json(const synthesis::GeneratedComponent& c, const sim::IntensityMeasures& m,
                                       double g_mps2) {
  nlohmann::ordered_json j;
  j["seed"] = c.seed;
  j["pga_mps2"] = m.pga_mps2;
  j["pga_g"] = m.pga_mps2 / g_mps2;
  j["pgv_mps"] = m.pgv_mps;
  j["pgd_m"] = m.pgd_m;
  j["d5_75_s"] = number_or_null(m.d5_75_s);
  j["d5_95_s"] = number_or_null(m.d5_95_s);
  j["arias_mps"] = m.arias_mps;
  j["spectral_ratio_min"] = c.check.min;
  j["spectral_ratio_max"] = c.check.max;
  j["spectrum_accepted"] = c.spectrum_accepted;
  j["durations_accepted"] = c.durations_accepted;
  j["accepted"] = c.accepted;
  j["attempts"] = c.attempts;
  j["final_velocity_mps"] = c.final_velocity_mps;
  j["final_displacement_m"] = c.final_displacement_m;
  return j;
}

nlohmann::ordered_json mean_json(const synthesis::BandRatio& ratio, bool accepted) {
  nlohmann::ordered_json j;
  j["ratio_min"] = ratio.min;
  j["ratio_max"] = ratio.max;
  j["accepted"] = accepted;
  return j;
}

void append_number(std::string& row, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  if (result.ec == std::errc{}) row.append(buffer, result.ptr);
}

void append_optional(std::string& row, const std::optional<double>& value) {
  if (value) append_number(row, *value);
}

// A duration with two decimals, or "-" when the record has none (no motion).
std::string duration_text(const std::optional<double>& value_s) {
  return value_s ? format("%.2f", *value_s) : std::string("-");
}

// "yes", or "NO" and what failed.
std::string verdict_text(const synthesis::GeneratedComponent& c) {
  if (c.accepted) return "yes";
  if (!c.spectrum_accepted && !c.durations_accepted) return "NO: spectrum, durations";
  if (!c.spectrum_accepted) return "NO: spectrum";
  if (!c.durations_accepted) return "NO: durations";
  return "NO";
}

std::string window_text(const synthesis::DurationWindow& w) {
  return number_text(w.min_s) + "-" + number_text(w.max_s) + " s";
}

std::string band_text(const synthesis::GeneratorSettings& s) {
  return number_text(s.check_from_s) + "-" + number_text(s.check_to_s) + " s";
}

}  // namespace

std::string set_file_name(int set) { return format("set%02d.txt", set); }

std::string generator_text(const GenerateRequest& q) {
  return std::string("rockwatch ") + tool_version() + " generate " + q.settings_arguments;
}

std::string regenerating_command(const GenerateRequest& q) {
  return "rockwatch generate --out " + shell_quoted(q.out_dir) + " " + q.settings_arguments;
}

std::string target_header_text(const core::SpectrumShape& s) {
  return std::string(core::spectrum_name(s.kind)) + " p=" + number_text(s.p) + " tb_s=" + number_text(s.tb_s) +
         " tc_s=" + number_text(s.tc_s) + " td_s=" + number_text(s.td_s);
}

records::SuiteRecordFile suite_record_file(const GenerateRequest& q, const synthesis::GeneratedSet& set) {
  const synthesis::GeneratorSettings& s = q.settings;
  records::SuiteRecordFile file;
  file.suite = core::spectrum_name(s.horizontal_target.kind);
  file.set = set.set_number;
  file.dt_s = s.dt_s;
  file.g_mps2 = s.g_mps2;
  file.ag_mps2 = target_pga_mps2(s, synthesis::Component::x);
  file.avg_mps2 = target_pga_mps2(s, synthesis::Component::z);
  file.horizontal_target = target_header_text(s.horizontal_target);
  file.vertical_target = target_header_text(s.vertical_target);
  file.seed = s.seed;
  file.generator = generator_text(q);
  for (std::size_t i = 0; i < set.components.size(); ++i) file.components_mps2[i] = set.components[i].acc_mps2;
  return file;
}

nlohmann::ordered_json manifest_json(const GenerateRequest& q, const GeneratedSuite& suite) {
  const double g = q.settings.g_mps2;
  nlohmann::ordered_json j;
  j["format"] = records::kSuiteManifestFormat;
  j["version"] = 1;
  j["suite"] = core::spectrum_name(q.settings.horizontal_target.kind);
  j["command"] = regenerating_command(q);
  j["generator"] = std::string("rockwatch ") + tool_version();
  j["accepted"] = not_accepted(q, suite).empty();
  j["settings"] = settings_json(q);
  nlohmann::ordered_json sets = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < suite.sets.size(); ++i) {
    const synthesis::GeneratedSet& set = suite.sets[i];
    nlohmann::ordered_json entry;
    entry["set"] = set.set_number;
    entry["file"] = set_file_name(set.set_number);
    nlohmann::ordered_json components;
    for (std::size_t c = 0; c < set.components.size(); ++c) {
      components[component_name(set.components[c].component)] =
          component_json(set.components[c], suite.measures[i][c], g);
    }
    entry["components"] = components;
    sets.push_back(entry);
  }
  j["sets"] = sets;
  nlohmann::ordered_json mean;
  mean["horizontal"] = mean_json(suite.mean.horizontal, suite.mean.horizontal_accepted);
  mean["vertical"] = mean_json(suite.mean.vertical, suite.mean.vertical_accepted);
  j["suite_mean"] = mean;
  return j;
}

void write_manifest_csv(std::ostream& out, const GeneratedSuite& suite, double g_mps2) {
  out << kManifestCsvHeader << '\n';
  std::string row;
  for (std::size_t i = 0; i < suite.sets.size(); ++i) {
    const synthesis::GeneratedSet& set = suite.sets[i];
    for (std::size_t c = 0; c < set.components.size(); ++c) {
      const synthesis::GeneratedComponent& g = set.components[c];
      const sim::IntensityMeasures& m = suite.measures[i][c];
      row = std::to_string(set.set_number) + "," + component_name(g.component) + "," + std::to_string(g.seed) + ",";
      append_number(row, m.pga_mps2);
      row += ',';
      append_number(row, m.pga_mps2 / g_mps2);
      row += ',';
      append_number(row, m.pgv_mps);
      row += ',';
      append_number(row, m.pgd_m);
      row += ',';
      append_optional(row, m.d5_75_s);
      row += ',';
      append_optional(row, m.d5_95_s);
      row += ',';
      append_number(row, m.arias_mps);
      row += ',';
      append_number(row, g.check.min);
      row += ',';
      append_number(row, g.check.max);
      row += g.spectrum_accepted ? ",true" : ",false";
      row += g.durations_accepted ? ",true" : ",false";
      row += g.accepted ? ",true," : ",false,";
      row += std::to_string(g.attempts) + ",";
      append_number(row, g.final_velocity_mps);
      row += ',';
      append_number(row, g.final_displacement_m);
      row += '\n';
      out << row;
    }
  }
}

std::string generate_summary_text(const GenerateRequest& q, const GeneratedSuite& suite) {
  const synthesis::GeneratorSettings& s = q.settings;
  const double g = s.g_mps2;
  std::string out;
  out += "rockwatch generate: spectrum-compatible ground-motion suite (SPEC 6)\n\n";

  out += "Settings\n";
  line(out, "suite", format("%s: %d set%s x 3 components (X, Y horizontal; Z vertical), seed ",
                            core::spectrum_name(s.horizontal_target.kind), q.sets, q.sets == 1 ? "" : "s") +
                         std::to_string(s.seed));
  line(out, "horizontal target", spectrum_text(s.horizontal_target) +
                                     format("; a_g = %s g = %.4f m/s2", number_text(s.pga_g).c_str(), s.pga_g * g));
  line(out, "", core::spectrum_provenance(s.horizontal_target.kind));
  line(out, "vertical target", spectrum_text(s.vertical_target) +
                                   format("; a_vg = %s x a_g = %.4f m/s2", number_text(s.vertical_pga_ratio).c_str(),
                                          target_pga_mps2(s, synthesis::Component::z)));
  line(out, "", core::spectrum_provenance(s.vertical_target.kind));
  line(out, "records", format("dt %s s, duration %s s, %zu Fourier-correction iterations over %s-%s s",
                              number_text(s.dt_s).c_str(), number_text(s.duration_s).c_str(), s.iterations,
                              number_text(s.match_from_s).c_str(), number_text(s.match_to_s).c_str()));
  line(out, "acceptance", format("%s-damped spectrum within [%s, %s] x target over %s; suite mean within 1 +- %s",
                                 (number_text(100.0 * s.damping) + " %").c_str(), number_text(s.accept_min).c_str(),
                                 number_text(s.accept_max).c_str(), band_text(s).c_str(),
                                 number_text(s.suite_mean_tolerance).c_str()));
  line(out, "", "D5-75 " + window_text(s.horizontal_d5_75_s) + " and D5-95 " + window_text(s.horizontal_d5_95_s) +
                    " (X, Y); D5-75 " + window_text(s.vertical_d5_75_s) + " and D5-95 " +
                    window_text(s.vertical_d5_95_s) + " (Z); up to " + std::to_string(s.max_attempts) +
                    " draws per record");

  out += "\nRecords (PGA as generated; PGV after baseline correction; ratio = PSA / target over " + band_text(s) + ")\n";
  out += format("  %3s %4s %9s %9s %9s %9s %9s %9s %5s  %s\n", "set", "comp", "PGA [g]", "PGV [m/s]", "D5-75 [s]",
                "D5-95 [s]", "ratio min", "ratio max", "draws", "accepted");
  for (std::size_t i = 0; i < suite.sets.size(); ++i) {
    for (std::size_t c = 0; c < suite.sets[i].components.size(); ++c) {
      const synthesis::GeneratedComponent& gc = suite.sets[i].components[c];
      const sim::IntensityMeasures& m = suite.measures[i][c];
      out += format("  %3d %4s %9.4f %9.4f %9s %9s %9.3f %9.3f %5zu  %s\n", suite.sets[i].set_number,
                    component_name(gc.component).c_str(), m.pga_mps2 / g, m.pgv_mps,
                    duration_text(m.d5_75_s).c_str(), duration_text(m.d5_95_s).c_str(), gc.check.min,
                    gc.check.max, gc.attempts, verdict_text(gc).c_str());
    }
  }

  out += "\nSuite mean (mean of the ratios at every period of " + band_text(s) + ")\n";
  const auto mean_line = [&out](const char* label, const synthesis::BandRatio& r, bool accepted) {
    line(out, label, format("%.3f to %.3f: %s", r.min, r.max, accepted ? "accepted" : "NOT ACCEPTED"));
  };
  mean_line("horizontal (X and Y)", suite.mean.horizontal, suite.mean.horizontal_accepted);
  mean_line("vertical (Z)", suite.mean.vertical, suite.mean.vertical_accepted);

  out += "\nFiles\n";
  line(out, "directory", q.out_dir);
  line(out, "set files", set_file_name(1) + (q.sets > 1 ? " to " + set_file_name(q.sets) : std::string()));
  line(out, "manifest", std::string(records::kSuiteManifestName) + ", " + kManifestCsvName);
  line(out, "regenerate with", regenerating_command(q));
  line(out, "use a record with", "--suite " + shell_quoted(q.out_dir) + " --set N --component X|Y|Z");
  return out;
}

std::vector<std::string> not_accepted(const GenerateRequest& q, const GeneratedSuite& suite) {
  const synthesis::GeneratorSettings& s = q.settings;
  std::vector<std::string> failures;
  for (const synthesis::GeneratedSet& set : suite.sets) {
    for (const synthesis::GeneratedComponent& c : set.components) {
      if (c.accepted) continue;
      const bool vertical = synthesis::is_vertical(c.component);
      const synthesis::DurationWindow& w75 = vertical ? s.vertical_d5_75_s : s.horizontal_d5_75_s;
      const synthesis::DurationWindow& w95 = vertical ? s.vertical_d5_95_s : s.horizontal_d5_95_s;
      std::vector<std::string> why;
      if (!c.spectrum_accepted) {
        why.push_back(format("spectral ratio %.3f to %.3f, outside [%s, %s] over %s", c.check.min, c.check.max,
                             number_text(s.accept_min).c_str(), number_text(s.accept_max).c_str(),
                             band_text(s).c_str()));
      }
      if (!w75.contains(c.d5_75_s)) why.push_back(format("D5-75 %.2f s, outside ", c.d5_75_s) + window_text(w75));
      if (!w95.contains(c.d5_95_s)) why.push_back(format("D5-95 %.2f s, outside ", c.d5_95_s) + window_text(w95));
      if (why.empty()) why.push_back("not accepted by the generator");
      std::string text = format("set %d %s: ", set.set_number, component_name(c.component).c_str());
      for (std::size_t i = 0; i < why.size(); ++i) text += (i == 0 ? "" : "; ") + why[i];
      failures.push_back(text + format(" (best of %zu draws)", c.attempts));
    }
  }
  const auto mean_failure = [&](const char* label, const synthesis::BandRatio& r, bool accepted) {
    if (accepted) return;
    failures.push_back(format("suite mean %s: ratio %.3f to %.3f, outside 1 +- %s over %s", label, r.min, r.max,
                              number_text(s.suite_mean_tolerance).c_str(), band_text(s).c_str()));
  };
  mean_failure("horizontal (X and Y)", suite.mean.horizontal, suite.mean.horizontal_accepted);
  mean_failure("vertical (Z)", suite.mean.vertical, suite.mean.vertical_accepted);
  return failures;
}

}  // namespace rockwatch::cli
