// PEER NGA strong-motion `.AT2` files: 4 header lines, then free-format acceleration values in g.
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

constexpr int kNptsLine = 4;
constexpr std::size_t kHeaderLines = 4;
const char* const kNptsExamples = "'NPTS=   5372, DT=   .0100 SEC,' or '4164    0.0100    NPTS, DT'";

struct At2Sampling {
  long long npts = 0;
  double dt_s = 0.0;
};

bool is_word_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_'; }

// Position just after "KEY =" (blanks allowed around '='), with KEY a whole word; npos when absent.
std::size_t after_key_equals(const std::string& upper, std::string_view key, std::size_t from = 0) {
  for (std::size_t at = upper.find(key, from); at != std::string::npos; at = upper.find(key, at + 1)) {
    if (at > 0 && is_word_char(upper[at - 1])) continue;
    std::size_t i = at + key.size();
    while (i < upper.size() && detail::is_blank(upper[i])) ++i;
    if (i < upper.size() && upper[i] == '=') return i + 1;
  }
  return std::string::npos;
}

std::string_view value_after(std::string_view line, std::size_t at) {
  while (at < line.size() && detail::is_blank(line[at])) ++at;
  std::size_t end = at;
  while (end < line.size() && !detail::is_blank(line[end]) && line[end] != ',') ++end;
  return line.substr(at, end - at);
}

long long parse_npts(const std::string& path, std::string_view text) {
  long long npts = 0;
  const auto result = std::from_chars(text.data(), text.data() + text.size(), npts);
  if (text.empty() || result.ec != std::errc{} || result.ptr != text.data() + text.size() || npts <= 0) {
    throw RecordError(path, kNptsLine, "NPTS = " + shown(text) + ": expected a positive whole number of points");
  }
  return npts;
}

double parse_dt(const std::string& path, std::string_view text) {
  double dt_s = 0.0;
  if (detail::parse_number(text, dt_s) != detail::NumberStatus::ok || dt_s <= 0.0) {
    throw RecordError(path, kNptsLine, "DT = " + shown(text) + ": expected a positive sample interval in seconds");
  }
  return dt_s;
}

// Line 4 comes in three spellings across NGA-West1/West2 downloads; all carry the same two numbers.
At2Sampling parse_sampling_line(const std::string& path, std::string_view line) {
  const std::string upper = detail::to_upper(line);
  const std::size_t npts_at = after_key_equals(upper, "NPTS");
  if (npts_at != std::string::npos) {
    At2Sampling sampling;
    sampling.npts = parse_npts(path, value_after(line, npts_at));
    const std::size_t dt_at = after_key_equals(upper, "DT");
    if (dt_at == std::string::npos) {
      throw RecordError(path, kNptsLine, "no 'DT=' on the NPTS line: expected " + std::string(kNptsExamples));
    }
    sampling.dt_s = parse_dt(path, value_after(line, dt_at));
    return sampling;
  }
  // Older form: the numbers first, their names after ("4164    0.0100    NPTS, DT").
  std::string names = upper;
  for (char& c : names) {
    if (c == ',') c = ' ';
  }
  const auto tokens = detail::split_blanks(names);
  if (tokens.size() >= 4 && tokens[2] == "NPTS" && tokens[3] == "DT") {
    const auto raw = detail::split_blanks(line);
    auto strip_comma = [](std::string_view t) {
      if (!t.empty() && t.back() == ',') t.remove_suffix(1);
      return t;
    };
    At2Sampling sampling;
    sampling.npts = parse_npts(path, strip_comma(raw.at(0)));
    sampling.dt_s = parse_dt(path, strip_comma(raw.at(1)));
    return sampling;
  }
  throw RecordError(
      path, kNptsLine,
      "expected the NPTS/DT line, e.g. " + std::string(kNptsExamples) + ", found " + shown(detail::trim(line)));
}

bool says_units_of_g(std::string_view line) {
  const std::string upper = detail::to_upper(line);
  const std::size_t at = upper.find("UNITS OF G");
  if (at == std::string::npos) return false;
  const std::size_t after = at + std::string_view("UNITS OF G").size();
  return after >= upper.size() || !is_word_char(upper[after]);
}

// PEER writes every value as .dddddddE-dd. A last token without its two exponent digits, or without an exponent when
// the others have one, is a number the file was cut in, even though it parses.
bool looks_cut_short(std::string_view token, bool others_have_exponent) {
  const std::size_t e = token.find_first_of("eE");
  if (e == std::string_view::npos) return others_have_exponent;
  std::size_t digits_at = e + 1;
  if (digits_at < token.size() && (token[digits_at] == '-' || token[digits_at] == '+')) ++digits_at;
  return token.size() - digits_at < 2;
}

}  // namespace

Record read_peer_at2(const std::string& path, const ReadOptions& options) {
  detail::check_options(path, options);
  detail::reject_multi_component_options(path, options, "a PEER AT2 record");
  const std::string content = detail::read_whole_file(path);
  const std::vector<std::string_view> lines = detail::split_lines(content);
  if (detail::all_blank(lines)) {
    throw RecordError(path, 1, "empty file: expected a PEER AT2 header (4 lines) followed by acceleration values");
  }
  if (lines.size() < kHeaderLines) {
    throw RecordError(path, detail::line_number(lines.size() - 1),
                      "file ends inside the header: expected 4 PEER AT2 header lines, the last giving NPTS and DT");
  }

  Record record;
  record.path = path;
  record.format = "peer-at2";
  record.description = std::string(detail::trim(lines[1]));

  const std::string units_line = detail::to_upper(lines[2]);
  if (units_line.find("VELOCITY") != std::string::npos || units_line.find("DISPLACEMENT") != std::string::npos) {
    throw RecordError(path, 3,
                      "this is a velocity or displacement file (" + shown(detail::trim(lines[2])) +
                          "): expected an ACCELERATION time series (.AT2)");
  }
  const bool in_g = says_units_of_g(lines[2]);
  if (options.units) {
    record.units_in_file = *options.units;
    if (!in_g || *options.units != AccelUnit::g) {
      record.notes.push_back(detail::file_name_of(path) + ": units taken as " +
                             std::string(accel_unit_name(*options.units)) + " from the options, header says " +
                             shown(detail::trim(lines[2])));
    }
  } else if (in_g) {
    record.units_in_file = AccelUnit::g;
  } else {
    throw RecordError(path, 3,
                      "expected 'ACCELERATION TIME SERIES IN UNITS OF G', found " + shown(detail::trim(lines[2])) +
                          "; pass --units (g|mps2|cmps2|mmps2) if the values are in other units");
  }

  const At2Sampling sampling = parse_sampling_line(path, lines[3]);
  record.dt_s = sampling.dt_s;
  record.t0_s = 0.0;
  if (options.dt_s && std::fabs(*options.dt_s - record.dt_s) > 1e-6 * record.dt_s) {
    record.notes.push_back(detail::file_name_of(path) + ": --dt " + detail::number_text(*options.dt_s) +
                           " s ignored, the header gives DT = " + detail::number_text(record.dt_s) + " s");
  }

  // A truncated download ends without a newline in the middle of a number; that number must not be read as if whole.
  const bool ends_mid_token = !content.empty() && content.back() != '\n' && !detail::is_blank(content.back());

  std::vector<double> values;
  std::vector<int> value_lines;
  std::size_t count = 0;  // values in the file, including any beyond NPTS
  bool saw_exponent = false;
  const auto npts = static_cast<std::size_t>(sampling.npts);
  for (std::size_t index = kHeaderLines; index < lines.size(); ++index) {
    const auto tokens = detail::split_blanks(lines[index]);
    for (std::size_t k = 0; k < tokens.size(); ++k) {
      const bool last_in_file = ends_mid_token && index + 1 == lines.size() && k + 1 == tokens.size();
      double value = 0.0;
      const detail::NumberStatus status = detail::parse_number(tokens[k], value);
      if (status != detail::NumberStatus::ok) {
        std::string message = detail::number_problem(status, tokens[k]);
        if (last_in_file) message += "; the file ends in the middle of this number, it looks truncated";
        throw RecordError(path, detail::line_number(index), message);
      }
      if (last_in_file && count < npts && looks_cut_short(tokens[k], saw_exponent)) {
        throw RecordError(path, detail::line_number(index),
                          "the file ends in the middle of the number " + shown(tokens[k]) + " after " +
                              std::to_string(count) + " of NPTS=" + std::to_string(npts) +
                              " values: it looks truncated (expected complete values ending with a newline)");
      }
      saw_exponent = saw_exponent || tokens[k].find_first_of("eE") != std::string_view::npos;
      if (count < npts) {
        values.push_back(value);
        value_lines.push_back(detail::line_number(index));
      }
      ++count;
    }
  }
  if (count == 0) {
    throw RecordError(
        path, detail::line_number(std::min(kHeaderLines, lines.size() - 1)),
        "no data values: expected NPTS=" + std::to_string(npts) + " acceleration values after the header");
  }
  if (count != npts) {
    record.notes.push_back(detail::file_name_of(path) + ": NPTS=" + std::to_string(npts) + " but " +
                           std::to_string(count) + " values; read " + std::to_string(values.size()));
  }

  detail::scale_to_mps2(path, values, value_lines, accel_unit_to_mps2(record.units_in_file, options.g_mps2));
  record.horizontal_mps2 = std::move(values);
  return record;
}

}  // namespace rockwatch::records
