// The wall file: one wall as JSON, written by `rockwatch identify --wall-out` and read by every tool that runs the
// model (`--wall-file FILE.json`, and the monitor's configuration key `wall_file`), so that a wall identified from a
// test predicts with its own capacity and restitution.
//
// Format (docs/TOOLS.md "The wall file"): one object with every field required —
//   "format": "rockwatch-wall", "version": 1,
//   "b_m", "h1_m", "h2_m", "rho_kgpm3", "fp_npm", "a", "a_prime", "g_mps2"   the wall of SPEC §1 (an equivalent wall
//                                                                          when identified),
//   "r"                                                                    the energy ratio at impact, in [0, 1]
// and optionally "reduced" (SPEC §9's c_neg_mps2, c_pos_mps2, k_ps2, gamma, x_inst_m, omega_radps, threshold_mps2: what
// the wall gives; read back, each must agree with the wall's own to 1e-6 relative, so a hand edit of one and not the
// other is caught), "identified" (how it was obtained: free-form provenance, an object) and "comment" (a string).
// Anything else, a missing field, a wrong type or a value out of range is refused naming the field.
#pragma once

#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "rockwatch/core/wall.hpp"

namespace rockwatch::options {

struct WallFile {
  core::WallParameters wall{};
  double r = 0.0;                  // energy ratio at impact [-]
  nlohmann::ordered_json identified = nlohmann::ordered_json::object();  // provenance (written as given)
  std::string comment;
};

// Reads and checks `path`. Throws UsageError "OPTION PATH: field \"NAME\" ..." (the tools exit 2). `option` names
// where the path came from, e.g. "--wall-file" or "wall_file".
WallFile read_wall_file(const std::string& option, const std::string& path);

// The JSON object of a wall file (reduced parameters included).
nlohmann::ordered_json wall_file_json(const WallFile& file);

}  // namespace rockwatch::options
