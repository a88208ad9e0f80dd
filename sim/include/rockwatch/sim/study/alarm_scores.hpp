// How well an alarm foretells collapse over a study's runs: recall (collapses flagged IMMINENT strictly before they
// collapse), false-alarm rate (survivors ever flagged) and lead times, at the alarm's computation (alarm_outcome) and
// at its publication by the monitor's engine, which does at most a budget of work per call (published_alarm;
// docs/FIXED_POINT.md "carry-over"). Used by `rockwatch study --alarms` (summary.json "alarm", "published_alarm")
// and the observer's evaluation; reachable from Python as rockwatch.study.alarm_outcome.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "rockwatch/core/work_meter.hpp"
#include "rockwatch/sim/study/batch_study.hpp"

namespace rockwatch::sim::study {

// One run as the alarm scores take it: the verdict of record, its collapse time, the alarm's first IMMINENT.
struct AlarmRun {
  bool collapsed = false;
  std::optional<double> t_collapse_s;        // [s]
  std::optional<double> t_first_imminent_s;  // [s]
};

// How well IMMINENT foretells the collapses of the verdict of record, over the runs given.
struct AlarmOutcome {
  std::size_t runs = 0;                  // runs with a verdict
  std::size_t collapsed = 0;             // of them collapsed (the verdict of record)
  std::size_t collapsed_flagged = 0;     // of those, IMMINENT strictly before t_collapse
  std::size_t survivors = 0;
  std::size_t survivors_flagged = 0;     // survivors ever at IMMINENT
  std::optional<double> recall;          // collapsed_flagged / collapsed
  std::optional<double> false_alarm_rate;  // survivors_flagged / survivors
  std::vector<double> lead_times_s;      // t_collapse − first IMMINENT of the flagged collapses, ascending [s]
  std::optional<double> lead_time_s_median, lead_time_s_p05, lead_time_s_min;
};

AlarmOutcome alarm_outcome(const std::vector<AlarmRun>& runs);

// --alarms: IMMINENT of the plan's engine against the double engine's verdict (the verdict of record), over the runs
// done without error.
AlarmOutcome alarm_outcome(const std::vector<RunResult>& results);

// --arith fixed --alarms: the same alarm as the monitor publishes it, its engine doing at most a budget of work per
// call: the recall and lead times at the publication, and the latency.
struct PublishedAlarm {
  std::int32_t work_budget_units = 0;              // of the monitor's engine, per call
  std::size_t collapsed = 0, collapsed_flagged = 0;  // as AlarmOutcome, with IMMINENT published before t_collapse
  std::optional<double> recall;
  std::size_t survivors = 0, survivors_flagged = 0;  // survivors whose IMMINENT was ever published
  std::optional<double> false_alarm_rate;
  std::optional<double> lead_time_s_median, lead_time_s_min;
  std::optional<double> imminent_delay_s_max;  // publication − the step end it was computed for, over runs [s]
  std::size_t runs_imminent_delayed = 0;       // runs whose first IMMINENT was published late
  std::size_t runs_late = 0;                   // runs with any sample published late
  std::uint32_t max_late_samples = 0;          // the most samples one sample waited, over the runs
  std::size_t shed_samples = 0;                // samples shed (events not located), over the runs
  core::WorkOverflow work_overflow = core::WorkOverflow::shed;  // what the engine did at a full queue
  std::size_t overrun_calls = 0;               // calls that worked beyond the budget, over the runs
  std::size_t runs_overrun = 0;                // runs with an overrun
  std::int32_t max_call_units = 0;             // the most work one call did, over the runs [work units]
};

// The publication figures of the runs done without error (work_budget_units and work_overflow left to the caller,
// who knows the plan).
PublishedAlarm published_alarm(const std::vector<RunResult>& results);

}  // namespace rockwatch::sim::study
