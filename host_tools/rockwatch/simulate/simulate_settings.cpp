#include "simulate/simulate_settings.hpp"

#include <cmath>
#include <string>

#include "rockwatch/core/stepper_alarm_chain.hpp"
#include "rockwatch/options/engine_options.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

namespace {

// A 10-minute record at 0.5 ms is 1.2e6 steps.
constexpr double kMaxIntegrationSteps = 1e8;
constexpr double kMaxHistoryRows = 2e7;  // a run keeping the history holds every step in memory before writing

}  // namespace

void apply_simulate_settings(const SimulateSettings& s, SimulateRequest& q) {
  q.wall = s.wall.wall;
  q.wall_name = s.wall.name;
  q.wall_options_given = s.wall.options_given;
  q.wall_file_path = s.wall.wall_file_path;
  if (s.scale_pga_g) q.scale_pga_g = check_positive_number("--scale-pga", *s.scale_pga_g, " (a multiple of g)");
  q.analysis.restitution = restitution_of(s.r, s.wall, "exp");
  q.analysis.model = parse_model("--model", s.model);
  check_computable(q.wall, q.analysis);
  apply_alarm_options(s.alarm, q.analysis);
  q.arith_given = s.arith_given;
  if (q.analysis.evaluate_alarm) q.analysis.max_alarm_transitions_kept = kMaxAlarmTransitionsListed;
  if (s.kappa) q.analysis.kappa = check_kappa("--kappa", *s.kappa);
  if (s.max_step_s) q.analysis.max_step_s = check_positive_number("--max-step", *s.max_step_s, " s");
  if (s.t_end_s) {
    check_finite_number("--t-end", *s.t_end_s);
    if (!(*s.t_end_s >= 0.0)) throw UsageError("--t-end must be >= 0 s (got " + number_text(*s.t_end_s) + ")");
    q.analysis.t_end_s = *s.t_end_s;
  }
  q.analysis.keep_history = s.keep_history;
  q.history_kept_by = s.history_kept_by;
}

void check_work_size(const SimulateRequest& q, const sim::GroundMotion& motion) {
  const double dt_s = motion.dt_s;
  if (core::substeps_per_sample(dt_s, q.analysis.max_step_s) == 0) {
    throw UsageError("--max-step " + number_text(q.analysis.max_step_s) + " s would need more than " +
                     std::to_string(core::kMaxSubsteps) + " sub-steps per record sample (the record's dt is " +
                     number_text(dt_s) + " s): give --max-step >= dt / " + std::to_string(core::kMaxSubsteps));
  }
  const double n_sub = std::fmax(1.0, double(core::substeps_per_sample(dt_s, q.analysis.max_step_s)));
  const double h_s = dt_s / n_sub;
  const double t_end_s = q.analysis.t_end_s ? *q.analysis.t_end_s : motion.duration_s();
  const double worst_steps = (t_end_s + q.analysis.free_motion_limit_s) / h_s;
  // The history and --engine-input-out keep a row per step in memory before writing.
  const bool keeps_rows = q.analysis.keep_history || q.engine_input_out_path;
  const double limit = keeps_rows ? kMaxHistoryRows : kMaxIntegrationSteps;
  if (worst_steps > limit) {
    throw UsageError("integration step " + number_text(h_s) + " s over t_end = " + number_text(t_end_s) +
                     " s (plus up to " + number_text(q.analysis.free_motion_limit_s) + " s of free rocking) means up to " +
                     number_text(std::round(worst_steps)) + " steps, more than the " + number_text(limit) +
                     (q.analysis.keep_history   ? " a run " + q.history_kept_by + " may take"
                      : q.engine_input_out_path ? std::string(" a run with --engine-input-out may take")
                                                : std::string(" a run may take")) +
                     ": raise --max-step or lower --t-end");
  }
  if (q.sensors_out_path) {
    const double rate_hz = q.sensor_model.rate_hz > 0.0 ? q.sensor_model.rate_hz : 1.0 / dt_s;
    const double worst_samples = rate_hz * (t_end_s + q.analysis.free_motion_limit_s);
    if (worst_samples > kMaxHistoryRows) {
      throw UsageError("--sensor-rate-hz " + number_text(rate_hz) + " over t_end = " + number_text(t_end_s) +
                       " s (plus up to " + number_text(q.analysis.free_motion_limit_s) +
                       " s of free rocking) means up to " + number_text(std::round(worst_samples)) +
                       " sensor samples, more than the " + number_text(kMaxHistoryRows) +
                       " --sensors-out may write: lower the rate or --t-end");
    }
  }
}

}  // namespace rockwatch::cli
