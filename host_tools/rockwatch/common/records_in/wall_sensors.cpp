#include "common/records_in/wall_sensors.hpp"

#include <ostream>
#include <string>
#include <vector>

#include "rockwatch/options/option_values.hpp"
#include "common/process/options_namespace.hpp"
#include "rockwatch/records/wall_sensor_csv.hpp"

namespace rockwatch::cli {

std::vector<core::WallSensorSample> read_wall_sensor_samples(const std::string& path) {
  const records::WallSensorFile file = records::read_wall_sensor_csv(path);
  std::vector<core::WallSensorSample> samples;
  samples.reserve(file.rows.size());
  for (const records::WallSensorRow& row : file.rows) {
    core::WallSensorSample s;
    s.utime_us = row.utime_us;
    s.x_mid_m = row.x_mid_m;
    s.a_mid_mps2 = row.a_mid_mps2;
    s.x_valid = row.x_valid;
    s.a_valid = row.a_valid;
    samples.push_back(s);
  }
  return samples;
}

void write_wall_sensor_csv(std::ostream& out, const std::vector<core::WallSensorSample>& samples, bool with_accel) {
  out << records::kWallSensorTimeColumn << ',' << records::kWallSensorXColumn;
  if (with_accel) out << ',' << records::kWallSensorAColumn;
  out << '\n';
  std::string row;
  for (const core::WallSensorSample& s : samples) {
    row.clear();
    // utime / 1e6 reads back to the same utime: llround(t_s * 1e6) of the shortest text of utime * 1e-6.
    row += number_text(double(s.utime_us) / 1e6);
    row += ',';
    if (s.x_valid) row += number_text(s.x_mid_m);
    if (with_accel) {
      row += ',';
      if (s.a_valid) row += number_text(s.a_mid_mps2);
    }
    row += '\n';
    out << row;
  }
}

}  // namespace rockwatch::cli
