// Engineering Strong-Motion database (ESM, ORFEUS) ASCII records (.ASC): about 64 header lines `KEY: value`
// (EVENT_NAME, ..., NETWORK, STATION_CODE, STREAM, UNITS, NDATA, SAMPLING_INTERVAL_S, DATA_TYPE, ..., USER5), then
// one value per line.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "civil_time.hpp"
#include "rockwatch/records/record.hpp"
#include "rockwatch/records/record_error.hpp"
#include "text_scan.hpp"

namespace rockwatch::records {

namespace {

using detail::shown;

struct HeaderValue {
  std::string text;  // trimmed value
  int line = 0;
};

using Header = std::map<std::string, HeaderValue, std::less<>>;

bool is_key_char(char c) {
  const auto u = static_cast<unsigned char>(c);
  return std::isalnum(u) != 0 || c == '_' || c == '/' || c == '^' || c == '.' || c == '-' || c == '(' || c == ')';
}

// "KEY: value" with KEY one word of letters, digits and the unit punctuation ESM uses ("VS30_M/S", "PGA_CM/S^2").
// Values never contain a line break; data lines never contain ':', so the first non-key line ends the header.
std::optional<std::pair<std::string_view, std::string_view>> key_value(std::string_view line) {
  const std::size_t colon = line.find(':');
  if (colon == std::string_view::npos || colon == 0) return std::nullopt;
  const std::string_view key = line.substr(0, colon);
  if (std::isalpha(static_cast<unsigned char>(key.front())) == 0) return std::nullopt;
  for (const char c : key) {
    if (!is_key_char(c)) return std::nullopt;
  }
  return std::make_pair(key, detail::trim(line.substr(colon + 1)));
}

const HeaderValue& required(const std::string& path, const Header& header, std::string_view key, int header_end_line,
                            std::string_view expected) {
  const auto found = header.find(key);
  if (found == header.end()) {
    throw RecordError(path, header_end_line,
                      "the ESM header has no " + std::string(key) + ": expected a line '" + std::string(key) + ": " +
                          std::string(expected) + "'");
  }
  return found->second;
}

std::string_view optional_text(const Header& header, std::string_view key) {
  const auto found = header.find(key);
  return found == header.end() ? std::string_view{} : std::string_view(found->second.text);
}

std::size_t parse_ndata(const std::string& path, const HeaderValue& value) {
  long long ndata = 0;
  const char* const first = value.text.data();
  const char* const last = first + value.text.size();
  const auto result = std::from_chars(first, last, ndata);
  if (value.text.empty() || result.ec != std::errc{} || result.ptr != last || ndata <= 0) {
    throw RecordError(path, value.line, "NDATA: " + shown(value.text) + ": expected a positive whole number of values");
  }
  return static_cast<std::size_t>(ndata);
}

double parse_sampling_interval(const std::string& path, const HeaderValue& value) {
  double dt_s = 0.0;
  if (detail::parse_number(value.text, dt_s) != detail::NumberStatus::ok || dt_s <= 0.0) {
    throw RecordError(path, value.line,
                      "SAMPLING_INTERVAL_S: " + shown(value.text) + ": expected a positive sample interval in seconds");
  }
  return dt_s;
}

// ESM also distributes velocity, displacement and response-spectrum files with the same header; only acceleration
// time series are ground motions for the wall.
void check_data_type(const std::string& path, const Header& header, Record& record) {
  const auto found = header.find("DATA_TYPE");
  if (found == header.end()) {
    record.notes.push_back(detail::file_name_of(path) +
                           ": the ESM header has no DATA_TYPE; read as ACCELERATION from its UNITS");
    return;
  }
  if (detail::to_upper(found->second.text) != "ACCELERATION") {
    throw RecordError(path, found->second.line,
                      "DATA_TYPE: " + shown(found->second.text) +
                          ": expected ACCELERATION (a velocity, displacement or spectrum file is not a ground "
                          "acceleration record; take the .ACC file of the same stream)");
  }
}

AccelUnit resolve_units(const std::string& path, const Header& header, const ReadOptions& options, int header_end_line,
                        Record& record) {
  const auto found = header.find("UNITS");
  const std::optional<AccelUnit> stated = found == header.end() ? std::nullopt : parse_accel_unit(found->second.text);
  if (options.units) {
    if (!stated || *stated != *options.units) {
      const std::string says = found == header.end() ? std::string("no UNITS")
                                                     : "UNITS: " + shown(found->second.text) + " on line " +
                                                           std::to_string(found->second.line);
      record.notes.push_back(detail::file_name_of(path) + ": units taken as " +
                             std::string(accel_unit_name(*options.units)) + " from the options, the header says " +
                             says);
    }
    return *options.units;
  }
  if (found == header.end()) {
    throw RecordError(path, header_end_line,
                      "the ESM header has no UNITS: expected a line 'UNITS: cm/s^2' (or m/s^2, g), or pass --units");
  }
  if (!stated) {
    throw RecordError(path, found->second.line,
                      "UNITS: " + shown(found->second.text) +
                          ": expected acceleration units cm/s^2, m/s^2, mm/s^2 or g, or pass --units "
                          "(g|mps2|cmps2|mmps2)");
  }
  return *stated;
}

bool all_digits(std::string_view text) {
  if (text.empty()) return false;
  for (const char c : text) {
    if (std::isdigit(static_cast<unsigned char>(c)) == 0) return false;
  }
  return true;
}

unsigned digits_value(std::string_view text) {
  unsigned value = 0;
  for (const char c : text) value = value * 10U + static_cast<unsigned>(c - '0');
  return value;
}

// "20190728_160919.870" (DATE_TIME_FIRST_SAMPLE_YYYYMMDD_HHMMSS), fraction optional, to epoch ns.
std::optional<std::int64_t> first_sample_time_ns(std::string_view text) {
  if (text.size() < 15 || text[8] != '_') return std::nullopt;
  const std::string_view date = text.substr(0, 8);
  const std::string_view time = text.substr(9, 6);
  std::string_view fraction = text.substr(15);
  if (!all_digits(date) || !all_digits(time)) return std::nullopt;
  if (!fraction.empty()) {
    if (fraction.front() != '.' || fraction.size() > 10 || !all_digits(fraction.substr(1))) return std::nullopt;
    fraction.remove_prefix(1);
  }
  const unsigned year = digits_value(date.substr(0, 4));
  const unsigned month = digits_value(date.substr(4, 2));
  const unsigned day = digits_value(date.substr(6, 2));
  const unsigned hour = digits_value(time.substr(0, 2));
  const unsigned minute = digits_value(time.substr(2, 2));
  const unsigned second = digits_value(time.substr(4, 2));
  // Years outside 1900-2199 are typos, and beyond what epoch nanoseconds hold at the far end.
  if (year < 1900 || year > 2199 || month < 1 || month > 12 || day < 1 || day > 31 || hour > 23 || minute > 59 ||
      second > 60) {
    return std::nullopt;
  }
  std::int64_t ns = 0;
  std::int64_t scale = detail::kNanosecondsPerSecond;
  for (const char c : fraction) {
    scale /= 10;
    ns += static_cast<std::int64_t>(c - '0') * scale;
  }
  const std::int64_t days = detail::days_from_civil(year, month, day);
  const std::int64_t seconds = days * detail::kSecondsPerDay + hour * 3600LL + minute * 60LL + second;
  return seconds * detail::kNanosecondsPerSecond + ns;
}

std::string describe(const Header& header) {
  std::string station(optional_text(header, "NETWORK"));
  const std::string_view code = optional_text(header, "STATION_CODE");
  if (!code.empty()) station += station.empty() ? std::string(code) : "." + std::string(code);
  std::string description;
  for (const std::string_view part :
       {optional_text(header, "EVENT_NAME"), std::string_view(station), optional_text(header, "STREAM")}) {
    if (part.empty()) continue;
    if (!description.empty()) description += ", ";
    description += part;
  }
  return description;
}

}  // namespace

Record read_esm_ascii(const std::string& path, const ReadOptions& options) {
  detail::check_options(path, options);
  detail::reject_multi_component_options(path, options, "an ESM ASCII record");
  const std::string content = detail::read_whole_file(path);
  const std::vector<std::string_view> lines = detail::split_lines(content);
  if (detail::all_blank(lines)) {
    throw RecordError(path, 1,
                      "empty file: expected an ESM ASCII header ('EVENT_NAME: ...', ..., 'NDATA: ...') "
                      "followed by acceleration values");
  }

  Header header;
  std::size_t index = 0;
  for (; index < lines.size(); ++index) {
    const std::string_view line = detail::trim(lines[index]);
    if (line.empty()) continue;
    const auto pair = key_value(line);
    if (!pair) break;
    const std::string key = detail::to_upper(pair->first);
    const auto [at, inserted] = header.emplace(key, HeaderValue{std::string(pair->second), detail::line_number(index)});
    if (!inserted) {
      throw RecordError(
          path, detail::line_number(index),
          key + " appears twice (also on line " + std::to_string(at->second.line) + "): expected each header key once");
    }
  }
  // The header ends at the first line that is not `KEY: value`; messages about a missing key point there.
  const int header_end_line = detail::line_number(index == 0 ? 0 : index - 1);

  Record record;
  record.path = path;
  record.format = "esm";
  record.description = describe(header);

  check_data_type(path, header, record);
  const std::size_t ndata = parse_ndata(path, required(path, header, "NDATA", header_end_line, "19128"));
  record.dt_s =
      parse_sampling_interval(path, required(path, header, "SAMPLING_INTERVAL_S", header_end_line, "0.005000"));
  record.t0_s = 0.0;
  detail::note_ignored_dt(path, options, record.dt_s, "the header's SAMPLING_INTERVAL_S", record);
  record.units_in_file = resolve_units(path, header, options, header_end_line, record);

  const auto start = header.find("DATE_TIME_FIRST_SAMPLE_YYYYMMDD_HHMMSS");
  if (start != header.end()) {
    record.start_time_ns = first_sample_time_ns(start->second.text);
    if (!record.start_time_ns) {
      record.notes.push_back(detail::file_name_of(path) + ":" + std::to_string(start->second.line) +
                             ": first-sample time " + shown(start->second.text) +
                             " not understood (expected YYYYMMDD_HHMMSS.fff); the record has no absolute time");
    }
  }

  std::vector<double> values;
  std::vector<int> value_lines;
  // NDATA is only a claim: reserve no more than the rest of the file can hold (a value and a line break need two
  // bytes), so "NDATA: 99999999999" in a small file is reported as truncated instead of allocating 800 GB.
  const std::size_t room = std::min(ndata, content.size() / 2 + 1);
  values.reserve(room);
  value_lines.reserve(room);
  int last_value_line = header_end_line;
  for (; index < lines.size(); ++index) {
    const auto tokens = detail::split_blanks(lines[index]);
    if (tokens.empty()) continue;
    const int line = detail::line_number(index);
    if (tokens.size() != 1) {
      throw RecordError(path, line, "found " + std::to_string(tokens.size()) + " values: expected one value per line");
    }
    double value = 0.0;
    const detail::NumberStatus status = detail::parse_number(tokens[0], value);
    if (status != detail::NumberStatus::ok) {
      std::string message = detail::number_problem(status, tokens[0]);
      if (values.empty() && key_value(detail::trim(lines[index]))) {
        message += " (a header line after a line that is not 'KEY: value'?)";
      }
      throw RecordError(path, line, message);
    }
    if (values.size() == ndata) {
      throw RecordError(path, line,
                        "more values than NDATA=" + std::to_string(ndata) + ": expected exactly " +
                            std::to_string(ndata) + " values (the last on line " + std::to_string(last_value_line) +
                            ")");
    }
    values.push_back(value);
    value_lines.push_back(line);
    last_value_line = line;
  }
  if (values.size() < ndata) {
    throw RecordError(path, last_value_line,
                      "the file ends after " + std::to_string(values.size()) + " of NDATA=" + std::to_string(ndata) +
                          " values: expected " + std::to_string(ndata) + " (a truncated file?)");
  }

  detail::scale_to_mps2(path, values, value_lines, accel_unit_to_mps2(record.units_in_file, options.g_mps2));
  record.horizontal_mps2 = std::move(values);
  return record;
}

}  // namespace rockwatch::records
