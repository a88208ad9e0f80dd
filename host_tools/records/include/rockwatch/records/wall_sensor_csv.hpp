// Wall-sensor files: samples of the sensors mounted on the wall (a displacement transducer at the mid-height hinge, an
// accelerometer at mid-height), as `rockwatch simulate --wall-sensors` and `rockwatch replay --wall-sensors` read them
// and `rockwatch simulate --sensors-out` writes them.
//
//   # comment lines and blank lines are ignored anywhere
//   t_s,x_mid_m,a_mid_mps2
//   0.000,0.0021,
//   0.005,0.0020,-0.13
//
// The first other line is the header: comma-separated column names, in any order, `t_s` and at least one of
// `x_mid_m` [m] (same sign convention as the model's x) and `a_mid_mps2` [m/s², absolute horizontal acceleration at
// mid-height]. Then one row per sample with as many fields: t_s on the ground record's clock [s] (any rate, strictly
// increasing, at least 1 µs apart), an empty field = that sensor has no value in this sample. Values are finite
// decimal numbers. Any defect throws RecordError naming the file, the line and what was expected.
//
// Uses nothing of the project outside records (the layer rule): the rows are converted to core::WallSensorSample by
// the tool (host_tools/rockwatch/common/records_in/wall_sensors.hpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace rockwatch::records {

// One row: the time in whole microseconds (llround(t_s · 1e6)) and the values that are present.
struct WallSensorRow {
  std::int64_t utime_us = 0;     // [µs] on the ground record's clock
  double x_mid_m = 0.0;          // when x_valid [m]
  double a_mid_mps2 = 0.0;       // when a_valid [m/s²]
  bool x_valid = false;
  bool a_valid = false;
  int line = 0;                  // line of the file (for messages of later checks)
};

struct WallSensorFile {
  std::string path;
  bool has_x_column = false;     // the header names x_mid_m
  bool has_a_column = false;     // the header names a_mid_mps2
  std::vector<WallSensorRow> rows;  // at least one, utime strictly increasing
};

// Largest |t_s| accepted [s] (about 31 years: the microsecond count stays exact in a double and in int64).
inline constexpr double kMaxWallSensorTime_s = 1e9;

// The column names.
inline constexpr const char* kWallSensorTimeColumn = "t_s";
inline constexpr const char* kWallSensorXColumn = "x_mid_m";
inline constexpr const char* kWallSensorAColumn = "a_mid_mps2";

WallSensorFile read_wall_sensor_csv(const std::string& path);

}  // namespace rockwatch::records
