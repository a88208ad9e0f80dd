// table3.md of a `rockwatch study`: the design paper's Table 3 (minimum PGA that collapsed the wall, mean and
// standard deviation of the fitted normal distribution) with this study's numbers beside the paper's, and the
// probability of collapse at the static capacities, ours and implied by the paper's fit.
#pragma once

#include <optional>
#include <string>

#include "rockwatch/sim/study/batch_study.hpp"
#include "study/plan/study_records.hpp"
#include "study/report/study_summary.hpp"

namespace rockwatch::cli {


// The paper's Table 3 row for a case (SPEC section 6), with the real NPR 9998 records.
struct PaperRow {
  const char* r_label;  // "ana" | "exp"
  bool vertical;
  double min_pga_collapse_g, mean_g, std_g;
};

inline constexpr PaperRow kPaperTable3[] = {
    {"ana", false, 0.15, 0.221, 0.055},
    {"ana", true, 0.16, 0.219, 0.053},
    {"exp", false, 0.21, 0.268, 0.047},
    {"exp", true, 0.21, 0.271, 0.045},
};

// The paper's row for a restitution label and vertical setting, if its table has one.
std::optional<PaperRow> paper_row(const std::string& r_label, bool vertical);

// The Markdown document, ending with a newline.
std::string table3_markdown(const sim::study::StudyPlan& plan, const StudyRecords& records,
                            const StudyOutcome& outcome);

}  // namespace rockwatch::cli
