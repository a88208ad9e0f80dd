// The wall observer's evaluation (run_observer_evaluation, `rockwatch study --alarms --observer`) scored against the
// TRUE wall's verdict with the study's own alarm scores (alarm_outcome: recall, false alarms, lead times), for the
// nominal wall open loop and fused, plus the estimation errors: x RMS error over x_inst (fused and open loop against
// the true trajectory) and |r̂ − r_true| after n impacts; over all runs and per mismatch case.
#pragma once

#include <cstddef>
#include <vector>

#include "rockwatch/sim/study/alarm_scores.hpp"
#include "rockwatch/sim/study/batch_study.hpp"
#include "rockwatch/sim/study/observer_evaluation.hpp"
#include "rockwatch/sim/study/quantile.hpp"

namespace rockwatch::sim::study {

struct ObserverScore {
  std::size_t runs = 0;              // runs with results (no error)
  std::size_t runs_with_error = 0;
  AlarmOutcome open_loop, fused;     // against the true wall's verdict
  Spread fused_x_rms_over_x_inst;    // per run, over the rows where the true or the fused wall moves
  Spread open_x_rms_over_x_inst;
  std::size_t fused_x_within_2_percent = 0;
  Spread r_error_after_impacts;      // |r̂ − r_true| after n impacts, over the runs with at least n
  Spread r_error_final;              // |r̂ − r_true| at the end, over the same runs
  std::size_t r_within_0_02 = 0;     // of them, after n impacts
  Spread x_inst_error_after_impacts;  // |x̂_inst − x_inst,true| / x_inst,true after n impacts, same runs
  std::size_t x_inst_within_3_percent = 0;  // of them
  // The same after n counted impacts of the TRUE wall (issue 27's "once the wall has impacted 5 times"), over the runs
  // whose true wall impacted more than n times: the fused wall's own first impacts can be noise-driven chatter of the
  // model while the real wall is still at rest.
  Spread r_error_after_true_impacts, x_inst_error_after_true_impacts;
  std::size_t r_within_0_02_after_true_impacts = 0, x_inst_within_3_percent_after_true_impacts = 0;
  std::size_t runs_reinitialised = 0, runs_sensor_lost = 0;
};

struct ObserverOutcome {
  ObserverScore all;
  std::vector<ObserverScore> per_case;  // in the evaluation's case order
};

ObserverOutcome observer_outcome(const StudyPlan& plan, const ObserverEvaluationPlan& evaluation,
                                 const std::vector<ObserverRunResult>& results);

}  // namespace rockwatch::sim::study
