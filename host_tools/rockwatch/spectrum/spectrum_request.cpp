#include "spectrum/spectrum_request.hpp"

#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "common/process/output_file.hpp"
#include "rockwatch/core/design_spectrum.hpp"
#include "rockwatch/options/command_line.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

// The helpers in a namespace of their own: the files that include CLI11 are compiled as one unit (CMakeLists.txt),
// and theirs have the same names.
namespace {
namespace spectrum_request {

// Options are read as text and converted by option_values, so every message has one form and nan/inf are refused
// the same way everywhere.
struct RawOptions {
  RecordOptionTexts record;
  std::string g, damping, periods, out, plot, target, pga, p, tb, tc, td;
  bool json = false;
};

const char* const kFooter =
    "Spectrum: a damped SDOF oscillator per period (Nigam-Jennings recurrence, exact for input linear between\n"
    "samples), at rest at the first sample, peaks at the samples. sa_mps2 is the pseudo-spectral acceleration\n"
    "omega^2 * max|u|, the quantity design spectra Se(T) give.\n"
    "Intensity measures: PGA of the record as read; PGV and PGD after baseline correction (a least-squares\n"
    "c2 t^2 + c3 t^3 fit to the displacement, its second derivative subtracted from the acceleration; trapezoidal\n"
    "integration); Arias intensity pi/(2g) * integral of a^2 dt; D5-75 and D5-95 from the Husid curve.\n"
    "\n"
    "--json prints one object with exactly the keys periods_s, sa_mps2, pga_mps2, pgv_mps, pgd_m, arias_mps,\n"
    "d5_75_s, d5_95_s (null for a record without motion); only with --target also target_sa_mps2 (Se(T) at the\n"
    "same periods) and target (the spectrum's name); only with --suite also suite (dir, name, set, component,\n"
    "file, vertical_component), with --component on a --record file component, with --channel channel,\n"
    "with --gain gain_counts_per_mps2.\n"
    "--out writes the CSV columns period_s,sa_mps2 (and target_sa_mps2 with --target).\n"
    "The npr9998-2015 shape is back-calculated from the design paper's static results (NPR 9998:2015 bedrock\n"
    "parameters are not public); outputs that use it say so.\n"
    "\n"
    "Exit status: 0 done, 2 invalid options or input, 1 internal error (including a plot that could not be drawn).\n"
    "\n"
    "Examples:\n"
    "  rockwatch spectrum --record RSN6_IMPVALL.I_I-ELC180-hor1.AT2\n"
    "  rockwatch spectrum --record RSN6_IMPVALL.I_I-ELC180-hor1.AT2 --target npr9998-2015 --pga 0.25 --plot sa.png\n"
    "  rockwatch spectrum --record motion.csv --units cmps2 --periods 0.05:2:50 --out spectrum.csv --json\n"
    "  rockwatch spectrum --suite suite --set 3 --component X --target npr9998-2015 --pga 0.2\n";

void add_options(CLI::App& app, RawOptions& raw) {
  add_record_options(app, raw.record, VerticalOptions::none);
  app.add_option("--g", raw.g, "Gravity [m/s2] (default 9.81): converts records in g, --pga and the Arias intensity")
      ->type_name("MPS2");
  app.add_option("--damping", raw.damping, "Damping ratio of the oscillators, in [0, 1) (default 0.05)")->type_name("Z");
  app.add_option("--periods", raw.periods, "Log-spaced periods FROM:TO:N [s] (default 0.02:4:100)")
      ->type_name("FROM:TO:N");
  app.add_option("--out", raw.out, "Write the spectrum as CSV")->type_name("FILE.csv");
  app.add_flag("--json", raw.json, "Print the result as one JSON object on stdout");
  app.add_option("--plot", raw.plot, "Draw Sa(T) (and the target) to a PNG with matplotlib")->type_name("FILE.png");
  app.add_option("--target", raw.target,
                 "Design spectrum to compare with: npr9998-2015 | ec8-1A | ec8-2A | vertical-default | custom "
                 "(needs --pga; custom needs --p --tb --tc --td)")
      ->type_name("SPEC");
  app.add_option("--pga", raw.pga, "Design PGA a_g of the target [g]: Se(T) = a_g * g * shape(T)")->type_name("G");
  app.add_option("--p", raw.p, "custom target: plateau amplification p (>= 1)")->type_name("P");
  app.add_option("--tb", raw.tb, "custom target: start of the plateau TB [s]")->type_name("S");
  app.add_option("--tc", raw.tc, "custom target: end of the plateau TC [s]")->type_name("S");
  app.add_option("--td", raw.td, "custom target: start of the constant-displacement branch TD [s]")->type_name("S");
  app.footer(kFooter);
}

constexpr const char* kCustomOptions[] = {"--p", "--tb", "--tc", "--td"};

core::SpectrumShape custom_shape(const CLI::App& app, const RawOptions& raw) {
  std::string missing;
  for (const char* option : kCustomOptions) {
    if (!given(app, option)) missing += (missing.empty() ? "" : ", ") + std::string(option);
  }
  if (!missing.empty()) throw UsageError("--target custom needs --p, --tb, --tc and --td (missing " + missing + ")");
  const core::SpectrumShape s =
      core::spectrum_custom(parse_finite_number("--p", raw.p), parse_finite_number("--tb", raw.tb),
                            parse_finite_number("--tc", raw.tc), parse_finite_number("--td", raw.td));
  if (!(s.p >= 1.0)) throw UsageError("--p must be >= 1 (got " + number_text(s.p) + ")");
  if (!(s.tb_s > 0.0)) throw UsageError("--tb must be > 0 s (got " + number_text(s.tb_s) + ")");
  if (!(s.tc_s > s.tb_s)) {
    throw UsageError("--tc must be greater than --tb (got --tb " + number_text(s.tb_s) + ", --tc " + number_text(s.tc_s) +
                     ")");
  }
  if (!(s.td_s > s.tc_s)) {
    throw UsageError("--td must be greater than --tc (got --tc " + number_text(s.tc_s) + ", --td " + number_text(s.td_s) +
                     ")");
  }
  return s;
}

std::optional<SpectrumTarget> parse_target(const CLI::App& app, const RawOptions& raw) {
  const bool custom_given = given(app, "--p") || given(app, "--tb") || given(app, "--tc") || given(app, "--td");
  if (!given(app, "--target")) {
    if (given(app, "--pga")) throw UsageError("--pga is the design PGA of a --target spectrum: give --target too");
    if (custom_given) throw UsageError("--p, --tb, --tc and --td set a --target custom spectrum: give --target custom");
    return std::nullopt;
  }
  SpectrumTarget target;
  if (raw.target == "custom") {
    target.shape = custom_shape(app, raw);
  } else if (core::parse_spectrum_name(raw.target.c_str(), target.shape)) {
    if (custom_given) {
      throw UsageError("--p, --tb, --tc and --td apply to --target custom only (got --target " + quoted(raw.target) +
                       ")");
    }
  } else {
    throw UsageError("--target must be npr9998-2015, ec8-1A, ec8-2A, vertical-default or custom (got " +
                     quoted(raw.target) + ")");
  }
  if (!given(app, "--pga")) throw UsageError("--target needs --pga, the design PGA a_g in g");
  target.pga_g = parse_positive_number("--pga", raw.pga, " (a multiple of g)");
  return target;
}

}  // namespace spectrum_request
}  // namespace

PeriodGrid parse_period_grid(const std::string& option, const std::string& text) {
  using namespace spectrum_request;
  const std::string expected = option + " expects FROM:TO:N, e.g. 0.02:4:100 (got " + quoted(text) + ")";
  const std::size_t first = text.find(':');
  const std::size_t second = first == std::string::npos ? std::string::npos : text.find(':', first + 1);
  if (second == std::string::npos || text.find(':', second + 1) != std::string::npos) throw UsageError(expected);
  const std::string from_text = text.substr(0, first);
  const std::string to_text = text.substr(first + 1, second - first - 1);
  const std::string n_text = text.substr(second + 1);
  PeriodGrid grid;
  try {
    grid.from_s = parse_finite_number(option, from_text);
    grid.to_s = parse_finite_number(option, to_text);
  } catch (const UsageError&) {
    throw UsageError(expected);
  }
  if (!(grid.from_s > 0.0)) throw UsageError(option + ": FROM must be > 0 s (got " + quoted(text) + ")");
  if (!(grid.to_s > grid.from_s)) throw UsageError(option + ": TO must be greater than FROM (got " + quoted(text) + ")");
  // N: a plain decimal integer, so "1e2" and "10.5" are refused rather than read as something else.
  if (n_text.empty() || n_text.size() > 9 || n_text.find_first_not_of("0123456789") != std::string::npos) {
    throw UsageError(option + ": N must be a whole number of periods, >= 2 (got " + quoted(text) + ")");
  }
  const unsigned long n = std::stoul(n_text);
  if (n < 2) throw UsageError(option + ": N must be >= 2 (got " + quoted(text) + ")");
  if (n > kMaxSpectrumPeriods) {
    throw UsageError(option + ": N must be <= " + std::to_string(kMaxSpectrumPeriods) + " (got " + quoted(text) + ")");
  }
  grid.count = static_cast<std::size_t>(n);
  return grid;
}

SpectrumParse parse_spectrum_arguments(int argc, const char* const* argv) {
  using namespace spectrum_request;
  CLI::App app{"Elastic response spectrum and intensity measures (PGA, PGV, PGD, Arias intensity, D5-75, D5-95) "
               "of a ground-motion record, optionally against a design spectrum.",
               "rockwatch spectrum"};
  RawOptions raw;
  add_options(app, raw);
  if (std::optional<std::string> help = parse_command_line(app, argc, argv, "spectrum")) {
    return SpectrumParse{std::nullopt, std::move(*help)};
  }

  SpectrumRequest q;
  const double g_mps2 = given(app, "--g") ? parse_positive_number("--g", raw.g, " m/s2") : records::ReadOptions{}.g_mps2;
  q.record = parse_record_selection(app, raw.record, g_mps2);
  if (given(app, "--damping")) {
    q.damping = parse_finite_number("--damping", raw.damping);
    if (!(q.damping >= 0.0 && q.damping < 1.0)) {
      throw UsageError("--damping must be a ratio in [0, 1), e.g. 0.05 for 5 % (got " + number_text(q.damping) + ")");
    }
  }
  if (given(app, "--periods")) q.periods = parse_period_grid("--periods", raw.periods);
  q.target = parse_target(app, raw);
  if (given(app, "--out")) {
    if (raw.out.empty()) throw UsageError("--out needs a file name");
    check_output_file("--out", raw.out);
    q.out_csv_path = raw.out;
  }
  if (given(app, "--plot")) {
    if (raw.plot.empty()) throw UsageError("--plot needs a file name");
    // matplotlib takes the format from the extension and adds ".png" to a name without one, so "--plot fig" would
    // write fig.png while the tool reports fig.
    const std::string suffix = raw.plot.size() >= 4 ? raw.plot.substr(raw.plot.size() - 4) : std::string();
    if (suffix != ".png" && suffix != ".PNG") {
      throw UsageError("--plot must name a .png file, the image written (got " + options::quoted(raw.plot) + ")");
    }
    check_output_file("--plot", raw.plot);
    q.plot_path = raw.plot;
  }
  q.json = raw.json;
  return SpectrumParse{q, {}};
}

}  // namespace rockwatch::cli
