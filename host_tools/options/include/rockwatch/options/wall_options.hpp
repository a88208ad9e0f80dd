// The wall options of every tool that runs the two-block model (simulate, study): --wall paper and the fields
// that override it (--b, --h1, --h2, --rho, --fp, --a, --a-prime, --g), validated by core so the CLI and the engine
// agree on what a valid wall is, with messages that name the option at fault.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

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

// The base wall with the given fields replaced. Throws UsageError naming the option at fault, and saying when its
// value was the base wall's rather than the user's.
WallChoice parse_wall_options(const CLI::App& app, const WallOptionTexts& texts);

// validate_wall accepts every finite positive size, but extremes (--rho 1e308, --h1 1e300) overflow the model's
// constants into inf/NaN, which would come out as null results rather than an error. Throws UsageError.
void check_computable(const core::WallParameters& wall, const sim::AnalysisOptions& options);

}  // namespace rockwatch::options
