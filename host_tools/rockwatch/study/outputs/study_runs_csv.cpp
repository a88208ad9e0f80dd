#include "study/outputs/study_runs_csv.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstddef>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "common/process/command_runner.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

namespace {

namespace study = sim::study;

const char* const kColumns[] = {"record", "component", "vertical", "r", "pga_g", "collapsed", "t_collapse_s",
                                "t_exceed_s", "max_abs_x_m", "n_impacts", "run"};

bool fixed_point(const study::StudyPlan& plan) { return plan.analysis.arithmetic == sim::Arithmetic::fixed_point; }
bool alarms(const study::StudyPlan& plan) { return plan.analysis.evaluate_alarm; }

// The columns of the plan, in file order: the fixed ones, then those of the options that add some.
std::vector<std::string> columns(const study::StudyPlan& plan) {
  std::vector<std::string> c(std::begin(kColumns), std::end(kColumns));
  if (alarms(plan)) c.emplace_back("t_first_imminent_s");
  if (fixed_point(plan)) {
    for (const char* name : {"saturated", "collapsed_double", "t_collapse_double_s", "max_abs_x_double_m"}) {
      c.emplace_back(name);
    }
    if (alarms(plan)) c.emplace_back("t_first_imminent_double_s");
    c.emplace_back("verdict_differs");
    if (alarms(plan)) {
      for (const char* name : {"t_first_imminent_published_s", "imminent_late_samples", "max_late_samples",
                               "shed_samples", "overrun_calls", "max_call_units"}) {
        c.emplace_back(name);
      }
    }
  }
  if (plan.dt_check) {
    c.emplace_back("collapsed_reference");
    c.emplace_back("max_abs_x_reference_m");
  }
  c.emplace_back("error");
  return c;
}

std::size_t column_of(const std::vector<std::string>& header, const char* name) {
  return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted_text = "\"";
  for (const char c : text) quoted_text += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted_text + "\"";
}

// Error messages are one line in the file: a row is one line.
std::string one_line(std::string text) {
  for (char& c : text) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  return text;
}

const char* bool_text(bool value) { return value ? "true" : "false"; }

std::string optional_number(const std::optional<double>& value) { return value ? number_text(*value) : std::string(); }

// One CSV line into fields, RFC 4180 quotes (the writer puts no line break into a field, so a row is one line).
bool split_csv(const std::string& line, std::vector<std::string>& fields) {
  fields.clear();
  std::string field;
  bool in_quotes = false, was_quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (in_quotes) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        in_quotes = false;
      } else {
        field += c;
      }
    } else if (c == '"' && field.empty() && !was_quoted) {
      in_quotes = was_quoted = true;
    } else if (c == ',') {
      fields.push_back(field);
      field.clear();
      was_quoted = false;
    } else {
      field += c;
    }
  }
  if (in_quotes) return false;
  fields.push_back(field);
  return true;
}

class RowReader {
 public:
  RowReader(const std::string& where, const std::vector<std::string>& header, const std::vector<std::string>& fields)
      : where_(where), header_(header), fields_(fields) {}

  const std::string& text(std::size_t column) const { return fields_[column]; }

  bool boolean(std::size_t column) const {
    const std::string& t = fields_[column];
    if (t == "true") return true;
    if (t == "false") return false;
    throw error(column, "true or false");
  }

  std::optional<bool> optional_boolean(std::size_t column) const {
    if (fields_[column].empty()) return std::nullopt;
    return boolean(column);
  }

  double number(std::size_t column) const {
    const std::string& t = fields_[column];
    double value = 0.0;
    const auto result = std::from_chars(t.data(), t.data() + t.size(), value);
    if (t.empty() || result.ec != std::errc{} || result.ptr != t.data() + t.size()) throw error(column, "a number");
    return value;
  }

  std::optional<double> optional_number(std::size_t column) const {
    if (fields_[column].empty()) return std::nullopt;
    return number(column);
  }

  std::size_t whole(std::size_t column) const {
    const std::string& t = fields_[column];
    std::size_t value = 0;
    const auto result = std::from_chars(t.data(), t.data() + t.size(), value);
    if (t.empty() || result.ec != std::errc{} || result.ptr != t.data() + t.size()) {
      throw error(column, "a whole number");
    }
    return value;
  }

  UsageError error(std::size_t column, const std::string& expected) const {
    return UsageError(where_ + ": " + header_[column] + " must be " + expected + " (got " +
                      options::quoted(fields_[column]) + ")");
  }

 private:
  std::string where_;
  const std::vector<std::string>& header_;
  const std::vector<std::string>& fields_;
};

// The row must be the one the plan has at its run index: a runs.csv of another plan (edited, or a study.json
// replaced) must not be mistaken for this one's results.
void check_row_identity(const RowReader& row, const std::string& where, const study::StudyPlan& plan,
                        std::size_t index) {
  const study::RunKey key = study::run_key(plan, index);
  const study::StudyRecord& record = plan.records[key.record_index];
  const bool same = row.text(0) == record.name && row.text(1) == record.component &&
                    row.boolean(2) == plan.vertical[key.vertical_index] &&
                    row.text(3) == plan.restitutions[key.restitution_index].label &&
                    row.number(4) == plan.pga_g[key.pga_index];
  if (!same) {
    throw UsageError(where + ": run " + std::to_string(index) + " is " + record.name + " " + record.component +
                     ", vertical " + bool_text(plan.vertical[key.vertical_index]) + ", r " +
                     plan.restitutions[key.restitution_index].label + ", PGA " + number_text(plan.pga_g[key.pga_index]) +
                     " g in this study's plan, but the row says " + row.text(0) + " " + row.text(1) + ", vertical " +
                     row.text(2) + ", r " + row.text(3) + ", PGA " + row.text(4) +
                     " g: the file belongs to another study");
  }
}

}  // namespace

std::string runs_csv_header(const study::StudyPlan& plan) {
  std::string header;
  for (const std::string& column : columns(plan)) header += (header.empty() ? "" : ",") + column;
  return header;
}

void write_runs_csv(std::ostream& out, const study::StudyPlan& plan, const std::vector<study::RunResult>& results) {
  out << runs_csv_header(plan) << '\n';
  std::string row;
  for (std::size_t index = 0; index < results.size(); ++index) {
    const study::RunResult& r = results[index];
    if (!r.done) continue;
    const study::RunKey key = study::run_key(plan, index);
    const study::StudyRecord& record = plan.records[key.record_index];
    const bool verdict = r.error.empty();
    row = csv_field(record.name) + ',' + csv_field(record.component) + ',' +
          bool_text(plan.vertical[key.vertical_index]) + ',' + csv_field(plan.restitutions[key.restitution_index].label) +
          ',' + number_text(plan.pga_g[key.pga_index]) + ',';
    if (verdict) {
      row += std::string(bool_text(r.collapsed)) + ',' + optional_number(r.t_collapse_s) + ',' +
             optional_number(r.t_exceed_s) + ',' + number_text(r.max_abs_x_m) + ',' + std::to_string(r.n_impacts);
    } else {
      row += ",,,,";
    }
    row += ',' + std::to_string(index);
    if (alarms(plan)) row += ',' + (verdict ? optional_number(r.t_first_imminent_s) : std::string());
    if (fixed_point(plan)) {
      if (verdict && r.reference) {
        const study::DoubleReference& d = *r.reference;
        row += std::string(",") + bool_text(r.saturated) + ',' + bool_text(d.collapsed) + ',' +
               optional_number(d.t_collapse_s) + ',' + number_text(d.max_abs_x_m);
        if (alarms(plan)) row += ',' + optional_number(d.t_first_imminent_s);
        row += std::string(",") + bool_text(d.collapsed != r.collapsed);
        if (alarms(plan)) {
          row += ',' + optional_number(r.t_first_imminent_published_s) + ',' + std::to_string(r.imminent_late_samples) +
                 ',' + std::to_string(r.max_late_samples) + ',' + std::to_string(r.shed_samples) + ',' +
                 std::to_string(r.overrun_calls) + ',' + std::to_string(r.max_call_units);
        }
      } else {
        row += alarms(plan) ? ",,,,,,,,,,,," : ",,,,,";
      }
    }
    if (plan.dt_check) {
      row += std::string(",") + (r.collapsed_reference ? bool_text(*r.collapsed_reference) : "") + ',' +
             optional_number(r.max_abs_x_reference_m);
    }
    row += ',' + csv_field(one_line(r.error)) + '\n';
    out << row;
  }
}

bool split_runs_csv_line(const std::string& line, std::vector<std::string>& fields) { return split_csv(line, fields); }

std::size_t read_runs_csv_row(const std::string& where, const std::vector<std::string>& fields,
                              const study::StudyPlan& plan, std::vector<study::RunResult>& results) {
  const std::size_t total = study::run_count(plan);
  if (results.empty()) results.resize(total);
  const std::vector<std::string> header = columns(plan);
  const std::string expected_header = runs_csv_header(plan);
  const std::size_t run_column = 10, error_column = header.size() - 1;
  const std::size_t imminent_column = column_of(header, "t_first_imminent_s");
  const std::size_t saturated_column = column_of(header, "saturated");
  const std::size_t differs_column = column_of(header, "verdict_differs");
  const std::size_t reference_column = column_of(header, "collapsed_reference");
  const std::size_t reference_x_column = column_of(header, "max_abs_x_reference_m");
  {
    if (fields.size() != header.size()) {
      throw UsageError(where + ": expected " + std::to_string(header.size()) + " comma-separated fields (" +
                       expected_header + ")");
    }
    const RowReader row(where, header, fields);
    const std::size_t index = row.whole(run_column);
    if (index >= total) {
      throw UsageError(where + ": run " + std::to_string(index) + " is beyond this study's " + std::to_string(total) +
                       " runs: the file belongs to another study");
    }
    check_row_identity(row, where, plan, index);
    study::RunResult r;
    r.done = true;
    r.error = row.text(error_column);
    if (r.error.empty()) {
      r.collapsed = row.boolean(5);
      r.t_collapse_s = row.optional_number(6);
      r.t_exceed_s = row.optional_number(7);
      r.max_abs_x_m = row.number(8);
      r.n_impacts = static_cast<int>(row.whole(9));
      if (alarms(plan)) r.t_first_imminent_s = row.optional_number(imminent_column);
      if (fixed_point(plan)) {
        r.saturated = row.boolean(saturated_column);
        study::DoubleReference d;
        d.collapsed = row.boolean(saturated_column + 1);
        d.t_collapse_s = row.optional_number(saturated_column + 2);
        d.max_abs_x_m = row.number(saturated_column + 3);
        if (alarms(plan)) d.t_first_imminent_s = row.optional_number(saturated_column + 4);
        if (row.boolean(differs_column) != (d.collapsed != r.collapsed)) {
          throw row.error(differs_column, std::string(bool_text(d.collapsed != r.collapsed)) +
                                              " (collapsed and collapsed_double say so)");
        }
        r.reference = d;
        if (alarms(plan)) {
          const std::size_t published_column = column_of(header, "t_first_imminent_published_s");
          r.t_first_imminent_published_s = row.optional_number(published_column);
          r.imminent_late_samples = static_cast<std::uint32_t>(row.whole(published_column + 1));
          r.max_late_samples = static_cast<std::uint32_t>(row.whole(published_column + 2));
          r.shed_samples = static_cast<std::uint32_t>(row.whole(published_column + 3));
          r.overrun_calls = static_cast<std::uint32_t>(row.whole(published_column + 4));
          r.max_call_units = static_cast<std::int32_t>(row.whole(published_column + 5));
        }
      }
    }
    if (plan.dt_check) {
      r.collapsed_reference = row.optional_boolean(reference_column);
      r.max_abs_x_reference_m = row.optional_number(reference_x_column);
    }
    if (results[index].done) throw UsageError(where + ": run " + std::to_string(index) + " appears twice");
    results[index] = r;
    return index;
  }
}

std::size_t read_runs_csv(const std::string& path, const study::StudyPlan& plan,
                          std::vector<study::RunResult>& results) {
  const std::size_t total = study::run_count(plan);
  if (results.empty()) results.resize(total);
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UsageError("--resume: cannot open " + path + system_reason());
  std::string line;
  const std::string expected_header = runs_csv_header(plan);
  if (!std::getline(in, line) || line != expected_header) {
    throw UsageError(path + ":1: expected the header " + expected_header + " (got " + options::quoted(line) +
                     "): the file belongs to another study (with or without --dt-check, --alarms, --arith fixed?)");
  }
  std::size_t read = 0;
  std::vector<std::string> fields;
  for (int number = 2; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    const std::string where = path + ":" + std::to_string(number);
    if (!split_runs_csv_line(line, fields)) {
      throw UsageError(where + ": expected " + std::to_string(columns(plan).size()) + " comma-separated fields (" +
                       expected_header + ")");
    }
    read_runs_csv_row(where, fields, plan, results);
    ++read;
  }
  if (in.bad()) throw UsageError("--resume: reading " + path + " failed");
  return read;
}

}  // namespace rockwatch::cli
