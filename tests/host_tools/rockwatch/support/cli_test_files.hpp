// Inputs the CLI tests write (synthetic records with known answers) and outputs they read back (CSV histories).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "cli_process.hpp"

namespace rockwatch::test {

inline constexpr double kG = 9.81;

std::string record_path(const std::string& file_name);  // a file in tests/data/records

// The project's reference pulse G7: triangular 0 -> -0.20 g at t = 0.5 s -> 0 at t = 1 s, zero after [m/s2].
double g7_ug_mps2(double t_s);

// A plain record "# units: mps2" with columns t, ü(t) [, v̈(t)] sampled at dt from 0 to t_end. Times are written
// as exact decimals of k·dt so the reader recovers dt exactly.
void write_plain_record(const std::string& path, const std::function<double(double)>& ug_mps2, double dt_s,
                        double t_end_s, const std::function<double(double)>* vg_mps2 = nullptr);
void write_text(const std::string& path, const std::string& text);

struct Csv {
  std::string header;
  std::vector<std::vector<double>> rows;
  std::vector<double> column(std::size_t index) const;
};
Csv read_csv(const std::string& path);  // throws std::runtime_error on a malformed file

// Everything about a run, for a failure message.
std::string describe(const ProcessResult& r);

}  // namespace rockwatch::test
