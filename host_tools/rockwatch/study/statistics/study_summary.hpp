// What a finished `rockwatch study` says: the statistics of each case (sim::study::case_statistics over its runs
// with a verdict), the verdicts the --dt-check flipped, summary.json and the summary for engineers on stdout.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rockwatch/sim/study/batch_study.hpp"
#include "rockwatch/sim/study/collapse_statistics.hpp"
#include "study/plan/study_plan.hpp"
#include "study/plan/study_records.hpp"
#include "study/plan/study_request.hpp"

namespace rockwatch::cli {

struct CaseOutcome {
  StudyCase study_case;
  std::string title;                  // "r_exp H+V"
  std::string tag;                    // "exp_HV"
  double r_value = 0.0;               // the energy ratio of the case's restitution for the wall
  std::size_t runs_with_error = 0;    // refused by the engine: no verdict, left out of the statistics
  std::optional<sim::study::CaseStatistics> statistics;  // none when no run of the case has a verdict
};

// --alarms: how well IMMINENT (of the plan's engine) foretells the collapses of the verdict of record (the double
// engine's), over the runs with a verdict.
struct AlarmOutcome {
  std::size_t runs = 0;                  // runs with a verdict
  std::size_t collapsed = 0;             // of them collapsed (double verdict)
  std::size_t collapsed_flagged = 0;     // of those, IMMINENT strictly before t_collapse
  std::size_t survivors = 0;
  std::size_t survivors_flagged = 0;     // survivors ever at IMMINENT
  std::optional<double> recall;          // collapsed_flagged / collapsed
  std::optional<double> false_alarm_rate;  // survivors_flagged / survivors
  std::vector<double> lead_times_s;      // t_collapse − first IMMINENT of the flagged collapses, ascending [s]
  std::optional<double> lead_time_s_median, lead_time_s_p05, lead_time_s_min;
};

// --arith fixed --alarms: the same alarm as the monitor publishes it, its engine doing at most a budget of work per
// call (docs/FIXED_POINT.md "carry-over"): the recall and lead times at the publication, and the latency.
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

// --arith fixed: the fixed engine against the double engine, run by run.
struct FixedComparison {
  std::size_t runs_compared = 0;         // runs with a verdict
  std::size_t verdicts_same = 0;
  std::vector<std::size_t> verdict_flips;            // run indices where the verdicts differ
  std::vector<std::size_t> flips_also_at_reference;  // --dt-check: flips whose double verdict changes at the reference step
  std::optional<double> max_abs_x_diff_m_max;        // over runs that survive in both engines [m]
  std::size_t survivors_compared = 0;                // runs that survive in both engines
  std::size_t survivors_within_half_mm = 0;          //   of which max|x| differs by at most 0.5 mm (the bound)
  std::optional<std::size_t> first_imminent_diff_samples_max;  // --alarms: over runs where both reach IMMINENT
                                                              // [integration steps]
  std::size_t imminent_compared = 0;                 // --alarms: runs where both engines reach IMMINENT
  std::size_t imminent_within_one_step = 0;          //   of which the first IMMINENT is at most one step apart
  std::size_t runs_saturated = 0;
};

// --dt-check: the plan's engine at its max step against the double engine at the reference step (dt_check_step_s).
struct DtCheckFigures {
  double reference_step_s = 0.0;            // [s]
  std::size_t survivors_compared = 0;       // runs both survive, the reference with max |x| > 0
  std::optional<double> rel_error_median, rel_error_p90, rel_error_max;  // |max|x| − reference| / reference [-]
  std::optional<double> abs_error_m_median, abs_error_m_p90, abs_error_m_max;  // |max|x| − reference| [m]
};

struct StudyOutcome {
  StaticCapacities capacities;
  std::vector<CaseOutcome> cases;     // in study_cases() order
  std::vector<std::size_t> flipped_runs;  // --dt-check: runs whose verdict of record differs at the reference step
  std::optional<DtCheckFigures> dt_check;  // --dt-check: the survivors' max |x| against the reference
  std::size_t runs_with_error = 0;
  std::optional<AlarmOutcome> alarm;              // with --alarms
  std::optional<PublishedAlarm> published;        // with --arith fixed --alarms
  std::optional<FixedComparison> fixed_vs_double;  // with --arith fixed
};

// The p-quantile (p in [0, 1]) of ascending values by linear interpolation between order statistics (Hyndman and
// Fan's type 7, NumPy's and R's default): h = (n − 1) p, x[⌊h⌋] + (h − ⌊h⌋)(x[⌊h⌋+1] − x[⌊h⌋]). None when empty.
std::optional<double> quantile_type7(const std::vector<double>& ascending, double p);

AlarmOutcome alarm_outcome(const std::vector<sim::study::RunResult>& results);
PublishedAlarm published_alarm(const std::vector<sim::study::RunResult>& results);
// The outcome's scores as JSON: recall, false_alarm_rate, lead times, counts (summary.json "alarm" and the observer
// evaluation's per-arm scores).
nlohmann::ordered_json alarm_score_json(const AlarmOutcome& a);
FixedComparison fixed_comparison(const sim::study::StudyPlan& plan, const std::vector<sim::study::RunResult>& results);

// `results` must be complete (every run done).
StudyOutcome summarise_study(const sim::study::StudyPlan& plan, const std::vector<sim::study::RunResult>& results,
                             const StaticCapacities& capacities);

// summary.json: "format", "version", "records_source", "plan" (plan_json), "capacities", "runs", "dt_check",
// "cases" (per case the keys the help lists; null where a value is undetermined), with --alarms "alarm" and with
// --arith fixed "fixed_vs_double". Deterministic: the same plan and results give the same text.
nlohmann::ordered_json summary_json(const sim::study::StudyPlan& plan, const StudyRecords& records,
                                    const std::vector<sim::study::RunResult>& results, const StudyOutcome& outcome);

// The human summary, ending with a newline; `files` lists what was written, after `before_files` (more lines, e.g.
// the observer evaluation's).
std::string study_summary_text(const StudyRequest& request, const sim::study::StudyPlan& plan,
                               const StudyRecords& records, const StudyOutcome& outcome,
                               const std::vector<std::string>& files, const std::string& before_files = {});

// "0.221 g" style texts shared with table3.md: a probability with three decimals, or "-" when undetermined.
std::string probability_text(const std::optional<double>& p);

// The collapse probabilities of one case at a capacity, as the table and the summary show them.
const sim::study::CollapseProbability& at_capacity(const sim::study::CaseStatistics& s, bool nzsee2016);

// "set01 X, H+V, r_ana, 0.21 g (run 123)": one run as messages name it.
std::string run_text(const sim::study::StudyPlan& plan, std::size_t index);

}  // namespace rockwatch::cli
