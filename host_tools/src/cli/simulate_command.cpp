// `rockwatch simulate`: one record (pair) through sim::analyse, the engine every tool shares. This file only wires
// the parts together and maps every failure to a one-line message and exit status 2; the CLI adds no physics.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <new>
#include <optional>
#include <string>
#include <system_error>

#include "commands.hpp"
#include "history_csv.hpp"
#include "input_motion.hpp"
#include "option_values.hpp"
#include "rockwatch/records/record_error.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "simulate_report.hpp"
#include "simulate_request.hpp"
#include "usage_error.hpp"

namespace rockwatch::cli {

namespace {

constexpr const char* kPrefix = "rockwatch simulate: error: ";

// Bounds on the work one run may ask for: a typo such as --max-step 1e-9 or --t-end 1e9 should be an error message,
// not hours of computing or an exhausted machine. A 10-minute record at 0.5 ms is 1.2e6 steps.
constexpr double kMaxIntegrationSteps = 1e8;
constexpr double kMaxHistoryRows = 2e7;  // --out keeps every step in memory before writing

void check_work_size(const SimulateRequest& q, const InputMotion& in) {
  const double dt_s = in.motion.dt_s;
  const double n_sub = std::fmax(1.0, std::ceil(dt_s / q.analysis.max_step_s - 1e-9));  // as sim::analyse does
  const double h_s = dt_s / n_sub;
  const double t_end_s = q.analysis.t_end_s ? *q.analysis.t_end_s : in.motion.duration_s();
  const double worst_steps = (t_end_s + q.analysis.free_motion_limit_s) / h_s;
  const double limit = q.analysis.keep_history ? kMaxHistoryRows : kMaxIntegrationSteps;
  if (worst_steps > limit) {
    throw UsageError("integration step " + number_text(h_s) + " s over t_end = " + number_text(t_end_s) +
                     " s (plus up to " + number_text(q.analysis.free_motion_limit_s) + " s of free rocking) means up to " +
                     number_text(std::round(worst_steps)) + " steps, more than the " + number_text(limit) +
                     (q.analysis.keep_history ? " a run with --out may take" : " a run may take") +
                     ": raise --max-step or lower --t-end");
  }
}

std::string system_reason() {
  const int code = errno;
  return code != 0 ? std::string(": ") + std::strerror(code) : std::string();
}

// The CSV file is opened before the analysis, so a wrong directory is reported at once, not after a long run.
class CsvOutput {
 public:
  explicit CsvOutput(const SimulateRequest& q) {
    if (!q.out_csv_path) return;
    path_ = *q.out_csv_path;
    std::error_code ec;
    if (std::filesystem::equivalent(path_, q.record_path, ec) ||
        (q.vertical_path && std::filesystem::equivalent(path_, *q.vertical_path, ec))) {
      throw UsageError("--out " + path_ + " is an input record: choose another file name");
    }
    errno = 0;
    file_.open(path_, std::ios::out | std::ios::trunc | std::ios::binary);
    if (!file_) throw UsageError("--out " + path_ + ": cannot open the file for writing" + system_reason());
    opened_ = true;
  }
  CsvOutput(const CsvOutput&) = delete;
  CsvOutput& operator=(const CsvOutput&) = delete;

  // A failed run must not leave a truncated or empty file that looks like a result.
  ~CsvOutput() {
    if (opened_ && !complete_) {
      file_.close();
      std::remove(path_.c_str());
    }
  }

  void write(const sim::AnalysisResult& result) {
    if (!opened_) return;
    errno = 0;
    write_history_csv(file_, result.history);
    file_.close();
    if (file_.fail()) throw UsageError("--out " + path_ + ": writing the time history failed" + system_reason());
    complete_ = true;
  }

 private:
  std::string path_;
  std::ofstream file_;
  bool opened_ = false;
  bool complete_ = false;
};

int run(const SimulateRequest& q) {
  const InputMotion input = prepare_input(q);
  for (const std::string& note : input.notes) std::cerr << "note: " << note << '\n';
  check_work_size(q, input);
  CsvOutput csv(q);

  const sim::AnalysisResult result = sim::analyse(q.wall, input.motion, q.analysis);
  csv.write(result);

  if (q.json) {
    if (result.free_motion_undecided) {
      std::cerr << "note: free rocking after the record neither settled nor collapsed within "
                << number_text(q.analysis.free_motion_limit_s) << " s; collapse_after_end is false but undecided\n";
    }
    std::cout << result_json(q, result).dump(2) << '\n';
  } else {
    std::cout << summary_text(q, input, result);
  }
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

int simulate_main(int argc, const char* const* argv) {
  try {
    const SimulateParse parsed = parse_simulate_arguments(argc, argv);
    if (!parsed.request) {
      std::cout << parsed.help_text;
      return kExitOk;
    }
    return run(*parsed.request);
  } catch (const UsageError& e) {
    return fail(e.what(), kExitUsageError);
  } catch (const records::RecordError& e) {
    return fail(e.what(), kExitUsageError);
  } catch (const sim::AnalysisError& e) {
    return fail(std::string("analysis refused the input: ") + e.what(), kExitUsageError);
  } catch (const std::bad_alloc&) {
    return fail("out of memory (a very long record or --out history?)", kExitInternalError);
  } catch (const std::exception& e) {
    return fail(std::string("internal error: ") + e.what(), kExitInternalError);
  }
}

}  // namespace rockwatch::cli
