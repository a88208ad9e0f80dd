#include "generate/generate_request.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "common/process/text_report.hpp"
#include "rockwatch/options/command_line.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

// The helpers in a namespace of their own: the files that include CLI11 are compiled as one unit (CMakeLists.txt),
// and theirs have the same names.
namespace {
namespace generate_request {

// Options are read as text and converted by option_values, so every message has one form and nan/inf are refused
// the same way everywhere.
struct RawOptions {
  std::string out, sets, seed, target = "npr9998-2015", vertical_target = "vertical-default", pga, vertical_ratio;
  std::string dt, duration, iterations;
  bool no_plots = false, json = false, force = false;
};

const char* const kFooterMethod =
    "Generates the project's NPR 9998-compatible ground-motion suite (SPEC section 6): per set three independent\n"
    "components, X and Y horizontal (target SPEC, PGA a_g) and Z vertical (--vertical-target, PGA a_vg = R a_g),\n"
    "each filtered white noise under a Groningen-like envelope, its Fourier amplitudes corrected until the\n"
    "5 %-damped spectrum matches the target over 0.05-4 s with the PGA anchored to the target PGA, then\n"
    "baseline-corrected (zero final velocity and displacement). Deterministic: the same options give the same\n"
    "records; each (set, component) has its own random stream, so --sets 12 keeps sets 1-11 unchanged.\n";

// The acceptance rules with the generator's values, so the help cannot drift from what it checks.
std::string acceptance_text(const sim::synthesis::GeneratorSettings& s) {
  const auto window = [](const sim::synthesis::DurationWindow& w) {
    return number_text(w.min_s) + "-" + number_text(w.max_s) + " s";
  };
  return "Acceptance: every component's spectrum within [" + number_text(s.accept_min) + ", " +
         number_text(s.accept_max) + "] x target at every period of " + number_text(s.check_from_s) + "-" +
         number_text(s.check_to_s) + " s and its\nsignificant durations in their windows (X, Y: D5-75 " +
         window(s.horizontal_d5_75_s) + ", D5-95 " + window(s.horizontal_d5_95_s) + "; Z: D5-75 " +
         window(s.vertical_d5_75_s) + ",\nD5-95 " + window(s.vertical_d5_95_s) +
         "); a record that misses is drawn again from its own stream, up to " + std::to_string(s.max_attempts) +
         " times,\nelse the closest draw is kept and reported; and the suite mean of the X and Y ratios (and of the "
         "Z ratios)\nwithin 1 +- " + number_text(s.suite_mean_tolerance) + ".\n";
}

const char* const kFooterFiles =
    "\n"
    "SPEC: npr9998-2015 (p 2.5, TB 0.15, TC 0.40, TD 0.67 s; BACK-CALCULATED from the design paper's static\n"
    "results, the NPR 9998:2015 bedrock parameters are not public), ec8-1A, ec8-2A, vertical-default (EC8 vertical:\n"
    "p 3.0, TB 0.05, TC 0.15, TD 1.0 s), or custom:P,TB,TC,TD (p >= 1, 0 < TB < TC < TD, e.g. custom:2.5,0.1,0.3,0.8).\n"
    "\n"
    "Writes into DIR (created if missing; an existing suite is only replaced with --force):\n"
    "  setNN.txt         one per set: time, X, Y, Z [m/s2] with a header naming the targets, seed and command\n"
    "  manifest.json     the sets, the regenerating command, the settings and per record seed, pga_mps2, pga_g,\n"
    "                    pgv_mps, pgd_m, d5_75_s, d5_95_s, arias_mps, spectral_ratio_min, spectral_ratio_max,\n"
    "                    spectrum_accepted, durations_accepted, accepted, attempts, final_velocity_mps,\n"
    "                    final_displacement_m; the suite mean's ratios and verdicts\n"
    "  manifest.csv      one row per record with the same measures\n"
    "  spectra_horizontal.png, spectra_vertical.png, spectra_X.png, spectra_Y.png, spectra_Z.png\n"
    "                    every spectrum, the suite mean, the target and the acceptance limits (not with --no-plots;\n"
    "                    matplotlib: $ROCKWATCH_PYTHON, else /usr/bin/python3, else python3 on PATH)\n"
    "Use a record with --suite DIR --set N --component X|Y|Z in rockwatch simulate and rockwatch spectrum.\n"
    "Progress goes to stderr; the summary (or with --json the manifest) to stdout.\n"
    "\n"
    "Exit status: 0 every record and the suite mean accepted; 1 some not accepted (listed on stderr; the files are\n"
    "written all the same), a plot could not be made, or an internal error; 2 invalid options or an unwritable or\n"
    "occupied DIR (nothing written).\n"
    "\n"
    "Examples:\n"
    "  rockwatch generate --out suite\n"
    "  rockwatch generate --out suite-ec8 --target ec8-1A --pga 0.25 --sets 7 --seed 42 --no-plots\n"
    "  rockwatch generate --out suite-custom --target custom:2.5,0.1,0.3,0.8 --vertical-ratio 0.7 --force\n";

// The defaults in the help are the generator's, so they cannot drift apart.
void add_options(CLI::App& app, RawOptions& raw) {
  const sim::synthesis::GeneratorSettings defaults;
  app.add_option("--out", raw.out, "Directory for the set files, manifest and plots (created if missing)")
      ->type_name("DIR");
  app.add_option("--sets", raw.sets, "Number of record sets, 1 to " + std::to_string(kMaxGenerateSets) + " (default " +
                                         std::to_string(GenerateRequest{}.sets) + ")")
      ->type_name("N");
  app.add_option("--seed", raw.seed,
                 "Suite seed, a whole number 0 to 2^64-1 (default " + std::to_string(defaults.seed) + ")")
      ->type_name("S");
  app.add_option("--target", raw.target,
                 "Horizontal target spectrum: npr9998-2015 (default, back-calculated) | ec8-1A | ec8-2A | "
                 "vertical-default | custom:P,TB,TC,TD")
      ->type_name("SPEC");
  app.add_option("--vertical-target", raw.vertical_target,
                 "Vertical target spectrum, as --target (default vertical-default)")
      ->type_name("SPEC");
  app.add_option("--pga", raw.pga, "Horizontal target PGA a_g [g] (default " + number_text(defaults.pga_g) + ")")
      ->type_name("G");
  app.add_option("--vertical-ratio", raw.vertical_ratio,
                 "Vertical PGA ratio a_vg / a_g (default " + number_text(defaults.vertical_pga_ratio) +
                     "; the paper: a_vg = a_g)")
      ->type_name("R");
  app.add_option("--dt", raw.dt, "Sample interval [s] (default " + number_text(defaults.dt_s) + ")")->type_name("S");
  app.add_option("--duration", raw.duration,
                 "Record length including the quiet lead and tail [s] (default " + number_text(defaults.duration_s) +
                     ")")
      ->type_name("S");
  app.add_option("--iterations", raw.iterations,
                 "Fourier-correction iterations per draw, 1 to " + std::to_string(kMaxGenerateIterations) +
                     " (default " + std::to_string(defaults.iterations) + ")")
      ->type_name("N");
  app.add_flag("--no-plots", raw.no_plots, "Write no PNG plots (no Python needed)");
  app.add_flag("--json", raw.json, "Print the manifest (JSON) on stdout instead of the summary");
  app.add_flag("--force", raw.force, "Replace an existing suite (manifest.json) in --out");
  app.footer(std::string(kFooterMethod) + acceptance_text(defaults) + kFooterFiles);
}

// Plausible ranges: beyond them the generator's arithmetic underflows (a PGA of 1e-320 g gives no measurable
// record, a ratio of 1e-320 a vertical that "cannot be measured") or the records mean nothing.
constexpr double kMinGeneratePga_g = 1e-6, kMaxGeneratePga_g = 10.0;
constexpr double kMinVerticalRatio = 1e-3, kMaxVerticalRatio = 10.0;

// A number in [min, max] or a UsageError naming the option, its range and what was given.
double parse_in_range(const char* option, const std::string& text, double min, double max, const char* unit) {
  const double value = parse_positive_number(option, text, unit);
  if (value < min || value > max) {
    throw UsageError(std::string(option) + " must be from " + number_text(min) + " to " + number_text(max) + unit +
                     " (got " + number_text(value) + ")");
  }
  return value;
}

// whole_number or a UsageError; `what` completes "OPTION must be a whole number WHAT".
std::uint64_t parse_whole(const char* option, const std::string& text, std::uint64_t min, std::uint64_t max,
                          const std::string& what) {
  const std::optional<std::uint64_t> value = whole_number(text, min, max);
  if (!value) {
    throw UsageError(std::string(option) + " must be a whole number " + what + " (got " + quoted(text) + ")");
  }
  return *value;
}

void append_option(std::string& arguments, const char* option, const std::string& value) {
  arguments += (arguments.empty() ? "" : " ") + std::string(option) + " " + shell_quoted(value);
}

std::string canonical_arguments(const GenerateRequest& q) {
  const sim::synthesis::GeneratorSettings& s = q.settings;
  std::string a;
  append_option(a, "--sets", std::to_string(q.sets));
  append_option(a, "--seed", std::to_string(s.seed));
  append_option(a, "--target", target_spec_text(s.horizontal_target));
  append_option(a, "--vertical-target", target_spec_text(s.vertical_target));
  append_option(a, "--pga", number_text(s.pga_g));
  append_option(a, "--vertical-ratio", number_text(s.vertical_pga_ratio));
  append_option(a, "--dt", number_text(s.dt_s));
  append_option(a, "--duration", number_text(s.duration_s));
  append_option(a, "--iterations", std::to_string(s.iterations));
  return a;
}

}  // namespace generate_request
}  // namespace

core::SpectrumShape parse_target_spec(const std::string& option, const std::string& text) {
  using namespace generate_request;
  constexpr const char* kCustom = "custom:";
  core::SpectrumShape shape;
  if (text.rfind(kCustom, 0) != 0) {
    if (core::parse_spectrum_name(text.c_str(), shape)) return shape;
    throw UsageError(option + " must be npr9998-2015, ec8-1A, ec8-2A, vertical-default or custom:P,TB,TC,TD (got " +
                     quoted(text) + ")");
  }
  const std::vector<std::string> fields = split_fields(text.substr(std::string(kCustom).size()), ',');
  const std::string expected = option + " custom:P,TB,TC,TD needs four numbers, e.g. custom:2.5,0.1,0.3,0.8 (got " +
                               quoted(text) + ")";
  if (fields.size() != 4) throw UsageError(expected);
  double values[4] = {};
  for (std::size_t i = 0; i < 4; ++i) {
    try {
      values[i] = parse_finite_number(option, fields[i]);
    } catch (const UsageError&) {
      throw UsageError(expected);
    }
  }
  shape = core::spectrum_custom(values[0], values[1], values[2], values[3]);
  const std::string got = " (got " + quoted(text) + ")";
  if (!(shape.p >= 1.0)) throw UsageError(option + ": the plateau amplification P must be >= 1" + got);
  if (!(shape.tb_s > 0.0)) throw UsageError(option + ": TB must be > 0 s" + got);
  if (!(shape.tc_s > shape.tb_s)) throw UsageError(option + ": TC must be greater than TB (TB < TC < TD)" + got);
  if (!(shape.td_s > shape.tc_s)) throw UsageError(option + ": TD must be greater than TC (TB < TC < TD)" + got);
  return shape;
}

std::string target_spec_text(const core::SpectrumShape& s) {
  using namespace generate_request;
  if (s.kind != core::SpectrumKind::custom) return core::spectrum_name(s.kind);
  return "custom:" + number_text(s.p) + "," + number_text(s.tb_s) + "," + number_text(s.tc_s) + "," +
         number_text(s.td_s);
}

GenerateParse parse_generate_arguments(int argc, const char* const* argv) {
  using namespace generate_request;
  CLI::App app{"Spectrum-compatible ground-motion suite (SPEC section 6): record sets of X, Y (horizontal) and Z "
               "(vertical) matched to design spectra, with a manifest of their measures and plots of their spectra.",
               "rockwatch generate"};
  RawOptions raw;
  add_options(app, raw);
  if (std::optional<std::string> help = parse_command_line(app, argc, argv, "generate")) {
    return GenerateParse{std::nullopt, std::move(*help)};
  }

  GenerateRequest q;
  if (!given(app, "--out")) throw UsageError("--out DIR is required: the directory the suite is written to");
  if (raw.out.empty()) throw UsageError("--out needs a directory name");
  q.out_dir = raw.out;
  sim::synthesis::GeneratorSettings& s = q.settings;
  if (given(app, "--sets")) {
    q.sets = static_cast<int>(parse_whole("--sets", raw.sets, 1, kMaxGenerateSets,
                                          "from 1 to " + std::to_string(kMaxGenerateSets)));
  }
  if (given(app, "--seed")) s.seed = parse_whole("--seed", raw.seed, 0, UINT64_MAX, "from 0 to 2^64-1");
  s.horizontal_target = parse_target_spec("--target", raw.target);
  s.vertical_target = parse_target_spec("--vertical-target", raw.vertical_target);
  if (given(app, "--pga")) s.pga_g = parse_in_range("--pga", raw.pga, kMinGeneratePga_g, kMaxGeneratePga_g, " g");
  if (given(app, "--vertical-ratio")) {
    s.vertical_pga_ratio =
        parse_in_range("--vertical-ratio", raw.vertical_ratio, kMinVerticalRatio, kMaxVerticalRatio, " (a_vg / a_g)");
  }
  if (given(app, "--dt")) {
    s.dt_s = parse_positive_number("--dt", raw.dt, " s");
    // Two samples per period at the shortest period matched (Nyquist); coarser, the generator fails mid-run with a
    // message about its baseline correction instead.
    const double max_dt_s = std::min(s.match_from_s, s.check_from_s) / 2.0;
    if (s.dt_s > max_dt_s) {
      throw UsageError("--dt must be at most " + number_text(max_dt_s) + " s: the spectrum is matched down to " +
                       number_text(2.0 * max_dt_s) + " s periods, which need two samples per period (got " +
                       number_text(s.dt_s) + ")");
    }
  }
  if (given(app, "--duration")) s.duration_s = parse_positive_number("--duration", raw.duration, " s");
  if (given(app, "--iterations")) {
    s.iterations = static_cast<std::size_t>(parse_whole("--iterations", raw.iterations, 1, kMaxGenerateIterations,
                                                        "from 1 to " + std::to_string(kMaxGenerateIterations)));
  }
  const double samples = s.duration_s / s.dt_s;
  if (samples > kMaxGenerateSamples) {
    throw UsageError("--duration " + number_text(s.duration_s) + " s at --dt " + number_text(s.dt_s) + " s means " +
                     number_text(samples) + " samples per record, more than the " + number_text(kMaxGenerateSamples) +
                     " a run may take: raise --dt or shorten --duration");
  }
  // The generator's own limits (an envelope longer than the record, a band outside the Nyquist range): named by
  // the generator, refused here before anything is written.
  try {
    sim::synthesis::validate_settings(s);
  } catch (const sim::synthesis::GeneratorError& e) {
    throw UsageError(std::string("the generator refuses these settings (--dt ") + number_text(s.dt_s) +
                     " s, --duration " + number_text(s.duration_s) + " s): " + e.what());
  }
  q.plots = !raw.no_plots;
  q.json = raw.json;
  q.force = raw.force;
  q.settings_arguments = canonical_arguments(q);
  return GenerateParse{q, {}};
}

}  // namespace rockwatch::cli
