// The wall options of every tool that runs the two-block model (simulate, study): --wall paper and the fields
// that override it (--b, --h1, --h2, --rho, --fp, --a, --a-prime, --g), validated by core so the CLI and the engine
// agree on what a valid wall is, with messages that name the option at fault.
#pragma once

#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "rockwatch/options/cli11_fwd.hpp"

#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/sim/analysis.hpp"

namespace rockwatch::options {

// The options as typed; parse_wall_options converts and checks them, so every message has one form.
struct WallOptionTexts {
  std::string wall = "paper";
  std::string wall_file;   // --wall-file FILE.json (rockwatch/options/wall_file.hpp)
  std::string b, h1, h2, rho, fp, a, a_prime, g;
};

// Registers --wall, --wall-file, --b, --h1, --h2, --rho, --fp, --a, --a-prime and --g, in that order.
void add_wall_options(CLI::App& app, WallOptionTexts& texts);

struct WallChoice {
  std::string name = "paper";                   // the base wall the field options modify
  core::WallParameters wall = core::paper_wall();
  std::vector<std::string> options_given;       // e.g. {"--b", "--h1"}, for the reports
  // --wall-file: the base wall is the file's (name "file"), and its r is the restitution unless --r is given.
  std::optional<std::string> wall_file_path;
  std::optional<double> r_from_file;            // [-]
};

// The restitution of a tool: --r when given, else the wall file's r, else r_text (the tool's default).
core::Restitution restitution_of(const CLI::App& app, const WallChoice& wall, const std::string& r_text);

// --r as a typed value: a name (ana | exp | impulse) or a number's text, as the command line has it, or a number, as
// the Python module has it.
using RestitutionSetting = std::variant<std::string, double>;

// The same for typed settings: `r` when given (checked: "--r must be ..."), else the wall file's r, else
// default_text.
core::Restitution restitution_of(const std::optional<RestitutionSetting>& r, const WallChoice& wall,
                                 const std::string& default_text);

// The wall options as typed values: what was given (an empty optional: not given). The command line's parser converts
// its texts into them, the Python module (rockwatch.Wall) fills them from its keywords; both call check_wall_settings,
// so the checks and the messages (naming the option, e.g. "--b must be > 0 ...") are the same.
struct WallSettings {
  std::optional<std::string> wall;       // --wall: the base wall's name (only "paper")
  std::optional<std::string> wall_file;  // --wall-file FILE.json
  std::optional<double> b_m, h1_m, h2_m, rho_kgpm3, fp_npm, a, a_prime, g_mps2;  // --b, --h1, ... [m, kg/m3, N/m, -]
};

// The base wall with the given fields replaced. Throws UsageError naming the option at fault, and saying when its
// value was the base wall's rather than the user's.
WallChoice check_wall_settings(const WallSettings& settings);

// The texts converted (a number that is not one: "--b expects a finite number"), then check_wall_settings.
WallChoice parse_wall_options(const CLI::App& app, const WallOptionTexts& texts);

// validate_wall accepts every finite positive size, but extremes (--rho 1e308, --h1 1e300) overflow the model's
// constants into inf/NaN, which would come out as null results rather than an error. Throws UsageError.
void check_computable(const core::WallParameters& wall, const sim::AnalysisOptions& options);

}  // namespace rockwatch::options
