// The two alarm timelines `rockwatch demo` compares: the transitions rockwatch-monitor printed (JSON lines) while the
// replay fed it, and those of the offline fixed-point analysis of the same samples (sim::analyse with
// Arithmetic::fixed_point and evaluate_alarm), both placed on the replay's sample grid.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/sim/analysis.hpp"

namespace rockwatch::cli {

struct TimelineEntry {
  std::int64_t sample = 0;  // the seq of the sample at (or, offline, inside) which the level changed
  double t_s = 0.0;         // monitor: sample / rate; offline: the analysis time (an event located inside a step)
  std::string level;        // "QUIET" ... "COLLAPSED"
};

struct MonitorOutput {
  std::vector<TimelineEntry> transitions;
  std::optional<nlohmann::json> summary;  // the {"summary": {...}} line's object
  std::vector<std::string> other_lines;   // lines that are neither (shown when something went wrong)
  std::size_t other_walls_transitions = 0;  // a walls configuration: transitions of walls other than "wall"
};

// Reads the monitor's stdout. The sample of a transition is its "input_seq" when present, else
// round((utime − start_utime)·rate/1e6).
MonitorOutput parse_monitor_output(const std::string& text, std::int64_t start_utime, double rate_hz);

struct OfflineRun {
  sim::AnalysisResult result;
  std::vector<TimelineEntry> transitions;  // those up to the last sample (the monitor sees no more)
  std::size_t after_record = 0;            // transitions of the free motion after the record (not compared)
};

// The analysis the monitor's engine reproduces: the fixed-point engine, one step per sample (max step = 1/rate),
// the alarm after every step; transitions at time t belong to sample ceil(t·rate) (the step ending there).
OfflineRun run_offline(const core::WallParameters& wall, const sim::GroundMotion& motion,
                       const sim::AnalysisOptions& base);

// The true wall of the instrumented case: the verified double engine (one step per sample, the alarm after every
// step, the history kept for the wall's simulated sensors) with restitution `r`.
OfflineRun run_truth(const core::WallParameters& wall, const sim::GroundMotion& motion, const core::Restitution& r);

struct TimelineComparison {
  bool match = false;
  std::size_t same_sample = 0;  // pairs in the same sample
  std::size_t next_sample = 0;  // pairs one sample apart
  std::string reason;           // why not, when not
};

// Match: the same number of transitions, the same levels in the same order, each pair at most one sample apart.
TimelineComparison compare_timelines(const std::vector<TimelineEntry>& monitor,
                                     const std::vector<TimelineEntry>& offline);

// The two timelines side by side, one transition a row, each line starting with `indent`.
std::string side_by_side(const std::vector<TimelineEntry>& monitor, const std::vector<TimelineEntry>& offline,
                         const std::string& indent);

// Several timelines in columns (the instrumented case: the true wall, the monitor's nominal wall open loop, the
// monitor fused with the wall's sensors), one transition a row: time [s] and level.
struct TimelineColumn {
  std::string title;
  std::vector<TimelineEntry> entries;
};
std::string columns_text(const std::vector<TimelineColumn>& columns, const std::string& indent);

}  // namespace rockwatch::cli
