#include "cli_test_files.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace rockwatch::test {

std::string record_path(const std::string& file_name) {
  return std::string(ROCKWATCH_TEST_DATA_DIR) + "/records/" + file_name;
}

double g7_ug_mps2(double t_s) {
  const double peak = -0.20 * kG;
  if (t_s <= 0.0 || t_s >= 1.0) return 0.0;
  return t_s <= 0.5 ? peak * t_s / 0.5 : peak * (1.0 - t_s) / 0.5;
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path);
}

void write_plain_record(const std::string& path, const std::function<double(double)>& ug_mps2, double dt_s,
                        double t_end_s, const std::function<double(double)>* vg_mps2) {
  std::string text = "# synthetic record written by test_cli\n# units: mps2\n";
  const auto n = static_cast<long>(std::llround(t_end_s / dt_s));
  char line[160];
  for (long k = 0; k <= n; ++k) {
    const double t = static_cast<double>(k) * dt_s;
    if (vg_mps2 != nullptr) {
      std::snprintf(line, sizeof line, "%.6f %.17g %.17g\n", t, ug_mps2(t), (*vg_mps2)(t));
    } else {
      std::snprintf(line, sizeof line, "%.6f %.17g\n", t, ug_mps2(t));
    }
    text += line;
  }
  write_text(path, text);
}

std::vector<double> Csv::column(std::size_t index) const {
  std::vector<double> values;
  values.reserve(rows.size());
  for (const auto& row : rows) values.push_back(row.at(index));
  return values;
}

Csv read_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  Csv csv;
  std::getline(in, csv.header);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream fields(line);
    std::string field;
    while (std::getline(fields, field, ',')) {
      // strtod, not stod: a subnormal value is a number here, not an out_of_range error.
      char* end = nullptr;
      const double value = std::strtod(field.c_str(), &end);
      if (field.empty() || end != field.c_str() + field.size()) {
        throw std::runtime_error("bad number '" + field + "' in " + path);
      }
      row.push_back(value);
    }
    csv.rows.push_back(row);
  }
  return csv;
}

std::string describe(const ProcessResult& r) {
  return "exit " + std::to_string(r.exit_status) + " signal " + std::to_string(r.signal) + "\n--- stdout:\n" + r.out +
         "\n--- stderr:\n" + r.err;
}

}  // namespace rockwatch::test
