#include "rockwatch/sim/study/alarm_scores.hpp"

#include <algorithm>

#include "rockwatch/sim/study/quantile.hpp"

namespace rockwatch::sim::study {

AlarmOutcome alarm_outcome(const std::vector<AlarmRun>& runs) {
  AlarmOutcome a;
  for (const AlarmRun& r : runs) {
    ++a.runs;
    if (r.collapsed) {
      ++a.collapsed;
      if (r.t_first_imminent_s && r.t_collapse_s && *r.t_first_imminent_s < *r.t_collapse_s) {
        ++a.collapsed_flagged;
        a.lead_times_s.push_back(*r.t_collapse_s - *r.t_first_imminent_s);
      }
    } else {
      ++a.survivors;
      if (r.t_first_imminent_s) ++a.survivors_flagged;
    }
  }
  if (a.collapsed > 0) a.recall = double(a.collapsed_flagged) / double(a.collapsed);
  if (a.survivors > 0) a.false_alarm_rate = double(a.survivors_flagged) / double(a.survivors);
  std::sort(a.lead_times_s.begin(), a.lead_times_s.end());
  a.lead_time_s_median = quantile_type7(a.lead_times_s, 0.5);
  a.lead_time_s_p05 = quantile_type7(a.lead_times_s, 0.05);
  if (!a.lead_times_s.empty()) a.lead_time_s_min = a.lead_times_s.front();
  return a;
}

AlarmOutcome alarm_outcome(const std::vector<RunResult>& results) {
  std::vector<AlarmRun> runs;
  for (const RunResult& r : results) {
    if (!r.done || !r.error.empty()) continue;
    runs.push_back(AlarmRun{double_collapsed(r), double_t_collapse_s(r), r.t_first_imminent_s});
  }
  return alarm_outcome(runs);
}

PublishedAlarm published_alarm(const std::vector<RunResult>& results) {
  PublishedAlarm p;
  std::vector<double> lead;
  for (const RunResult& r : results) {
    if (!r.done || !r.error.empty()) continue;
    if (r.max_late_samples > 0) ++p.runs_late;
    p.max_late_samples = std::max(p.max_late_samples, r.max_late_samples);
    p.shed_samples += r.shed_samples;
    p.overrun_calls += r.overrun_calls;
    if (r.overrun_calls > 0) ++p.runs_overrun;
    p.max_call_units = std::max(p.max_call_units, r.max_call_units);
    if (r.t_first_imminent_s && r.t_first_imminent_published_s) {
      const double delay = *r.t_first_imminent_published_s - *r.t_first_imminent_s;
      if (!p.imminent_delay_s_max || delay > *p.imminent_delay_s_max) p.imminent_delay_s_max = delay;
    }
    if (!double_collapsed(r)) {
      ++p.survivors;
      if (r.t_first_imminent_published_s) ++p.survivors_flagged;
      continue;
    }
    ++p.collapsed;
    const std::optional<double> t_collapse = double_t_collapse_s(r);
    if (r.t_first_imminent_published_s && t_collapse && *r.t_first_imminent_published_s < *t_collapse) {
      ++p.collapsed_flagged;
      lead.push_back(*t_collapse - *r.t_first_imminent_published_s);
    }
  }
  for (const RunResult& r : results) {
    if (r.done && r.error.empty() && r.imminent_late_samples > 0) ++p.runs_imminent_delayed;
  }
  if (p.collapsed > 0) p.recall = double(p.collapsed_flagged) / double(p.collapsed);
  if (p.survivors > 0) p.false_alarm_rate = double(p.survivors_flagged) / double(p.survivors);
  std::sort(lead.begin(), lead.end());
  p.lead_time_s_median = quantile_type7(lead, 0.5);
  if (!lead.empty()) p.lead_time_s_min = lead.front();
  return p;
}

}  // namespace rockwatch::sim::study
