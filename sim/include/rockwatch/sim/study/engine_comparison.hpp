// A study's engine against its reference, run by run: the fixed-point engine against the double one
// (`rockwatch study --arith fixed`: verdicts, max |x|, first IMMINENT) and the plan's step against the reference step
// (`--dt-check`: the survivors' max |x|). Figures in summary.json's "fixed_vs_double" and "dt_check".
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "rockwatch/sim/study/batch_study.hpp"

namespace rockwatch::sim::study {

// --arith fixed: the fixed engine against the double engine (RunResult::reference), run by run.
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

FixedComparison fixed_comparison(const StudyPlan& plan, const std::vector<RunResult>& results);

// --dt-check: the plan's engine at its max step against the double engine at the reference step (dt_check_step_s).
struct DtCheckFigures {
  double reference_step_s = 0.0;            // [s]
  std::size_t survivors_compared = 0;       // runs both survive, the reference with max |x| > 0
  std::optional<double> rel_error_median, rel_error_p90, rel_error_max;  // |max|x| − reference| / reference [-]
  std::optional<double> abs_error_m_median, abs_error_m_p90, abs_error_m_max;  // |max|x| − reference| [m]
};

DtCheckFigures dt_check_figures(const StudyPlan& plan, const std::vector<RunResult>& results);

// Runs whose verdict of record (the double engine's) differs at the reference step.
std::vector<std::size_t> dt_check_flipped_runs(const std::vector<RunResult>& results);

}  // namespace rockwatch::sim::study
