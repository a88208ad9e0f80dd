// One component of a rockwatch suite set file as a Record, for read_record and every tool that takes --record.
#include <array>
#include <cctype>
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>

#include "rockwatch/records/record.hpp"
#include "rockwatch/records/record_error.hpp"
#include "rockwatch/records/suite_format.hpp"
#include "text_scan.hpp"

namespace rockwatch::records {

namespace {

constexpr std::array<std::string_view, 3> kComponentNames{"X", "Y", "Z"};

std::size_t component_index(const std::string& path, const ReadOptions& options) {
  if (!options.channel) {
    throw RecordError(path, 0,
                      "the file holds 3 components (X, Y, Z: horizontal, horizontal, vertical): choose one with "
                      "--component X|Y|Z");
  }
  const std::string wanted = detail::to_upper(detail::trim(*options.channel));
  for (std::size_t c = 0; c < kComponentNames.size(); ++c) {
    if (wanted == kComponentNames[c]) return c;
  }
  throw RecordError(
      path, 0,
      "component " + detail::shown(*options.channel) + ": expected X, Y or Z; choose one with --component X|Y|Z");
}

}  // namespace

Record read_suite_component(const std::string& path, const ReadOptions& options) {
  detail::check_options(path, options);
  // The format fixes the units; a different --units would silently rescale a generated motion.
  if (options.units && *options.units != AccelUnit::mps2) {
    throw RecordError(path, 0,
                      "a rockwatch suite record is always in m/s²; --units " +
                          std::string(accel_unit_name(*options.units)) + " does not apply");
  }
  if (options.gain_counts_per_mps2) {
    throw RecordError(path, 0, "a rockwatch suite record holds m/s², not counts; --gain does not apply");
  }
  const std::size_t component = component_index(path, options);
  SuiteRecordFile file = read_suite_record(path);

  Record record;
  record.path = path;
  record.format = "rockwatch-suite";
  record.description = "suite";
  if (!file.suite.empty()) record.description += " " + file.suite;
  if (file.set > 0) record.description += " set " + std::to_string(file.set);
  record.description += " component " + std::string(kComponentNames[component]);
  record.dt_s = file.dt_s;
  record.t0_s = 0.0;
  record.units_in_file = AccelUnit::mps2;
  detail::note_ignored_dt(path, options, record.dt_s, "the header's dt_s", record);
  record.horizontal_mps2 = std::move(file.components_mps2[component]);
  return record;
}

}  // namespace rockwatch::records
