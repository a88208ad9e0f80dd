// Wall-sensor files as the observer takes them: records::read_wall_sensor_csv's rows converted to
// core::WallSensorSample (what `rockwatch simulate --wall-sensors` and `rockwatch replay --wall-sensors` read), and
// the writer of the same format (`rockwatch simulate --sensors-out`), so a written file reads back sample for sample.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "rockwatch/core/wall_observer.hpp"

namespace rockwatch::cli {

// Throws records::RecordError naming the file and line (the commands exit 2).
std::vector<core::WallSensorSample> read_wall_sensor_samples(const std::string& path);

// The header `t_s,x_mid_m` (and `,a_mid_mps2` when with_accel) and one row per sample: t_s = utime/1e6 and the values
// as shortest round-trip text, an empty field where a value is not valid.
void write_wall_sensor_csv(std::ostream& out, const std::vector<core::WallSensorSample>& samples, bool with_accel);

}  // namespace rockwatch::cli
