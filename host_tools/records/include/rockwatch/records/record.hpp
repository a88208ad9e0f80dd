// A ground-motion record read from a file, in SI units, and the options that control reading it.
#pragma once

#include <cstdint>
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
  // --gain: integer miniSEED counts per m/s² (the station's InstrumentSensitivity, e.g. from StationXML). Only
  // miniSEED integer data use it; any other file given a gain is rejected rather than read unscaled.
  std::optional<double> gain_counts_per_mps2;
  // Selects one component of a multi-component file: a miniSEED channel code ("HGE") or full id
  // ("NL.BGAR..HGE"), or a suite component "X", "Y" or "Z" (case-insensitive). Required when the file holds
  // several; an error for single-component formats.
  std::optional<std::string> channel;
};

struct Record {
  std::string path;                     // file it was read from
  std::string format;                   // "peer-at2", "plain", "esm", "itaca-cor-acc", "miniseed", "rockwatch-suite"
  std::string description;              // header text (event, station, component) when the file has it
  double dt_s = 0.0;                    // constant sample interval [s]
  double t0_s = 0.0;                    // time of the first sample [s] (0 unless the file states a time column)
  std::vector<double> horizontal_mps2;  // out-of-plane ground acceleration ü [m/s²], file's sign
  std::vector<double> vertical_mps2;    // vertical v̈ [m/s², up +]; empty unless the file has a third column
  AccelUnit units_in_file = AccelUnit::mps2;
  std::vector<std::string> notes;       // non-fatal findings, e.g. "file.AT2: NPTS=1999 but 2000 values; read 1999"

  // Absolute time of the first sample [ns since 1970-01-01 UTC] when the file states it (miniSEED, ESM); t0_s
  // stays relative (0 = first sample here), so tools that only need the record's own time axis ignore it.
  std::optional<std::int64_t> start_time_ns;
};

// Reads a record, detecting the format from its content, never from the extension: a miniSEED fixed header,
// the rockwatch suite magic line, an ESM ASCII header, an ITACA .cor.acc header, a PEER AT2 header, else plain
// columns. Throws RecordError naming the file and line on any defect (see record_error.hpp).
Record read_record(const std::string& path, const ReadOptions& options = {});

Record read_peer_at2(const std::string& path, const ReadOptions& options = {});
Record read_plain_text(const std::string& path, const ReadOptions& options = {});
// Engineering Strong-Motion database ASCII (.ASC): `KEY: value` header lines, then one value per line.
Record read_esm_ascii(const std::string& path, const ReadOptions& options = {});
// ITACA `.cor.acc`: `key : value` header lines, an "Acceleration time series in UNITS" line, then 14-character
// fixed-width fields with no separating blanks.
Record read_itaca_cor_acc(const std::string& path, const ReadOptions& options = {});
// miniSEED 2 (via libmseed): one channel, chosen by ReadOptions::channel when the file holds several.
Record read_miniseed(const std::string& path, const ReadOptions& options = {});
// One component (ReadOptions::channel = X, Y or Z) of a rockwatch suite set file (suite_format.hpp).
Record read_suite_component(const std::string& path, const ReadOptions& options = {});

// True when the first four lines of the file look like a PEER NGA AT2 header.
bool looks_like_peer_at2(const std::string& path);
// True when the header lines name both SAMPLING_INTERVAL_S and NDATA.
bool looks_like_esm_ascii(const std::string& path);
// True when the header lines give `Time Increment (s)` and `Number of Data`.
bool looks_like_itaca_cor_acc(const std::string& path);
// True when the file starts with a valid miniSEED data-record fixed header.
bool looks_like_miniseed(const std::string& path);

}  // namespace rockwatch::records
