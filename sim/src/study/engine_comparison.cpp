#include "rockwatch/sim/study/engine_comparison.hpp"

#include <algorithm>
#include <cmath>

#include "rockwatch/sim/study/quantile.hpp"

namespace rockwatch::sim::study {

FixedComparison fixed_comparison(const StudyPlan& plan, const std::vector<RunResult>& results) {
  FixedComparison f;
  for (std::size_t index = 0; index < results.size(); ++index) {
    const RunResult& r = results[index];
    if (!r.done || !r.error.empty() || !r.reference) continue;
    const DoubleReference& d = *r.reference;
    ++f.runs_compared;
    f.runs_saturated += r.saturated ? 1U : 0U;
    if (r.collapsed == d.collapsed) {
      ++f.verdicts_same;
    } else {
      f.verdict_flips.push_back(index);
      if (r.collapsed_reference && *r.collapsed_reference != d.collapsed) f.flips_also_at_reference.push_back(index);
    }
    if (!r.collapsed && !d.collapsed) {
      const double diff = std::fabs(r.max_abs_x_m - d.max_abs_x_m);
      f.max_abs_x_diff_m_max = std::max(f.max_abs_x_diff_m_max.value_or(0.0), diff);
      ++f.survivors_compared;
      if (diff <= 5e-4) ++f.survivors_within_half_mm;
    }
    if (r.t_first_imminent_s && d.t_first_imminent_s) {
      // The alarm runs once per record sample: both times are sample ends (a collapse point only when IMMINENT comes
      // with the collapse), a whole number of samples apart.
      const double h = plan.records[run_key(plan, index).record_index].dt_s;
      const auto steps =
          static_cast<std::size_t>(std::llround(std::fabs(*r.t_first_imminent_s - *d.t_first_imminent_s) / h));
      f.first_imminent_diff_samples_max = std::max(f.first_imminent_diff_samples_max.value_or(0), steps);
      ++f.imminent_compared;
      if (steps <= 1) ++f.imminent_within_one_step;
    }
  }
  return f;
}

DtCheckFigures dt_check_figures(const StudyPlan& plan, const std::vector<RunResult>& results) {
  DtCheckFigures d;
  d.reference_step_s = dt_check_step_s(plan);
  std::vector<double> rel, abs_m;
  for (const RunResult& r : results) {
    if (!r.error.empty() || !r.done || !r.collapsed_reference || !r.max_abs_x_reference_m) continue;
    if (r.collapsed || *r.collapsed_reference || !(*r.max_abs_x_reference_m > 0.0)) continue;
    const double e = std::fabs(r.max_abs_x_m - *r.max_abs_x_reference_m);
    abs_m.push_back(e);
    rel.push_back(e / *r.max_abs_x_reference_m);
  }
  std::sort(rel.begin(), rel.end());
  std::sort(abs_m.begin(), abs_m.end());
  d.survivors_compared = rel.size();
  d.rel_error_median = quantile_type7(rel, 0.5);
  d.rel_error_p90 = quantile_type7(rel, 0.9);
  d.rel_error_max = quantile_type7(rel, 1.0);
  d.abs_error_m_median = quantile_type7(abs_m, 0.5);
  d.abs_error_m_p90 = quantile_type7(abs_m, 0.9);
  d.abs_error_m_max = quantile_type7(abs_m, 1.0);
  return d;
}

std::vector<std::size_t> dt_check_flipped_runs(const std::vector<RunResult>& results) {
  std::vector<std::size_t> flipped;
  for (std::size_t index = 0; index < results.size(); ++index) {
    const RunResult& r = results[index];
    if (r.error.empty() && r.collapsed_reference && *r.collapsed_reference != double_collapsed(r)) {
      flipped.push_back(index);
    }
  }
  return flipped;
}

}  // namespace rockwatch::sim::study
