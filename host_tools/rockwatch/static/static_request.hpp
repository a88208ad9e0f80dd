// What `rockwatch static` was asked to do, parsed and validated from its command line.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "rockwatch/core/static_check.hpp"

namespace rockwatch::cli {

// One instability factor to evaluate: a code's (--code) or the user's (--lambda).
struct StaticCase {
  std::optional<core::InstabilityCode> code;  // empty for --lambda
  double lambda = 0.0;
};

struct StaticRequest {
  core::StaticInputs inputs;      // wall, overburden, ψ, g and spectrum; `lambda` is set per case
  std::vector<StaticCase> cases;  // ntc2008 then nzsee2016 for --code both (the default)
  std::vector<std::string> wall_options_given;  // e.g. {"--h", "--b"}, for the report
  bool a_without_fp = false;      // --a given while Fp = 0: it changes nothing, say so
  bool json = false;
  bool sweep = false;             // --sweep: the allowable-PGA-versus-lambda study, written to out_dir
  std::string out_dir;
};

// The sweep of the design paper's Figure 3: h/b = 20, 25, ..., 40 with b = 0.1 m, lambda = 0.10 ... 0.90 by 0.01.
inline constexpr double kSweepB_m = 0.1;
inline constexpr double kSweepSlenderness[] = {20.0, 25.0, 30.0, 35.0, 40.0};
inline constexpr int kSweepLambdaFirstPercent = 10;
inline constexpr int kSweepLambdaLastPercent = 90;

// Outcome of reading the command line: a request to run, or the help text to print (exit status 0).
struct StaticParse {
  std::optional<StaticRequest> request;
  std::string help_text;
};

// What `rockwatch static` checks, as typed values (an empty optional: not given). The command line's parser converts
// its texts into them, the Python module (rockwatch.static_check) fills them from its keywords; both call
// build_static_request, so the checks and the messages (naming the option) are the same.
struct StaticSettings {
  std::optional<std::string> wall;                           // --wall: the base wall's name (only "paper")
  std::optional<double> b_m, h_m, h1_m, h2_m;                // --b, --h, --h1, --h2 [m]
  std::optional<double> fp_npm, a, psi_rad, rho_kgpm3, g_mps2;  // --fp [N/m], --a, --psi [rad], --rho, --g
  std::optional<double> lambda;                              // --lambda
  std::optional<std::string> code, spectrum;                 // --code (default both), --spectrum (npr9998-2015)
  std::optional<double> p, tb_s, tc_s, td_s;                 // the custom spectrum: --p, --tb, --tc, --td
  bool json = false, sweep = false;                          // --json, --sweep
  std::optional<std::string> out_dir;                        // --out DIR
};

// Checks the settings and builds the request. Throws UsageError with a message that names the option at fault and
// what it expects.
StaticRequest build_static_request(const StaticSettings& settings);

// Parses `rockwatch static` arguments (argv[0] is the command name) into StaticSettings, then build_static_request.
StaticParse parse_static_arguments(int argc, const char* const* argv);

// The inputs of one case (request inputs with the case's lambda).
core::StaticInputs case_inputs(const StaticRequest& request, const StaticCase& c);

}  // namespace rockwatch::cli
