#include "study/plan/study_records.hpp"

#include <algorithm>
#include <cerrno>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/process/command_runner.hpp"
#include "common/records_in/input_motion.hpp"
#include "common/records_in/shipped_suite.hpp"
#include "common/process/text_report.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"
#include "rockwatch/records/record.hpp"
#include "rockwatch/records/record_error.hpp"
#include "rockwatch/records/suite_format.hpp"
#include "rockwatch/sim/analysis.hpp"

namespace rockwatch::cli {

namespace {

namespace study = sim::study;

bool uses_vertical(const StudyRequest& q) {
  return std::find(q.vertical.begin(), q.vertical.end(), true) != q.vertical.end();
}

void check_peak(const study::StudyRecord& r, const std::string& where) {
  if (!(r.peak_ug_mps2 > 0.0)) {
    throw UsageError(where + ": the record " + r.name + " has peak |u''| = 0: no factor scales it to a PGA level");
  }
}

// ---- suite -------------------------------------------------------------------------------------------------

std::vector<int> chosen_sets(const StudyRequest& q, const std::string& dir) {
  const std::vector<int> available = records::suite_sets(dir);
  if (!q.sets) return available;
  std::vector<int> sorted = available;
  std::sort(sorted.begin(), sorted.end());
  for (const int set : *q.sets) {
    if (!std::binary_search(sorted.begin(), sorted.end(), set)) {
      throw UsageError("--sets " + quoted(q.sets_text) + ": the suite " + dir + " has no set " + std::to_string(set) +
                       " (its sets: " + set_list_text(sorted) + ")");
    }
  }
  return *q.sets;
}

void load_suite(const StudyRequest& q, StudyRecords& out) {
  if (q.suite_dir) {
    out.suite_dir = *q.suite_dir;
  } else {
    const SuiteLocation location = find_shipped_suite();
    out.suite_dir = location.dir;
    out.suite_found_by = location.found_by;
  }
  out.sets = chosen_sets(q, out.suite_dir);
  const bool with_vertical = uses_vertical(q);
  for (const int set : out.sets) {
    const std::string path = records::suite_set_path(out.suite_dir, set);
    records::SuiteRecordFile file = records::read_suite_record(path);
    if (out.suite_name.empty()) out.suite_name = file.suite;
    for (std::size_t c = 0; c < 2; ++c) {  // X and Y: the horizontal components
      study::StudyRecord r;
      r.name = format("set%02d", set);
      r.component = std::string(1, "XY"[c]);
      r.dt_s = file.dt_s;
      r.ug_mps2 = file.components_mps2[c];
      if (with_vertical) r.vg_mps2 = file.components_mps2[2];
      r.peak_ug_mps2 = sim::peak_abs(r.ug_mps2);
      const std::string where = "set " + std::to_string(set) + " " + r.component;
      check_peak(r, "suite " + out.suite_dir + " " + where);
      out.records.push_back(std::move(r));
      out.sources.push_back(StudyRecordSource{path, with_vertical ? std::optional<std::string>(path) : std::nullopt,
                                              where});
    }
  }
}

// ---- --records LIST ----------------------------------------------------------------------------------------

struct ListLine {
  int number = 0;
  std::vector<std::string> fields;
};

// Whitespace-separated fields, a field in double quotes may hold blanks; '#' at the start of a field starts a
// comment.
std::vector<std::string> list_fields(const std::string& text, const std::string& where) {
  std::vector<std::string> fields;
  std::size_t i = 0;
  while (i < text.size()) {
    const char c = text[i];
    if (c == ' ' || c == '\t' || c == '\r') {
      ++i;
      continue;
    }
    if (c == '#') break;
    std::string field;
    if (c == '"') {
      const std::size_t close = text.find('"', i + 1);
      if (close == std::string::npos) throw UsageError(where + ": a quoted path has no closing \"");
      field = text.substr(i + 1, close - i - 1);
      i = close + 1;
    } else {
      while (i < text.size() && text[i] != ' ' && text[i] != '\t' && text[i] != '\r') field += text[i++];
    }
    fields.push_back(field);
  }
  return fields;
}

std::vector<ListLine> read_list(const std::string& list) {
  errno = 0;
  std::ifstream in(list, std::ios::binary);
  if (!in) throw UsageError("--records " + list + ": cannot open the list" + system_reason());
  std::vector<ListLine> lines;
  std::string text;
  for (int number = 1; std::getline(in, text); ++number) {
    const std::string where = list + ":" + std::to_string(number);
    ListLine l{number, list_fields(text, where)};
    if (l.fields.empty()) continue;
    if (l.fields.size() > 2) {
      throw UsageError(where + ": expected PATH [VERTICAL_PATH] (got " + std::to_string(l.fields.size()) +
                       " fields; put a path with spaces in double quotes)");
    }
    for (const std::string& f : l.fields) {
      if (f.empty()) throw UsageError(where + ": an empty path (\"\")");
    }
    lines.push_back(std::move(l));
  }
  if (in.bad()) throw UsageError("--records " + list + ": reading the list failed");
  if (lines.empty()) {
    throw UsageError("--records " + list + " lists no records: expected one per line, PATH [VERTICAL_PATH]");
  }
  return lines;
}

std::string resolve(const std::string& list, const std::string& path) {
  const std::filesystem::path p(path);
  if (p.is_absolute()) return path;
  return (std::filesystem::path(list).parent_path() / p).string();
}

// --gain converts miniSEED counts: the readers of other formats reject a gain, and a list may mix formats.
records::ReadOptions options_for(const std::string& path, records::ReadOptions options, bool& gain_used) {
  if (options.gain_counts_per_mps2) {
    if (records::looks_like_miniseed(path)) {
      gain_used = true;
    } else {
      options.gain_counts_per_mps2.reset();
    }
  }
  return options;
}

// The reader's message (file, line, what was expected) after the list line that named the file.
records::Record read_listed(const std::string& path, const records::ReadOptions& options, const std::string& where) {
  try {
    return records::read_record(path, options);
  } catch (const records::RecordError& e) {
    throw UsageError(where + ": " + e.what());
  }
}

void load_list(const StudyRequest& q, StudyRecords& out) {
  out.from_suite = false;
  out.list_path = *q.records_list;
  const bool with_vertical = uses_vertical(q);
  bool gain_used = false;
  for (const ListLine& l : read_list(out.list_path)) {
    const std::string where = out.list_path + ":" + std::to_string(l.number);
    StudyRecordSource source{resolve(out.list_path, l.fields[0]), std::nullopt, where};
    records::Record h = read_listed(source.path, options_for(source.path, q.read_options, gain_used), where);
    out.notes.insert(out.notes.end(), h.notes.begin(), h.notes.end());
    study::StudyRecord r;
    r.name = l.fields[0];  // shortened to the file name below when that is unique
    r.dt_s = h.dt_s;
    std::vector<double> partner;
    if (l.fields.size() == 2) {
      if (!h.vertical_mps2.empty()) {
        throw UsageError(where + ": ambiguous vertical: " + source.path + " has a third (vertical) column and " +
                         l.fields[1] + " is given too; remove one");
      }
      source.vertical_path = resolve(out.list_path, l.fields[1]);
      records::ReadOptions options = q.read_options;
      options.channel = q.vertical_channel;
      const std::string& vertical_path = *source.vertical_path;
      records::Record v = read_listed(vertical_path, options_for(vertical_path, options, gain_used), where);
      out.notes.insert(out.notes.end(), v.notes.begin(), v.notes.end());
      if (!v.vertical_mps2.empty()) {
        throw UsageError(where + ": the vertical partner " + *source.vertical_path +
                         " has three columns (time, horizontal, vertical): expected one acceleration component");
      }
      partner = vertical_on_horizontal_grid(h, v, out.notes);
    } else if (!h.vertical_mps2.empty()) {
      source.vertical_path = source.path;  // the third column
      partner = std::move(h.vertical_mps2);
    }
    if (with_vertical) {
      if (!source.vertical_path) {
        throw UsageError(where + ": " + l.fields[0] + " has no vertical partner, but --vertical includes with: add "
                                                      "VERTICAL_PATH to the line, or give --vertical without");
      }
      r.vg_mps2 = std::move(partner);
    }
    r.ug_mps2 = std::move(h.horizontal_mps2);
    r.peak_ug_mps2 = sim::peak_abs(r.ug_mps2);
    check_peak(r, where);
    out.records.push_back(std::move(r));
    out.sources.push_back(std::move(source));
  }
  if (q.read_options.gain_counts_per_mps2 && !gain_used) {
    throw UsageError("--gain converts miniSEED counts, but no file of --records " + out.list_path + " is miniSEED");
  }
  // Reports name a record by its file name, unless two records share it.
  std::map<std::string, int> uses;
  for (const study::StudyRecord& r : out.records) ++uses[file_name(r.name)];
  for (study::StudyRecord& r : out.records) {
    if (uses[file_name(r.name)] == 1) r.name = file_name(r.name);
  }
}

}  // namespace

StudyRecords load_study_records(const StudyRequest& q) {
  StudyRecords out;
  if (q.records_list) {
    load_list(q, out);
  } else {
    load_suite(q, out);
  }
  return out;
}

std::string set_list_text(const std::vector<int>& sets) {
  std::string text;
  for (std::size_t i = 0; i < sets.size();) {
    std::size_t j = i;
    while (j + 1 < sets.size() && sets[j + 1] == sets[j] + 1) ++j;
    text += (text.empty() ? "" : ",") + std::to_string(sets[i]);
    if (j > i) text += "-" + std::to_string(sets[j]);
    i = j + 1;
  }
  return text;
}

std::string records_text(const StudyRecords& r) {
  const std::size_t n = r.sources.size();  // the records themselves may have moved into the plan
  if (r.from_suite) {
    const std::string name = r.suite_name.empty() ? r.suite_dir : r.suite_name;
    std::string text = "suite " + name + ", set" + (r.sets.size() == 1 ? " " : "s ") + set_list_text(r.sets) +
                       ", components X and Y (" + std::to_string(n) + " records)";
    const bool partners = !r.sources.empty() && r.sources.front().vertical_path.has_value();
    if (partners) text += ", vertical partner Z of the same set";
    return text;
  }
  std::size_t with_partner = 0;
  for (const StudyRecordSource& s : r.sources) with_partner += s.vertical_path ? 1 : 0;
  return std::to_string(n) + " record" + (n == 1 ? "" : "s") + " of " + r.list_path + " (" +
         std::to_string(with_partner) + " with a vertical partner)";
}

}  // namespace rockwatch::cli
