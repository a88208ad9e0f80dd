// What `rockwatch spectrum` computes and prints: the JSON object for scripts, the summary for engineers, the CSV.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/records_in/input_motion.hpp"
#include "rockwatch/sim/intensity_measures.hpp"
#include "rockwatch/sim/response_spectrum.hpp"
#include "spectrum/spectrum_request.hpp"

namespace rockwatch::cli {

// The periods of the summary table, computed exactly (own oscillators), not interpolated from the grid.
inline constexpr double kStandardPeriods_s[] = {0.1, 0.2, 0.3, 0.5, 1.0, 2.0};

struct SpectrumResult {
  RecordInfo record;
  bool vertical_column_ignored = false;   // a plain file's third column: only the horizontal is used
  sim::ResponseSpectrum spectrum;         // at the requested periods
  sim::ResponseSpectrum standard;         // at kStandardPeriods_s
  sim::IntensityMeasures measures;
  std::vector<double> target_sa_mps2;     // Se(T) at spectrum.periods_s; empty without --target
  std::vector<double> standard_target_sa_mps2;
};

// Se(T) = a_g · g · shape(T) [m/s²].
double target_sa_mps2(const SpectrumTarget& target, double g_mps2, double period_s);

// Exactly the documented keys, in a fixed order; target keys only with --target; undefined durations are null; the
// record-selection keys (add_selection_json) only when --suite, --component, --channel or --gain was used.
nlohmann::ordered_json spectrum_json(const SpectrumRequest& request, const SpectrumResult& result);

// Multi-line, human-readable summary ending with a newline.
std::string spectrum_summary_text(const SpectrumRequest& request, const SpectrumResult& result);

inline constexpr const char* kSpectrumCsvHeader = "period_s,sa_mps2";
inline constexpr const char* kSpectrumCsvHeaderWithTarget = "period_s,sa_mps2,target_sa_mps2";

// Header and one row per period, numbers in shortest round-trip form; the caller checks the stream.
void write_spectrum_csv(std::ostream& out, const SpectrumResult& result);

// The target's name and parameters in one line, e.g. "npr9998-2015 (p 2.5, TB 0.15 s, TC 0.4 s, TD 0.67 s)".
std::string target_text(const SpectrumTarget& target);

}  // namespace rockwatch::cli
