// Wall-sensor CSV files (wall_sensor_csv.hpp): a header naming the columns, then one sample per row.
#include "rockwatch/records/wall_sensor_csv.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "rockwatch/records/record_error.hpp"
#include "text_scan.hpp"

namespace rockwatch::records {

namespace {

using detail::NumberStatus;
using detail::shown;

enum class Column { time, x, a };

const char* const kColumnsExpected =
    "expected a header line naming the columns t_s and x_mid_m and/or a_mid_mps2, separated by commas "
    "(e.g. t_s,x_mid_m,a_mid_mps2)";

// Fields of a line split at every ',' (an empty field is kept: it means "absent" in a data row), each trimmed.
std::vector<std::string_view> comma_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  for (;;) {
    const std::size_t end = line.find(',', start);
    if (end == std::string_view::npos) {
      fields.push_back(detail::trim(line.substr(start)));
      return fields;
    }
    fields.push_back(detail::trim(line.substr(start, end - start)));
    start = end + 1;
  }
}

std::vector<Column> parse_header(const std::string& path, int line, std::string_view text, WallSensorFile& file) {
  std::vector<Column> columns;
  bool has_time = false;
  for (const std::string_view name : comma_fields(text)) {
    const std::string lower = [&] {
      std::string s(name);
      for (char& c : s) c = static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
      return s;
    }();
    Column column;
    bool* seen = nullptr;
    if (lower == kWallSensorTimeColumn) {
      column = Column::time;
      seen = &has_time;
    } else if (lower == kWallSensorXColumn) {
      column = Column::x;
      seen = &file.has_x_column;
    } else if (lower == kWallSensorAColumn) {
      column = Column::a;
      seen = &file.has_a_column;
    } else {
      double ignored = 0.0;
      if (detail::parse_number(name, ignored) != NumberStatus::invalid) {
        throw RecordError(path, line, "found a number " + shown(name) + " where the header belongs: " + kColumnsExpected);
      }
      throw RecordError(path, line,
                        "unknown column " + shown(name) + ": " + kColumnsExpected);
    }
    if (*seen) throw RecordError(path, line, "column " + shown(name) + " named twice: expected each column once");
    *seen = true;
    columns.push_back(column);
  }
  if (!has_time) throw RecordError(path, line, std::string("no t_s column: ") + kColumnsExpected);
  if (!file.has_x_column && !file.has_a_column) {
    throw RecordError(path, line, std::string("no sensor column: ") + kColumnsExpected);
  }
  return columns;
}

// A value field: empty = absent (false), else a finite number.
bool parse_value(const std::string& path, int line, std::string_view field, const char* column, double& value) {
  if (field.empty()) return false;
  const NumberStatus status = detail::parse_number(field, value);
  if (status != NumberStatus::ok) {
    throw RecordError(path, line,
                      std::string(column) + ": " + detail::number_problem(status, field) +
                          " (or an empty field when the sensor has no value)");
  }
  return true;
}

WallSensorRow parse_row(const std::string& path, int line, std::string_view text, const std::vector<Column>& columns) {
  const std::vector<std::string_view> fields = comma_fields(text);
  if (fields.size() != columns.size()) {
    throw RecordError(path, line,
                      "found " + std::to_string(fields.size()) + " field" + (fields.size() == 1 ? "" : "s") +
                          ", expected " + std::to_string(columns.size()) + " as the header names");
  }
  WallSensorRow row;
  row.line = line;
  for (std::size_t i = 0; i < columns.size(); ++i) {
    const std::string_view field = fields[i];
    switch (columns[i]) {
      case Column::time: {
        if (field.empty()) throw RecordError(path, line, "t_s is empty: expected the sample time in seconds");
        double t_s = 0.0;
        const NumberStatus status = detail::parse_number(field, t_s);
        if (status != NumberStatus::ok) throw RecordError(path, line, "t_s: " + detail::number_problem(status, field));
        if (!(std::fabs(t_s) <= kMaxWallSensorTime_s)) {
          throw RecordError(path, line,
                            "t_s = " + detail::number_text(t_s) + ": expected a time within +-" +
                                detail::number_text(kMaxWallSensorTime_s) + " s of the record's start");
        }
        row.utime_us = static_cast<std::int64_t>(std::llround(t_s * 1e6));
        break;
      }
      case Column::x: row.x_valid = parse_value(path, line, field, kWallSensorXColumn, row.x_mid_m); break;
      case Column::a: row.a_valid = parse_value(path, line, field, kWallSensorAColumn, row.a_mid_mps2); break;
    }
  }
  return row;
}

}  // namespace

WallSensorFile read_wall_sensor_csv(const std::string& path) {
  const std::string content = detail::read_whole_file(path);
  const std::vector<std::string_view> lines = detail::split_lines(content);
  WallSensorFile file;
  file.path = path;
  std::vector<Column> columns;
  bool have_header = false;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const int line = detail::line_number(i);
    const std::string_view text = detail::trim(lines[i]);
    if (text.empty() || text.front() == '#') continue;
    if (!have_header) {
      columns = parse_header(path, line, text, file);
      have_header = true;
      continue;
    }
    WallSensorRow row = parse_row(path, line, text, columns);
    if (!file.rows.empty() && row.utime_us <= file.rows.back().utime_us) {
      const WallSensorRow& before = file.rows.back();
      throw RecordError(path, line,
                        "t_s = " + detail::number_text(double(row.utime_us) * 1e-6) + " s does not follow t_s = " +
                            detail::number_text(double(before.utime_us) * 1e-6) + " s of line " +
                            std::to_string(before.line) + ": expected times strictly increasing, at least 1 us apart");
    }
    file.rows.push_back(row);
  }
  if (!have_header) {
    throw RecordError(path, 0, std::string("no header line: ") + kColumnsExpected + ", then one row per sample");
  }
  if (file.rows.empty()) throw RecordError(path, 0, "no sample rows after the header: expected at least one sample");
  return file;
}

}  // namespace rockwatch::records
