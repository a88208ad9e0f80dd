#include "rockwatch/options/wall_file.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "rockwatch/sim/identification.hpp"

namespace rockwatch::options {

namespace {

struct WallFileField {
  const char* name;
  double core::WallParameters::*member;
};

constexpr WallFileField kWallFileFields[] = {
    {"b_m", &core::WallParameters::b_m},       {"h1_m", &core::WallParameters::h1_m},
    {"h2_m", &core::WallParameters::h2_m},     {"rho_kgpm3", &core::WallParameters::rho_kgpm3},
    {"fp_npm", &core::WallParameters::fp_npm}, {"a", &core::WallParameters::a},
    {"a_prime", &core::WallParameters::a_prime}, {"g_mps2", &core::WallParameters::g_mps2},
};

// core::validate_wall's field names → the file's.
const char* file_field(const std::string& core_field) {
  if (core_field == "b") return "b_m";
  if (core_field == "h1") return "h1_m";
  if (core_field == "h2") return "h2_m";
  if (core_field == "rho") return "rho_kgpm3";
  if (core_field == "fp") return "fp_npm";
  if (core_field == "g") return "g_mps2";
  if (core_field == "a_prime") return "a_prime";
  return "a";
}

nlohmann::ordered_json reduced_json(const core::WallParameters& wall) {
  const sim::ReducedParameters r = sim::reduced_parameters(wall);
  nlohmann::ordered_json j;
  j["c_neg_mps2"] = r.c_mps2[0];
  j["c_pos_mps2"] = r.c_mps2[1];
  j["k_ps2"] = r.k_ps2;
  j["gamma"] = r.gamma;
  j["x_inst_m"] = r.x_inst_m;
  j["omega_radps"] = r.omega_radps;
  j["threshold_mps2"] = r.threshold_mps2;
  return j;
}

}  // namespace

WallFile read_wall_file(const std::string& option, const std::string& path) {
  const std::string where = option + " " + path;
  std::ifstream in(path);
  if (!in) throw UsageError(where + ": cannot be read (a wall file written by rockwatch identify --wall-out is expected)");
  std::stringstream text;
  text << in.rdbuf();
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::parse_error& e) {
    throw UsageError(where + ": not valid JSON (" + e.what() + ")");
  }
  if (!j.is_object()) throw UsageError(where + ": a JSON object is expected");
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string& key = it.key();
    bool known = key == "format" || key == "version" || key == "r" || key == "reduced" || key == "identified" ||
                 key == "comment";
    for (const WallFileField& f : kWallFileFields) known = known || key == f.name;
    if (!known) {
      throw UsageError(where + ": unknown field " + quoted(key) +
                       " (expected format, version, b_m, h1_m, h2_m, rho_kgpm3, fp_npm, a, a_prime, g_mps2, r, and "
                       "optionally reduced, identified, comment)");
    }
  }
  const auto require = [&](const char* name) -> const nlohmann::json& {
    if (!j.contains(name)) throw UsageError(where + ": field " + quoted(name) + " is missing");
    return j.at(name);
  };
  if (!require("format").is_string() || j.at("format").get<std::string>() != "rockwatch-wall") {
    throw UsageError(where + ": field 'format' must be \"rockwatch-wall\"");
  }
  if (!require("version").is_number_integer() || j.at("version").get<long long>() != 1) {
    throw UsageError(where + ": field 'version' must be 1 (the only version this rockwatch reads)");
  }
  const auto number = [&](const char* name) {
    const nlohmann::json& v = require(name);
    if (!v.is_number()) throw UsageError(where + ": field " + quoted(name) + " must be a number");
    const double d = v.get<double>();
    if (!std::isfinite(d)) throw UsageError(where + ": field " + quoted(name) + " must be finite");
    return d;
  };
  WallFile file;
  for (const WallFileField& f : kWallFileFields) file.wall.*f.member = number(f.name);
  const core::WallCheck check = core::validate_wall(file.wall);
  if (!check.ok()) {
    const std::string name = file_field(check.field);
    double got = 0.0;
    for (const WallFileField& f : kWallFileFields) {
      if (name == f.name) got = file.wall.*f.member;
    }
    std::string message = where + ": field " + quoted(name) + " " + check.message + " (got " + number_text(got);
    if (check.code == core::WallError::h1_not_above_b || check.code == core::WallError::h2_not_above_b) {
      message += "; b_m " + number_text(file.wall.b_m);
    }
    throw UsageError(message + ")");
  }
  file.r = number("r");
  if (!(file.r >= 0.0 && file.r <= 1.0)) {
    throw UsageError(where + ": field 'r' must be in [0, 1] (got " + number_text(file.r) + ")");
  }
  const sim::ReducedParameters own = sim::reduced_parameters(file.wall);
  if (!(std::isfinite(own.x_inst_m) && own.x_inst_m > 0.0 && std::isfinite(own.k_ps2) && own.k_ps2 > 0.0 &&
        std::isfinite(own.threshold_mps2) && own.threshold_mps2 > 0.0)) {
    throw UsageError(where + ": the wall fields give values the model cannot compute (x_inst " +
                     number_text(own.x_inst_m) + " m): check b_m, h1_m, h2_m, rho_kgpm3, fp_npm, g_mps2");
  }
  if (j.contains("reduced")) {
    const nlohmann::json& red = j.at("reduced");
    if (!red.is_object()) throw UsageError(where + ": field 'reduced' must be an object");
    const nlohmann::ordered_json expect = reduced_json(file.wall);
    for (auto it = red.begin(); it != red.end(); ++it) {
      const std::string name = "reduced." + it.key();
      if (!expect.contains(it.key())) {
        throw UsageError(where + ": unknown field " + quoted(name) +
                         " (expected c_neg_mps2, c_pos_mps2, k_ps2, gamma, x_inst_m, omega_radps, threshold_mps2)");
      }
      if (!it.value().is_number()) throw UsageError(where + ": field " + quoted(name) + " must be a number");
      const double got = it.value().get<double>(), want = expect.at(it.key()).get<double>();
      if (!(std::fabs(got - want) <= 1e-6 * std::fabs(want))) {
        throw UsageError(where + ": field " + quoted(name) + " = " + number_text(got) +
                         " disagrees with the wall fields, which give " + number_text(want) +
                         " (the wall fields are what the tools run: edit those, or drop \"reduced\")");
      }
    }
  }
  if (j.contains("identified")) {
    if (!j.at("identified").is_object()) throw UsageError(where + ": field 'identified' must be an object");
    file.identified = nlohmann::ordered_json::parse(j.at("identified").dump());
  }
  if (j.contains("comment")) {
    if (!j.at("comment").is_string()) throw UsageError(where + ": field 'comment' must be a string");
    file.comment = j.at("comment").get<std::string>();
  }
  return file;
}

nlohmann::ordered_json wall_file_json(const WallFile& file) {
  nlohmann::ordered_json j;
  j["format"] = "rockwatch-wall";
  j["version"] = 1;
  for (const WallFileField& f : kWallFileFields) j[f.name] = file.wall.*f.member;
  j["r"] = file.r;
  j["reduced"] = reduced_json(file.wall);
  if (!file.identified.empty()) j["identified"] = file.identified;
  if (!file.comment.empty()) j["comment"] = file.comment;
  return j;
}

}  // namespace rockwatch::options
