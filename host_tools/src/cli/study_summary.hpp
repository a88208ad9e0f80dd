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
#include "study_plan.hpp"
#include "study_records.hpp"
#include "study_request.hpp"

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
  std::vector<std::size_t> flipped_runs;  // --dt-check: runs whose verdict differs at half the step
  std::size_t runs_with_error = 0;
};

// `results` must be complete (every run done).
StudyOutcome summarise_study(const sim::study::StudyPlan& plan, const std::vector<sim::study::RunResult>& results,
                             const StaticCapacities& capacities);

// summary.json: "format", "version", "records_source", "plan" (plan_json), "capacities", "runs", "dt_check" and
// "cases" (per case the keys the help lists; null where a value is undetermined). Deterministic: the same plan
// and results give the same text.
nlohmann::ordered_json summary_json(const sim::study::StudyPlan& plan, const StudyRecords& records,
                                    const std::vector<sim::study::RunResult>& results, const StudyOutcome& outcome);

// The human summary, ending with a newline; `files` lists what was written.
std::string study_summary_text(const StudyRequest& request, const sim::study::StudyPlan& plan,
                               const StudyRecords& records, const StudyOutcome& outcome,
                               const std::vector<std::string>& files);

// "0.221 g" style texts shared with table3.md: a probability with three decimals, or "-" when undetermined.
std::string probability_text(const std::optional<double>& p);

// The collapse probabilities of one case at a capacity, as the table and the summary show them.
const sim::study::CollapseProbability& at_capacity(const sim::study::CaseStatistics& s, bool nzsee2016);

// "set01 X, H+V, r_ana, 0.21 g (run 123)": one run as messages name it.
std::string run_text(const sim::study::StudyPlan& plan, std::size_t index);

}  // namespace rockwatch::cli
