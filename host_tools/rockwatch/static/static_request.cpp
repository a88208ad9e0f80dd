#include "static/static_request.hpp"

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "rockwatch/core/design_spectrum.hpp"
#include "rockwatch/core/static_check.hpp"
#include "rockwatch/options/command_line.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

// The helpers in a namespace of their own: the files that include CLI11 are compiled as one unit (CMakeLists.txt),
// and theirs have the same names.
namespace {
namespace static_request {

// Options are read as text and converted by option_values, so messages have one form and nan/inf are refused the
// same way as in `simulate`.
struct RawOptions {
  std::string wall = "paper", b, h, h1, h2, fp, a, psi, rho, g;
  std::string lambda, code = "both", spectrum = "npr9998-2015", p, tb, tc, td, out;
  bool json = false, sweep = false;
};

const char* const kFooter =
    "Static non-linear kinematic analysis (SPEC section 5, the design paper's section 3), per metre of wall:\n"
    "  K = 4b/h, X = b/2, T = 2 pi lambda sqrt(h / (8 g (1 - lambda^2))), x_eq,max = lambda X,\n"
    "  allowable PGA a_g = x_eq,max (2 pi / T)^2 / shape(T), i.e. Sd(T) = Se(T) (T / 2 pi)^2 = x_eq,max.\n"
    "With --fp > 0 or --psi != 0 the general case applies (f = Fp / W, W = rho g b h):\n"
    "  K = (4b/h)(1 + (2 - a) f) - psi, X = (b (1 + (2 - a) f) - psi h / 4) / (2 (1 + 2f)),\n"
    "  T = 2 pi lambda sqrt(h / (8 g (1 + 2f)(1 - lambda^2))); its output is labelled \"derived by virtual work\".\n"
    "Only h = h1 + h2 enters; h1 and h2 are checked (> b) when given. --a matters only with --fp > 0.\n"
    "Codes: ntc2008 lambda = 0.4, nzsee2016 lambda = 0.6.\n"
    "Spectra (EC8 shape: 1 + (T/TB)(p - 1), p, p TC/T, p TC TD/T^2):\n"
    "  npr9998-2015  p 2.5, TB 0.15, TC 0.40, TD 0.67 s: BACK-CALCULATED from the paper's static results (the\n"
    "                NPR 9998:2015 bedrock parameters are not public); the default\n"
    "  ec8-1A        EN 1998-1 type 1, ground A: p 2.5, TB 0.15, TC 0.40, TD 2.0 s\n"
    "  ec8-2A        EN 1998-1 type 2, ground A: p 2.5, TB 0.05, TC 0.25, TD 1.2 s\n"
    "  custom        --p P --tb S --tc S --td S (p >= 1, 0 < TB < TC < TD), e.g. from the NEN web tool\n"
    "\n"
    "--json prints one object with exactly the keys T_s, x_eq_max_m, allowable_pga_g, K, X_m, lambda, spectrum\n"
    "(the spectrum's name) for --lambda or a single --code; with --code both (the default) an array of two such\n"
    "objects, ntc2008 then nzsee2016. Labels (back-calculated spectrum, virtual-work derivation) go to stderr as\n"
    "notes.\n"
    "\n"
    "--sweep --out DIR writes DIR/static_sweep.csv (h_over_b, h_m, lambda, T_s, x_eq_max_m, allowable_pga_g;\n"
    "h/b = 20, 25, 30, 35, 40 with b = 0.1 m, lambda = 0.10 to 0.90 by 0.01: 405 rows) and DIR/static_sweep.png\n"
    "(the paper's Figure 3, drawn by matplotlib: $ROCKWATCH_PYTHON, else /usr/bin/python3, else python3 on PATH).\n"
    "DIR is created if missing.\n"
    "\n"
    "Exit status: 0 done; 2 invalid options or an unwritable --out (nothing written); 1 the PNG could not be made\n"
    "(no Python with matplotlib, or the plot failed: the CSV is written all the same) or an internal error.\n"
    "\n"
    "Examples:\n"
    "  rockwatch static                                   the paper's wall, NTC 2008 and NZSEE 2016\n"
    "  rockwatch static --h 4 --b 0.1 --lambda 0.5 --json\n"
    "  rockwatch static --spectrum custom --p 2.5 --tb 0.1 --tc 0.3 --td 0.8 --code ntc2008\n"
    "  rockwatch static --sweep --out figure3\n";

void add_options(CLI::App& app, RawOptions& raw) {
  app.add_option("--wall", raw.wall, "Base wall: paper (b 0.10, h1 = h2 = 1.75, rho 1800, Fp 0, a 0)")
      ->type_name("paper");
  app.add_option("--b", raw.b, "Wall thickness b [m]")->type_name("M");
  app.add_option("--h", raw.h, "Total height h [m] (sets h1 = h2 = h/2; not with --h1/--h2)")->type_name("M");
  app.add_option("--h1", raw.h1, "Bottom block height [m] (only h1 + h2 enters the static check)")->type_name("M");
  app.add_option("--h2", raw.h2, "Top block height [m] (only h1 + h2 enters the static check)")->type_name("M");
  app.add_option("--fp", raw.fp, "Overburden on the top of the wall [N per m of wall] (default 0)")
      ->type_name("N_PER_M");
  app.add_option("--a", raw.a, "Overburden eccentricity, fraction of b from the top hinge, in [0, 1] (default 0)")
      ->type_name("A");
  app.add_option("--psi", raw.psi, "Out-of-plumb angle psi [rad] (default 0); must leave K > 0")->type_name("RAD");
  app.add_option("--rho", raw.rho, "Masonry density [kg/m3] (default 1800; enters only through f = Fp / W)")
      ->type_name("KG_M3");
  app.add_option("--g", raw.g, "Gravity [m/s2] (default 9.81)")->type_name("MPS2");
  app.add_option("--lambda", raw.lambda, "Instability factor x_eq,max / X in (0, 1) (not with --code)")->type_name("L");
  app.add_option("--code", raw.code, "Lambda of a code: ntc2008 (0.4), nzsee2016 (0.6) or both (default)")
      ->type_name("ntc2008|nzsee2016|both");
  app.add_option("--spectrum", raw.spectrum, "Spectrum shape: npr9998-2015 (default, back-calculated) | ec8-1A | "
                                             "ec8-2A | custom")
      ->type_name("NAME");
  app.add_option("--p", raw.p, "Custom spectrum: plateau amplification (>= 1)")->type_name("P");
  app.add_option("--tb", raw.tb, "Custom spectrum: start of the plateau TB [s]")->type_name("S");
  app.add_option("--tc", raw.tc, "Custom spectrum: end of the plateau TC [s]")->type_name("S");
  app.add_option("--td", raw.td, "Custom spectrum: start of the constant-displacement branch TD [s]")->type_name("S");
  app.add_flag("--json", raw.json, "Print the result as JSON (an object, or an array of two for --code both)");
  app.add_flag("--sweep", raw.sweep, "Allowable PGA versus lambda for h/b = 20...40 (the paper's Figure 3), to --out");
  app.add_option("--out", raw.out, "Directory for --sweep's static_sweep.csv and static_sweep.png")->type_name("DIR");
  app.footer(kFooter);
}

void reject_together(bool first_given, const char* first, bool second_given, const char* second,
                     const std::string& why) {
  if (first_given && second_given) {
    throw UsageError(std::string(first) + " cannot be combined with " + second + ": " + why);
  }
}

constexpr const char* kSpectrumNames = "npr9998-2015, ec8-1A, ec8-2A or custom";

struct CustomParameter {
  const char* option;
  std::string RawOptions::*text;
  std::optional<double> StaticSettings::*value;
  double core::SpectrumShape::*member;
};

constexpr CustomParameter kCustomParameters[] = {
    {"--p", &RawOptions::p, &StaticSettings::p, &core::SpectrumShape::p},
    {"--tb", &RawOptions::tb, &StaticSettings::tb_s, &core::SpectrumShape::tb_s},
    {"--tc", &RawOptions::tc, &StaticSettings::tc_s, &core::SpectrumShape::tc_s},
    {"--td", &RawOptions::td, &StaticSettings::td_s, &core::SpectrumShape::td_s},
};

core::SpectrumShape parse_custom_spectrum(const StaticSettings& raw) {
  std::string missing;
  for (const CustomParameter& c : kCustomParameters) {
    if (!(raw.*c.value)) missing += (missing.empty() ? "" : ", ") + std::string(c.option);
  }
  if (!missing.empty()) {
    throw UsageError("--spectrum custom needs --p, --tb, --tc and --td (missing " + missing + ")");
  }
  core::SpectrumShape s = core::spectrum_custom(0.0, 0.0, 0.0, 0.0);
  for (const CustomParameter& c : kCustomParameters) s.*c.member = check_finite_number(c.option, *(raw.*c.value));
  if (!(s.p >= 1.0)) throw UsageError("--p must be >= 1: the plateau amplifies the PGA (got " + number_text(s.p) + ")");
  if (!(s.tb_s > 0.0)) throw UsageError("--tb must be > 0 s (got " + number_text(s.tb_s) + ")");
  if (!(s.tc_s > s.tb_s)) {
    throw UsageError("--tc must be greater than --tb (TB < TC < TD; got TB " + number_text(s.tb_s) + " s, TC " +
                     number_text(s.tc_s) + " s)");
  }
  if (!(s.td_s > s.tc_s)) {
    throw UsageError("--td must be greater than --tc (TB < TC < TD; got TC " + number_text(s.tc_s) + " s, TD " +
                     number_text(s.td_s) + " s)");
  }
  return s;
}

core::SpectrumShape parse_spectrum(const StaticSettings& settings) {
  const std::string name = settings.spectrum.value_or("npr9998-2015");
  if (name == "custom") return parse_custom_spectrum(settings);
  for (const CustomParameter& c : kCustomParameters) {
    if (settings.*c.value) {
      throw UsageError(std::string(c.option) + " sets a custom spectrum: it needs --spectrum custom (got --spectrum " +
                       quoted(name) + ")");
    }
  }
  core::SpectrumShape s;
  if (name == "vertical-default") {
    throw UsageError("--spectrum vertical-default is the vertical shape; the static check needs a horizontal one: " +
                     std::string(kSpectrumNames));
  }
  if (!core::parse_spectrum_name(name.c_str(), s)) {
    throw UsageError("--spectrum must be " + std::string(kSpectrumNames) + " (got " + quoted(name) + ")");
  }
  return s;
}

std::vector<StaticCase> parse_cases(const StaticSettings& raw) {
  reject_together(bool(raw.lambda), "--lambda", bool(raw.code), "--code",
                  "give one instability factor, or the code(s) that set it");
  if (raw.lambda) {
    const double lambda = check_finite_number("--lambda", *raw.lambda);
    if (!(lambda > 0.0 && lambda < 1.0)) {
      throw UsageError("--lambda must be in (0, 1), exclusive: x_eq,max = lambda X lies between rest and instability "
                       "(got " + number_text(lambda) + ")");
    }
    return {StaticCase{std::nullopt, lambda}};
  }
  const std::string code_name = raw.code.value_or("both");
  if (code_name == "both") {
    return {StaticCase{core::InstabilityCode::ntc2008, core::code_lambda(core::InstabilityCode::ntc2008)},
            StaticCase{core::InstabilityCode::nzsee2016, core::code_lambda(core::InstabilityCode::nzsee2016)}};
  }
  core::InstabilityCode code{};
  if (!core::parse_code_name(code_name.c_str(), code)) {
    throw UsageError("--code must be ntc2008 (lambda 0.4), nzsee2016 (lambda 0.6) or both (got " + quoted(code_name) +
                     ")");
  }
  return {StaticCase{code, core::code_lambda(code)}};
}

struct InputField {
  const char* field;   // core::run_static_check's name
  const char* option;  // the option that sets it
  std::string RawOptions::*text;
  std::optional<double> StaticSettings::*value;
  double core::StaticInputs::*member;
};

constexpr InputField kInputFields[] = {
    {"b", "--b", &RawOptions::b, &StaticSettings::b_m, &core::StaticInputs::b_m},
    {"h1", "--h1", &RawOptions::h1, &StaticSettings::h1_m, &core::StaticInputs::h1_m},
    {"h2", "--h2", &RawOptions::h2, &StaticSettings::h2_m, &core::StaticInputs::h2_m},
    {"fp", "--fp", &RawOptions::fp, &StaticSettings::fp_npm, &core::StaticInputs::fp_npm},
    {"a", "--a", &RawOptions::a, &StaticSettings::a, &core::StaticInputs::a},
    {"psi", "--psi", &RawOptions::psi, &StaticSettings::psi_rad, &core::StaticInputs::psi_rad},
    {"rho", "--rho", &RawOptions::rho, &StaticSettings::rho_kgpm3, &core::StaticInputs::rho_kgpm3},
    {"g", "--g", &RawOptions::g, &StaticSettings::g_mps2, &core::StaticInputs::g_mps2},
};

core::StaticInputs parse_inputs(const StaticSettings& raw, std::vector<std::string>& given_options) {
  if (raw.wall && *raw.wall != "paper") {
    throw UsageError("--wall must be paper, the only built-in wall (got " + quoted(*raw.wall) +
                     "); set its dimensions with --b and --h (or --h1 and --h2)");
  }
  reject_together(bool(raw.h_m), "--h", bool(raw.h1_m), "--h1", "--h sets h1 = h2 = h/2");
  reject_together(bool(raw.h_m), "--h", bool(raw.h2_m), "--h2", "--h sets h1 = h2 = h/2");
  core::StaticInputs in;  // the paper's wall
  for (const InputField& f : kInputFields) {
    if (!(raw.*f.value)) continue;
    // The command line's values are finite already; the module's may not be.
    in.*f.member = check_finite_number(f.option, *(raw.*f.value));
    given_options.emplace_back(f.option);
  }
  if (raw.h_m) {
    core::set_total_height(in, check_finite_number("--h", *raw.h_m));
    given_options.emplace_back("--h");
  }
  return in;
}

// The message for a core rejection: the option at fault, what it expects, the value it had and where that value
// came from when the user did not give it.
[[noreturn]] void report_invalid(const StaticSettings& given, const core::StaticInputs& in, const core::StaticCheck& check,
                                 const std::string& context) {
  const std::string field = check.field;
  const std::string where = context.empty() ? std::string() : " " + context;
  if (field == "h" && check.code == core::StaticError::not_finite) {
    throw UsageError("the total height h = h1 + h2 is not a finite number: check --h, --h1 and --h2" + where);
  }
  if (field == "h") {
    const std::string h_text = number_text(in.h_m());
    throw UsageError("--h must be greater than b (got " + h_text + " m; b " + number_text(in.b_m) + " m)" + where);
  }
  if (field == "lambda") {
    throw UsageError(std::string("--lambda ") + check.message + " (got " + number_text(in.lambda) + ")" + where);
  }
  if (field == "psi" && check.code == core::StaticError::psi_too_large) {
    const double limit_rad = 4.0 * in.b_m / in.h_m() *
                             (1.0 + (2.0 - in.a) * (in.fp_npm / (in.rho_kgpm3 * in.g_mps2 * in.b_m * in.h_m())));
    throw UsageError("--psi must leave K > 0 and X > 0: psi < 4b(1 + (2 - a)f)/h = " + number_text(limit_rad) +
                     " rad for this wall (got " + number_text(in.psi_rad) + " rad)" + where);
  }
  for (const InputField& f : kInputFields) {
    if (field != f.field) continue;
    std::string message = std::string(f.option) + " " + check.message + " (got " + number_text(in.*f.member);
    if (!(given.*f.value)) message += ", the paper wall's value";
    const bool compares_with_b =
        check.code == core::StaticError::h1_not_above_b || check.code == core::StaticError::h2_not_above_b;
    if (compares_with_b && given.b_m) message += "; --b " + number_text(in.b_m);
    throw UsageError(message + ")" + where);
  }
  if (field == "spectrum") throw UsageError(std::string("--spectrum ") + check.message + where);
  throw UsageError("the wall options are too extreme for the static check (a result overflows or underflows): check "
                   "--b, --h, --h1, --h2, --fp, --rho, --g and --lambda (lambda " + number_text(in.lambda) + ")" +
                   where);
}

void validate_cases(const StaticSettings& given, const StaticRequest& q) {
  for (const StaticCase& c : q.cases) {
    const core::StaticInputs in = case_inputs(q, c);
    const core::StaticCheck check = core::validate_static_inputs(in);
    if (!check.ok()) report_invalid(given, in, check, "");
  }
}

void validate_sweep(const StaticSettings& given, const StaticRequest& q) {
  for (const double slenderness : kSweepSlenderness) {
    for (int percent = kSweepLambdaFirstPercent; percent <= kSweepLambdaLastPercent; ++percent) {
      core::StaticInputs in = q.inputs;
      in.b_m = kSweepB_m;
      core::set_total_height(in, slenderness * kSweepB_m);
      in.lambda = percent / 100.0;
      const core::StaticCheck check = core::validate_static_inputs(in);
      if (!check.ok()) {
        report_invalid(given, in, check, "in the sweep at h/b = " + number_text(slenderness) + ", lambda = " +
                                           number_text(in.lambda));
      }
    }
  }
}

void check_sweep_options(const StaticSettings& raw) {
  if (!raw.sweep) {
    if (raw.out_dir) throw UsageError("--out is the directory of --sweep: give --sweep too");
    return;
  }
  const std::pair<const char*, bool> set_by_sweep[] = {
      {"--lambda", bool(raw.lambda)}, {"--code", bool(raw.code)}, {"--wall", bool(raw.wall)}, {"--b", bool(raw.b_m)},
      {"--h", bool(raw.h_m)},         {"--h1", bool(raw.h1_m)},   {"--h2", bool(raw.h2_m)}};
  for (const auto& [option, given_option] : set_by_sweep) {
    if (given_option) {
      throw UsageError(std::string(option) + " cannot be combined with --sweep: the sweep sets b = 0.1 m, h/b = 20 "
                                             "to 40 and lambda = 0.10 to 0.90");
    }
  }
  if (raw.json) throw UsageError("--json cannot be combined with --sweep: the sweep writes a CSV file and a PNG");
  if (!raw.out_dir) throw UsageError("--sweep needs --out DIR, the directory for its CSV and PNG");
  if (raw.out_dir->empty()) throw UsageError("--out needs a directory name");
}

}  // namespace static_request
}  // namespace

core::StaticInputs case_inputs(const StaticRequest& q, const StaticCase& c) {
  using namespace static_request;
  core::StaticInputs in = q.inputs;
  in.lambda = c.lambda;
  return in;
}

StaticRequest build_static_request(const StaticSettings& s) {
  using namespace static_request;
  check_sweep_options(s);
  StaticRequest q;
  q.inputs = parse_inputs(s, q.wall_options_given);
  q.inputs.spectrum = parse_spectrum(s);
  q.a_without_fp = s.a && q.inputs.fp_npm == 0.0 && q.inputs.a != 0.0;
  q.json = s.json;
  q.sweep = s.sweep;
  if (q.sweep) {
    q.out_dir = *s.out_dir;
    validate_sweep(s, q);
  } else {
    q.cases = parse_cases(s);
    validate_cases(s, q);
  }
  return q;
}

StaticParse parse_static_arguments(int argc, const char* const* argv) {
  using namespace static_request;
  CLI::App app{"Static non-linear kinematic analysis of an unreinforced masonry wall rocking out of plane: "
               "allowable PGA for the NTC 2008 / NZSEE 2016 instability factors.",
               "rockwatch static"};
  RawOptions raw;
  add_options(app, raw);
  if (std::optional<std::string> help = parse_command_line(app, argc, argv, "static")) {
    return StaticParse{std::nullopt, std::move(*help)};
  }
  StaticSettings s;
  if (given(app, "--wall")) s.wall = raw.wall;
  for (const InputField& f : kInputFields) {
    if (given(app, f.option)) s.*f.value = parse_finite_number(f.option, raw.*f.text);
  }
  if (given(app, "--h")) s.h_m = parse_finite_number("--h", raw.h);
  if (given(app, "--lambda")) s.lambda = parse_finite_number("--lambda", raw.lambda);
  if (given(app, "--code")) s.code = raw.code;
  if (given(app, "--spectrum")) s.spectrum = raw.spectrum;
  for (const CustomParameter& c : kCustomParameters) {
    if (given(app, c.option)) s.*c.value = parse_finite_number(c.option, raw.*c.text);
  }
  s.json = raw.json;
  s.sweep = raw.sweep;
  if (given(app, "--out")) s.out_dir = raw.out;
  return StaticParse{build_static_request(s), {}};
}

}  // namespace rockwatch::cli
