// Private helpers shared by the record readers: whole-file reading, line splitting and strict number parsing.
// Header-only so the library's source list stays as declared in host_tools/CMakeLists.txt.
#pragma once

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "rockwatch/records/record.hpp"
#include "rockwatch/records/record_error.hpp"
#include "rockwatch/records/text_format.hpp"

namespace rockwatch::records::detail {

using text::NumberStatus;
using text::number_text;
using text::parse_number;
using text::shown;

// Real records are a few MB; the cap keeps a wrong path (a disk image, a log) from exhausting memory and keeps
// line numbers within int.
inline constexpr std::uintmax_t kMaxRecordFileBytes = std::uintmax_t{512} * 1024U * 1024U;

inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

inline std::string_view trim(std::string_view text) {
  while (!text.empty() && (is_blank(text.front()) || text.front() == '\n')) text.remove_prefix(1);
  while (!text.empty() && (is_blank(text.back()) || text.back() == '\n')) text.remove_suffix(1);
  return text;
}

inline std::string to_upper(std::string_view text) {
  std::string upper(text);
  for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return upper;
}

inline std::string file_name_of(const std::string& path) { return std::filesystem::path(path).filename().string(); }

inline int line_number(std::size_t index) { return static_cast<int>(index) + 1; }

inline std::string read_whole_file(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || !fs::exists(status)) {
    throw RecordError(path, 0, "cannot open the file: it does not exist (expected a readable record file)");
  }
  if (fs::is_directory(status)) throw RecordError(path, 0, "is a directory, expected a record file");
  // A FIFO or device would block or never end; records are ordinary files.
  if (!fs::is_regular_file(status)) throw RecordError(path, 0, "is not a regular file, expected a record file");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw RecordError(path, 0, "cannot read the file size: " + ec.message());
  if (size > kMaxRecordFileBytes) {
    throw RecordError(path, 0,
                      "file is " + std::to_string(size) + " bytes, expected a record file of at most " +
                          std::to_string(kMaxRecordFileBytes) + " bytes");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw RecordError(path, 0, "cannot open the file for reading (expected a readable record file)");
  std::string content;
  content.reserve(static_cast<std::size_t>(size));
  char chunk[65536];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    content.append(chunk, static_cast<std::size_t>(in.gcount()));
    if (content.size() > kMaxRecordFileBytes) {
      throw RecordError(path, 0, "file grew while being read; expected a record file that is not being written");
    }
  }
  if (in.bad()) throw RecordError(path, 0, "read error (expected a readable record file)");
  return content;
}

// Lines without their terminators; "\r\n" files (several PEER downloads) read like "\n" files.
// A UTF-8 byte-order mark (spreadsheet exports write one) is not part of the first line.
inline std::vector<std::string_view> split_lines(std::string_view content) {
  std::vector<std::string_view> lines;
  constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";
  std::size_t start = content.substr(0, kByteOrderMark.size()) == kByteOrderMark ? kByteOrderMark.size() : 0;
  while (start < content.size()) {
    std::size_t end = content.find('\n', start);
    if (end == std::string_view::npos) end = content.size();
    std::string_view line = content.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back(line);
    start = end + 1;
  }
  return lines;
}

inline bool all_blank(const std::vector<std::string_view>& lines) {
  for (const std::string_view line : lines) {
    if (!trim(line).empty()) return false;
  }
  return true;
}

inline std::vector<std::string_view> split_blanks(std::string_view text) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && is_blank(text[i])) ++i;
    const std::size_t start = i;
    while (i < text.size() && !is_blank(text[i])) ++i;
    if (i > start) tokens.push_back(text.substr(start, i - start));
  }
  return tokens;
}

inline std::string number_problem(NumberStatus status, std::string_view token) {
  switch (status) {
    case NumberStatus::ok:
      break;
    case NumberStatus::invalid:
      return "expected a decimal number, found " + shown(token);
    case NumberStatus::not_finite:
      return "expected a finite number, found " + shown(token) + " (NaN and Inf are not measurements)";
    case NumberStatus::out_of_range:
      return "expected a finite number, found " + shown(token) + " (out of the range of double)";
  }
  return "expected a decimal number, found " + shown(token);
}

inline void check_options(const std::string& path, const ReadOptions& options) {
  if (!std::isfinite(options.g_mps2) || options.g_mps2 <= 0.0) {
    throw RecordError(path, 0, "gravity g_mps2 = " + number_text(options.g_mps2) + ": expected a positive value");
  }
  if (options.dt_s && (!std::isfinite(*options.dt_s) || *options.dt_s <= 0.0)) {
    throw RecordError(
        path, 0, "sample interval --dt " + number_text(*options.dt_s) + " s: expected a positive number of seconds");
  }
  if (options.gain_counts_per_mps2 &&
      (!std::isfinite(*options.gain_counts_per_mps2) || *options.gain_counts_per_mps2 <= 0.0)) {
    throw RecordError(path, 0,
                      "--gain " + number_text(*options.gain_counts_per_mps2) +
                          ": expected a positive number of counts per m/s² (the station's InstrumentSensitivity)");
  }
}

// Formats with one acceleration series per file: a component choice or a counts gain given for them is a user
// mistake (the wrong file, or options meant for another one), so it is refused rather than ignored.
inline void reject_multi_component_options(const std::string& path, const ReadOptions& options,
                                           std::string_view format_label) {
  if (options.channel) {
    throw RecordError(path, 0,
                      "the file holds one component (" + std::string(format_label) + "); --channel/--component " +
                          shown(*options.channel) + " does not apply");
  }
  if (options.gain_counts_per_mps2) {
    throw RecordError(path, 0,
                      "the file holds acceleration values (" + std::string(format_label) +
                          "), not counts; --gain applies to miniSEED integer counts only");
  }
}

// "--dt 0.01 s ignored" for formats whose header states the sample interval.
inline void note_ignored_dt(const std::string& path, const ReadOptions& options, double dt_s, std::string_view source,
                            Record& record) {
  if (options.dt_s && std::fabs(*options.dt_s - dt_s) > 1e-6 * dt_s) {
    record.notes.push_back(file_name_of(path) + ": --dt " + number_text(*options.dt_s) + " s ignored, " +
                           std::string(source) + " gives dt = " + number_text(dt_s) + " s");
  }
}

// Multiplies in place; a huge value times g can overflow, which must not pass as a number.
inline void scale_to_mps2(const std::string& path, std::vector<double>& values, const std::vector<int>& lines,
                          double factor) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double scaled = values[i] * factor;
    if (!std::isfinite(scaled)) {
      throw RecordError(
          path, i < lines.size() ? lines[i] : 0,
          "value " + number_text(values[i]) + " overflows when converted to m/s²: expected a finite acceleration");
    }
    values[i] = scaled;
  }
}

}  // namespace rockwatch::records::detail
