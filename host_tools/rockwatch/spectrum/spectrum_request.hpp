// What `rockwatch spectrum` was asked to do, parsed and validated from its command line.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "common/records_in/record_selection.hpp"
#include "rockwatch/core/design_spectrum.hpp"
#include "rockwatch/core/response_oscillator.hpp"
#include "rockwatch/sim/response_spectrum.hpp"

namespace rockwatch::cli {

// Longest --periods list: a typo such as 0.02:4:1e9 must be an error, not hours of work.
inline constexpr std::size_t kMaxSpectrumPeriods = 10000;

struct PeriodGrid {
  double from_s = sim::kDefaultSpectrumFromS;
  double to_s = sim::kDefaultSpectrumToS;
  std::size_t count = sim::kDefaultSpectrumPeriods;
};

// The design spectrum to compare with: Se(T) = pga_g · g · shape(T).
struct SpectrumTarget {
  core::SpectrumShape shape;
  double pga_g = 0.0;  // design PGA a_g in units of g (the --g value)
};

struct SpectrumRequest {
  RecordSelection record;             // --record or --suite, --units, --dt, --gain; g from --g
  double damping = core::kDefaultDampingRatio;
  PeriodGrid periods;
  std::optional<SpectrumTarget> target;
  std::optional<std::string> out_csv_path;
  std::optional<std::string> plot_path;
  bool json = false;
  double g_mps2() const { return record.read_options.g_mps2; }
};

struct SpectrumParse {
  std::optional<SpectrumRequest> request;  // empty: print help_text, exit 0
  std::string help_text;
};

// Parses `rockwatch spectrum` arguments (argv[0] is the command name). Throws UsageError naming the option at fault.
SpectrumParse parse_spectrum_arguments(int argc, const char* const* argv);

// "FROM:TO:N" with 0 < FROM < TO and 2 ≤ N ≤ kMaxSpectrumPeriods. Throws UsageError naming `option`.
PeriodGrid parse_period_grid(const std::string& option, const std::string& text);

}  // namespace rockwatch::cli
