// What `rockwatch generate` was asked to do, parsed and validated from its command line.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "rockwatch/core/design_spectrum.hpp"
#include "rockwatch/sim/synthesis/ground_motion_generator.hpp"

namespace rockwatch::cli {

// Bounds on the work one run may ask for: a typo such as --sets 1000 or --dt 1e-7 should be an error message, not
// hours of computing. The paper's suite is 11 sets of 4001 samples.
inline constexpr int kMaxGenerateSets = 100;
inline constexpr std::size_t kMaxGenerateIterations = 1000;
inline constexpr double kMaxGenerateSamples = 1e6;  // per component: duration / dt

struct GenerateRequest {
  std::string out_dir;                        // --out, created if missing
  int sets = 11;                              // --sets: set 1 .. sets
  sim::synthesis::GeneratorSettings settings; // seed, targets, a_g, a_vg / a_g, dt, duration, iterations
  bool plots = true;                          // false with --no-plots
  bool json = false;
  bool force = false;                         // overwrite an existing suite in out_dir
  // Every setting that shapes the records, as options ("--sets 11 --seed 9998 --target npr9998-2015 ..."), with
  // the defaults written out: the regenerating command, even if a later version changes a default.
  std::string settings_arguments;
};

struct GenerateParse {
  std::optional<GenerateRequest> request;  // empty: print help_text, exit 0
  std::string help_text;
};

// Parses `rockwatch generate` arguments (argv[0] is the command name). Throws UsageError naming the option at fault.
GenerateParse parse_generate_arguments(int argc, const char* const* argv);

// A target spectrum: a name core::parse_spectrum_name knows, or "custom:P,TB,TC,TD" (p >= 1, 0 < TB < TC < TD).
// Throws UsageError naming `option`.
core::SpectrumShape parse_target_spec(const std::string& option, const std::string& text);

// The text parse_target_spec reads back as the same shape: the name, or "custom:P,TB,TC,TD".
std::string target_spec_text(const core::SpectrumShape& shape);

}  // namespace rockwatch::cli
