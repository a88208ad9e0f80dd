// A ground-motion record read from a file, in SI units, and the options that control reading it.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace rockwatch::records {

// Acceleration units a record file may hold. `g` is converted with the caller's g (ReadOptions::g_mps2),
// the same g the wall model uses, so a record read in g and reported in g round-trips exactly.
enum class AccelUnit { g, mps2, cmps2, mmps2 };

// Parses "g", "mps2", "cmps2", "mmps2" (also "m/s2", "m/s^2", "cm/s2", "cm/s^2", "gal", "mm/s2", "mm/s^2").
std::optional<AccelUnit> parse_accel_unit(std::string_view text);
std::string_view accel_unit_name(AccelUnit unit);
// Factor that turns a value in `unit` into m/s².
double accel_unit_to_mps2(AccelUnit unit, double g_mps2);

struct ReadOptions {
  std::optional<AccelUnit> units;  // overrides/supplies the units (required for plain files without units)
  std::optional<double> dt_s;      // sample interval for one-column plain files [s]
  double g_mps2 = 9.81;            // gravity used to convert `g` units [m/s²]
};

struct Record {
  std::string path;                     // file it was read from
  std::string format;                   // "peer-at2" or "plain"
  std::string description;              // header text (event, station, component) when the file has it
  double dt_s = 0.0;                    // constant sample interval [s]
  double t0_s = 0.0;                    // time of the first sample [s] (0 unless the file states a time column)
  std::vector<double> horizontal_mps2;  // out-of-plane ground acceleration ü [m/s²], file's sign
  std::vector<double> vertical_mps2;    // vertical v̈ [m/s², up +]; empty unless the file has a third column
  AccelUnit units_in_file = AccelUnit::mps2;
  std::vector<std::string> notes;       // non-fatal findings, e.g. "file.AT2: NPTS=1999 but 2000 values; read 1999"
};

// Reads a record, detecting the format from its content (an AT2 header, else plain columns).
// Throws RecordError naming the file and line on any defect (see record_error.hpp).
Record read_record(const std::string& path, const ReadOptions& options = {});

Record read_peer_at2(const std::string& path, const ReadOptions& options = {});
Record read_plain_text(const std::string& path, const ReadOptions& options = {});

// True when the first four lines of the file look like a PEER NGA AT2 header.
bool looks_like_peer_at2(const std::string& path);

}  // namespace rockwatch::records
