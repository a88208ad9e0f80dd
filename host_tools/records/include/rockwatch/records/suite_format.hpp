// The rockwatch ground-motion suite: one text file per record set (time, X, Y, Z in m/s²) and a directory
// manifest (manifest.json) that lists the sets. Written by `rockwatch generate`, read by every tool that takes a
// record (`--suite DIR --set N --component X|Y|Z`, or `--record FILE --component X`).
//
// Set file (text, '#' header lines of `key: value`, then one row per sample):
//   # rockwatch-suite-record: 1
//   # suite: npr9998-2015
//   # set: 3
//   # units: m/s2
//   # dt_s: 0.005
//   # g_mps2: 9.81
//   # ag_mps2: 1.962          (target PGA of X and Y, a_g)
//   # avg_mps2: 1.962         (target PGA of Z, a_vg)
//   # horizontal_target: npr9998-2015 p=2.5 tb_s=0.15 tc_s=0.4 td_s=0.67
//   # vertical_target: vertical-default p=3 tb_s=0.05 tc_s=0.15 td_s=1
//   # seed: 9998
//   # generator: rockwatch 0.4.0 generate --sets 11 --seed 9998
//   # columns: time_s x_mps2 y_mps2 z_mps2
//   0.000000 1.234567890e-05 ...
// X and Y are horizontal (out-of-plane use: either), Z vertical, up positive. Times are k·dt exactly.
//
// Manifest (manifest.json): {"format": "rockwatch-suite-manifest", "version": 1, "suite": "...",
//   "sets": [{"set": 1, "file": "set01.txt", ...}, ...], ...}; only "format", "sets", "set" and "file" are
//   required to find a set file, the rest (measures per record, the regenerating command) is for people.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace rockwatch::records {

inline constexpr const char* kSuiteRecordMagic = "rockwatch-suite-record";
inline constexpr int kSuiteRecordVersion = 1;
inline constexpr const char* kSuiteManifestName = "manifest.json";
inline constexpr const char* kSuiteManifestFormat = "rockwatch-suite-manifest";

struct SuiteRecordFile {
  std::string suite;             // suite name, e.g. "npr9998-2015"
  int set = 0;                   // 1-based set number
  double dt_s = 0.0;             // sample interval [s]
  double g_mps2 = 9.81;          // g used for the targets in g
  double ag_mps2 = 0.0;          // target PGA of X and Y [m/s²]
  double avg_mps2 = 0.0;         // target PGA of Z [m/s²]
  std::string horizontal_target; // target spectrum, name and parameters
  std::string vertical_target;
  std::uint64_t seed = 0;        // suite seed
  std::string generator;         // tool version and command that made it
  std::array<std::vector<double>, 3> components_mps2;  // X, Y, Z [m/s²], equal lengths, sample k at k·dt
};

// Writes the file (values with 10 significant digits, times with 6 decimals). Throws RecordError naming the path
// when the file cannot be written completely or the components differ in length / are empty / non-finite.
void write_suite_record(const std::string& path, const SuiteRecordFile& record);

// Reads a whole set file. Throws RecordError naming the file, line and field on any defect.
SuiteRecordFile read_suite_record(const std::string& path);

// True when the file's first line is the suite-record magic line.
bool looks_like_suite_record(const std::string& path);

// The set file of set `set` in suite directory `dir`, from its manifest. Throws RecordError naming the manifest
// when it is missing or malformed, or when the set is not in it (listing the sets it has).
std::string suite_set_path(const std::string& dir, int set);

// The set numbers the manifest lists, in its order.
std::vector<int> suite_sets(const std::string& dir);

}  // namespace rockwatch::records
