#include "study/plan/study_walls.hpp"

#include <cerrno>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "common/process/command_runner.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "rockwatch/options/wall_options.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

namespace {

bool id_character(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
         c == '.';
}

// An id goes into CSV fields, JSON and file names unquoted: a plain token.
void check_wall_id(const std::string& where, const std::string& id) {
  if (id.empty() || id.size() > 64) throw UsageError(where + ": id must be 1 to 64 characters (got " + options::quoted(id) + ")");
  for (const char c : id) {
    if (!id_character(c)) {
      throw UsageError(where + ": id must hold only letters, digits, '_', '-' and '.' (got " + options::quoted(id) + ")");
    }
  }
}

void read_field(const std::string& where, const char* name, const std::string& text, double& value) {
  if (text.empty()) return;  // the paper's value
  try {
    value = parse_finite_number(name, text);
  } catch (const UsageError&) {
    throw UsageError(where + ": " + name + " must be a finite number or empty for the paper's value (got " +
                     options::quoted(text) + ")");
  }
}

}  // namespace

std::vector<PortfolioWall> read_wall_portfolio(const std::string& path, double g_mps2,
                                               const sim::AnalysisOptions& options,
                                               const std::vector<sim::study::RestitutionCase>& restitutions) {
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UsageError("--walls: cannot open " + path + system_reason());
  std::vector<PortfolioWall> walls;
  std::set<std::string> ids;
  std::string line;
  bool header_seen = false;
  for (int number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string where = path + ":" + std::to_string(number);
    if (line.empty() || line[0] == '#') continue;
    if (!header_seen) {
      if (line != kWallsHeader) {
        throw UsageError(where + ": expected the header " + std::string(kWallsHeader) + " (got " + options::quoted(line) + ")");
      }
      header_seen = true;
      continue;
    }
    const std::vector<std::string> fields = split_fields(line, ',');
    if (fields.size() != 8) {
      throw UsageError(where + ": expected 8 comma-separated fields (" + kWallsHeader + "), got " +
                       std::to_string(fields.size()));
    }
    if (walls.size() == kMaxPortfolioWalls) {
      throw UsageError(where + ": more than " + std::to_string(kMaxPortfolioWalls) +
                       " walls: split the portfolio into several studies");
    }
    PortfolioWall w;
    w.line = number;
    w.id = fields[0];
    check_wall_id(where, w.id);
    if (!ids.insert(w.id).second) throw UsageError(where + ": id " + w.id + " appears twice");
    w.wall = core::paper_wall();
    w.wall.g_mps2 = g_mps2;
    read_field(where, "b", fields[1], w.wall.b_m);
    read_field(where, "h1", fields[2], w.wall.h1_m);
    read_field(where, "h2", fields[3], w.wall.h2_m);
    read_field(where, "rho", fields[4], w.wall.rho_kgpm3);
    read_field(where, "fp", fields[5], w.wall.fp_npm);
    read_field(where, "a", fields[6], w.wall.a);
    read_field(where, "a_prime", fields[7], w.wall.a_prime);
    const core::WallCheck check = core::validate_wall(w.wall);
    if (!check.ok()) throw UsageError(where + ": wall " + w.id + ": " + check.field + " " + check.message);
    try {
      for (const sim::study::RestitutionCase& c : restitutions) {
        sim::AnalysisOptions o = options;
        o.restitution = c.restitution;
        check_computable(w.wall, o);
      }
      w.capacities = static_capacities(w.wall);
    } catch (const UsageError& e) {
      throw UsageError(where + ": wall " + w.id + ": " + e.what());
    }
    walls.push_back(w);
  }
  if (in.bad()) throw UsageError("--walls: reading " + path + " failed");
  if (!header_seen) throw UsageError(path + ": empty: expected the header " + std::string(kWallsHeader));
  if (walls.empty()) throw UsageError(path + ": no walls (one row per wall after the header)");
  return walls;
}

}  // namespace rockwatch::cli
