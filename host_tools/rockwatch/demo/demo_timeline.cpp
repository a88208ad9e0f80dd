#include "demo/demo_timeline.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "rockwatch/core/alarm.hpp"

namespace rockwatch::cli {

namespace {

std::string level_text(const nlohmann::json& level) {
  if (level.is_string()) return level.get<std::string>();
  if (level.is_number_integer()) {
    const auto v = level.get<std::int64_t>();
    if (v >= 0 && v <= static_cast<std::int64_t>(core::AlarmLevel::collapsed)) {
      return core::alarm_level_name(static_cast<core::AlarmLevel>(v));
    }
    return "LEVEL" + std::to_string(v);
  }
  return "?";
}

std::int64_t sample_of_time(double t_s, double rate_hz) {
  return static_cast<std::int64_t>(std::ceil(t_s * rate_hz - 1e-6));
}

// The run's transitions on the sample grid: those up to the last sample, and the count of those after it.
void split_transitions(OfflineRun& run, const sim::GroundMotion& motion) {
  const double rate_hz = 1.0 / motion.dt_s;
  const auto last = static_cast<std::int64_t>(motion.ug_mps2.size()) - 1;
  for (const sim::AlarmTransition& t : run.result.alarm.transitions) {
    const std::int64_t sample = sample_of_time(t.t_s, rate_hz);
    if (sample > last) {
      ++run.after_record;
      continue;
    }
    run.transitions.push_back({sample, t.t_s, core::alarm_level_name(t.level)});
  }
}

}  // namespace

MonitorOutput parse_monitor_output(const std::string& text, std::int64_t start_utime, double rate_hz) {
  MonitorOutput out;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.empty()) continue;
    const nlohmann::json j = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (j.is_object() && j.contains("summary") && j["summary"].is_object()) {
      out.summary = j["summary"];
      continue;
    }
    if (!j.is_object() || !j.contains("level") || !j.contains("utime") || !j["utime"].is_number_integer()) {
      out.other_lines.push_back(line);
      continue;
    }
    // A monitor with many walls names the wall of each transition: the timeline is the paper wall's ("wall").
    if (j.contains("wall") && j["wall"] != "wall") {
      ++out.other_walls_transitions;
      continue;
    }
    TimelineEntry e;
    if (j.contains("input_seq") && j["input_seq"].is_number_integer()) {
      e.sample = j["input_seq"].get<std::int64_t>();
    } else {
      const auto utime = j["utime"].get<std::int64_t>();
      e.sample = std::llround(static_cast<double>(utime - start_utime) * rate_hz * 1e-6);
    }
    e.t_s = static_cast<double>(e.sample) / rate_hz;
    e.level = level_text(j["level"]);
    out.transitions.push_back(e);
  }
  return out;
}

OfflineRun run_offline(const core::WallParameters& wall, const sim::GroundMotion& motion,
                       const sim::AnalysisOptions& base) {
  OfflineRun run;
  sim::AnalysisOptions o = base;
  o.arithmetic = sim::Arithmetic::fixed_point;
  o.model = core::ModelKind::linear;
  o.evaluate_alarm = true;
  o.t_end_s = motion.duration_s();
  o.max_alarm_transitions_kept = 100000;
  run.result = sim::analyse(wall, motion, o);
  split_transitions(run, motion);
  return run;
}

OfflineRun run_truth(const core::WallParameters& wall, const sim::GroundMotion& motion, const core::Restitution& r) {
  OfflineRun run;
  sim::AnalysisOptions o;
  o.arithmetic = sim::Arithmetic::double_precision;
  o.restitution = r;
  o.evaluate_alarm = true;
  o.keep_history = true;
  o.t_end_s = motion.duration_s();
  o.max_alarm_transitions_kept = 100000;
  run.result = sim::analyse(wall, motion, o);
  split_transitions(run, motion);
  return run;
}

TimelineComparison compare_timelines(const std::vector<TimelineEntry>& monitor,
                                     const std::vector<TimelineEntry>& offline) {
  TimelineComparison c;
  const std::size_t n = std::min(monitor.size(), offline.size());
  for (std::size_t k = 0; k < n; ++k) {
    const TimelineEntry& m = monitor[k];
    const TimelineEntry& o = offline[k];
    if (m.level != o.level) {
      c.reason = "transition " + std::to_string(k + 1) + ": the monitor went to " + m.level + " at sample " +
                 std::to_string(m.sample) + ", the offline run to " + o.level + " at sample " +
                 std::to_string(o.sample);
      return c;
    }
    const std::int64_t apart = std::llabs(m.sample - o.sample);
    if (apart > 1) {
      c.reason = "transition " + std::to_string(k + 1) + " (" + m.level + "): the monitor at sample " +
                 std::to_string(m.sample) + ", the offline run at sample " + std::to_string(o.sample) + ", " +
                 std::to_string(apart) + " samples apart";
      return c;
    }
    ++(apart == 0 ? c.same_sample : c.next_sample);
  }
  if (monitor.size() != offline.size()) {
    c.reason = "the monitor made " + std::to_string(monitor.size()) + " transitions, the offline run " +
               std::to_string(offline.size());
    return c;
  }
  c.match = true;
  return c;
}

std::string side_by_side(const std::vector<TimelineEntry>& monitor, const std::vector<TimelineEntry>& offline,
                         const std::string& indent) {
  std::string text;
  char line[200];
  std::snprintf(line, sizeof line, "%4s   %-9s %-10s %7s   %-9s %-10s %7s   %s\n", "#", "monitor", "", "", "offline",
                "", "", "");
  text += indent + line;
  std::snprintf(line, sizeof line, "%4s   %-9s %-10s %7s   %-9s %-10s %7s   %s\n", "", "t [s]", "level", "sample",
                "t [s]", "level", "sample", "");
  text += indent + line;
  const std::size_t n = std::max(monitor.size(), offline.size());
  for (std::size_t k = 0; k < n; ++k) {
    std::string m_t = "-", m_level = "", m_sample = "", o_t = "-", o_level = "", o_sample = "", note;
    if (k < monitor.size()) {
      std::snprintf(line, sizeof line, "%.3f", monitor[k].t_s);
      m_t = line;
      m_level = monitor[k].level;
      m_sample = std::to_string(monitor[k].sample);
    }
    if (k < offline.size()) {
      std::snprintf(line, sizeof line, "%.4f", offline[k].t_s);
      o_t = line;
      o_level = offline[k].level;
      o_sample = std::to_string(offline[k].sample);
    }
    if (k < monitor.size() && k < offline.size()) {
      const std::int64_t apart = std::llabs(monitor[k].sample - offline[k].sample);
      if (monitor[k].level != offline[k].level) {
        note = "different level";
      } else {
        note = apart == 0 ? "same sample" : apart == 1 ? "next sample" : std::to_string(apart) + " samples apart";
      }
    } else {
      note = k < monitor.size() ? "monitor only" : "offline only";
    }
    std::snprintf(line, sizeof line, "%4zu   %-9s %-10s %7s   %-9s %-10s %7s   %s\n", k + 1, m_t.c_str(),
                  m_level.c_str(), m_sample.c_str(), o_t.c_str(), o_level.c_str(), o_sample.c_str(), note.c_str());
    text += indent + line;
  }
  if (n == 0) text += indent + "   (no transitions on either side: the wall never moved)\n";
  return text;
}

std::string columns_text(const std::vector<TimelineColumn>& columns, const std::string& indent) {
  constexpr int kWidth = 24;
  std::string text = indent + "  #  ";
  std::size_t rows = 0;
  for (const TimelineColumn& c : columns) {
    std::string title = c.title.substr(0, kWidth - 2);
    title.resize(kWidth, ' ');
    text += title;
    rows = std::max(rows, c.entries.size());
  }
  while (!text.empty() && text.back() == ' ') text.pop_back();
  text += "\n";
  char cell[64];
  for (std::size_t k = 0; k < rows; ++k) {
    std::snprintf(cell, sizeof cell, "%3zu  ", k + 1);
    text += indent + cell;
    for (const TimelineColumn& c : columns) {
      std::string value = "-";
      if (k < c.entries.size()) {
        std::snprintf(cell, sizeof cell, "%7.3f s  %s", c.entries[k].t_s, c.entries[k].level.c_str());
        value = cell;
      }
      value.resize(kWidth, ' ');
      text += value;
    }
    while (!text.empty() && text.back() == ' ') text.pop_back();
    text += "\n";
  }
  if (rows == 0) text += indent + "   (no transitions: the wall never moved)\n";
  return text;
}

}  // namespace rockwatch::cli
