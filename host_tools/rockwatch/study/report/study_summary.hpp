// What a finished `rockwatch study` says: the statistics of each case (sim::study::case_statistics over its runs
// with a verdict), the verdicts the --dt-check flipped, the alarm's scores and the engine comparisons (computed in
// sim/study: alarm_scores, engine_comparison), summary.json and the summary for engineers on stdout.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rockwatch/sim/study/alarm_scores.hpp"
#include "rockwatch/sim/study/batch_study.hpp"
#include "rockwatch/sim/study/collapse_statistics.hpp"
#include "rockwatch/sim/study/engine_comparison.hpp"
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

struct StudyOutcome {
  StaticCapacities capacities;
  std::vector<CaseOutcome> cases;     // in study_cases() order
  std::vector<std::size_t> flipped_runs;  // --dt-check: runs whose verdict of record differs at the reference step
  std::optional<sim::study::DtCheckFigures> dt_check;  // --dt-check: the survivors' max |x| against the reference
  std::size_t runs_with_error = 0;
  std::optional<sim::study::AlarmOutcome> alarm;              // with --alarms
  std::optional<sim::study::PublishedAlarm> published;        // with --arith fixed --alarms
  std::optional<sim::study::FixedComparison> fixed_vs_double;  // with --arith fixed
};

// The outcome's scores as JSON: recall, false_alarm_rate, lead times, counts (summary.json "alarm" and the observer
// evaluation's per-arm scores).
nlohmann::ordered_json alarm_score_json(const sim::study::AlarmOutcome& a);

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
