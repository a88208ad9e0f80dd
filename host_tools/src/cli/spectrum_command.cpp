// `rockwatch spectrum`: one record through sim::response_spectrum and sim::intensity_measures. This file only wires
// the parts together and maps every failure to a one-line message; the CLI adds no physics.
#include <cerrno>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <new>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "commands.hpp"
#include "input_motion.hpp"
#include "option_values.hpp"
#include "python_plot.hpp"
#include "rockwatch/core/design_spectrum.hpp"
#include "rockwatch/records/record.hpp"
#include "rockwatch/records/record_error.hpp"
#include "rockwatch/sim/intensity_measures.hpp"
#include "rockwatch/sim/measure_error.hpp"
#include "rockwatch/sim/response_spectrum.hpp"
#include "spectrum_plot.hpp"
#include "spectrum_report.hpp"
#include "spectrum_request.hpp"
#include "usage_error.hpp"

namespace rockwatch::cli {

namespace {

constexpr const char* kPrefix = "rockwatch spectrum: error: ";

// One oscillator step is a few ns; 2e9 of them is several seconds. More is a typo (a huge N or a huge record).
constexpr double kMaxOscillatorSteps = 2e9;

std::string system_reason() {
  const int code = errno;
  return code != 0 ? std::string(": ") + std::strerror(code) : std::string();
}

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  return std::filesystem::equivalent(a, b, ec);
}

void check_output_paths(const SpectrumRequest& q) {
  if (q.out_csv_path && same_file(*q.out_csv_path, q.record_path)) {
    throw UsageError("--out " + *q.out_csv_path + " is the input record: choose another file name");
  }
  if (q.plot_path && same_file(*q.plot_path, q.record_path)) {
    throw UsageError("--plot " + *q.plot_path + " is the input record: choose another file name");
  }
  if (q.plot_path && q.out_csv_path && *q.plot_path == *q.out_csv_path) {
    throw UsageError("--plot and --out name the same file " + quoted(*q.plot_path));
  }
}

// Opened before the computation, so a wrong directory is reported at once; removed again if the run fails.
class CsvOutput {
 public:
  explicit CsvOutput(const SpectrumRequest& q) {
    if (!q.out_csv_path) return;
    path_ = *q.out_csv_path;
    errno = 0;
    file_.open(path_, std::ios::out | std::ios::trunc | std::ios::binary);
    if (!file_) throw UsageError("--out " + path_ + ": cannot open the file for writing" + system_reason());
    opened_ = true;
  }
  CsvOutput(const CsvOutput&) = delete;
  CsvOutput& operator=(const CsvOutput&) = delete;
  ~CsvOutput() {
    if (opened_ && !complete_) {
      file_.close();
      std::remove(path_.c_str());
    }
  }

  void write(const SpectrumResult& result) {
    if (!opened_) return;
    errno = 0;
    write_spectrum_csv(file_, result);
    file_.close();
    if (file_.fail()) throw UsageError("--out " + path_ + ": writing the spectrum failed" + system_reason());
    complete_ = true;
  }

 private:
  std::string path_;
  std::ofstream file_;
  bool opened_ = false;
  bool complete_ = false;
};

RecordInfo info_of(const records::Record& r) {
  RecordInfo info;
  info.path = r.path;
  info.format = r.format;
  info.description = r.description;
  info.units = std::string(records::accel_unit_name(r.units_in_file));
  info.dt_s = r.dt_s;
  info.t0_s = r.t0_s;
  info.samples = r.horizontal_mps2.size();
  info.peak_as_read_mps2 = sim::peak_abs(r.horizontal_mps2);
  return info;
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
  r.record = info_of(record);
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
  const records::Record record = records::read_record(q.record_path, q.read_options);
  for (const std::string& note : record.notes) std::cerr << "note: " << note << '\n';
  if (!record.vertical_mps2.empty()) {
    std::cerr << "note: " << q.record_path << " has a third (vertical) column; the spectrum is of the second\n";
  }
  check_work_size(q, record.horizontal_mps2.size());
  CsvOutput csv(q);

  const SpectrumResult result = compute(q, record);
  csv.write(result);

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
      std::cerr << kPrefix << "plot not written: " << plot.message << '\n';
      return kExitInternalError;
    }
    if (!q.json) std::cout << "wrote " << *q.plot_path << '\n';
  }
  if (q.out_csv_path && !q.json) std::cout << "wrote " << *q.out_csv_path << '\n';
  std::cout.flush();
  if (!std::cout) {
    std::cerr << kPrefix << "cannot write the result to standard output\n";
    return kExitUsageError;
  }
  return kExitOk;
}

int fail(const std::string& message, int status) {
  std::cerr << kPrefix << message << '\n';
  return status;
}

}  // namespace

int spectrum_main(int argc, const char* const* argv) {
  try {
    const SpectrumParse parsed = parse_spectrum_arguments(argc, argv);
    if (!parsed.request) {
      std::cout << parsed.help_text;
      return kExitOk;
    }
    return run(*parsed.request);
  } catch (const UsageError& e) {
    return fail(e.what(), kExitUsageError);
  } catch (const records::RecordError& e) {
    return fail(e.what(), kExitUsageError);
  } catch (const sim::MeasureError& e) {
    return fail(std::string("the record cannot be measured: ") + e.what(), kExitUsageError);
  } catch (const std::bad_alloc&) {
    return fail("out of memory (a very long record?)", kExitInternalError);
  } catch (const std::exception& e) {
    return fail(std::string("internal error: ") + e.what(), kExitInternalError);
  }
}

}  // namespace rockwatch::cli
