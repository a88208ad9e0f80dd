// Plain text / CSV records: one column (ü), two (t, ü) or three (t, ü, v̈), with '#' comments and an optional
// header line of column names that may carry the units.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rockwatch/records/record.hpp"
#include "rockwatch/records/record_error.hpp"
#include "text_scan.hpp"

namespace rockwatch::records {

namespace {

using detail::NumberStatus;
using detail::shown;

const char* const kAcceptedColumns =
    "accepted are 1 column (acceleration, with --dt), 2 columns (time, horizontal acceleration) or "
    "3 columns (time, horizontal, vertical acceleration)";
const char* const kUnitsHint = "pass --units (g|mps2|cmps2|mmps2)";

struct StatedUnit {
  AccelUnit unit;
  int line;
};

// ';' separates fields in locales that write a decimal comma; there ',' must stay inside the number so that
// "0,005" is rejected instead of silently split into 0 and 5.
char field_separator(std::string_view body) { return body.find(';') != std::string_view::npos ? ';' : ','; }

// Splits a data row on blanks and the separator. Two separators with nothing between them is a missing value;
// one trailing separator ("1.0, 2.0,") is tolerated, as spreadsheets write it.
std::vector<std::string_view> split_fields(const std::string& path, int line, std::string_view body) {
  const char separator = field_separator(body);
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (start <= body.size()) {
    std::size_t end = body.find(separator, start);
    const bool last_field = end == std::string_view::npos;
    if (last_field) end = body.size();
    const std::string_view field = body.substr(start, end - start);
    const auto tokens = detail::split_blanks(field);
    if (tokens.empty()) {
      const bool trailing = last_field && start > 0;
      if (!trailing) {
        throw RecordError(path, line,
                          std::string("empty field between separators '") + separator + "': expected a number");
      }
    }
    fields.insert(fields.end(), tokens.begin(), tokens.end());
    if (last_field) break;
    start = end + 1;
  }
  return fields;
}

// Header words, split loosely: a header is text, so empty fields and quotes do not matter there.
std::vector<std::string_view> header_words(std::string_view body) {
  const std::string_view rest = body;
  std::vector<std::string_view> words;
  std::size_t i = 0;
  auto is_separator = [](char c) { return detail::is_blank(c) || c == ',' || c == ';' || c == '"' || c == '\''; };
  while (i < rest.size()) {
    while (i < rest.size() && is_separator(rest[i])) ++i;
    const std::size_t start = i;
    while (i < rest.size() && !is_separator(rest[i])) ++i;
    if (i > start) words.push_back(rest.substr(start, i - start));
  }
  return words;
}

bool is_time_unit(std::string_view text) {
  const std::string upper = detail::to_upper(detail::trim(text));
  return upper == "S" || upper == "SEC" || upper == "SECS" || upper == "SECOND" || upper == "SECONDS";
}

bool looks_numeric(std::string_view token) {
  double ignored = 0.0;
  const NumberStatus status = detail::parse_number(token, ignored);
  // "nan" and "1e999" are numbers in the wrong place, not column names; the data path reports them properly.
  return status != NumberStatus::invalid;
}

// Units written into column names: "accel_g", "a_mps2", "HGE_m/s2", "a [m/s2]", "acc (cm/s^2)". Time units
// ("time_s", "t [s]") are skipped; words that are not units ("HGE(East)") are ignored.
std::optional<StatedUnit> units_from_header(const std::string& path, int line, std::string_view header) {
  std::vector<std::string> candidates;
  std::string rest;
  for (std::size_t i = 0; i < header.size(); ++i) {
    const char open = header[i];
    const char close = open == '[' ? ']' : open == '(' ? ')' : open == '{' ? '}' : '\0';
    const std::size_t end = close != '\0' ? header.find(close, i + 1) : std::string_view::npos;
    if (end != std::string_view::npos) {
      candidates.emplace_back(header.substr(i + 1, end - i - 1));
      rest += ' ';
      i = end;
    } else {
      rest += header[i];
    }
  }
  for (const std::string_view word : header_words(rest)) {
    const std::size_t underscore = word.find('_');
    if (underscore != std::string_view::npos && underscore + 1 < word.size()) {
      // The unit is everything after the first '_' that parses ("acc_m/s2"), else after the last ("a_east_g").
      candidates.emplace_back(word.substr(underscore + 1));
      const std::size_t last = word.rfind('_');
      if (last != underscore && last + 1 < word.size()) candidates.emplace_back(word.substr(last + 1));
    }
  }
  std::optional<AccelUnit> found;
  for (const std::string& candidate : candidates) {
    if (is_time_unit(candidate)) continue;
    const std::optional<AccelUnit> unit = parse_accel_unit(detail::trim(candidate));
    if (!unit) continue;
    if (found && *found != *unit) {
      throw RecordError(path, line,
                        "column names state different units (" + std::string(accel_unit_name(*found)) + " and " +
                            std::string(accel_unit_name(*unit)) + "): expected one acceleration unit, or " +
                            kUnitsHint);
    }
    found = unit;
  }
  if (!found) return std::nullopt;
  return StatedUnit{*found, line};
}

// "# units: g" or "# unit = cm/s2" (key case-insensitive). Returns the text after the key, or nullopt when the
// comment is about something else.
std::optional<std::string_view> units_comment_value(std::string_view comment) {
  std::string_view text = detail::trim(comment);
  const std::string upper = detail::to_upper(text.substr(0, std::min<std::size_t>(text.size(), 5)));
  std::size_t key_length = 0;
  if (upper.rfind("UNITS", 0) == 0) {
    key_length = 5;
  } else if (upper.rfind("UNIT", 0) == 0) {
    key_length = 4;
  } else {
    return std::nullopt;
  }
  text.remove_prefix(key_length);
  text = detail::trim(text);
  if (text.empty() || (text.front() != ':' && text.front() != '=')) return std::nullopt;
  text.remove_prefix(1);
  return detail::trim(text);
}

struct CommentUnits {
  std::optional<StatedUnit> unit;
  int bad_line = 0;  // a units comment we could not understand; only an error when nothing else gives the units
  std::string bad_text;
};

void take_units_comment(const std::string& path, int line, std::string_view comment, CommentUnits& units) {
  const std::optional<std::string_view> value = units_comment_value(comment);
  if (!value) return;
  std::optional<AccelUnit> unit = parse_accel_unit(*value);
  if (!unit) {
    const auto words = header_words(*value);
    if (!words.empty()) unit = parse_accel_unit(words.front());
  }
  if (!unit) {
    if (units.bad_line == 0) {
      units.bad_line = line;
      units.bad_text = std::string(*value);
    }
    return;
  }
  if (units.unit && units.unit->unit != *unit) {
    throw RecordError(path, line,
                      "units comment says " + std::string(accel_unit_name(*unit)) + " but line " +
                          std::to_string(units.unit->line) + " says " + std::string(accel_unit_name(units.unit->unit)) +
                          ": expected one unit for the file, or " + kUnitsHint);
  }
  units.unit = StatedUnit{*unit, line};
}

struct Columns {
  std::size_t count = 0;
  int first_data_line = 0;
  std::vector<std::vector<double>> values;
  std::vector<int> row_lines;
};

AccelUnit resolve_units(const std::string& path, const ReadOptions& options, const CommentUnits& comment,
                        const std::optional<StatedUnit>& header, int fallback_line, Record& record) {
  if (comment.unit && header && comment.unit->unit != header->unit) {
    throw RecordError(path, comment.unit->line,
                      "units comment says " + std::string(accel_unit_name(comment.unit->unit)) +
                          " but the column names on line " + std::to_string(header->line) + " say " +
                          std::string(accel_unit_name(header->unit)) + ": expected one unit, or " + kUnitsHint);
  }
  const std::optional<StatedUnit> stated = comment.unit ? comment.unit : header;
  if (options.units) {
    if (stated && stated->unit != *options.units) {
      record.notes.push_back(detail::file_name_of(path) + ": units " + std::string(accel_unit_name(*options.units)) +
                             " from the options override " + std::string(accel_unit_name(stated->unit)) +
                             " stated on line " + std::to_string(stated->line));
    }
    return *options.units;
  }
  if (stated) return stated->unit;
  if (comment.bad_line != 0) {
    throw RecordError(path, comment.bad_line,
                      "unknown units " + shown(comment.bad_text) +
                          ": expected g, mps2, cmps2 or mmps2 (or m/s2, "
                          "cm/s2, gal, mm/s2), or " +
                          kUnitsHint);
  }
  throw RecordError(path, fallback_line,
                    "the file does not state its units (no '# units: g' comment, no unit in the column names such as "
                    "accel_g or a [m/s2]): expected units, " +
                        std::string(kUnitsHint));
}

// Sets t0 and dt from the time column. The step must be constant: a record with gaps or jitter replayed at one dt
// would shift every later sample in time.
void take_time_column(const std::string& path, const Columns& columns, const ReadOptions& options, Record& record) {
  const std::vector<double>& t = columns.values[0];
  if (t.size() < 2) {
    throw RecordError(path, columns.first_data_line,
                      "only one row: expected at least two rows to determine the time step");
  }
  const double reference_step = t[1] - t[0];
  for (std::size_t k = 1; k < t.size(); ++k) {
    const double step = t[k] - t[k - 1];
    const int line = columns.row_lines[k];
    if (!(step > 0.0) || !std::isfinite(step)) {
      throw RecordError(path, line,
                        "time " + detail::number_text(t[k]) + " s after " + detail::number_text(t[k - 1]) +
                            " s on line " + std::to_string(columns.row_lines[k - 1]) +
                            ": expected strictly increasing time");
    }
    // Tolerance: relative 1e-6, plus 1e-9 s, plus the rounding of the two times themselves (large t0 values).
    const double rounding =
        4.0 * std::numeric_limits<double>::epsilon() * std::max(std::fabs(t[k]), std::fabs(t[k - 1]));
    if (std::fabs(step - reference_step) > 1e-6 * reference_step + 1e-9 + rounding) {
      throw RecordError(path, line,
                        "uneven time step: expected step " + detail::number_text(reference_step) + " s (lines " +
                            std::to_string(columns.row_lines[0]) + "-" + std::to_string(columns.row_lines[1]) +
                            "), found " + detail::number_text(step) + " s (t = " + detail::number_text(t[k - 1]) +
                            " s to " + detail::number_text(t[k]) + " s)");
    }
  }
  record.t0_s = t.front();
  record.dt_s = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  if (options.dt_s && std::fabs(*options.dt_s - record.dt_s) > 1e-6 * record.dt_s + 1e-9) {
    record.notes.push_back(detail::file_name_of(path) + ": --dt " + detail::number_text(*options.dt_s) +
                           " s ignored, the time column gives dt = " + detail::number_text(record.dt_s) + " s");
  }
}

}  // namespace

Record read_plain_text(const std::string& path, const ReadOptions& options) {
  detail::check_options(path, options);
  detail::reject_multi_component_options(path, options, "a plain-text record");
  const std::string content = detail::read_whole_file(path);
  const std::vector<std::string_view> lines = detail::split_lines(content);

  CommentUnits comment_units;
  std::optional<StatedUnit> header_units;
  int header_line = 0;
  Columns columns;

  for (std::size_t index = 0; index < lines.size(); ++index) {
    const int line = detail::line_number(index);
    std::string_view body = lines[index];
    const std::size_t hash = body.find('#');
    if (hash != std::string_view::npos) {
      take_units_comment(path, line, body.substr(hash + 1), comment_units);
      body = body.substr(0, hash);
    }
    body = detail::trim(body);
    if (body.empty()) continue;

    if (columns.count == 0) {
      const auto words = header_words(body);
      const bool any_number = std::any_of(words.begin(), words.end(), looks_numeric);
      if (!words.empty() && !any_number) {
        if (header_line != 0) {
          throw RecordError(path, line,
                            "expected numbers, found " + shown(words.front()) +
                                " (only one header line of column "
                                "names is allowed, on line " +
                                std::to_string(header_line) + "; use '#' for comments)");
        }
        header_line = line;
        header_units = units_from_header(path, line, body);
        continue;
      }
    }

    const std::vector<std::string_view> fields = split_fields(path, line, body);
    if (columns.count == 0) {
      if (fields.size() > 3) {
        throw RecordError(path, line,
                          "found " + std::to_string(fields.size()) + " columns: " + kAcceptedColumns +
                              "; extract the wanted columns first");
      }
      columns.count = fields.size();
      columns.first_data_line = line;
      columns.values.resize(columns.count);
    } else if (fields.size() != columns.count) {
      std::string message = "found " + std::to_string(fields.size()) + " columns: expected " +
                            std::to_string(columns.count) + " like the first data row on line " +
                            std::to_string(columns.first_data_line);
      if (fields.size() < columns.count) message += " (a truncated row?)";
      throw RecordError(path, line, message);
    }
    for (std::size_t c = 0; c < fields.size(); ++c) {
      double value = 0.0;
      const NumberStatus status = detail::parse_number(fields[c], value);
      if (status != NumberStatus::ok) throw RecordError(path, line, detail::number_problem(status, fields[c]));
      columns.values[c].push_back(value);
    }
    columns.row_lines.push_back(line);
  }

  if (columns.count == 0) {
    if (detail::all_blank(lines)) {
      throw RecordError(path, 1, "empty file: expected rows of numbers (time and acceleration)");
    }
    throw RecordError(path, detail::line_number(lines.size() - 1),
                      "no data values: expected rows of numbers (time and acceleration) after the comments/header");
  }

  Record record;
  record.path = path;
  record.format = "plain";
  const int units_line = header_line != 0 ? header_line : columns.first_data_line;
  record.units_in_file = resolve_units(path, options, comment_units, header_units, units_line, record);

  if (columns.count == 1) {
    if (!options.dt_s) {
      throw RecordError(path, columns.first_data_line,
                        "one column of values and no time column: expected the sample interval, pass --dt SECONDS "
                        "(or add a time column)");
    }
    record.dt_s = *options.dt_s;
    record.t0_s = 0.0;
  } else {
    take_time_column(path, columns, options, record);
  }

  const double factor = accel_unit_to_mps2(record.units_in_file, options.g_mps2);
  const std::size_t first_accel = columns.count == 1 ? 0 : 1;
  detail::scale_to_mps2(path, columns.values[first_accel], columns.row_lines, factor);
  record.horizontal_mps2 = std::move(columns.values[first_accel]);
  if (columns.count == 3) {
    detail::scale_to_mps2(path, columns.values[2], columns.row_lines, factor);
    record.vertical_mps2 = std::move(columns.values[2]);
  }
  return record;
}

}  // namespace rockwatch::records
