// Shared by the record-reader fuzz targets: the invariants every successfully read record must satisfy, and reading
// one input with several sets of options.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fuzz_support.hpp"
#include "rockwatch/records/record.hpp"
#include "rockwatch/records/record_error.hpp"

namespace rockwatch::fuzz {

inline bool all_finite(const std::vector<double>& values) {
  for (const double v : values) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

// What record.hpp promises of every Record a reader returns: SI units, a constant positive dt, finite values, a
// vertical series empty or as long as the horizontal one, the format named.
inline void check_record(const records::Record& record) {
  ROCKWATCH_FUZZ_CHECK(!record.format.empty());
  ROCKWATCH_FUZZ_CHECK(std::isfinite(record.dt_s) && record.dt_s > 0.0);
  ROCKWATCH_FUZZ_CHECK(std::isfinite(record.t0_s));
  ROCKWATCH_FUZZ_CHECK(!record.horizontal_mps2.empty());
  ROCKWATCH_FUZZ_CHECK(all_finite(record.horizontal_mps2));
  ROCKWATCH_FUZZ_CHECK(record.vertical_mps2.empty() || record.vertical_mps2.size() == record.horizontal_mps2.size());
  ROCKWATCH_FUZZ_CHECK(all_finite(record.vertical_mps2));
}

// Reads the file with each set of options: a record that satisfies check_record, or a RecordError. Anything else
// escapes (a defect).
// With ROCKWATCH_FUZZ_VERBOSE set (running a fuzzer on chosen files), each outcome is printed.
template <typename Reader>
void read_with_each(const std::string& path, const std::vector<records::ReadOptions>& options, Reader read) {
  static const bool verbose = std::getenv("ROCKWATCH_FUZZ_VERBOSE") != nullptr;
  for (const records::ReadOptions& o : options) {
    try {
      const records::Record record = read(path, o);
      check_record(record);
      if (verbose) {
        std::fprintf(stderr, "read: %s, %zu samples, dt %g s, %zu notes\n", record.format.c_str(),
                     record.horizontal_mps2.size(), record.dt_s, record.notes.size());
      }
    } catch (const records::RecordError& error) {
      ROCKWATCH_FUZZ_CHECK(error.what()[0] != '\0');
      if (verbose) std::fprintf(stderr, "RecordError: %s\n", error.what());
    }
  }
}

inline records::ReadOptions options_with(std::optional<records::AccelUnit> units, std::optional<double> dt_s = {},
                                         std::optional<double> gain = {}, std::optional<std::string> channel = {}) {
  records::ReadOptions o;
  o.units = units;
  o.dt_s = dt_s;
  o.gain_counts_per_mps2 = gain;
  o.channel = std::move(channel);
  return o;
}

}  // namespace rockwatch::fuzz
