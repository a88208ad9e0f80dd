// The rockwatch suite set file (suite_format.hpp): writing, strict reading and detection.
#include "rockwatch/records/suite_format.hpp"

#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <ios>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "rockwatch/records/record.hpp"
#include "rockwatch/records/record_error.hpp"
#include "text_scan.hpp"

namespace rockwatch::records {

namespace {

using detail::shown;

constexpr std::size_t kComponents = 3;
constexpr std::string_view kColumns = "time_s x_mps2 y_mps2 z_mps2";
constexpr std::string_view kUnitsText = "m/s2";

// ---- writing ----------------------------------------------------------------------------------------------------

// Shortest text that reads back as the same double, so dt_s and the targets round-trip exactly.
std::string exact_text(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

void append_fixed6(std::string& out, double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::fixed, 6);
  out.append(buffer, result.ptr);
}

// 10 significant digits: "1.234567890e-05". Negative zero (the sign of a zero-envelope sample) is written as 0.
void append_value(std::string& out, double value) {
  char buffer[64];
  if (value == 0.0) value = 0.0;
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::scientific, 9);
  out.append(buffer, result.ptr);
}

void check_header_text(const std::string& path, std::string_view key, const std::string& value) {
  if (value.find_first_of("\r\n") != std::string::npos) {
    throw RecordError(path, 0, std::string(key) + " " + shown(value) + ": expected one line of text (no line breaks)");
  }
}

void check_writable(const std::string& path, const SuiteRecordFile& record) {
  if (!std::isfinite(record.dt_s) || record.dt_s <= 0.0) {
    throw RecordError(path, 0, "dt_s " + detail::number_text(record.dt_s) + ": expected a positive sample interval");
  }
  if (record.set < 1) {
    throw RecordError(path, 0, "set " + std::to_string(record.set) + ": expected a set number of 1 or more");
  }
  for (const double value : {record.g_mps2, record.ag_mps2, record.avg_mps2}) {
    if (!std::isfinite(value)) {
      throw RecordError(path, 0, "g_mps2/ag_mps2/avg_mps2 " + detail::number_text(value) + ": expected finite values");
    }
  }
  check_header_text(path, "suite", record.suite);
  check_header_text(path, "horizontal_target", record.horizontal_target);
  check_header_text(path, "vertical_target", record.vertical_target);
  check_header_text(path, "generator", record.generator);
  const std::size_t rows = record.components_mps2[0].size();
  if (rows == 0) throw RecordError(path, 0, "no samples: expected X, Y and Z components with at least one sample");
  const char* const names[kComponents] = {"X", "Y", "Z"};
  for (std::size_t c = 0; c < kComponents; ++c) {
    const std::vector<double>& values = record.components_mps2[c];
    if (values.size() != rows) {
      throw RecordError(path, 0,
                        std::string("component ") + names[c] + " has " + std::to_string(values.size()) +
                            " samples, X has " + std::to_string(rows) + ": expected equal lengths");
    }
    for (std::size_t k = 0; k < values.size(); ++k) {
      if (!std::isfinite(values[k])) {
        throw RecordError(path, 0,
                          std::string("component ") + names[c] + " sample " + std::to_string(k) + " is " +
                              detail::number_text(values[k]) + ": expected finite accelerations");
      }
    }
  }
}

std::string header_text(const SuiteRecordFile& record) {
  std::string out;
  auto line = [&out](std::string_view key, const std::string& value) {
    out += "# ";
    out += key;
    out += ": ";
    out += value;
    out += '\n';
  };
  line(kSuiteRecordMagic, std::to_string(kSuiteRecordVersion));
  line("suite", record.suite);
  line("set", std::to_string(record.set));
  line("units", std::string(kUnitsText));
  line("dt_s", exact_text(record.dt_s));
  line("g_mps2", exact_text(record.g_mps2));
  line("ag_mps2", exact_text(record.ag_mps2));
  line("avg_mps2", exact_text(record.avg_mps2));
  line("horizontal_target", record.horizontal_target);
  line("vertical_target", record.vertical_target);
  line("seed", std::to_string(record.seed));
  line("generator", record.generator);
  line("columns", std::string(kColumns));
  return out;
}

// ---- reading ----------------------------------------------------------------------------------------------------

struct HeaderLine {
  std::string value;
  int line = 0;
};

// "# key: value" -> (key, value); nullopt for a '#' line without ':' (a free comment).
std::optional<std::pair<std::string_view, std::string_view>> header_key_value(std::string_view line) {
  std::string_view body = detail::trim(line);
  if (body.empty() || body.front() != '#') return std::nullopt;
  body = detail::trim(body.substr(1));
  const std::size_t colon = body.find(':');
  if (colon == std::string_view::npos) return std::nullopt;
  return std::make_pair(detail::trim(body.substr(0, colon)), detail::trim(body.substr(colon + 1)));
}

const HeaderLine* find_key(const std::map<std::string, HeaderLine, std::less<>>& header, std::string_view key) {
  const auto found = header.find(key);
  return found == header.end() ? nullptr : &found->second;
}

const HeaderLine& required_key(const std::string& path, const std::map<std::string, HeaderLine, std::less<>>& header,
                               std::string_view key, std::string_view example, int at_line) {
  const HeaderLine* found = find_key(header, key);
  if (found == nullptr) {
    throw RecordError(path, at_line,
                      "no '" + std::string(key) + "' header line: expected '# " + std::string(key) + ": " +
                          std::string(example) + "' before the data");
  }
  return *found;
}

template <typename Integer>
Integer parse_whole(const std::string& path, const HeaderLine& entry, std::string_view key, Integer minimum) {
  Integer value{};
  const char* const first = entry.value.data();
  const char* const last = first + entry.value.size();
  const auto result = std::from_chars(first, last, value);
  if (entry.value.empty() || result.ec != std::errc{} || result.ptr != last || value < minimum) {
    throw RecordError(path, entry.line,
                      std::string(key) + ": " + shown(entry.value) + ": expected a whole number of at least " +
                          std::to_string(minimum));
  }
  return value;
}

double parse_header_number(const std::string& path, const HeaderLine& entry, std::string_view key, bool positive) {
  double value = 0.0;
  const detail::NumberStatus status = detail::parse_number(entry.value, value);
  if (status != detail::NumberStatus::ok || (positive && value <= 0.0) || (!positive && value < 0.0)) {
    throw RecordError(path, entry.line,
                      std::string(key) + ": " + shown(entry.value) + ": expected a " +
                          (positive ? "positive" : "non-negative") + " number");
  }
  return value;
}

void check_magic(const std::string& path, const std::vector<std::string_view>& lines) {
  const std::string expected =
      "'# " + std::string(kSuiteRecordMagic) + ": " + std::to_string(kSuiteRecordVersion) + "'";
  const auto first = lines.empty() ? std::nullopt : header_key_value(lines.front());
  if (!first || first->first != kSuiteRecordMagic) {
    throw RecordError(path, 1,
                      "expected the first line " + expected + " of a rockwatch suite record, found " +
                          shown(lines.empty() ? std::string_view{} : detail::trim(lines.front())));
  }
  int version = 0;
  const std::string_view text = first->second;
  const auto result = std::from_chars(text.data(), text.data() + text.size(), version);
  if (text.empty() || result.ec != std::errc{} || result.ptr != text.data() + text.size()) {
    throw RecordError(path, 1, "format version " + shown(text) + ": expected " + expected);
  }
  if (version != kSuiteRecordVersion) {
    throw RecordError(path, 1,
                      "format version " + std::to_string(version) + ": expected version " +
                          std::to_string(kSuiteRecordVersion) + " (written by another rockwatch release?)");
  }
}

void check_columns(const std::string& path, const HeaderLine& entry) {
  const auto names = detail::split_blanks(entry.value);
  const auto expected = detail::split_blanks(kColumns);
  if (names != expected) {
    throw RecordError(path, entry.line,
                      "columns: " + shown(entry.value) + ": expected '" + std::string(kColumns) + "'");
  }
}

// Times are written with 6 decimals, so each is k·dt to within half a microsecond (and the rounding of k·dt).
void check_time(const std::string& path, int line, std::size_t k, double dt_s, double time_s) {
  const double expected = static_cast<double>(k) * dt_s;
  const double tolerance = 0.5e-6 + 1e-12 + 8.0 * std::numeric_limits<double>::epsilon() * std::fabs(expected);
  if (std::fabs(time_s - expected) > tolerance) {
    throw RecordError(path, line,
                      "time " + detail::number_text(time_s) + " s: expected " + detail::number_text(expected) +
                          " s, row " + std::to_string(k) + " times dt_s " + detail::number_text(dt_s) +
                          " (rows are one sample apart, from 0)");
  }
}

}  // namespace

void write_suite_record(const std::string& path, const SuiteRecordFile& record) {
  check_writable(path, record);
  // Written beside the target and renamed into place, so a failed write never leaves half a set file behind.
  const std::string partial = path + ".partial";
  {
    std::ofstream out(partial, std::ios::binary | std::ios::trunc);
    if (!out) throw RecordError(path, 0, "cannot create the file (expected a writable directory)");
    const std::string header = header_text(record);
    out.write(header.data(), static_cast<std::streamsize>(header.size()));
    std::string row;
    const std::size_t rows = record.components_mps2[0].size();
    for (std::size_t k = 0; k < rows && out; ++k) {
      row.clear();
      append_fixed6(row, static_cast<double>(k) * record.dt_s);
      for (const std::vector<double>& component : record.components_mps2) {
        row += ' ';
        append_value(row, component[k]);
      }
      row += '\n';
      out.write(row.data(), static_cast<std::streamsize>(row.size()));
    }
    out.close();
    if (!out) {
      std::error_code ignored;
      std::filesystem::remove(partial, ignored);
      throw RecordError(path, 0, "write failed (disk full?): expected to write the whole set file");
    }
  }
  std::error_code ec;
  std::filesystem::rename(partial, path, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(partial, ignored);
    throw RecordError(path, 0, "cannot put the written file in place: " + ec.message());
  }
}

SuiteRecordFile read_suite_record(const std::string& path) {
  const std::string content = detail::read_whole_file(path);
  const std::vector<std::string_view> lines = detail::split_lines(content);
  if (detail::all_blank(lines)) {
    throw RecordError(path, 1,
                      "empty file: expected '# " + std::string(kSuiteRecordMagic) + ": " +
                          std::to_string(kSuiteRecordVersion) + "' and the header of a rockwatch suite record");
  }
  check_magic(path, lines);

  std::map<std::string, HeaderLine, std::less<>> header;
  std::size_t index = 1;
  for (; index < lines.size(); ++index) {
    const std::string_view line = detail::trim(lines[index]);
    if (line.empty()) continue;
    if (line.front() != '#') break;
    const auto pair = header_key_value(line);
    if (!pair) continue;
    const int number = detail::line_number(index);
    const auto [at, inserted] = header.emplace(std::string(pair->first), HeaderLine{std::string(pair->second), number});
    if (!inserted) {
      throw RecordError(path, number,
                        "'" + std::string(pair->first) + "' appears twice (also on line " +
                            std::to_string(at->second.line) + "): expected each header key once");
    }
  }
  const int data_line = detail::line_number(std::min(index, lines.size() - 1));

  SuiteRecordFile record;
  const HeaderLine& units = required_key(path, header, "units", kUnitsText, data_line);
  if (parse_accel_unit(units.value) != AccelUnit::mps2) {
    throw RecordError(path, units.line,
                      "units: " + shown(units.value) + ": expected m/s2 (suite records are always in m/s²)");
  }
  record.dt_s = parse_header_number(path, required_key(path, header, "dt_s", "0.005", data_line), "dt_s", true);
  check_columns(path, required_key(path, header, "columns", kColumns, data_line));
  if (const HeaderLine* suite = find_key(header, "suite")) record.suite = suite->value;
  if (const HeaderLine* set = find_key(header, "set")) record.set = parse_whole<int>(path, *set, "set", 1);
  if (const HeaderLine* g = find_key(header, "g_mps2")) record.g_mps2 = parse_header_number(path, *g, "g_mps2", true);
  if (const HeaderLine* ag = find_key(header, "ag_mps2")) {
    record.ag_mps2 = parse_header_number(path, *ag, "ag_mps2", false);
  }
  if (const HeaderLine* avg = find_key(header, "avg_mps2")) {
    record.avg_mps2 = parse_header_number(path, *avg, "avg_mps2", false);
  }
  if (const HeaderLine* h = find_key(header, "horizontal_target")) record.horizontal_target = h->value;
  if (const HeaderLine* v = find_key(header, "vertical_target")) record.vertical_target = v->value;
  if (const HeaderLine* seed = find_key(header, "seed")) {
    record.seed = parse_whole<std::uint64_t>(path, *seed, "seed", 0);
  }
  if (const HeaderLine* generator = find_key(header, "generator")) record.generator = generator->value;

  std::size_t k = 0;
  for (; index < lines.size(); ++index) {
    const std::string_view line = detail::trim(lines[index]);
    if (line.empty()) continue;
    const int number = detail::line_number(index);
    if (line.front() == '#') {
      throw RecordError(path, number, "a '#' line among the data: expected all header lines before the first row");
    }
    const auto fields = detail::split_blanks(line);
    if (fields.size() != kComponents + 1) {
      throw RecordError(
          path, number,
          "found " + std::to_string(fields.size()) + " columns: expected 4 (" + std::string(kColumns) + ")");
    }
    double values[kComponents + 1] = {};
    for (std::size_t c = 0; c < fields.size(); ++c) {
      const detail::NumberStatus status = detail::parse_number(fields[c], values[c]);
      if (status != detail::NumberStatus::ok) {
        throw RecordError(path, number, detail::number_problem(status, fields[c]));
      }
    }
    check_time(path, number, k, record.dt_s, values[0]);
    for (std::size_t c = 0; c < kComponents; ++c) record.components_mps2[c].push_back(values[c + 1]);
    ++k;
  }
  if (k == 0) {
    throw RecordError(path, data_line,
                      "no data rows: expected rows of '" + std::string(kColumns) + "' after the header");
  }
  return record;
}

bool looks_like_suite_record(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::string head(256, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  const std::vector<std::string_view> lines = detail::split_lines(head);
  if (lines.empty()) return false;
  const auto first = header_key_value(lines.front());
  return first && first->first == kSuiteRecordMagic;
}

}  // namespace rockwatch::records
