// `rockwatch study --walls FILE.csv`: a portfolio of walls, one per row, each run through the same plan (records x
// PGA x restitution x vertical). The file's header is exactly id,b,h1,h2,rho,fp,a,a_prime (SI units as `rockwatch
// simulate` takes them: m, m, m, kg/m3, N/m, fractions of b); an empty field is the paper's value (Table 2).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "rockwatch/core/wall.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "study/plan/study_plan.hpp"

namespace rockwatch::cli {

inline constexpr const char* kWallsHeader = "id,b,h1,h2,rho,fp,a,a_prime";
// Bounds on a portfolio: a wall list of a building stock fits; a runaway file is an error, not hours of work.
inline constexpr std::size_t kMaxPortfolioWalls = 100000;

struct PortfolioWall {
  std::string id;                  // letters, digits, '_', '-', '.'; unique in the file
  core::WallParameters wall;
  StaticCapacities capacities;     // the static check's allowable PGA (NTC 2008, NZSEE 2016)
  int line = 0;                    // its line in the file, for messages
};

// Reads and checks every row: the header, the id, each number (finite; the wall as core::validate_wall and the
// model accept it, `options` with each of `restitutions`), the static check. `g_mps2` is the study's gravity.
// Throws UsageError "FILE:LINE: ..." naming the field at fault and what was expected. '#' lines and blank lines
// are skipped; a CR before the line end is allowed.
std::vector<PortfolioWall> read_wall_portfolio(const std::string& path, double g_mps2,
                                               const sim::AnalysisOptions& options,
                                               const std::vector<sim::study::RestitutionCase>& restitutions);

}  // namespace rockwatch::cli
