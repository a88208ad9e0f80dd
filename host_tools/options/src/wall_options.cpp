#include "rockwatch/options/wall_options.hpp"

#include <cmath>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <CLI/CLI.hpp>

#include "rockwatch/core/model.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/options/command_line.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "rockwatch/options/wall_file.hpp"

namespace rockwatch::options {

namespace {

struct WallField {
  const char* field;   // core::validate_wall's name
  const char* option;  // the option that sets it
  double core::WallParameters::*member;
  std::string WallOptionTexts::*text;
  std::optional<double> WallSettings::*value;
};

constexpr WallField kWallFields[] = {
    {"b", "--b", &core::WallParameters::b_m, &WallOptionTexts::b, &WallSettings::b_m},
    {"h1", "--h1", &core::WallParameters::h1_m, &WallOptionTexts::h1, &WallSettings::h1_m},
    {"h2", "--h2", &core::WallParameters::h2_m, &WallOptionTexts::h2, &WallSettings::h2_m},
    {"rho", "--rho", &core::WallParameters::rho_kgpm3, &WallOptionTexts::rho, &WallSettings::rho_kgpm3},
    {"fp", "--fp", &core::WallParameters::fp_npm, &WallOptionTexts::fp, &WallSettings::fp_npm},
    {"a", "--a", &core::WallParameters::a, &WallOptionTexts::a, &WallSettings::a},
    {"a_prime", "--a-prime", &core::WallParameters::a_prime, &WallOptionTexts::a_prime, &WallSettings::a_prime},
    {"g", "--g", &core::WallParameters::g_mps2, &WallOptionTexts::g, &WallSettings::g_mps2},
};

// Names the option at fault, and says when its value was the base wall's rather than the user's.
[[noreturn]] void report_invalid_wall(const WallSettings& given, const core::WallParameters& wall,
                                      const core::WallCheck& check) {
  for (const WallField& f : kWallFields) {
    if (std::string(check.field) != f.field) continue;
    std::string message = std::string(f.option) + " " + check.message + " (got " + number_text(wall.*f.member);
    if (!(given.*f.value)) message += given.wall_file ? ", the wall file's value" : ", the paper wall's value";
    const bool compares_with_b =
        check.code == core::WallError::h1_not_above_b || check.code == core::WallError::h2_not_above_b;
    if (compares_with_b && given.b_m) message += "; --b " + number_text(wall.b_m);
    throw UsageError(message + ")");
  }
  throw UsageError(std::string("wall parameter ") + check.field + " " + check.message);
}

}  // namespace

void add_wall_options(CLI::App& app, WallOptionTexts& texts) {
  app.add_option("--wall", texts.wall, "Base wall: paper (b 0.10, h1 = h2 = 1.75, rho 1800, Fp 0, a = a' = 0)")
      ->type_name("paper");
  app.add_option("--wall-file", texts.wall_file,
                 "Base wall from a wall file (JSON; rockwatch identify --wall-out): its fields and its r (unless --r)")
      ->type_name("FILE.json");
  app.add_option("--b", texts.b, "Wall thickness b [m]")->type_name("M");
  app.add_option("--h1", texts.h1, "Bottom block height, ground to mid-height hinge [m]")->type_name("M");
  app.add_option("--h2", texts.h2, "Top block height, mid-height hinge to top restraint [m]")->type_name("M");
  app.add_option("--rho", texts.rho, "Masonry density [kg/m3]")->type_name("KG_M3");
  app.add_option("--fp", texts.fp, "Overburden on the top of the wall [N per m of wall]")->type_name("N_PER_M");
  app.add_option("--a", texts.a, "Overburden eccentricity while x < 0, fraction of b from the top hinge, in [0, 1]")
      ->type_name("A");
  app.add_option("--a-prime", texts.a_prime, "Overburden eccentricity while x > 0, fraction of b, in [0, 1]")
      ->type_name("A");
  app.add_option("--g", texts.g, "Gravity [m/s2] (default 9.81); also converts records in units of g")
      ->type_name("MPS2");
}

WallChoice check_wall_settings(const WallSettings& s) {
  const std::string name = s.wall.value_or("paper");
  if (name != "paper") {
    throw UsageError("--wall must be paper, the only built-in wall (got " + quoted(name) +
                     "); set its dimensions with --b, --h1, --h2, --rho, --fp, --a, --a-prime");
  }
  WallChoice choice;
  choice.name = name;
  if (s.wall_file) {
    if (s.wall) throw UsageError("--wall and --wall-file both name the base wall: give one");
    if (s.wall_file->empty()) throw UsageError("--wall-file needs a file name");
    const WallFile file = read_wall_file("--wall-file", *s.wall_file);
    choice.name = "file";
    choice.wall = file.wall;
    choice.wall_file_path = *s.wall_file;
    choice.r_from_file = file.r;
  }
  for (const WallField& f : kWallFields) {
    if (!(s.*f.value)) continue;
    // The command line's values are finite already; the module's may not be.
    choice.wall.*f.member = check_finite_number(f.option, *(s.*f.value));
    choice.options_given.emplace_back(f.option);
  }
  const core::WallCheck check = core::validate_wall(choice.wall);
  if (!check.ok()) report_invalid_wall(s, choice.wall, check);
  return choice;
}

WallChoice parse_wall_options(const CLI::App& app, const WallOptionTexts& texts) {
  WallSettings s;
  if (given(app, "--wall")) s.wall = texts.wall;
  if (given(app, "--wall-file")) s.wall_file = texts.wall_file;
  for (const WallField& f : kWallFields) {
    if (given(app, f.option)) s.*f.value = parse_finite_number(f.option, texts.*f.text);
  }
  return check_wall_settings(s);
}

core::Restitution restitution_of(const CLI::App& app, const WallChoice& wall, const std::string& r_text) {
  return restitution_of(given(app, "--r") ? std::optional<RestitutionSetting>(r_text) : std::nullopt, wall, r_text);
}

core::Restitution restitution_of(const std::optional<RestitutionSetting>& r, const WallChoice& wall,
                                 const std::string& default_text) {
  if (!r && wall.r_from_file) {
    core::Restitution from_file;
    from_file.kind = core::RestitutionKind::value;
    from_file.value = *wall.r_from_file;
    return from_file;
  }
  if (r && std::holds_alternative<double>(*r)) return restitution_value("--r", std::get<double>(*r));
  return parse_restitution("--r", r ? std::get<std::string>(*r) : default_text);
}

void check_computable(const core::WallParameters& wall, const sim::AnalysisOptions& options) {
  const core::ModelConstants<double> c = core::model_constants(wall, options.model);
  const double r = core::restitution_energy_ratio(wall, options.restitution);
  for (const core::Side side : {core::Side::negative, core::Side::positive}) {
    const double x_inst_m = core::x_inst_m(c, side, wall.g_mps2);
    const double threshold_mps2 = core::threshold_mps2(c, side, wall.g_mps2);
    const bool ok = std::isfinite(x_inst_m) && x_inst_m > 0.0 && std::isfinite(threshold_mps2) &&
                    threshold_mps2 > 0.0 && std::isfinite(r) && r >= 0.0 && r <= 1.0;
    if (!ok) {
      throw UsageError("the wall options give values the model cannot compute (x_inst = " + number_text(x_inst_m) +
                       " m, threshold = " + number_text(threshold_mps2) + " m/s2, r = " + number_text(r) +
                       "): check --b, --h1, --h2, --rho, --fp and --g for extreme values");
    }
  }
}

}  // namespace rockwatch::options
