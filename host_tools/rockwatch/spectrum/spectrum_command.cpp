// `rockwatch spectrum`: one record through sim::response_spectrum and sim::intensity_measures. This file only wires
// the parts together and maps every failure to a one-line message; the CLI adds no physics.
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <iostream>
#include <iterator>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "common/process/command_runner.hpp"
#include "common/process/commands.hpp"
#include "common/records_in/input_motion.hpp"
#include "common/process/output_file.hpp"
#include "common/plots/python_plot.hpp"
#include "common/records_in/record_selection.hpp"
#include "rockwatch/core/design_spectrum.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"
#include "rockwatch/records/record.hpp"
#include "rockwatch/sim/intensity_measures.hpp"
#include "rockwatch/sim/response_spectrum.hpp"
#include "spectrum/spectrum_plot.hpp"
#include "spectrum/spectrum_report.hpp"
#include "spectrum/spectrum_request.hpp"

namespace rockwatch::cli {

namespace {

constexpr CommandErrors kErrors{"rockwatch spectrum: error: ", "out of memory (a very long record?)"};

// One oscillator step is a few ns; 2e9 of them is several seconds. More is a typo (a huge N or a huge record).
constexpr double kMaxOscillatorSteps = 2e9;

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  return std::filesystem::equivalent(a, b, ec);
}

void check_output_paths(const SpectrumRequest& q) {
  const std::string& record_path = q.record.record_path;
  if (q.out_csv_path && same_file(*q.out_csv_path, record_path)) {
    throw UsageError("--out " + *q.out_csv_path + " is the input record: choose another file name");
  }
  if (q.plot_path && same_file(*q.plot_path, record_path)) {
    throw UsageError("--plot " + *q.plot_path + " is the input record: choose another file name");
  }
  if (q.plot_path && q.out_csv_path && *q.plot_path == *q.out_csv_path) {
    throw UsageError("--plot and --out name the same file " + quoted(*q.plot_path));
  }
}

void check_work_size(const SpectrumRequest& q, std::size_t samples) {
  const double periods = static_cast<double>(q.periods.count + std::size(kStandardPeriods_s));
  const double steps = periods * static_cast<double>(samples);
  if (steps > kMaxOscillatorSteps) {
    throw UsageError("--periods " + std::to_string(q.periods.count) + " periods over " + std::to_string(samples) +
                     " samples means " + number_text(std::round(steps)) + " oscillator steps, more than the " +
                     number_text(kMaxOscillatorSteps) + " a run may take: ask for fewer periods");
  }
}

SpectrumResult compute(const SpectrumRequest& q, const records::Record& record) {
  SpectrumResult r;
  r.record = record_info(record, record.horizontal_mps2);
  r.record.source = selection_text(q.record);
  r.vertical_column_ignored = !record.vertical_mps2.empty();
  const std::vector<double>& a = record.horizontal_mps2;
  const std::vector<double> periods = sim::log_spaced_periods(q.periods.from_s, q.periods.to_s, q.periods.count);
  r.spectrum = sim::response_spectrum(a, record.dt_s, periods, q.damping);
  r.standard = sim::response_spectrum(
      a, record.dt_s, std::vector<double>(std::begin(kStandardPeriods_s), std::end(kStandardPeriods_s)), q.damping);
  r.measures = sim::intensity_measures(a, record.dt_s, q.g_mps2());
  if (q.target) {
    for (const double t : r.spectrum.periods_s) r.target_sa_mps2.push_back(target_sa_mps2(*q.target, q.g_mps2(), t));
    for (const double t : r.standard.periods_s) {
      r.standard_target_sa_mps2.push_back(target_sa_mps2(*q.target, q.g_mps2(), t));
    }
  }
  return r;
}

int run(const SpectrumRequest& q) {
  check_output_paths(q);
  const records::Record record = records::read_record(q.record.record_path, q.record.read_options);
  for (const std::string& note : record.notes) std::cerr << "note: " << note << '\n';
  if (!record.vertical_mps2.empty()) {
    std::cerr << "note: " << q.record.record_path << " has a third (vertical) column; the spectrum is of the second\n";
  }
  check_work_size(q, record.horizontal_mps2.size());
  PendingOutputFile csv(q.out_csv_path);  // opened now, so a wrong directory is reported at once

  const SpectrumResult result = compute(q, record);
  csv.write("the spectrum", [&result](std::ostream& out) { write_spectrum_csv(out, result); });

  if (q.json) {
    // The JSON has only the documented keys; the provenance SPEC §5 asks for goes to stderr.
    if (q.target && q.target->shape.kind == core::SpectrumKind::npr9998_2015) {
      std::cerr << "note: target npr9998-2015: " << core::spectrum_provenance(q.target->shape.kind) << '\n';
    }
    std::cout << spectrum_json(q, result).dump(2) << '\n';
  } else {
    std::cout << spectrum_summary_text(q, result);
  }
  if (q.plot_path) {
    const PlotOutcome plot = plot_spectrum(q, result);
    if (!plot.ok) {
      std::cout.flush();
      return fail(kErrors, "plot not written: " + plot.message, kExitInternalError);
    }
    if (!q.json) std::cout << "wrote " << *q.plot_path << '\n';
  }
  if (q.out_csv_path && !q.json) std::cout << "wrote " << *q.out_csv_path << '\n';
  return finish_stdout(kErrors);
}

}  // namespace

int spectrum_main(int argc, const char* const* argv) {
  return run_command(kErrors, [&] {
    const SpectrumParse parsed = parse_spectrum_arguments(argc, argv);
    if (!parsed.request) return print_help(parsed.help_text);
    return run(*parsed.request);
  });
}

}  // namespace rockwatch::cli
