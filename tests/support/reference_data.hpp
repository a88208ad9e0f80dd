// Access to tests/data/reference/two_block_reference.json (copied from the project's shared reference set;
// values from an independent high-accuracy solver, see tests/data/reference/SOURCE.md).
#pragma once

#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

namespace rockwatch::test {

inline std::string data_path(const std::string& relative) { return std::string(ROCKWATCH_TEST_DATA_DIR) + "/" + relative; }

// Parsed afresh by each caller: CppUTest's leak checker would report a cached static as a leak.
inline nlohmann::json load_reference() {
  std::ifstream in(data_path("reference/two_block_reference.json"));
  if (!in) throw std::runtime_error("cannot open reference JSON");
  return nlohmann::json::parse(in);
}

// Tolerance `rel` relative to the expected value (absolute `rel` when the expected value is 0).
inline double rel_tol(double expected, double rel) { return expected == 0.0 ? rel : rel * std::fabs(expected); }

}  // namespace rockwatch::test
