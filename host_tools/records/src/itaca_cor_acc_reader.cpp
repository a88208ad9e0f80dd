// ITACA `.cor.acc` records (as distributed with GEM's gmpe-smtk): `key : value` header lines (`Time Increment (s)`,
// `Number of Data`, `PGA (m/s/s)`, ...), the line `Accelaration time series in m/s/s` (sic), then values in
// fixed-width 14-character fields, 5 per line, with no blanks between them (`-1.3724600E-07-2.6835700E-07...`).
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstddef>
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

constexpr std::size_t kFieldWidth = 14;
const char* const kSeriesLineExample = "'Acceleration time series in m/s/s'";

struct HeaderValue {
  std::string text;
  int line = 0;
};

struct Header {
  std::optional<HeaderValue> dt;
  std::optional<HeaderValue> npts;
  std::optional<HeaderValue> pga;
  std::string event_time;
  std::string station;
  std::string orientation;
};

// ITACA writes "Accelaration"; a corrected file may not. Returns the units text after "... time series in", or
// nullopt when the line is not an acceleration series line.
std::optional<std::string_view> acceleration_series_units(std::string_view line) {
  const std::string upper = detail::to_upper(line);
  for (const std::string_view prefix : {"ACCELARATION TIME SERIES IN", "ACCELERATION TIME SERIES IN"}) {
    if (upper.rfind(prefix, 0) == 0) return detail::trim(line.substr(prefix.size()));
  }
  return std::nullopt;
}

bool is_other_series_line(std::string_view line) {
  const std::string upper = detail::to_upper(line);
  return upper.find("TIME SERIES") != std::string::npos &&
         (upper.rfind("VELOCITY", 0) == 0 || upper.rfind("DISPLACEMENT", 0) == 0);
}

bool starts_like_number(std::string_view line) {
  const std::string_view body = detail::trim(line);
  if (body.empty()) return false;
  const char c = body.front();
  return std::isdigit(static_cast<unsigned char>(c)) != 0 || c == '-' || c == '+' || c == '.';
}

void take_header_line(std::string_view key, std::string_view value, int line, Header& header) {
  const std::string upper = detail::to_upper(key);
  HeaderValue entry{std::string(value), line};
  if (upper == "TIME INCREMENT (S)") {
    header.dt = std::move(entry);
  } else if (upper == "NUMBER OF DATA") {
    header.npts = std::move(entry);
  } else if (upper.rfind("PGA", 0) == 0) {
    header.pga = std::move(entry);
  } else if (upper == "EVENT DATE & TIME") {
    header.event_time = std::string(value);
  } else if (upper.rfind("STATION CODE", 0) == 0) {
    header.station = std::string(value);
  } else if (upper == "ORIENTATION") {
    header.orientation = std::string(value);
  }
}

std::size_t parse_npts(const std::string& path, const HeaderValue& value) {
  long long npts = 0;
  const char* const first = value.text.data();
  const char* const last = first + value.text.size();
  const auto result = std::from_chars(first, last, npts);
  if (value.text.empty() || result.ec != std::errc{} || result.ptr != last || npts <= 0) {
    throw RecordError(path, value.line,
                      "Number of Data : " + shown(value.text) + ": expected a positive whole number of values");
  }
  return static_cast<std::size_t>(npts);
}

double parse_dt(const std::string& path, const HeaderValue& value) {
  double dt_s = 0.0;
  if (detail::parse_number(value.text, dt_s) != detail::NumberStatus::ok || dt_s <= 0.0) {
    throw RecordError(path, value.line,
                      "Time Increment (s) : " + shown(value.text) + ": expected a positive sample interval in seconds");
  }
  return dt_s;
}

std::string describe(const Header& header) {
  std::string description;
  for (const std::string* part : {&header.event_time, &header.station, &header.orientation}) {
    if (part->empty()) continue;
    if (!description.empty()) description += ", ";
    description += *part;
  }
  return description;
}

// Values of one data line, split by column: the fields run together, so blanks cannot separate them.
void read_fields(const std::string& path, int line, std::string_view text, std::vector<double>& values) {
  while (!text.empty() && detail::is_blank(text.back())) text.remove_suffix(1);
  if (text.size() % kFieldWidth != 0) {
    throw RecordError(path, line,
                      "line of " + std::to_string(text.size()) +
                          " characters: expected values in fixed-width fields of 14 characters (e.g. "
                          "'-1.3724600E-07-2.6835700E-07'), a multiple of 14 per line");
  }
  for (std::size_t at = 0; at < text.size(); at += kFieldWidth) {
    const std::string_view field = detail::trim(text.substr(at, kFieldWidth));
    const std::string columns = "columns " + std::to_string(at + 1) + "-" + std::to_string(at + kFieldWidth);
    if (field.empty()) throw RecordError(path, line, columns + " are blank: expected a value in every field");
    double value = 0.0;
    const detail::NumberStatus status = detail::parse_number(field, value);
    if (status != detail::NumberStatus::ok) {
      throw RecordError(path, line, columns + ": " + detail::number_problem(status, field));
    }
    values.push_back(value);
  }
}

void check_pga(const std::string& path, const Header& header, const std::vector<double>& values, Record& record) {
  if (!header.pga) return;
  double stated = 0.0;
  if (detail::parse_number(header.pga->text, stated) != detail::NumberStatus::ok) return;
  double peak = 0.0;
  for (const double v : values) peak = std::max(peak, std::fabs(v));
  // Header and values are printed with 8 significant digits; a larger difference means a damaged or edited file.
  if (std::fabs(peak - std::fabs(stated)) > 1e-6 * std::fabs(stated) + 1e-300) {
    record.notes.push_back(detail::file_name_of(path) + ":" + std::to_string(header.pga->line) + ": header PGA " +
                           detail::number_text(stated) + " but the values peak at " + detail::number_text(peak) +
                           " (file units)");
  }
}

}  // namespace

Record read_itaca_cor_acc(const std::string& path, const ReadOptions& options) {
  detail::check_options(path, options);
  detail::reject_multi_component_options(path, options, "an ITACA .cor.acc record");
  const std::string content = detail::read_whole_file(path);
  const std::vector<std::string_view> lines = detail::split_lines(content);
  if (detail::all_blank(lines)) {
    throw RecordError(path, 1,
                      "empty file: expected ITACA 'key : value' header lines, " + std::string(kSeriesLineExample) +
                          " and the values");
  }

  Header header;
  std::optional<std::string_view> series_units;
  int series_line = 0;
  std::size_t index = 0;
  for (; index < lines.size() && !series_units; ++index) {
    const std::string_view line = detail::trim(lines[index]);
    const int number = detail::line_number(index);
    if (line.empty()) continue;
    series_units = acceleration_series_units(line);
    if (series_units) {
      series_line = number;
      continue;
    }
    if (is_other_series_line(line)) {
      throw RecordError(path, number,
                        shown(line) +
                            ": expected an acceleration time series (.cor.acc), not velocity or "
                            "displacement");
    }
    const std::size_t colon = line.find(':');
    if (colon == std::string_view::npos) {
      if (starts_like_number(line)) {
        throw RecordError(path, number,
                          "values before the line " + std::string(kSeriesLineExample) +
                              ": expected that line after the header, naming the units");
      }
      throw RecordError(
          path, number,
          "expected a 'key : value' header line or " + std::string(kSeriesLineExample) + ", found " + shown(line));
    }
    take_header_line(detail::trim(line.substr(0, colon)), detail::trim(line.substr(colon + 1)), number, header);
  }
  if (!series_units) {
    throw RecordError(path, detail::line_number(lines.size() - 1),
                      "no line " + std::string(kSeriesLineExample) +
                          ": expected it after the header, before the "
                          "values");
  }
  if (!header.dt) {
    throw RecordError(path, series_line, "no 'Time Increment (s) : ...' header line: expected the sample interval");
  }
  if (!header.npts) {
    throw RecordError(path, series_line, "no 'Number of Data : ...' header line: expected the number of values");
  }

  Record record;
  record.path = path;
  record.format = "itaca-cor-acc";
  record.description = describe(header);
  record.dt_s = parse_dt(path, *header.dt);
  record.t0_s = 0.0;
  detail::note_ignored_dt(path, options, record.dt_s, "the header's Time Increment", record);
  const std::size_t npts = parse_npts(path, *header.npts);

  const std::optional<AccelUnit> stated = parse_accel_unit(*series_units);
  if (options.units) {
    record.units_in_file = *options.units;
    if (!stated || *stated != *options.units) {
      record.notes.push_back(detail::file_name_of(path) + ": units taken as " +
                             std::string(accel_unit_name(*options.units)) + " from the options, line " +
                             std::to_string(series_line) + " says " + shown(*series_units));
    }
  } else if (stated) {
    record.units_in_file = *stated;
  } else {
    throw RecordError(path, series_line,
                      "unknown units " + shown(*series_units) +
                          ": expected m/s/s, cm/s/s or g, or pass --units (g|mps2|cmps2|mmps2)");
  }

  std::vector<double> values;
  std::vector<int> value_lines;
  // 'Number of Data' is only a claim: reserve no more than the file can hold (14 bytes a value), so a huge count in a
  // small file is reported as truncated instead of allocating gigabytes.
  values.reserve(std::min(npts, content.size() / kFieldWidth + 1));
  std::size_t fields_per_line = 0;
  int short_line = 0;  // a line with fewer fields than the first; only the last line may be one
  std::size_t short_line_fields = 0;
  int last_value_line = series_line;
  for (; index < lines.size(); ++index) {
    if (detail::trim(lines[index]).empty()) continue;
    const int line = detail::line_number(index);
    if (short_line != 0) {
      throw RecordError(path, short_line,
                        "only " + std::to_string(short_line_fields) + " fields where the lines before have " +
                            std::to_string(fields_per_line) +
                            ": expected a short line only at the end (a damaged line?)");
    }
    const std::size_t before = values.size();
    read_fields(path, line, lines[index], values);
    const std::size_t fields = values.size() - before;
    if (fields_per_line == 0) {
      fields_per_line = fields;
    } else if (fields > fields_per_line) {
      throw RecordError(path, line,
                        std::to_string(fields) + " fields: expected at most " + std::to_string(fields_per_line) +
                            " per line like the first data line");
    } else if (fields < fields_per_line) {
      short_line = line;
      short_line_fields = fields;
    }
    if (values.size() > npts) {
      throw RecordError(
          path, line,
          "more values than 'Number of Data : " + std::to_string(npts) + "': expected exactly " + std::to_string(npts));
    }
    value_lines.insert(value_lines.end(), fields, line);
    last_value_line = line;
  }
  if (values.size() < npts) {
    throw RecordError(path, last_value_line,
                      "the file ends after " + std::to_string(values.size()) + " of " + std::to_string(npts) +
                          " values ('Number of Data'): expected " + std::to_string(npts) + " (a truncated file?)");
  }

  check_pga(path, header, values, record);
  detail::scale_to_mps2(path, values, value_lines, accel_unit_to_mps2(record.units_in_file, options.g_mps2));
  record.horizontal_mps2 = std::move(values);
  return record;
}

}  // namespace rockwatch::records
