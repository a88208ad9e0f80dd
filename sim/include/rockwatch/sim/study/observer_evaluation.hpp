// The wall observer's evaluation (`rockwatch study --alarms --observer`): for each record × PGA level × vertical
// setting of a study plan and each mismatch case — a *true* wall that differs from the nominal one (another r, b,
// h1/h2) — three analyses on the same scaled input:
//   truth      the true wall, double engine, history kept: its verdict is the verdict of record, and its sensor
//              samples (SensorModel: by default 0.5 mm noise and a 2 mm zero offset at the record's rate) are made
//              from its history, in memory;
//   open loop  the nominal wall on the ground motion alone, with the alarm (the plan's arithmetic);
//   fused      the nominal wall with the observer fed those samples, with the alarm (the plan's arithmetic).
// Each run keeps what the scores need: the true verdict and collapse time, the first IMMINENT of both nominal runs,
// the x error of both against the true trajectory, the observer's r̂ (after n impacts and at the end) and health.
//
// Run order (the run index), outermost first: mismatch case, vertical setting, record, PGA level. Each run's sensor
// noise has its own seed (from the model's seed and the run index), so the results do not depend on the thread count.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/core/wall_observer.hpp"
#include "rockwatch/sim/study/batch_study.hpp"
#include "rockwatch/sim/wall_sensor_synthesis.hpp"

namespace rockwatch::sim::study {

// A true wall that differs from the nominal one.
struct MismatchCase {
  std::string name;                  // "r_ana", "b_0.9", ...: reports and file names
  std::string description;           // "true r = r_ana, nominal r_exp"
  core::WallParameters wall;         // the true wall
  core::Restitution restitution;     // the true wall's restitution (evaluated for the true wall)
  // The sensor set: with an accelerometer at the hinge (this σ of its noise) besides the displacement transducer;
  // none: the transducer alone (the plan's sensor model otherwise).
  std::optional<double> accel_noise_mps2;
};

// The mismatch cases for a nominal wall with restitution r_exp, the monitor told only the nominal wall (issue 27):
// true r = r_ana and r = 0.8; true b = 0.85 b, 0.9 b and 1.1 b; the mid-height hinge moved, h1 : h2 = 1.5 : 2.0 with
// the same total height; an overburden of 2 and 3 kN/m. Each true wall with r_exp of its own geometry except the r
// cases. Each with the displacement transducer alone, then again with an accelerometer (0.05 m/s², "+accel").
std::vector<MismatchCase> standard_mismatch_cases(const core::WallParameters& nominal);

// The study's sensors: 0.5 mm noise, a 2 mm zero offset, no accelerometer, the record's rate, seed 1.
SensorModel study_sensor_model();

struct ObserverEvaluationPlan {
  core::Restitution nominal_restitution{};  // the nominal wall's (r_exp)
  std::vector<MismatchCase> cases;
  SensorModel sensors = study_sensor_model();
  core::ObserverOptions observer{};
  int r_after_impacts = 5;                   // r̂ is scored after this many impacts
};

struct ObserverRunResult {
  bool done = false;
  std::string error;                          // an analysis refused the input: no scores
  // The true wall.
  bool true_collapsed = false;                // verdict_collapse()
  std::optional<double> true_t_collapse_s;
  double true_r = 0.0;                        // its energy ratio
  double true_x_inst_m = 0.0;
  double true_max_abs_x_m = 0.0;
  int true_impacts = 0;
  // The nominal wall, open loop and fused.
  bool open_collapsed = false, fused_collapsed = false;
  std::optional<double> open_t_first_imminent_s, fused_t_first_imminent_s;
  // x − x_true over the common step grid, over the rows where either moves; none when neither moved.
  std::optional<double> open_x_rms_error_m, fused_x_rms_error_m;
  // The observer.
  double r_estimate = 0.0;
  std::optional<double> r_estimate_after_impacts;
  double x_inst_estimate_m = 0.0;                         // the observer's x̂_inst at the end [m]
  std::optional<double> x_inst_estimate_after_impacts_m;  // ... when r̂ after n impacts was taken [m]
  // r̂ and x̂_inst after n counted impacts of the TRUE wall: before the input sample that holds its impact n + 1 (none
  // when the true wall impacted n times or fewer) [-, m].
  std::optional<double> r_estimate_after_true_impacts, x_inst_estimate_after_true_impacts_m;
  int fused_impacts = 0;
  double bias_estimate_m = 0.0;
  std::int64_t n_updates = 0, n_rejected = 0, n_reinitialised = 0;
  std::size_t steps_sensor_lost = 0;
};

std::size_t observer_run_count(const StudyPlan& plan, const ObserverEvaluationPlan& evaluation);

struct ObserverRunKey {
  std::size_t case_index = 0, vertical_index = 0, record_index = 0, pga_index = 0;
};
ObserverRunKey observer_run_key(const StudyPlan& plan, const ObserverEvaluationPlan& evaluation, std::size_t index);

// Runs every run not done (results resized to observer_run_count if empty), on `jobs` threads (0: all), the plan
// validated as run_study does; stops early when *cancel becomes true. Throws AnalysisError for an inconsistent plan,
// SensorModelError for an invalid sensor model.
void run_observer_evaluation(const StudyPlan& plan, const ObserverEvaluationPlan& evaluation,
                             std::vector<ObserverRunResult>& results, std::size_t jobs,
                             const ProgressFn& progress = {}, const std::atomic<bool>* cancel = nullptr);

}  // namespace rockwatch::sim::study
